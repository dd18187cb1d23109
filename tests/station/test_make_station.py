"""The station factory: a station from a scenario alone, with a user's models added."""

import numpy as np
import pytest
from pydrake.geometry import Sphere
from pydrake.math import RigidTransform
from pydrake.multibody.tree import SpatialInertia

from gbh_drake.core.gripper import BAR_RETRACTED, HOOK_GRIPPER
from gbh_drake.modeling.names import GRIPPER
from gbh_drake.scenario import Scenario
from gbh_drake.station import make_station

pytestmark = pytest.mark.sim


def test_a_station_from_the_scenario_alone():
    station = make_station(Scenario(grasp_method="antipodal"))
    plant = station.plant
    assert plant.HasBodyNamed(station.object_name)
    assert station.X_WO_initial.translation()[:2] == pytest.approx([0.55, 0.0])
    gripper = plant.GetModelInstanceByName(GRIPPER)
    q = plant.GetDefaultPositions(gripper)
    assert q == pytest.approx([HOOK_GRIPPER.q_open, HOOK_GRIPPER.q_open, BAR_RETRACTED])
    assert station.HasOutputPort("panda.state") and station.HasInputPort("hook_gripper.command")


def test_prefinalize_adds_a_users_model_before_the_plant_is_finalized():
    seen = []

    def add_marker(parser):
        plant = parser.plant()
        seen.append(plant.is_finalized())
        body = plant.AddRigidBody("marker", plant.AddModelInstance("marker"),
                                  SpatialInertia.SolidSphereWithMass(0.1, 0.01))
        plant.RegisterVisualGeometry(body, RigidTransform(), Sphere(0.01), "marker",
                                     np.array([1.0, 0, 0, 1]))
        plant.WeldFrames(plant.world_frame(), body.body_frame(), RigidTransform([0.3, 0.3, 0.1]))

    station = make_station(Scenario(), prefinalize=add_marker)
    assert seen == [False] and station.plant.HasBodyNamed("marker")
