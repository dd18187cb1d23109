"""The station sub-diagram: exported ports, gains by name, settling, seeded start poses."""

import numpy as np
import pytest
from pydrake.systems.analysis import Simulator
from pydrake.systems.framework import DiagramBuilder, LeafSystem
from pydrake.systems.primitives import ConstantVectorSource
from station_helpers import make_station

from gbh_drake.core.gripper import HOOK_GRIPPER
from gbh_drake.modeling.object_asset import initial_object_pose, load_object_asset, make_asset
from gbh_drake.run import run
from gbh_drake.scenario import load_scenario

STATION_PORTS = {
    "inputs": {"panda.desired_state", "hook_gripper.command"},
    "outputs": {"panda.state", "hook_gripper.state", "hook_gripper.actuation", "object.state",
                "body_poses", "contact_results", "query_object", "camera_query_object"},
}


class _Recorder(LeafSystem):
    """A user's own system: reads the object's state from the station's exported port."""

    def __init__(self):
        super().__init__()
        self.DeclareVectorInputPort("object_state", 13)
        self.DeclareVectorOutputPort("height", 1, lambda c, out: out.SetFromVector(
            [self.get_input_port().Eval(c)[6]]))


@pytest.mark.sim
def test_a_users_system_wires_to_exported_ports_only(scenario):
    station = make_station(scenario)
    names_in = {station.get_input_port(i).get_name() for i in range(station.num_input_ports())}
    names_out = {station.get_output_port(i).get_name() for i in range(station.num_output_ports())}
    assert STATION_PORTS["inputs"] <= names_in and STATION_PORTS["outputs"] <= names_out
    builder = DiagramBuilder()
    builder.AddSystem(station)
    hold = builder.AddSystem(ConstantVectorSource(np.concatenate([station.q_home, np.zeros(7)])))
    # Close the hook's loop (width command q_closed, 30 N at most, the bar out).
    close = builder.AddSystem(ConstantVectorSource([HOOK_GRIPPER.q_closed, 30.0, 0.0]))
    recorder = builder.AddSystem(_Recorder())
    builder.Connect(hold.get_output_port(), station.GetInputPort("panda.desired_state"))
    builder.Connect(close.get_output_port(), station.GetInputPort("hook_gripper.command"))
    builder.Connect(station.GetOutputPort("object.state"), recorder.get_input_port())
    simulator = Simulator(builder.Build())
    simulator.AdvanceTo(0.8)
    context = simulator.get_context()
    height = recorder.get_output_port().Eval(recorder.GetMyContextFromRoot(context))[0]
    assert abs(height - station.X_WO_initial.translation()[2]) < 0.005
    arm = station.GetOutputPort("panda.state").Eval(station.GetMyContextFromRoot(context))
    np.testing.assert_allclose(arm[:7], station.q_home, atol=2e-3)
    hand = station.GetOutputPort("hook_gripper.state").Eval(station.GetMyContextFromRoot(context))
    # With nothing between them the fingers close until the bar's tip is on the straight rod.
    np.testing.assert_allclose(hand[:2], HOOK_GRIPPER.q_closed, atol=5e-4)


@pytest.mark.sim
def test_gains_are_set_by_actuator_name(scenario):
    scenario.robot.arm_kp = [100.0, 200.0, 300.0, 400.0, 500.0, 600.0, 700.0]
    station = make_station(scenario)
    plant = station.plant
    arm = plant.GetModelInstanceByName("panda")
    gains = {plant.get_joint_actuator(i).joint().name():
             plant.get_joint_actuator(i).get_controller_gains().p
             for i in plant.GetJointActuatorIndices(arm)}
    assert gains == {f"panda_joint{i + 1}": pytest.approx(100.0 * (i + 1)) for i in range(7)}


@pytest.mark.sim
def test_settle_keeps_object_and_writes_outputs(scenario, staple_mesh):
    scenario.settle_time = 0.3
    scenario.task = "settle"
    scenario.object.mesh = "staple.obj"
    staple_mesh.export(scenario.directory / "staple.obj")
    summary = run(scenario)
    assert summary.settle_drift < 0.005
    html = (scenario.output_path() / "replay.html").read_text()
    assert "<html" in html.lower() and len(html) > 10_000
    for name in ("summary.yaml", "scenario.yaml"):
        assert (scenario.output_path() / name).is_file()


def test_object_starts_above_the_table_whatever_its_origin(scenario, staple_mesh):
    """A mesh centred at its middle is moved to rest on z = 0 of its frame O."""
    centred = staple_mesh.copy()
    centred.apply_translation(-centred.bounds.mean(axis=0))
    asset = make_asset("staple", centred, density=500.0)
    assert asset.mesh.bounds[0, 2] == pytest.approx(0.0, abs=1e-9)
    X_WO = initial_object_pose(scenario.object, asset, 0)
    low = (asset.mesh.vertices @ X_WO.rotation().matrix().T)[:, 2].min() + X_WO.translation()[2]
    assert low == pytest.approx(scenario.object.drop_height, abs=1e-9)


RANDOM_POSE = """
object:
  pose:
    translation: !UniformVector {min: [0.4, -0.2, 0.0], max: [0.7, 0.2, 0.0]}
    rotation: !Rpy {deg: !UniformVector {min: [0, 0, -180], max: [0, 0, 180]}}
"""


def _pose(tmp_path, seed):
    path = tmp_path / "random.yaml"
    path.write_text(RANDOM_POSE)
    scenario = load_scenario(path, overrides=f"seed: {seed}")
    from gbh_drake.seeds import derive_seeds

    asset = load_object_asset(scenario.object, scenario.directory)
    return initial_object_pose(scenario.object, asset, derive_seeds(seed).pose)


def test_seed_decides_the_random_pose(tmp_path):
    a, b, c = _pose(tmp_path, 3), _pose(tmp_path, 3), _pose(tmp_path, 4)
    np.testing.assert_array_equal(a.GetAsMatrix4(), b.GetAsMatrix4())
    assert not np.allclose(a.translation(), c.translation())
    assert 0.4 <= a.translation()[0] <= 0.7
