"""gbh_drake.planning."""
