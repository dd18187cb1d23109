"""Turns any triangle mesh into a Drake model of a free rigid body.

The body's visual and collision geometry is the mesh itself (written as an ``.obj`` next to the
SDF); the collision geometry is *rigid* hydroelastic, which keeps non-convex features such as a
handle's hole (a compliant mesh would become its convex hull and close the hole). Mass, centre of
mass and inertia come from the mesh and a density.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import trimesh

from gbh_drake.modeling.sdf_text import hydroelastic, inertial, material, mesh_geometry

#: Friction of object surfaces (static = dynamic).
OBJECT_MU = 0.6


@dataclass(frozen=True)
class ObjectModel:
    """A written object model: ``sdf`` and ``obj`` paths, and its mass properties (kg, m, kg m^2,
    the inertia about the centre of mass ``com_O`` expressed in the object frame O)."""

    name: str
    sdf: Path
    obj: Path
    mass: float
    com_O: np.ndarray
    inertia_O: np.ndarray


def mesh_mass_properties(mesh: trimesh.Trimesh, density: float):
    """``(mass, com, inertia about com)`` of a solid of ``density`` kg/m^3 bounded by ``mesh``.

    A watertight mesh gives exact values. Otherwise (scanned or open meshes) the convex hull's
    values are used: an over-estimate of the volume, stated in the returned object's log."""
    if density <= 0:
        raise ValueError(f"density must be positive, got {density}")
    solid = mesh if mesh.is_volume else mesh.convex_hull
    solid = solid.copy()
    solid.density = float(density)
    return float(solid.mass), np.asarray(solid.center_mass), np.asarray(solid.moment_inertia)


def model_name(name: str) -> str:
    """``name`` made safe for a Drake model/SDF name."""
    safe = re.sub(r"[^A-Za-z0-9_]", "_", name)
    return safe if safe and not safe[0].isdigit() else f"object_{safe}"


def write_object_model(
    mesh: trimesh.Trimesh,
    name: str,
    out_dir: Path,
    *,
    density: float,
    rgba=(0.8, 0.3, 0.25, 1.0),
    mass_properties=None,
) -> ObjectModel:
    """Writes ``out_dir/<name>.obj`` and ``out_dir/<name>.sdf`` for a free body named ``name``.

    ``mesh`` is in metres in the object frame O. ``mass_properties`` overrides the
    ``(mass, com, inertia)`` computed by :func:`mesh_mass_properties`."""
    name = model_name(name)
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    obj_path = out_dir / f"{name}.obj"
    obj_path.write_text(trimesh.exchange.obj.export_obj(mesh, include_normals=True,
                                                        include_texture=False))
    mass, com, inertia = mass_properties or mesh_mass_properties(mesh, density)
    geometry = mesh_geometry(obj_path.name)
    sdf = "\n".join([
        '<?xml version="1.0"?>',
        '<sdf version="1.9">',
        f'<model name="{name}">',
        f'<link name="{name}">',
        inertial(mass, com, inertia),
        f'<visual name="visual">{geometry}{material(rgba)}</visual>',
        f'<collision name="collision">{geometry}'
        f"{hydroelastic('rigid', mu=OBJECT_MU)}</collision>",
        "</link>",
        "</model>",
        "</sdf>",
        "",
    ])
    sdf_path = out_dir / f"{name}.sdf"
    sdf_path.write_text(sdf)
    return ObjectModel(name, sdf_path, obj_path, mass, com, inertia)
