"""Grasp methods behind one signature: the registry, each method's systems, one of your own."""

import pytest
from pydrake.common.value import AbstractValue
from pydrake.systems.primitives import ConstantValueSource

from gbh_drake.core.gripper import BAR_DEPLOYED, BAR_RETRACTED
from gbh_drake.methods import GraspMethod, GraspSource, method_named, method_names
from gbh_drake.modeling.names import GRIPPER
from gbh_drake.scenario import GRASP_METHODS, Scenario
from gbh_drake.systems import GraspSearchReport, Outcome
from gbh_drake.trial import build_trial, simulate_trial

pytestmark = pytest.mark.sim

GBH = {"hangability_detector", "grasp_synthesizer", "grasp_scorer"}


def test_the_registry_holds_what_a_scenario_may_name():
    assert method_names() == GRASP_METHODS


def test_an_unknown_method_names_the_known_ones():
    with pytest.raises(KeyError, match="known: antipodal, gbh, gbh_fallback"):
        method_named("graspnet")


@pytest.mark.parametrize(("name", "present", "absent", "bar"), [
    ("gbh", GBH, {"antipodal_sampler"}, BAR_DEPLOYED),
    ("antipodal", {"antipodal_sampler"}, GBH, BAR_RETRACTED),
    ("gbh_fallback", GBH | {"antipodal_sampler"}, set(), BAR_DEPLOYED),
])
def test_each_method_adds_its_own_systems(name, present, absent, bar):
    trial = build_trial(Scenario(grasp_method=name))
    names = {s.get_name() for s in trial.diagram.GetSystems()}
    assert present <= names and not absent & names and "grasp_search" in names
    assert (trial.source.fallback is not None) == (name == "gbh_fallback")
    plant = trial.station.plant
    bar_joint = plant.GetJointByName("bar_joint", plant.GetModelInstanceByName(GRIPPER))
    assert bar_joint.get_default_angle() == pytest.approx(bar)


class NoGrasps(GraspMethod):
    """A method of one's own: offers nothing, and says why in its own words."""

    name = "no_grasps"

    def add_systems(self, builder, *, scenario, seeds, scan) -> GraspSource:
        grasps = builder.AddNamedSystem("mine", ConstantValueSource(AbstractValue.Make([])))
        search = builder.AddNamedSystem("grasp_search", GraspSearchReport(
            hook=False, sampler="my sampler"))
        builder.Connect(scan, search.GetInputPort("scan"))
        return GraspSource(grasps.get_output_port(), search.get_output_port())


def test_a_method_of_ones_own_runs_through_the_same_trial():
    """Scan, plan, judge: the machine finds no grasp and the monitor's outcome and reason come
    from the method's own search report, copied into the record."""
    scenario = Scenario(max_time=1.5)
    trial = build_trial(scenario, method=NoGrasps())
    _, record = simulate_trial(trial)
    assert record.outcome is Outcome.NO_GRASP_FOUND
    assert record.reason == "my sampler found no grasp on the scan"
    assert record.verdict.outcome is record.outcome and record.verdict.reason == record.reason


class MisWired(NoGrasps):
    """Hands the scan itself to the machine as its grasps."""

    def add_systems(self, builder, *, scenario, seeds, scan) -> GraspSource:
        source = super().add_systems(builder, scenario=scenario, seeds=seeds, scan=scan)
        source.grasps = scan
        return source


def test_a_wrongly_wired_method_fails_when_the_trial_is_built():
    with pytest.raises(TypeError, match=r"scanner\.mesh_W \(ScanResult\) is connected to input "
                                        r"pick_and_carry\.grasps, which takes list"):
        build_trial(Scenario(), method=MisWired())
