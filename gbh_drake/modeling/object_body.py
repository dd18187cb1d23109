"""The object as a free rigid body of the plant, built in memory (no files written).

Its visual geometry is the mesh as given (what the cameras see and Meshcat shows); its collision
geometry is a *rigid hydroelastic* mesh, simplified to at most ``max_contact_faces`` triangles
when the given one is denser (a finely scanned user mesh would otherwise slow contact down
several times) — the simplification keeps handles' holes open at the sizes a hook can use. A
rigid mesh keeps non-convex features such as a handle's hole (a compliant mesh would become its
convex hull and close the hole). Mass, centre of mass and inertia come with the asset.
"""

from __future__ import annotations

import numpy as np
import trimesh
from pydrake.common import MemoryFile
from pydrake.geometry import (
    AddContactMaterial,
    AddRigidHydroelasticProperties,
    InMemoryMesh,
    Mesh,
    ProximityProperties,
)
from pydrake.math import RigidTransform
from pydrake.multibody.plant import CoulombFriction, MultibodyPlant
from pydrake.multibody.tree import RotationalInertia, SpatialInertia

from gbh_drake.modeling.object_asset import ObjectAsset
from gbh_drake.modeling.object_sdf import OBJECT_MU
from gbh_drake.objects.export import obj_bytes

#: Contact meshes denser than this are simplified (quadric decimation).
MAX_CONTACT_FACES = 6000


def contact_mesh(mesh: trimesh.Trimesh, max_faces: int = MAX_CONTACT_FACES) -> trimesh.Trimesh:
    """``mesh``, or its quadric decimation to ``max_faces`` triangles when it has more."""
    if len(mesh.faces) <= max_faces:
        return mesh
    import open3d as o3d

    o3d_mesh = o3d.geometry.TriangleMesh(o3d.utility.Vector3dVector(mesh.vertices),
                                         o3d.utility.Vector3iVector(mesh.faces))
    simple = o3d_mesh.simplify_quadric_decimation(target_number_of_triangles=max_faces)
    return trimesh.Trimesh(np.asarray(simple.vertices), np.asarray(simple.triangles))


def _in_memory(mesh: trimesh.Trimesh, name: str, *, with_normals: bool) -> InMemoryMesh:
    if with_normals:
        text = obj_bytes(mesh).decode()
    else:
        text = trimesh.exchange.obj.export_obj(mesh, include_normals=False, include_texture=False)
    return InMemoryMesh(mesh_file=MemoryFile(text, ".obj", name))


def add_object_body(plant: MultibodyPlant, asset: ObjectAsset, *,
                    max_contact_faces: int = MAX_CONTACT_FACES):
    """Adds ``asset`` to ``plant`` (before Finalize) as a free body in its own model instance,
    both named ``asset.model_name``; returns the body."""
    name = asset.model_name
    instance = plant.AddModelInstance(name)
    inertia = np.asarray(asset.inertia_O, dtype=float)
    M = SpatialInertia.MakeFromCentralInertia(
        asset.mass, np.asarray(asset.com_O, dtype=float),
        RotationalInertia(inertia[0, 0], inertia[1, 1], inertia[2, 2], inertia[0, 1],
                          inertia[0, 2], inertia[1, 2]))
    body = plant.AddRigidBody(name, instance, M)
    props = ProximityProperties()
    AddRigidHydroelasticProperties(props)
    AddContactMaterial(friction=CoulombFriction(OBJECT_MU, OBJECT_MU), properties=props)
    collision = contact_mesh(asset.mesh, max_contact_faces)
    plant.RegisterCollisionGeometry(
        body, RigidTransform(), Mesh(_in_memory(collision, f"{name}_contact", with_normals=False)),
        "collision", props)
    plant.RegisterVisualGeometry(
        body, RigidTransform(), Mesh(_in_memory(asset.mesh, name, with_normals=True)),
        "visual", np.asarray(asset.rgba, dtype=float))
    return body
