"""Write the object set to disk: ``<out_dir>/<name>/<name>.obj`` plus ``ground_truth.yaml``.

The .obj holds the mesh in frame O, metres, and normals (Drake's renderer refuses an OBJ without
them): each face corner gets the area-weighted mean normal of the faces around its vertex that are
within ``CREASE_DEG`` of its own face, so curved surfaces shade smoothly and edges stay sharp.
Faces are written ``f v//vn``; vertex positions are not duplicated, so the file stays watertight.
``ground_truth.yaml`` beside it records what a user of the mesh needs: density, mass,
centre of mass and inertia about it (frame O), colour, designed genus, bounds and the hangable
parts (centre, unit axis, kind, clear diameter).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import trimesh
import yaml

from gbh_drake.objects.catalog import list_objects, make_object
from gbh_drake.objects.mass import mass_properties_detailed
from gbh_drake.objects.spec import ObjectSpec

CREASE_DEG = 35.0


def corner_normals(mesh: trimesh.Trimesh, crease_deg: float = CREASE_DEG) -> np.ndarray:
    """Unit normals ``(F, 3, 3)`` per face corner, smoothed over the faces at the corner's vertex
    whose normals are within ``crease_deg`` of the corner's face (see the module docstring)."""
    face_n = np.asarray(mesh.face_normals)
    weighted = face_n * np.asarray(mesh.area_faces)[:, None]
    neighbours = np.asarray(mesh.vertex_faces)[np.asarray(mesh.faces)]  # (F, 3, maxdeg)
    valid = neighbours >= 0
    nb = np.where(valid, neighbours, 0)
    similar = np.einsum("fk,fcdk->fcd", face_n, face_n[nb]) > np.cos(np.radians(crease_deg))
    normals = (weighted[nb] * (valid & similar)[..., None]).sum(axis=2)
    normals /= np.linalg.norm(normals, axis=-1, keepdims=True)
    return normals


def obj_bytes(mesh: trimesh.Trimesh) -> bytes:
    """The mesh as Wavefront OBJ text (vertices, corner normals, faces), deterministic."""
    normals = np.round(corner_normals(mesh).reshape(-1, 3), 4) + 0.0  # +0.0: no "-0.0"
    unique, index = np.unique(normals, axis=0, return_inverse=True)
    faces = np.asarray(mesh.faces) + 1
    corners = index.reshape(-1, 3) + 1
    lines = ["# gbh_drake object mesh, metres, frame O"]
    lines += [f"v {x:.7f} {y:.7f} {z:.7f}" for x, y, z in np.asarray(mesh.vertices)]
    lines += [f"vn {x:.4f} {y:.4f} {z:.4f}" for x, y, z in unique]
    lines += [
        f"f {a}//{na} {b}//{nb} {c}//{nc}"
        for (a, b, c), (na, nb, nc) in zip(faces.tolist(), corners.tolist(), strict=True)
    ]
    return ("\n".join(lines) + "\n").encode("ascii")


def ground_truth(spec: ObjectSpec) -> dict:
    """Plain-python description of an object (for YAML)."""
    props = mass_properties_detailed(spec.mesh, spec.density)

    def rounded(a, digits=7):
        return np.round(np.asarray(a, dtype=np.float64), digits).tolist()

    return {
        "name": spec.name,
        "description": spec.description,
        "is_control": spec.is_control,
        "genus": spec.genus,
        "density_kg_m3": float(spec.density),
        "mass_kg": round(props.mass, 5),
        "mass_properties_method": props.method,
        "com_O": rounded(props.com),
        "inertia_about_com_O": rounded(props.inertia, 9),
        "rgba": [float(c) for c in spec.rgba],
        "bounds_O": rounded(spec.mesh.bounds, 5),
        "n_faces": len(spec.mesh.faces),
        "hangable_parts": [p.as_dict() for p in spec.hangable_parts],
    }


def write_object(spec: ObjectSpec, out_dir) -> Path:
    """Write one object's .obj and ground_truth.yaml; returns the .obj path."""
    folder = Path(out_dir) / spec.name
    folder.mkdir(parents=True, exist_ok=True)
    obj_path = folder / f"{spec.name}.obj"
    obj_path.write_bytes(obj_bytes(spec.mesh))
    with open(folder / "ground_truth.yaml", "w") as f:
        yaml.safe_dump(ground_truth(spec), f, sort_keys=False)
    return obj_path


def write_object_meshes(out_dir, names: list[str] | None = None) -> list[Path]:
    """Write every object (or ``names``) under ``out_dir``; returns the .obj paths."""
    return [write_object(make_object(n), out_dir) for n in (names or list_objects())]
