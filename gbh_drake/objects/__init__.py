"""The object set: parametric everyday objects with ground-truth hangable parts (metres, z up).

Public API::

    from gbh_drake.objects import list_objects, make_object, load_mesh_file, MeshImportError
    from gbh_drake.objects import mass_properties, write_object_meshes

Imported meshes that behave like real objects (pure numpy/trimesh)::

    from gbh_drake.objects import load_mesh_object, prepare_mesh_object  # all of the below
    from gbh_drake.objects import rest_on_table, lift_to_table            # resting frame O
    from gbh_drake.objects import stable_poses, sample_resting_pose       # stable poses, draws
    from gbh_drake.objects import plausibility_warnings                   # size, mass, filled
    from gbh_drake.objects import mass_properties_for                     # density or mass
"""

from gbh_drake.objects import real  # noqa: F401  (registers the non-procedural objects)
from gbh_drake.objects.catalog import list_objects, make_object
from gbh_drake.objects.export import write_object_meshes
from gbh_drake.objects.mass import MassProperties, mass_properties, mass_properties_for
from gbh_drake.objects.mesh_io import MeshImportError, load_mesh_file
from gbh_drake.objects.placement import Placement, lift_to_table, lowest_point_z, rest_on_table
from gbh_drake.objects.plausibility import plausibility_warnings
from gbh_drake.objects.spec import HangablePart, ObjectSpec
from gbh_drake.objects.stability import (
    StablePose,
    StablePoses,
    sample_resting_pose,
    stable_poses,
)
from gbh_drake.objects.user_mesh import MeshObject, load_mesh_object, prepare_mesh_object

__all__ = [
    "HangablePart",
    "MassProperties",
    "MeshImportError",
    "MeshObject",
    "ObjectSpec",
    "Placement",
    "StablePose",
    "StablePoses",
    "lift_to_table",
    "list_objects",
    "load_mesh_file",
    "load_mesh_object",
    "lowest_point_z",
    "make_object",
    "mass_properties",
    "mass_properties_for",
    "plausibility_warnings",
    "prepare_mesh_object",
    "rest_on_table",
    "sample_resting_pose",
    "stable_poses",
    "write_object_meshes",
]
