"""Pure geometry of Grasping by Hanging: numpy/trimesh/open3d only, no pydrake."""
