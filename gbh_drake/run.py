"""Runs a scenario: builds the station, simulates it, writes the Meshcat replay and a summary.

The steps of :func:`run`, in order: load the object, build the station (plant, scene graph,
cameras, Meshcat), drive the robot with a :class:`~gbh_drake.planning.trajectories.MotionScript`
(by default: hold the home configuration while the object settles), simulate, and write
``replay.html`` (a self-contained Meshcat recording, opens offline in any browser) and
``summary.yaml`` into the scenario's output folder.
"""

from __future__ import annotations

import logging
import time
from dataclasses import asdict, dataclass, field
from pathlib import Path

import numpy as np
import yaml
from pydrake.geometry import Meshcat
from pydrake.systems.analysis import ApplySimulatorConfig, Simulator
from pydrake.systems.framework import DiagramBuilder
from pydrake.systems.primitives import TrajectorySource

from gbh_drake.core.gripper import HOOK_GRIPPER
from gbh_drake.planning.trajectories import MotionScript
from gbh_drake.scenario import Scenario
from gbh_drake.station import ObjectAsset, Station, add_station

log = logging.getLogger("gbh_drake")


@dataclass
class RunSummary:
    """What a run did. Lengths in metres, times in seconds."""

    scenario: str
    object: str
    object_mass: float
    seed: int
    sim_time: float
    wall_time: float
    realtime_rate: float
    p_WO_initial: list[float]
    p_WO_final: list[float]
    object_drift: float
    """Distance the object moved during the run (settling only: should be ~0)."""
    object_tilt_deg: float
    """Angle between the object's initial and final up axes."""
    replay: str
    phases: list[str] = field(default_factory=list)

    def to_text(self) -> str:
        return (
            f"scenario {self.scenario}\n"
            f"  object {self.object} ({self.object_mass * 1000:.0f} g), seed {self.seed}\n"
            f"  simulated {self.sim_time:.2f} s in {self.wall_time:.2f} s wall "
            f"({self.realtime_rate:.2f}x real time); phases: {', '.join(self.phases)}\n"
            f"  object moved {self.object_drift * 1000:.1f} mm, tilted "
            f"{self.object_tilt_deg:.1f} deg while settling\n"
            f"  replay: {self.replay}"
        )


def settle_script(station: Station, duration: float) -> MotionScript:
    """Holds the home configuration with the gripper as the scenario says, for ``duration`` s."""
    q_f = HOOK_GRIPPER.q_open if station.plant.GetDefaultPositions(station.gripper)[0] > (
        HOOK_GRIPPER.q_closed + 1e-6) else HOOK_GRIPPER.q_closed
    return MotionScript().start(station.q_home, q_f).hold(max(duration, 1e-3), "settle")


def build_diagram(scenario: Scenario, script_fn=None, *, meshcat: Meshcat | None = None,
                  object_asset: ObjectAsset | None = None):
    """The diagram of ``scenario``: station plus trajectory sources for the arm and fingers.

    ``script_fn(station) -> MotionScript`` chooses the motion (default: settle in place);
    ``object_asset`` replaces the scenario's object. Returns ``(diagram, station, script)``."""
    builder = DiagramBuilder()
    station = add_station(builder, scenario, meshcat=meshcat, object_asset=object_asset)
    script = (script_fn or (lambda s: settle_script(s, scenario.settle_time)))(station)
    arm = builder.AddSystem(TrajectorySource(script.arm_trajectory(), output_derivative_order=1))
    arm.set_name("arm_trajectory")
    fingers = builder.AddSystem(
        TrajectorySource(script.finger_trajectory(), output_derivative_order=1)
    )
    fingers.set_name("finger_trajectory")
    builder.Connect(arm.get_output_port(), station.arm_desired_state)
    builder.Connect(fingers.get_output_port(), station.gripper_desired_state)
    diagram = builder.Build()
    diagram.set_name(f"gbh_station[{Path(scenario.source_path).stem or 'scenario'}]")
    return diagram, station, script


def run(scenario: Scenario, *, meshcat: Meshcat | None = None, script_fn=None,
        object_asset: ObjectAsset | None = None) -> RunSummary:
    """Simulates ``scenario`` and writes its replay and summary (see the module docstring)."""
    out = scenario.output_path()
    out.mkdir(parents=True, exist_ok=True)
    meshcat = meshcat or Meshcat()
    diagram, station, script = build_diagram(scenario, script_fn, meshcat=meshcat,
                                             object_asset=object_asset)

    simulator = Simulator(diagram)
    ApplySimulatorConfig(scenario.simulator_config, simulator)
    context = simulator.get_mutable_context()
    plant, body = station.plant, station.object_body()
    plant_context = plant.GetMyContextFromRoot(context)
    X_WO_0 = plant.EvalBodyPoseInWorld(plant_context, body)

    # A view of the work area from the front right (the user can orbit it in the browser).
    meshcat.SetCameraPose(camera_in_world=[1.3, -1.0, 0.8], target_in_world=[0.45, 0.0, 0.15])
    meshcat.StartRecording(frames_per_second=1.0 / scenario.visualization.publish_period)
    start = time.perf_counter()
    simulator.Initialize()
    simulator.AdvanceTo(script.end_time)
    wall = time.perf_counter() - start
    meshcat.StopRecording()
    meshcat.PublishRecording()
    replay = out / "replay.html"
    replay.write_text(meshcat.StaticHtml())

    X_WO_1 = plant.EvalBodyPoseInWorld(plant_context, body)
    up0, up1 = X_WO_0.rotation().col(2), X_WO_1.rotation().col(2)
    summary = RunSummary(
        scenario=scenario.source_path or "<in memory>",
        object=station.object_asset.source,
        object_mass=station.object_model.mass,
        seed=scenario.seed,
        sim_time=script.end_time,
        wall_time=wall,
        realtime_rate=script.end_time / wall if wall > 0 else float("inf"),
        p_WO_initial=X_WO_0.translation().tolist(),
        p_WO_final=X_WO_1.translation().tolist(),
        object_drift=float(np.linalg.norm(X_WO_1.translation() - X_WO_0.translation())),
        object_tilt_deg=float(np.degrees(np.arccos(np.clip(up0 @ up1, -1.0, 1.0)))),
        replay=str(replay),
        phases=list(script.labels[1:]),
    )
    (out / "summary.yaml").write_text(yaml.safe_dump(asdict(summary), sort_keys=False))
    return summary
