"""The simulation station: a sub-diagram named ``station`` that exports its ports by name.

Inside: a discrete ``MultibodyPlant`` (hydroelastic contact) and its ``SceneGraph``, holding
the Franka arm ``panda``, the ``hook_gripper`` welded to its flange, the ``table`` (all from the
scenario's directives) and the free object (added in memory). The arm's
seven joints are driven by the plant's implicit PD controllers (joint position control, like
Franka's joint impedance mode; gains set by actuator name); the fingers, which a coupler
constraint moves together as Franka's rack does, by the force-limited
:class:`~gbh_drake.systems.hand_driver.HandDriver`. Gravity is compensated on the robot (disabled
on its model instances), as Franka's controller does, and acts fully on the object. Cameras
(``CameraConfig``) and Meshcat visualisation (``VisualizationConfig``) are applied as in Drake's
``hardware_sim``. The scanner's VTK renderer ``default`` lives in a second scene graph that
holds only the perception geometry and is posed only when it renders
(:mod:`gbh_drake.systems.camera_scene`): in the plant's scene graph it would be re-posed at every
time step. As in the manipulation course's ``MakeHardwareStation``, callers wire to the
exported ports and never reach inside:

========================== ======= ======================================================
port                        kind    what
========================== ======= ======================================================
``panda.desired_state``     input   [q (7), v (7)] for the arm's joint controllers
``hook_gripper.command``    input   [finger target q (m), grasp force (N), bar angle (rad)]
``panda.state``             output  [q (7), v (7)] measured
``hook_gripper.state``      output  [q_straight, q_l, bar, v_straight, v_l, w_bar] measured
``hook_gripper.actuation``  output  the fingers' and bar's actuator efforts (N, N, N m)
``hook_gripper.load``       output  the force (N, W) the flange exerts on the hand: its load
``object.state``            output  the object's [quaternion (4), p (3), w (3), v (3)] in W
``body_poses``              output  every body's pose in W (the plant's ``body_poses``)
``contact_results``         output  the plant's ``contact_results``
``query_object``            output  the plant's scene graph's query object (contact queries;
                                    renders with the scenario cameras' renderers)
``camera_query_object``     output  the camera scene's query object: renders with the
                                    station's VTK renderer ``default`` (the scanner's)
``<camera>.color_image``    output  each camera's images (``color_image``,
                                    ``depth_image_32f``, ``label_image``)
========================== ======= ======================================================
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np
from pydrake.geometry import Meshcat
from pydrake.lcm import DrakeLcm
from pydrake.math import RigidTransform
from pydrake.multibody.parsing import ModelDirective, Parser
from pydrake.multibody.plant import AddMultibodyPlant, MultibodyPlantConfig
from pydrake.multibody.tree import PdControllerGains
from pydrake.systems.framework import Diagram, DiagramBuilder
from pydrake.systems.sensors import ApplyCameraConfig, CameraConfig
from pydrake.visualization import ApplyVisualizationConfig, VisualizationConfig

from gbh_drake.core.gripper import BAR_DEPLOYED, HOOK_GRIPPER
from gbh_drake.method_spec import method_spec
from gbh_drake.modeling.names import ARM, GRIPPER, HAND_ACTUATORS
from gbh_drake.modeling.object_asset import initial_object_pose, load_object_asset
from gbh_drake.modeling.object_body import ObjectAsset, add_object_body, filter_object_contacts
from gbh_drake.modeling.package_map import add_fixed_models
from gbh_drake.scenario import Scenario
from gbh_drake.scenario.loader import require_scenario
from gbh_drake.scenario.schema import RobotConfig
from gbh_drake.seeds import Seeds, derive_seeds
from gbh_drake.systems.camera_scene import add_camera_scene
from gbh_drake.systems.hand_driver import HandDriver
from gbh_drake.systems.wrist_load import WristLoad

#: Name of the camera scene's VTK render engine, the scanner's.
RENDERER_NAME = "default"
#: PD gains (N m/rad, N m s/rad) of the bar's servo.
BAR_KP, BAR_KD = 20.0, 0.5


class Station(Diagram):
    """The station sub-diagram (see the module docstring for its ports).

    Besides its ports it offers read-only model information: ``plant`` (for names and indices;
    do not wire into it), ``object_name`` (the free object's body and model instance;
    :meth:`object_body`),
    ``asset`` (the object), ``X_WO_initial`` and ``q_home``.
    """

    def __init__(self, *, directives: Sequence[ModelDirective], plant_config: MultibodyPlantConfig,
                 robot: RobotConfig, asset: ObjectAsset, X_WO: RigidTransform,
                 bar_angle: float = BAR_DEPLOYED, cameras: Sequence[CameraConfig] = (),
                 visualization: VisualizationConfig | None = None,
                 meshcat: Meshcat | None = None,
                 prefinalize: Callable[[Parser], None] | None = None):
        """``X_WO``: the object's initial pose; ``bar_angle`` (rad): the bar's initial angle;
        ``visualization`` and ``meshcat``: Meshcat visualisation (both or neither);
        ``prefinalize``: called with the station's parser (``parser.plant()`` is the plant)
        once every model is added, before the plant is finalized: add models or frames of your
        own (as ``MakeHardwareStation``'s ``parser_prefinalize_callback``)."""
        super().__init__()
        builder = DiagramBuilder()

        # The plant and its scene graph (contact and visualisation; the scanner renders in the
        # camera scene, added below).
        plant, scene_graph = AddMultibodyPlant(plant_config, builder)

        # The fixed models (arm, gripper, table and whatever the scenario adds), the object.
        parser = Parser(plant)
        add_fixed_models(parser, directives)
        arm = plant.GetModelInstanceByName(ARM)
        gripper = plant.GetModelInstanceByName(GRIPPER)
        body, collision_id, support_id = add_object_body(plant, asset)
        plant.SetDefaultFloatingBaseBodyPose(body, X_WO)

        # Robot control: implicit PD, gains by actuator name; gravity compensated on the robot.
        for i, (kp, kd) in enumerate(zip(robot.arm_kp, robot.arm_kd, strict=True)):
            _set_gains(plant, arm, f"panda_joint{i + 1}", kp, kd)
        hand = robot.hand
        for name, kp, kd in ((HAND_ACTUATORS[0], hand.kp, hand.kd),
                             (HAND_ACTUATORS[1], hand.kp, hand.kd),
                             (HAND_ACTUATORS[2], BAR_KP, BAR_KD)):
            _set_gains(plant, gripper, name, kp, kd)
        for name in HAND_ACTUATORS[:2]:
            actuator = plant.GetJointActuatorByName(name, gripper)
            actuator.set_effort_limit(min(actuator.effort_limit(), hand.max_force))
        # Franka's fingers are driven by one motor through a rack: they move together.
        plant.AddCouplerConstraint(
            joint0=plant.GetJointByName(HAND_ACTUATORS[0], gripper),
            joint1=plant.GetJointByName(HAND_ACTUATORS[1], gripper), gear_ratio=1.0, offset=0.0)
        plant.set_gravity_enabled(arm, False)
        plant.set_gravity_enabled(gripper, False)
        if prefinalize is not None:
            prefinalize(parser)
        plant.Finalize()
        filter_object_contacts(plant, scene_graph, collision_id, support_id, (arm, gripper))
        camera_scene = add_camera_scene(builder, plant, scene_graph, RENDERER_NAME)
        q_home = np.asarray(robot.q_home, dtype=float)
        plant.SetDefaultPositions(arm, q_home)
        q_finger = HOOK_GRIPPER.q_open if robot.gripper_open else HOOK_GRIPPER.q_closed
        plant.SetDefaultPositions(gripper, [q_finger, q_finger, bar_angle])

        # The hand's force-limited drive.
        driver = builder.AddNamedSystem("hand_driver", HandDriver(hand))
        builder.Connect(plant.get_state_output_port(gripper), driver.GetInputPort("state"))
        builder.Connect(driver.GetOutputPort("desired_state"),
                        plant.get_desired_state_input_port(gripper))

        # The load the hand carries, as Franka estimates its external wrench.
        wrist = builder.AddNamedSystem(
            "wrist_load", WristLoad(plant, plant.GetBodyByName("panda_hand", gripper)))
        builder.Connect(plant.get_reaction_forces_output_port(),
                        wrist.GetInputPort("reaction_forces"))
        builder.Connect(plant.get_body_poses_output_port(), wrist.GetInputPort("body_poses"))

        # Cameras and visualisation. Their LCM publishers (images, Meldis messages) go to an
        # in-memory bus: Drake's default LCM bus is UDP multicast, i.e. network traffic.
        self._lcm = DrakeLcm("memq://gbh_drake")
        camera_systems = [ApplyCameraConfig(config=c, builder=builder, lcm=self._lcm) or c
                          for c in cameras]
        if meshcat is not None:
            ApplyVisualizationConfig(visualization or VisualizationConfig(), builder,
                                     meshcat=meshcat, lcm=self._lcm)

        # Exported ports.
        builder.ExportInput(plant.get_desired_state_input_port(arm), "panda.desired_state")
        builder.ExportInput(driver.GetInputPort("command"), "hook_gripper.command")
        builder.ExportOutput(plant.get_state_output_port(arm), "panda.state")
        builder.ExportOutput(plant.get_state_output_port(gripper), "hook_gripper.state")
        builder.ExportOutput(plant.get_net_actuation_output_port(gripper),
                             "hook_gripper.actuation")
        builder.ExportOutput(wrist.GetOutputPort("load_W"), "hook_gripper.load")
        builder.ExportOutput(plant.get_state_output_port(body.model_instance()), "object.state")
        builder.ExportOutput(plant.get_body_poses_output_port(), "body_poses")
        builder.ExportOutput(plant.get_contact_results_output_port(), "contact_results")
        builder.ExportOutput(scene_graph.get_query_output_port(), "query_object")
        builder.ExportOutput(camera_scene.get_query_output_port(), "camera_query_object")
        for camera in camera_systems:
            _export_camera(builder, camera)
        builder.BuildInto(self)
        self.set_name("station")

        self.plant = plant
        self.scene_graph = scene_graph
        self.object_name = asset.model_name
        self.asset = asset
        self.X_WO_initial = X_WO
        self.q_home = q_home

    def object_body(self):
        """The free object's body, looked up in its own model instance (a gripper body may
        have the same name: a user's mesh file ``bar.obj`` makes an object named ``bar``)."""
        return self.plant.GetBodyByName(self.object_name,
                                        self.plant.GetModelInstanceByName(self.object_name))


def scene_query_port(renderer_name: str) -> str:
    """The station's query output port that renders with ``renderer_name``: the camera scene's
    for the station's own renderer, the plant's scene graph's for a scenario camera's."""
    return "camera_query_object" if renderer_name == RENDERER_NAME else "query_object"


def make_station(scenario: Scenario, *, meshcat: Meshcat | None = None,
                 object_asset: ObjectAsset | None = None,
                 prefinalize: Callable[[Parser], None] | None = None,
                 seeds: Seeds | None = None) -> Station:
    """The :class:`Station` of ``scenario``: its directives, plant, robot, cameras and
    visualisation, the object (``object_asset``, else the scenario's, loaded) at its start pose
    (drawn from the scenario's seed), the bar as the scenario's grasp method starts it.
    ``meshcat``: visualise there; ``prefinalize``: see :class:`Station`; ``seeds``: the
    scenario's seeds when the caller has derived them already. Add it to your builder
    with ``builder.AddSystem(make_station(scenario))`` and wire to its exported ports."""
    require_scenario(scenario, "make_station")  # (a wrong field named at the call)
    asset = object_asset or load_object_asset(scenario.object, scenario.directory)
    X_WO = initial_object_pose(scenario.object, asset, (seeds or derive_seeds(scenario.seed)).pose)
    return Station(directives=scenario.station_directives(), plant_config=scenario.plant_config,
                   robot=scenario.robot, asset=asset, X_WO=X_WO,
                   bar_angle=method_spec(scenario.grasp_method).bar_angle,
                   cameras=scenario.cameras, visualization=scenario.visualization,
                   meshcat=meshcat, prefinalize=prefinalize)


def _set_gains(plant, instance, joint: str, kp: float, kd: float) -> None:
    """PD gains of the actuator of ``joint`` (found by name) in ``instance``."""
    # (GetJointActuatorIndices(instance) needs a finalized plant; gains must be set before.)
    actuators = [plant.get_joint_actuator(i) for i in plant.GetJointActuatorIndices()
                 if plant.get_joint_actuator(i).model_instance() == instance
                 and plant.get_joint_actuator(i).joint().name() == joint]
    if len(actuators) != 1:
        raise ValueError(f"{plant.GetModelInstanceName(instance)} has no actuated joint {joint!r}")
    actuators[0].set_controller_gains(PdControllerGains(p=kp, d=kd))


def _export_camera(builder: DiagramBuilder, camera: CameraConfig) -> None:
    """Exports the camera's image ports as ``<name>.<port>``."""
    sensor = builder.GetSubsystemByName(f"rgbd_sensor_{camera.name}")
    for port in ("color_image", "depth_image_32f", "label_image"):
        if sensor.HasOutputPort(port):
            builder.ExportOutput(sensor.GetOutputPort(port), f"{camera.name}.{port}")
