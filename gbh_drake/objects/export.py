"""Write the object set to disk: ``<out_dir>/<name>/<name>.obj`` plus ``ground_truth.yaml``.

The .obj holds the mesh in frame O, metres, without normals or materials (Drake computes face
normals). ``ground_truth.yaml`` beside it records what a user of the mesh needs: density, mass,
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


def obj_bytes(mesh: trimesh.Trimesh) -> bytes:
    """The mesh as Wavefront OBJ text (vertices and faces only), deterministic."""
    text = trimesh.exchange.obj.export_obj(
        mesh, include_normals=False, include_color=False, include_texture=False, digits=7
    )
    return text.encode("utf-8")


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
