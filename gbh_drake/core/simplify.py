"""Mesh simplification: Open3D's quadric decimation, for meshes denser than a use needs."""

from __future__ import annotations

import numpy as np
import trimesh


def simplified(mesh: trimesh.Trimesh, max_faces: int) -> trimesh.Trimesh:
    """``mesh`` itself when it has at most ``max_faces`` triangles, else a quadric decimation
    (Garland and Heckbert 1997, Open3D) to that many: flat regions collapse first, so shape and
    holes a few triangles wide survive."""
    from gbh_drake.core.o3d import open3d
    o3d = open3d()  # lazy: see gbh_drake.core.o3d
    if len(mesh.faces) <= max_faces:
        return mesh
    o3d_mesh = o3d.geometry.TriangleMesh(o3d.utility.Vector3dVector(np.asarray(mesh.vertices)),
                                         o3d.utility.Vector3iVector(np.asarray(mesh.faces)))
    reduced = o3d_mesh.simplify_quadric_decimation(target_number_of_triangles=int(max_faces))
    return trimesh.Trimesh(np.asarray(reduced.vertices), np.asarray(reduced.triangles),
                           process=False)
