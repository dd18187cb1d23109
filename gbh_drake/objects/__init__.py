"""gbh_drake.objects."""
