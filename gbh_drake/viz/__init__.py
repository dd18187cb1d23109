"""Debug views (may import pydrake; the algorithm core in ``gbh_drake.core`` does not)."""
