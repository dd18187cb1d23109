"""The object as a free rigid body of the plant, built in memory (no files written).

Its visual geometry is the mesh as given (what the cameras see and Meshcat shows). It has two
*rigid hydroelastic* collision meshes, each filtered against half of the scene:

* ``collision`` touches the robot: the mesh itself, simplified to at most
  ``max_contact_faces`` triangles when denser (a finely scanned user mesh would otherwise slow
  contact down several times). A rigid mesh keeps non-convex features such as a handle's hole
  (a compliant mesh would become its convex hull and close the hole), which is what the hook
  grips.
* ``support`` touches everything else (the table): a coarse simplification (at most
  ``support_faces`` triangles). Resting on the table, the fine mesh's bottom gave a contact
  surface of ~190 polygons, one SAP contact each, which made the simulation ~4x slower than
  without the object; a flat bottom of a few large triangles gives a handful.

Mass, centre of mass and inertia come with the asset.
"""

from __future__ import annotations

import numpy as np
import trimesh
from pydrake.common import MemoryFile
from pydrake.geometry import (
    AddContactMaterial,
    AddRigidHydroelasticProperties,
    CollisionFilterDeclaration,
    GeometrySet,
    InMemoryMesh,
    Mesh,
    ProximityProperties,
    Role,
    SceneGraph,
)
from pydrake.math import RigidTransform
from pydrake.multibody.plant import CoulombFriction, MultibodyPlant
from pydrake.multibody.tree import RotationalInertia, SpatialInertia

from gbh_drake.core.simplify import simplified
from gbh_drake.modeling.object_asset import ObjectAsset
from gbh_drake.modeling.object_sdf import OBJECT_MU
from gbh_drake.objects.export import obj_bytes

#: Contact meshes (against the robot) denser than this are simplified (quadric decimation).
MAX_CONTACT_FACES = 6000
#: Triangles of the support mesh (against the table).
SUPPORT_FACES = 300


def _in_memory(mesh: trimesh.Trimesh, name: str, *, with_normals: bool) -> InMemoryMesh:
    if with_normals:
        text = obj_bytes(mesh).decode()
    else:
        text = trimesh.exchange.obj.export_obj(mesh, include_normals=False, include_texture=False)
    return InMemoryMesh(mesh_file=MemoryFile(text, ".obj", name))


def add_object_body(plant: MultibodyPlant, asset: ObjectAsset, *,
                    max_contact_faces: int = MAX_CONTACT_FACES,
                    support_faces: int = SUPPORT_FACES):
    """Adds ``asset`` to ``plant`` (before Finalize) as a free body in its own model instance,
    both named ``asset.model_name``; returns the body and the geometry ids of its ``collision``
    (against the robot) and ``support`` (against the rest) meshes: apply
    :func:`filter_object_contacts` once the plant is finalized."""
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
    ids = []
    for label, faces in (("collision", max_contact_faces), ("support", support_faces)):
        mesh = simplified(asset.mesh, faces)
        ids.append(plant.RegisterCollisionGeometry(
            body, RigidTransform(), Mesh(_in_memory(mesh, f"{name}_{label}", with_normals=False)),
            label, props))
    plant.RegisterVisualGeometry(
        body, RigidTransform(), Mesh(_in_memory(asset.mesh, name, with_normals=True)),
        "visual", np.asarray(asset.rgba, dtype=float))
    return body, ids[0], ids[1]


def filter_object_contacts(plant: MultibodyPlant, scene_graph: SceneGraph, collision_id,
                           support_id, robot_instances) -> None:
    """The object's ``collision`` mesh touches only the robot's bodies, its ``support`` mesh
    everything but them (call after Finalize, before the diagram is built)."""
    robot = [g for instance in robot_instances for index in plant.GetBodyIndices(instance)
             for g in plant.GetCollisionGeometriesForBody(plant.get_body(index))]
    own = {collision_id, support_id}
    rest = [g for g in scene_graph.model_inspector().GetAllGeometryIds(Role.kProximity)
            if g not in own and g not in set(robot)]
    scene_graph.collision_filter_manager().Apply(
        CollisionFilterDeclaration()
        .ExcludeBetween(GeometrySet(support_id), GeometrySet(robot))
        .ExcludeBetween(GeometrySet(collision_id), GeometrySet(rest)))
