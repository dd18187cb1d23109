"""gbh_drake.systems."""
