"""Grasp methods behind one signature: the registry, each method's systems, one of your own."""

import pytest
from pydrake.common.value import AbstractValue
from pydrake.systems.primitives import ConstantValueSource

from gbh_drake.core.gripper import BAR_DEPLOYED, BAR_RETRACTED
from gbh_drake.method_spec import MethodSpec, Tier, method_names, method_spec
from gbh_drake.methods import GraspMethod, GraspSource, GraspTier, method_named, register_method
from gbh_drake.modeling.names import GRIPPER
from gbh_drake.scenario import Scenario, ScenarioError
from gbh_drake.scenario.loader import apply_overrides
from gbh_drake.systems import GraspSearchReport, Outcome
from gbh_drake.trial import build_trial, simulate_trial

pytestmark = pytest.mark.sim

GBH = {"hangability_detector", "grasp_synthesizer", "grasp_scorer"}


SHIPPED = ("gbh", "antipodal", "gbh_fallback", "gbh_scoop", "gbh_regrasp", "gbh_plus")


def test_every_shipped_spec_has_its_method_and_a_scenario_may_name_it():
    assert method_names()[:len(SHIPPED)] == SHIPPED
    for name in SHIPPED:
        assert method_named(name).spec is method_spec(name)
        assert apply_overrides(Scenario(), f"grasp_method: {name}").grasp_method == name


def test_an_unknown_method_names_the_known_ones():
    with pytest.raises(KeyError, match="known: gbh, antipodal, gbh_fallback"):
        method_named("graspnet")
    with pytest.raises(ScenarioError, match=r"grasp_method \(line 1\): must be one of gbh, antipodal, "
                                            r"gbh_fallback, .*; got 'graspnet'"):
        apply_overrides(Scenario(), "grasp_method: graspnet")


@pytest.mark.parametrize(("name", "present", "absent", "bar"), [
    ("gbh", GBH, {"antipodal_sampler"}, BAR_DEPLOYED),
    ("antipodal", {"antipodal_sampler"}, GBH, BAR_RETRACTED),
    ("gbh_fallback", GBH | {"antipodal_sampler"}, set(), BAR_DEPLOYED),
    ("gbh_scoop", GBH | {"scoop_synthesizer"}, {"antipodal_sampler"}, BAR_DEPLOYED),
    ("gbh_regrasp", GBH | {"antipodal_sampler", "regrasp_planner"}, {"scoop_synthesizer"},
     BAR_DEPLOYED),
    ("gbh_plus", GBH | {"antipodal_sampler", "regrasp_planner", "scoop_synthesizer"}, set(),
     BAR_DEPLOYED),
])
def test_each_method_adds_its_own_systems(name, present, absent, bar):
    trial = build_trial(Scenario(grasp_method=name))
    names = {s.get_name() for s in trial.diagram.GetSystems()}
    assert present <= names and not absent & names and "grasp_search" in names
    # The source offers the spec's tiers, in order, and the machine has one input per port.
    assert tuple(tier.tier for tier in trial.source.tiers) == method_spec(name).tiers
    inputs = {trial.pick.get_input_port(i).get_name()
              for i in range(trial.pick.num_input_ports())}
    for tier in Tier:
        assert (set(tier.ports) <= inputs) == (tier in method_spec(name).tiers), tier
    for offered in trial.source.tiers:  # each scoop tier is fed by its own port
        if offered.tier in (Tier.SCOOP, Tier.TALL_SCOOP):
            assert offered.grasps.get_name() == offered.tier.value
    plant = trial.station.plant
    bar_joint = plant.GetJointByName("bar_joint", plant.GetModelInstanceByName(GRIPPER))
    assert bar_joint.get_default_angle() == pytest.approx(bar)
    # The pinch tiers beyond the paper rank by the swing and add the side pass; the baseline
    # and gbh_fallback keep the scenario's sampler as it is.
    if "antipodal_sampler" in present:
        params = trial.source.systems["antipodal_sampler"].params
        beyond = name in ("gbh_regrasp", "gbh_plus")
        assert params.prefer_hanging == params.side_pass == beyond


def test_tall_scoops_come_after_the_surer_tiers_and_before_the_pinch():
    """A tall scoop may only pinch (a square underside the scan cannot see): gbh_plus tries it
    after its hooks, scoops and the regrasp, before the fallback's pinch; gbh_scoop after its
    scoops."""
    plus = method_spec("gbh_plus").tiers
    assert plus.index(Tier.REGRASP) < plus.index(Tier.TALL_SCOOP) < plus.index(Tier.FALLBACK)
    assert method_spec("gbh_scoop").tiers == (Tier.GRASPS, Tier.SCOOP, Tier.TALL_SCOOP)


class NoGrasps(GraspMethod):
    """A method of one's own: offers nothing, and says why in its own words."""

    spec = MethodSpec("no_grasps", "offers nothing", hooks=False)

    def add_systems(self, builder, *, scenario, seeds, scan) -> GraspSource:
        grasps = builder.AddNamedSystem("mine", ConstantValueSource(AbstractValue.Make([])))
        search = builder.AddNamedSystem("grasp_search", GraspSearchReport(
            hook=False, sampler="my sampler"))
        builder.Connect(scan, search.GetInputPort("scan"))
        return GraspSource([GraspTier(Tier.GRASPS, grasps.get_output_port())],
                           search.get_output_port())


def test_a_method_of_ones_own_runs_through_the_same_trial():
    """Scan, plan, judge: the machine finds no grasp and the monitor's outcome and reason come
    from the method's own search report, copied into the record."""
    scenario = Scenario(max_time=1.5)
    trial = build_trial(scenario, method=NoGrasps())
    _, record = simulate_trial(trial)
    assert record.outcome is Outcome.NO_GRASP_FOUND
    assert record.reason == "my sampler found no grasp on the scan"
    assert record.verdict.outcome is record.outcome and record.verdict.reason == record.reason


def test_a_registered_method_is_named_in_a_scenario_and_runs():
    """register_method makes a method of one's own a scenario's grasp_method, by name."""
    register_method(NoGrasps())
    scenario = apply_overrides(Scenario(max_time=1.5), "grasp_method: no_grasps")
    _, record = simulate_trial(build_trial(scenario))
    assert record.method == "no_grasps" and record.outcome is Outcome.NO_GRASP_FOUND


def test_a_spec_starts_with_the_methods_own_grasps():
    with pytest.raises(ValueError, match="tiers must start with grasps"):
        MethodSpec("odd", "a fallback first", tiers=(Tier.FALLBACK, Tier.GRASPS))


class MisWired(NoGrasps):
    """Hands the scan itself to the machine as its grasps."""

    def add_systems(self, builder, *, scenario, seeds, scan) -> GraspSource:
        source = super().add_systems(builder, scenario=scenario, seeds=seeds, scan=scan)
        source.tiers = [GraspTier(Tier.GRASPS, scan)]
        return source


def test_a_wrongly_wired_method_fails_when_the_trial_is_built():
    with pytest.raises(TypeError, match=r"scanner\.mesh_W \(ScanResult\) is connected to input "
                                        r"pick_and_carry\.grasps, which takes list"):
        build_trial(Scenario(), method=MisWired())


def _bar_shape(trial):
    plant = trial.station.plant
    bar = plant.GetBodyByName("bar", plant.GetModelInstanceByName(GRIPPER))
    (gid,) = plant.GetCollisionGeometriesForBody(bar)
    return type(trial.station.scene_graph.model_inspector().GetShape(gid)).__name__


def test_the_scoop_runs_with_the_wedge_gripper_and_the_others_with_the_papers():
    assert _bar_shape(build_trial(Scenario(grasp_method="gbh_scoop"))) == "Mesh"
    assert _bar_shape(build_trial(Scenario(grasp_method="gbh_plus"))) == "Mesh"
    assert _bar_shape(build_trial(Scenario(grasp_method="gbh_regrasp"))) == "Box"
    assert _bar_shape(build_trial(Scenario())) == "Box"
    wedge = Scenario()
    wedge.robot.gripper = "wedge"
    assert _bar_shape(build_trial(wedge)) == "Mesh"


@pytest.mark.trial
def test_a_key_ring_lying_flat_is_scooped_and_caged():
    """GbH has no grasp of a key ring lying flat (the bar cannot pass under it); the scoop slides
    the wedge under the ring and the cage test finds it held on the closed loop."""
    from gbh_drake.scenario.loader import apply_overrides

    scenario = apply_overrides(Scenario(), "{grasp_method: gbh_scoop, object: {name: key_ring}}")
    _, record = simulate_trial(build_trial(scenario))
    assert record.grasp_kind == "scoop" and record.n_ranked == 0
    assert record.outcome is Outcome.SUCCESS and record.held_by == "cage", record.reason


@pytest.mark.trial
def test_a_mug_resting_on_its_handle_is_set_upright_and_hooked():
    """The experiment's mug_classic, stable protocol, trial 0: it rests on its side and handle,
    GbH has no grasp; a pinch sets it upright, the Scanner scans it again, GbH hooks it there
    and the cage test finds it caged. The record keeps the regrasp and the final hook."""
    from gbh_drake import SCENARIOS_DIR
    from gbh_drake.experiment.config import trial_scenario

    scenario = trial_scenario(SCENARIOS_DIR / "experiment.yaml", "mug_classic", "gbh-10", 0)
    scenario.grasp_method = "gbh_regrasp"
    _, record = simulate_trial(build_trial(scenario))
    assert len(record.regrasps) == 1 and record.regrasps[0]["turn_deg"] > 45.0
    assert "rescan" in record.phases and record.phases["rescan"] < record.phases["approach"]
    assert record.grasp_kind in ("parallel", "vertical") and record.grasp_source == "grasps"
    assert record.outcome is Outcome.SUCCESS and record.held_by == "cage", record.reason
    assert len(record.verdict.planned_poses) == 2  # scanned where it lay, then set down anew


@pytest.mark.trial
def test_a_tape_roll_lying_flat_is_stood_on_its_rim_and_hooked_through_its_core():
    """A roll lying flat has no hook grasp (the bar cannot pass under it). Standing on its rim
    it rests on one of many facets, each improbable, together a pose (their family's
    probability); the pinch (one rod in the core) sets it there and backs out of the core the
    way it went in, GbH hooks it through the core, and the cage test finds it caged (the
    experiment's tape_roll, stable protocol, trial 0: lying flat, ten views)."""
    from gbh_drake import SCENARIOS_DIR
    from gbh_drake.experiment.config import trial_scenario

    scenario = trial_scenario(SCENARIOS_DIR / "experiment.yaml", "tape_roll", "gbh-10", 0)
    scenario.grasp_method = "gbh_regrasp"
    _, record = simulate_trial(build_trial(scenario))
    assert len(record.regrasps) == 1 and record.regrasps[0]["probability"] < 0.02
    assert abs(record.regrasps[0]["turn_deg"] - 90.0) < 10.0
    assert record.grasp_kind in ("parallel", "vertical") and record.grasp_source == "grasps"
    assert record.outcome is Outcome.SUCCESS and record.held_by == "cage", record.reason
