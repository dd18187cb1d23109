"""Meshes for the imported-mesh tests: a solid-filled mug, as a scan would give it; a
tetrahedron's OBJ bytes."""

import numpy as np
import trimesh

#: A tetrahedron, 1 m along each axis (an OBJ file's bytes).
CUBE_OBJ = b"v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n"


def filled_mug(radius=0.041, height=0.095, handle_major=0.028, handle_minor=0.0055):
    """A mug whose cup is a solid cylinder (the inside closed, as a scan gives it) with a torus
    handle on +x (hole axis +y); frame: base on z = 0, cup axis = z axis. Metres, watertight."""
    cup = trimesh.creation.cylinder(radius=radius, height=height, sections=48)
    cup.apply_translation((0.0, 0.0, 0.5 * height))
    handle = trimesh.creation.torus(handle_major, handle_minor, major_sections=48,
                                    minor_sections=16)
    handle.apply_transform(trimesh.transformations.rotation_matrix(np.pi / 2, (1, 0, 0)))
    handle.apply_translation((radius + handle_major - 2 * handle_minor, 0.0, 0.5 * height))
    mug = trimesh.boolean.union([cup, handle], engine="manifold")
    assert mug.is_watertight
    return mug


def random_rotation(rng: np.random.Generator) -> np.ndarray:
    """A uniformly random rotation matrix (3, 3)."""
    q = rng.normal(size=4)
    q /= np.linalg.norm(q)
    return trimesh.transformations.quaternion_matrix(q)[:3, :3]
