"""Scenes to scan without the full station: a SceneGraph with a VTK renderer, the table, an
object of the set and (by default) the Franka arm with the hook gripper at its home pose, its hand
above the object.

Built from Drake parts only (not ``gbh_drake.station``), for the perception tests, the scan
bench and trying the scanner on any object and placement. The object is a free body (it can be
moved in a context); nothing is simulated. For example::

    scene = build_scene("tote_bag", "/tmp/models", xyz=(0.55, 0.1, 0.0), yaw_deg=30)
    result = scan_object(scene.query_object, ScanConfig(), [0.55, 0.0, 0.06])
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
import trimesh
from pydrake.geometry import Box, MakeRenderEngineVtk, Mesh, RenderEngineVtkParams
from pydrake.math import RigidTransform, RollPitchYaw
from pydrake.multibody.parsing import ModelDirectives, ProcessModelDirectives
from pydrake.multibody.plant import AddMultibodyPlantSceneGraph
from pydrake.multibody.tree import SpatialInertia
from pydrake.systems.framework import DiagramBuilder

from gbh_drake.modeling.directives import DEFAULT_Q_HOME, default_directives
from gbh_drake.modeling.names import ARM, GRIPPER
from gbh_drake.modeling.package_map import make_parser
from gbh_drake.objects import make_object

#: The renderer the default ScanConfig uses.
RENDERER = "default"


@dataclass
class ObjectScene:
    """A scene with one object, in a default context; the truth in W."""

    name: str
    diagram: object
    context: object
    plant: object
    scene_graph: object
    body: object
    """The object's free body."""
    query_object: object
    X_WO: RigidTransform
    mesh_W: trimesh.Trimesh
    """The object's true mesh in W."""
    parts: list
    """The object's hangable parts (``HangablePart``, in O)."""
    table_height: float

    def part_W(self, index: int = 0) -> tuple[np.ndarray, np.ndarray, float]:
        """(centre (3,), unit axis (3,), clear diameter) of a hangable part, in W."""
        part = self.parts[index]
        return (self.X_WO @ part.center_O, self.X_WO.rotation() @ part.axis_O,
                part.clear_diameter)

    def query_port(self):
        return self.scene_graph.get_query_output_port()


def build_scene(name: str, model_dir: Path, *, xyz=(0.55, 0.0, 0.0), yaw_deg: float = 0.0,
                table_height: float = 0.0, robot: bool = True, lift: float = 0.002,
                systems=()) -> ObjectScene:
    """The object ``name`` of the set resting at ``xyz`` (its frame O's origin; z added to the
    table's height, plus ``lift``: 2 mm as the station drops it) turned by ``yaw_deg`` about
    z, on a table whose top is at ``table_height`` (m). ``systems``: callables taking (builder,
    scene_graph) that add and connect more systems before the diagram is built."""
    spec = make_object(name)
    model_dir = Path(model_dir)
    model_dir.mkdir(parents=True, exist_ok=True)
    obj_path = model_dir / f"{name}.obj"
    spec.mesh.export(obj_path, include_normals=True)

    builder = DiagramBuilder()
    plant, scene_graph = AddMultibodyPlantSceneGraph(builder, time_step=0.0)
    scene_graph.AddRenderer(RENDERER, MakeRenderEngineVtk(RenderEngineVtkParams()))
    world = plant.world_body()
    plant.RegisterVisualGeometry(world, RigidTransform([0.35, 0.0, table_height - 0.02]),
                                 Box(1.4, 1.0, 0.04), "table_top",
                                 np.array([0.72, 0.6, 0.45, 1.0]))
    if robot:
        ProcessModelDirectives(ModelDirectives(directives=default_directives(table=False)),
                               plant, make_parser(plant))
    body = plant.AddRigidBody(name, plant.AddModelInstance(name),
                              SpatialInertia.SolidSphereWithMass(0.3, 0.05))
    plant.RegisterVisualGeometry(body, RigidTransform(), Mesh(str(obj_path)), f"{name}_visual",
                                 np.asarray(spec.rgba, dtype=float))
    X_WO = RigidTransform(RollPitchYaw(0.0, 0.0, np.deg2rad(yaw_deg)),
                          [xyz[0], xyz[1], xyz[2] + table_height + lift])
    plant.Finalize()
    plant.SetDefaultFloatingBaseBodyPose(body, X_WO)
    if robot:
        plant.SetDefaultPositions(plant.GetModelInstanceByName(ARM), DEFAULT_Q_HOME)
        for index in plant.GetJointIndices(plant.GetModelInstanceByName(GRIPPER)):
            joint = plant.get_joint(index)
            if joint.num_positions() == 1:  # fingers open, as at the station's start
                upper = joint.position_upper_limits()[0]
                joint.set_default_positions([upper if np.isfinite(upper) else 0.0])
    for add in systems:
        add(builder, scene_graph)
    diagram = builder.Build()
    context = diagram.CreateDefaultContext()
    query_object = scene_graph.get_query_output_port().Eval(
        scene_graph.GetMyContextFromRoot(context))
    return ObjectScene(name, diagram, context, plant, scene_graph, body, query_object, X_WO,
                       spec.mesh.copy().apply_transform(X_WO.GetAsMatrix4()),
                       list(spec.hangable_parts), table_height)
