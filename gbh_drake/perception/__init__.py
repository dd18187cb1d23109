"""gbh_drake.perception."""
