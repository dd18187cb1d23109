"""The object set: parametric everyday objects with ground-truth hangable parts (metres, z up).

Public API::

    from gbh_drake.objects import list_objects, make_object, load_mesh_file, MeshImportError
    from gbh_drake.objects import mass_properties, write_object_meshes
"""

from gbh_drake.objects import real  # noqa: F401  (registers the non-procedural objects)
from gbh_drake.objects.catalog import list_objects, make_object
from gbh_drake.objects.export import write_object_meshes
from gbh_drake.objects.mass import mass_properties
from gbh_drake.objects.mesh_io import MeshImportError, load_mesh_file
from gbh_drake.objects.spec import HangablePart, ObjectSpec

__all__ = [
    "HangablePart",
    "MeshImportError",
    "ObjectSpec",
    "list_objects",
    "load_mesh_file",
    "make_object",
    "mass_properties",
    "write_object_meshes",
]
