"""Non-procedural objects: real meshes shipped with installed packages (found at run time).

``pybullet_mug``: ``pybullet_data/objects/mug.obj`` (a Blender export, already z up, resting on
z = 0, the cup centred on the z axis, handle on +y with its hole axis along x). The cup is one
watertight body; the handle is a separate open tube stuck into the cup, so the mesh is accepted
with a warning and its mass properties come from the voxel fill. The handle's ground truth is
measured on the mesh with :func:`fit_hole` from a first guess read off the vertices (handle
y in [0.045, 0.081] m, z in [0.016, 0.084] m).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from gbh_drake.objects.catalog import as_modelled, register_external
from gbh_drake.objects.holes import fit_hole
from gbh_drake.objects.mass import mass_properties_detailed
from gbh_drake.objects.mesh_io import load_mesh_file
from gbh_drake.objects.spec import HangablePart, ObjectSpec

PYBULLET_MUG_MASS = 0.3
"""kg; pybullet's URDF says 1 kg, a placeholder; a ceramic mug of this size weighs ~0.3 kg."""


def pybullet_mug_path() -> Path:
    """Where the installed pybullet_data keeps mug.obj."""
    import pybullet_data

    return Path(pybullet_data.getDataPath()) / "objects" / "mug.obj"


def pybullet_mug() -> ObjectSpec:
    """The mug of pybullet_data, in frame O (z up, resting on z = 0)."""
    mesh = load_mesh_file(pybullet_mug_path())
    mesh.apply_translation([0.0, 0.0, -mesh.bounds[0, 2]])
    axis = np.array([1.0, 0.0, 0.0])
    center, clear = fit_hole(mesh, np.array([0.0, 0.06, 0.05]), axis, search_radius=0.01)
    unit_mass = mass_properties_detailed(mesh, 1.0).mass
    return ObjectSpec(
        name="pybullet_mug",
        mesh=mesh,
        density=round(PYBULLET_MUG_MASS / unit_mass, 1),
        hangable_parts=[HangablePart("handle", center, axis, "closed", clear)],
        is_control=False,
        rgba=(1.0, 0.2, 0.2, 1.0),
        description="pybullet_data's mug.obj (real mesh, handle not watertight)",
        genus=None,
        metadata={"source": str(pybullet_mug_path())},
    )


register_external("pybullet_mug", pybullet_mug,
                  rest=as_modelled("upright on its base, as a mug is set down on a table or shelf"))
