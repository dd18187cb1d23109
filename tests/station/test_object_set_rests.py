"""Each object of the set rests stably on the table for 1 s: no explosion, no sinking, no toppling."""

import numpy as np
import pytest
from pydrake.systems.analysis import Simulator

from gbh_drake.objects import list_objects
from gbh_drake.trial import build_trial

pytestmark = pytest.mark.sim


@pytest.mark.parametrize("name", list_objects())
def test_object_rests_on_table(name, scenario):
    scenario.object.name = name
    scenario.settle_time = 1.1  # (the scan is taken then: after this test stops)
    trial = build_trial(scenario)
    station = trial.station
    simulator = Simulator(trial.diagram)
    plant = station.plant
    context = plant.GetMyContextFromRoot(simulator.get_mutable_context())
    body = plant.GetBodyByName(station.object_name)
    X0 = plant.EvalBodyPoseInWorld(context, body)
    simulator.AdvanceTo(1.0)
    X1 = plant.EvalBodyPoseInWorld(context, body)
    drift = np.linalg.norm(X1.translation()[:2] - X0.translation()[:2])
    tilt = np.degrees(np.arccos(np.clip(X0.rotation().col(2) @ X1.rotation().col(2), -1, 1)))
    lowest_z = (station.asset.mesh.vertices @ X1.rotation().matrix().T)[:, 2].min() + \
        X1.translation()[2]
    assert drift < 0.005, f"{name} slid {drift * 1000:.1f} mm"
    assert tilt < 3.0, f"{name} tilted {tilt:.1f} deg"
    assert -0.002 < lowest_z < 0.003, f"{name} lowest point at z = {lowest_z * 1000:.1f} mm"
    assert np.linalg.norm(plant.EvalBodySpatialVelocityInWorld(context, body).translational()) < 0.01
