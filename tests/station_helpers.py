"""Building blocks shared by the station tests (tests/station/) and the hand driver's (tests/systems/)."""

from gbh_drake.modeling.object_asset import initial_object_pose, load_object_asset
from gbh_drake.scenario import Scenario
from gbh_drake.station import Station


def make_station(scenario: Scenario, asset=None) -> Station:
    asset = asset or load_object_asset(scenario.object, scenario.directory)
    return Station(directives=scenario.directives, plant_config=scenario.plant_config,
                   robot=scenario.robot, asset=asset,
                   X_WO=initial_object_pose(scenario.object, asset, 0))
