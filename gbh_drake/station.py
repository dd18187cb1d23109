"""Builds the simulation station from a :class:`~gbh_drake.scenario.Scenario`.

The station is a ``MultibodyPlant`` (discrete, hydroelastic contact) and a ``SceneGraph`` with a
VTK render engine, holding the Franka arm ``panda``, the ``hook_gripper`` welded to its flange,
the ``table`` and the free ``object``. The arm's seven joints and the gripper's two fingers are
driven by the plant's own implicit PD controllers (joint position control, like Franka's
joint impedance mode); gravity is compensated on the robot (disabled on its model instances), as
Franka's controller does, and acts fully on the object. Cameras (``CameraConfig``) and Meshcat
visualisation (``VisualizationConfig``) are applied as in Drake's ``hardware_sim``.

Use :func:`add_station` to put the station into your own ``DiagramBuilder``; its
:class:`Station` result names every port you need (``arm_desired_state``,
``gripper_desired_state``, ``plant.get_state_output_port(...)``, ``query_object``).
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
import trimesh
from pydrake.common import RandomGenerator
from pydrake.geometry import Meshcat, RenderEngineVtkParams, SceneGraph
from pydrake.lcm import DrakeLcm
from pydrake.math import RigidTransform
from pydrake.multibody.parsing import ProcessModelDirectives
from pydrake.multibody.plant import AddMultibodyPlant, MultibodyPlant
from pydrake.multibody.tree import ModelInstanceIndex, PdControllerGains
from pydrake.systems.framework import DiagramBuilder, InputPort
from pydrake.systems.sensors import ApplyCameraConfig
from pydrake.visualization import ApplyVisualizationConfig

from gbh_drake.core.gripper import HOOK_GRIPPER
from gbh_drake.modeling.object_sdf import ObjectModelFiles, write_object_model
from gbh_drake.modeling.package_map import make_parser
from gbh_drake.scenario import Scenario

#: Name of the VTK render engine that cameras use.
RENDERER_NAME = "default"
#: Density (kg/m^3) of a mesh object when the scenario gives none.
DEFAULT_MESH_DENSITY = 600.0


@dataclass
class ObjectAsset:
    """The object to simulate: its mesh (metres, frame O, resting on z = 0) and appearance."""

    name: str
    mesh: trimesh.Trimesh
    density: float
    rgba: tuple[float, float, float, float]
    source: str
    """Where it came from: ``object set: <name>`` or the mesh file's path."""


@dataclass
class Station:
    """Handles to a station inside a diagram builder (or a built diagram)."""

    plant: MultibodyPlant
    scene_graph: SceneGraph
    arm: ModelInstanceIndex
    gripper: ModelInstanceIndex
    object: ModelInstanceIndex
    object_asset: ObjectAsset
    object_model: ObjectModelFiles
    X_WO_initial: RigidTransform
    """The object's initial pose (sampled from the scenario's seed)."""
    q_home: np.ndarray
    meshcat: Meshcat | None
    lcm: DrakeLcm | None = None
    """The in-memory LCM bus the visualisers' LCM publishers use (instead of Drake's default
    UDP-multicast bus). The diagram does not own it: keep this Station while the diagram lives."""

    @property
    def arm_desired_state(self) -> InputPort:
        """Input: desired arm state [q (7), v (7)] for the joint PD controller."""
        return self.plant.get_desired_state_input_port(self.arm)

    @property
    def gripper_desired_state(self) -> InputPort:
        """Input: desired finger state [q_straight, q_l, v_straight, v_l] (m, m/s)."""
        return self.plant.get_desired_state_input_port(self.gripper)

    def object_body(self):
        return self.plant.GetBodyByName(self.object_model.name, self.object)


def load_object_asset(scenario: Scenario) -> ObjectAsset:
    """The scenario's object: a named object of the set, or a mesh file through the same import."""
    # Imported here: the object set pulls in manifold3d and is not needed for other uses.
    from gbh_drake.objects import load_mesh_file, make_object

    obj = scenario.object
    if obj.mesh:
        path = scenario.resolve(obj.mesh)
        mesh = load_mesh_file(path, scale=obj.scale)
        density = obj.density or DEFAULT_MESH_DENSITY
        return ObjectAsset(path.stem, mesh, density, (0.85, 0.45, 0.2, 1.0), str(path))
    spec = make_object(obj.name)
    mesh = spec.mesh
    if obj.scale != 1.0:
        mesh = mesh.copy()
        mesh.apply_scale(obj.scale)
    return ObjectAsset(spec.name, mesh, obj.density or spec.density, tuple(spec.rgba),
                       f"object set: {spec.name}")


def add_station(
    builder: DiagramBuilder,
    scenario: Scenario,
    *,
    meshcat: Meshcat | None = None,
    model_dir: Path | None = None,
    object_asset: ObjectAsset | None = None,
) -> Station:
    """Adds the station of ``scenario`` to ``builder``.

    ``model_dir`` receives the object's generated model files (default: the scenario's output
    folder). ``object_asset`` replaces the scenario's object (e.g. a mesh already in memory)."""
    # The plant and scene graph, with a VTK renderer for the cameras.
    plant, scene_graph = AddMultibodyPlant(scenario.plant_config, builder)
    if not scene_graph.HasRenderer(RENDERER_NAME):
        scene_graph.AddRenderer(RENDERER_NAME, _make_vtk_renderer())
    parser = make_parser(plant)

    # The fixed models: arm, gripper, table (and whatever the scenario adds).
    try:
        ProcessModelDirectives(_directives(scenario), plant, parser)
    except RuntimeError as e:  # Drake's parser: a missing file, a bad frame name, ...
        raise ValueError(f"{scenario.source_path or 'scenario'}: directives: {e}") from e
    arm = plant.GetModelInstanceByName("panda")
    gripper = plant.GetModelInstanceByName("hook_gripper")

    # The free object, as a rigid-hydroelastic mesh with mass properties from its geometry.
    asset = object_asset or load_object_asset(scenario)
    model = write_object_model(
        asset.mesh, asset.name, Path(model_dir or scenario.output_path() / "models"),
        density=asset.density, rgba=asset.rgba,
    )
    (obj,) = parser.AddModels(str(model.sdf))
    X_WO = sample_object_pose(scenario)
    plant.SetDefaultFloatingBaseBodyPose(plant.GetBodyByName(model.name, obj), X_WO)

    # Robot control: implicit joint PD controllers; gravity compensated on the robot.
    _set_pd_gains(plant, arm, scenario.robot.arm_kp, scenario.robot.arm_kd)
    _set_pd_gains(plant, gripper, [scenario.robot.finger_kp] * 2, [scenario.robot.finger_kd] * 2)
    plant.set_gravity_enabled(arm, False)
    plant.set_gravity_enabled(gripper, False)
    plant.Finalize()
    q_home = np.asarray(scenario.robot.q_home, dtype=float)
    plant.SetDefaultPositions(arm, q_home)
    q_finger = HOOK_GRIPPER.q_open if scenario.robot.gripper_open else HOOK_GRIPPER.q_closed
    plant.SetDefaultPositions(gripper, [q_finger, q_finger])

    # Cameras and visualisation. Their LCM publishers (images, Meldis messages) go to an
    # in-memory bus: Drake's default LCM bus is UDP multicast, i.e. network traffic.
    lcm = DrakeLcm("memq://gbh_drake")
    for camera in scenario.cameras:
        ApplyCameraConfig(config=camera, builder=builder, lcm=lcm)
    if meshcat is not None:
        ApplyVisualizationConfig(scenario.visualization, builder, meshcat=meshcat, lcm=lcm)
    return Station(plant, scene_graph, arm, gripper, obj, asset, model, X_WO, q_home, meshcat, lcm)


def sample_object_pose(scenario: Scenario) -> RigidTransform:
    """X_WO from the scenario (deterministic for a given seed), lifted by ``drop_height``."""
    pose = scenario.object.pose
    if pose.IsDeterministic():
        X_WO = pose.GetDeterministicValue()
    else:
        X_WO = pose.Sample(RandomGenerator(scenario.seed))
    return RigidTransform(X_WO.rotation(),
                          X_WO.translation() + [0.0, 0.0, scenario.object.drop_height])


def _directives(scenario: Scenario):
    from pydrake.multibody.parsing import ModelDirectives

    return ModelDirectives(directives=scenario.directives)


def _set_pd_gains(plant: MultibodyPlant, instance, kp, kd) -> None:
    # (GetJointActuatorIndices(instance) needs a finalized plant; gains must be set before.)
    actuators = [i for i in plant.GetJointActuatorIndices()
                 if plant.get_joint_actuator(i).model_instance() == instance]
    if len(actuators) != len(kp):
        raise ValueError(f"{plant.GetModelInstanceName(instance)} has {len(actuators)} actuators,"
                         f" got {len(kp)} gains")
    for index, p, d in zip(actuators, kp, kd, strict=True):
        plant.get_joint_actuator(index).set_controller_gains(PdControllerGains(p=p, d=d))


def _make_vtk_renderer():
    from pydrake.geometry import MakeRenderEngineVtk

    return MakeRenderEngineVtk(RenderEngineVtkParams())
