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
from gbh_drake.objects.export import obj_bytes
from gbh_drake.objects.mass import mass_properties_detailed

#: Friction of object surfaces (static = dynamic): ceramic, glass and plastic objects against
#: the rods' metal or printed plastic are at about 0.3-0.5 (see ``gripper_sdf.GRIPPER_MU``).
OBJECT_MU = 0.4


@dataclass(frozen=True)
class ObjectModelFiles:
    """A written object model: ``sdf`` and ``obj`` paths, and its mass properties (kg, m, kg m^2,
    the inertia about the centre of mass ``com_O`` expressed in the object frame O)."""

    name: str
    sdf: Path
    obj: Path
    mass: float
    com_O: np.ndarray
    inertia_O: np.ndarray


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
) -> ObjectModelFiles:
    """Writes ``out_dir/<name>.obj`` and ``out_dir/<name>.sdf`` for a free body named ``name``.

    ``mesh`` is in metres in the object frame O. Mass properties come from
    :func:`gbh_drake.objects.mass.mass_properties_detailed` (exact for a watertight body, a voxel
    fill otherwise); ``mass_properties`` = ``(mass, com, inertia)`` overrides them."""
    name = model_name(name)
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    obj_path = out_dir / f"{name}.obj"
    obj_path.write_bytes(obj_bytes(mesh))
    if mass_properties is None:
        props = mass_properties_detailed(mesh, density)
        mass_properties = (props.mass, props.com, props.inertia)
    mass, com, inertia = mass_properties
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
    return ObjectModelFiles(name, sdf_path, obj_path, mass, com, inertia)
