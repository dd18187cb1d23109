"""The Scanner scans a still object: the stillness rule, and a dropped object scanned at rest."""

import math

import numpy as np
import pytest
from pydrake.geometry import MakeRenderEngineVtk, RenderEngineVtkParams
from pydrake.systems.analysis import Simulator
from pydrake.systems.framework import DiagramBuilder
from pydrake.systems.primitives import ConstantVectorSource

from gbh_drake.perception.config import ScanConfig
from gbh_drake.perception.scan import ScanResult
from gbh_drake.systems.scanner import Scanner, scan_pending, still_decision

CONFIG = ScanConfig()  # still under 3 mm/s and 3 deg/s for 0.2 s, at most 3 s after scan_time
SLOW, FAST = [0.001, 0.0, 0.0], [0.05, 0.0, 0.0]
STILL_W, SPIN_W = [0.0, 0.0, 0.01], [0.0, 0.0, np.deg2rad(10.0)]


def decide(t, v, w, since, scan_time=0.5):
    return still_decision(t, np.asarray(v), np.asarray(w), since, scan_time=scan_time,
                          config=CONFIG)


def test_a_still_object_is_scanned_after_the_dwell_and_not_before_the_scan_time():
    scan, since, warning = decide(0.1, SLOW, STILL_W, math.nan)
    assert (scan, since, warning) == (False, 0.1, "")  # still from now, before scan_time
    assert decide(0.4, SLOW, STILL_W, 0.1)[0] is False  # dwell done, but before scan_time
    assert decide(0.5, SLOW, STILL_W, 0.1) == (True, 0.1, "")  # at scan_time
    assert decide(0.6, SLOW, STILL_W, 0.45)[0] is False  # still for 0.15 s only
    assert decide(0.65, SLOW, STILL_W, 0.45) == (True, 0.45, "")  # 0.2 s


def test_moving_or_spinning_restarts_the_dwell():
    scan, since, _ = decide(0.6, FAST, STILL_W, 0.1)  # moving at 5 cm/s
    assert not scan and math.isnan(since)
    scan, since, _ = decide(0.6, SLOW, SPIN_W, 0.1)  # slow but turning at 10 deg/s
    assert not scan and math.isnan(since)
    # Just under both bounds is still; at a bound is not.
    just = [0.999 * CONFIG.still_speed, 0, 0]
    assert decide(0.7, just, [0, 0, 0.999 * np.deg2rad(CONFIG.still_angular_speed_deg)], 0.5)[0]
    assert not decide(0.7, [CONFIG.still_speed, 0, 0], STILL_W, 0.5)[0]


def test_a_moving_object_is_scanned_at_the_latest_bound_with_a_warning():
    assert decide(3.49, FAST, STILL_W, math.nan)[0] is False
    scan, _, warning = decide(3.5, FAST, STILL_W, math.nan)
    assert scan and "still moving when scanned at t = 3.50 s (50.0 mm/s" in warning


def test_only_the_placeholder_is_pending():
    assert scan_pending(ScanResult.empty_result("not scanned yet"))
    nothing = ScanResult.empty_result("empty scan: nothing stands on the table")
    assert not scan_pending(nothing)  # an empty scan is taken: the machine plans (no grasp)
    taken = ScanResult.empty_result("not scanned yet")
    taken.taken_at = 0.5
    assert not scan_pending(taken)


def test_the_object_state_port_comes_with_a_scan_time_only():
    live = Scanner(ScanConfig(), [0.55, 0.0, 0.06])
    assert live.num_input_ports() == 1  # get_input_port() keeps working
    held = Scanner(ScanConfig(), [0.55, 0.0, 0.06], scan_time=0.5)
    assert held.GetInputPort("object.state").size() == 13


def _empty_scene_scanner(x_object: np.ndarray):
    """A builder with an empty scene and a Scanner (1 view, scan_time 0.5 s) fed a constant
    object state ``x_object`` (13,)."""
    from pydrake.multibody.plant import AddMultibodyPlantSceneGraph

    builder = DiagramBuilder()
    plant, scene_graph = AddMultibodyPlantSceneGraph(builder, 0.0)
    plant.Finalize()
    scene_graph.AddRenderer("default", MakeRenderEngineVtk(RenderEngineVtkParams()))
    scanner = builder.AddSystem(Scanner(ScanConfig(num_views=1), [0.55, 0.0, 0.06],
                                        scan_time=0.5))
    builder.Connect(scene_graph.get_query_output_port(), scanner.GetInputPort("query_object"))
    state = builder.AddSystem(ConstantVectorSource(x_object))
    builder.Connect(state.get_output_port(), scanner.GetInputPort("object.state"))
    return builder, scanner


def _scan_with_state(x_object: np.ndarray, until: float):
    """A Scanner (scan_time 0.5 s) fed a constant object state, on an empty scene."""
    builder, scanner = _empty_scene_scanner(x_object)
    diagram = builder.Build()
    simulator = Simulator(diagram)
    simulator.AdvanceTo(until)
    return scanner.GetOutputPort("mesh_W").Eval(
        scanner.GetMyContextFromRoot(simulator.get_context()))


@pytest.mark.sim
def test_a_never_still_object_is_scanned_at_the_bound_with_a_warning():
    x = np.zeros(13)
    x[0], x[10] = 1.0, 0.05  # moving at 5 cm/s for ever
    assert scan_pending(_scan_with_state(x, 3.4))
    result = _scan_with_state(x, 3.6)
    assert not scan_pending(result) and result.taken_at == pytest.approx(3.5)
    assert any("still moving when scanned" in w for w in result.warnings)


@pytest.mark.sim
def test_an_object_dropped_from_a_few_cm_is_scanned_once_still():
    """A can dropped from 4 cm (it falls 0.09 s, then bounces and rocks): with scan_time 0.05 s
    (mid-fall) the scan waits until it has been still for the dwell, and sees it on the table."""
    from gbh_drake import SCENARIOS_DIR
    from gbh_drake.scenario.loader import load_scenario
    from gbh_drake.station import make_station

    scenario = load_scenario(
        SCENARIOS_DIR / "default.yaml",
        overrides="{object: {name: can, drop_height: 0.04}, scan: {num_views: 1}}")
    builder = DiagramBuilder()
    station = builder.AddSystem(make_station(scenario))
    scanner = builder.AddSystem(Scanner(scenario.scan, scenario.scan_target, scan_time=0.05))
    builder.Connect(station.GetOutputPort("camera_query_object"),
                    scanner.GetInputPort("query_object"))
    builder.Connect(station.GetOutputPort("object.state"), scanner.GetInputPort("object.state"))
    diagram = builder.Build()
    simulator = Simulator(diagram)
    context = simulator.get_mutable_context()
    station_context = station.GetMyContextFromRoot(context)
    x_arm = station.GetOutputPort("panda.state").Eval(station_context).copy()
    x_arm[7:] = 0.0
    station.GetInputPort("panda.desired_state").FixValue(station_context, x_arm)
    q_hand = station.GetOutputPort("hook_gripper.state").Eval(station_context)
    station.GetInputPort("hook_gripper.command").FixValue(
        station_context, np.array([np.mean(q_hand[:2]), scenario.robot.hand.force, 0.0]))
    scanner_context = scanner.GetMyContextFromRoot(context)
    config, t, still_from, scan = scenario.scan, 0.0, math.nan, None
    while t < 1.5 and scan is None:
        t = round(t + config.still_period, 6)
        simulator.AdvanceTo(t)
        x = station.GetOutputPort("object.state").Eval(station_context)
        still = (np.linalg.norm(x[10:13]) < config.still_speed
                 and np.linalg.norm(x[7:10]) < np.deg2rad(config.still_angular_speed_deg))
        still_from = (t if math.isnan(still_from) else still_from) if still else math.nan
        result = scanner.GetOutputPort("mesh_W").Eval(scanner_context)
        if not scan_pending(result):
            scan = result
    assert scan is not None and not scan.empty and scan.warnings == []
    assert scan.taken_at >= 0.09 + config.still_dwell  # not in the air, not at the bounce
    assert scan.taken_at - still_from >= config.still_dwell - 0.011  # still for the dwell
    # Seen on the table: the mesh's top is the resting can's top.
    p_W = station.GetOutputPort("object.state").Eval(station_context)[4:7]
    assert abs(scan.mesh_W.bounds[0][2]) < 0.01
    assert scan.mesh_W.bounds[1][2] == pytest.approx(
        station.asset.mesh.bounds[1][2] + p_W[2], abs=0.01)


@pytest.mark.sim
def test_a_scan_request_is_answered_by_a_new_scan_around_its_target():
    """The first scan at scan_time, then the request [1, x, y, z] (seen at 0.8 s) gets a second
    scan, aimed at the request's target: at once, the object having been still for longer than
    the dwell (stillness before the request counts, as before scan_time)."""
    from pydrake.systems.primitives import TrajectorySource
    from pydrake.trajectories import PiecewisePolynomial

    x = np.zeros(13)
    x[0] = 1.0  # still
    builder, scanner = _empty_scene_scanner(x)
    request = PiecewisePolynomial.ZeroOrderHold(
        [0.0, 0.8, 5.0], np.array([[0, 0, 0, 0], [1, 0.5, 0.1, 0.06], [1, 0.5, 0.1, 0.06]]).T)
    builder.Connect(builder.AddSystem(TrajectorySource(request)).get_output_port(),
                    scanner.GetInputPort("scan_request"))
    simulator = Simulator(builder.Build())
    context = scanner.GetMyContextFromRoot(simulator.get_context())
    simulator.AdvanceTo(0.7)
    first = scanner.GetOutputPort("mesh_W").Eval(context)
    assert first.request == 0 and first.taken_at == pytest.approx(0.5)
    simulator.AdvanceTo(1.5)
    second = scanner.GetOutputPort("mesh_W").Eval(context)
    assert second.request == 1 and second.taken_at == pytest.approx(0.8, abs=0.011)
    # Its first look looks from around the request's target, the first scan's from around T.
    distance = ScanConfig().first_look_distance
    for scan, target in ((first, [0.55, 0.0, 0.06]), (second, [0.5, 0.1, 0.06])):
        for X_WC in scan.first_look_X_WCs:
            assert np.linalg.norm(X_WC.translation() - target) == pytest.approx(distance)
    simulator.AdvanceTo(2.0)  # answered: no third scan
    assert scanner.GetOutputPort("mesh_W").Eval(context).taken_at == second.taken_at
