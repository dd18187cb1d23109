"""Drake model files: the package map, the hook gripper's SDF, object and table models."""
