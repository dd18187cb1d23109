"""The hook gripper cages a horizontal rod and lifts it by contact alone (no weld, no attach).

A grasp of one's own goes through the same machine, physics and judge as GbH's; the control
closes the same loop just above the rod and must lift nothing."""

from dataclasses import dataclass

import numpy as np
import pytest
from pydrake.common.value import AbstractValue
from pydrake.math import RigidTransform, RotationMatrix
from pydrake.systems.primitives import ConstantValueSource

from gbh_drake.core.gripper import HOOK_GRIPPER
from gbh_drake.method_spec import MethodSpec, Tier
from gbh_drake.methods import GraspMethod, GraspSource, GraspTier, add_search
from gbh_drake.trial import build_trial, simulate_trial

pytestmark = pytest.mark.sim

ROD_HEIGHT = 0.06


@dataclass
class Grasp:
    X_WG: np.ndarray
    kind: str = "parallel"


def _grasp(scenario, rod_depth: float, x: float = 0.0) -> Grasp:
    """Top-down (z_G = -z_W), the loop's plane normal to the rod (x_W), ``x`` (m) along it from
    its middle, the rod ``rod_depth`` short of the bar's centre line along z_G (negative:
    beyond the bar)."""
    R_WG = RotationMatrix(np.diag([1.0, -1.0, -1.0]))
    p_WRod = np.asarray(scenario.object.pose.translation) + [x, 0.0, ROD_HEIGHT]
    p_GRod = np.array([0.0, 0.0, HOOK_GRIPPER.finger_length - rod_depth])
    return Grasp(RigidTransform(R_WG, p_WRod - R_WG.matrix() @ p_GRod).GetAsMatrix4())


def _pick(scenario, staple_mesh, *rod_depths: float, method=None):
    """The staple picked with the grasps of :func:`_grasp` at ``rod_depths``, in that order
    (or with ``method``, made from the scenario)."""
    scenario.object.mesh = "staple.obj"
    staple_mesh.export(scenario.directory / "staple.obj")
    scenario.settle_time = 0.2
    trial = build_trial(scenario, method=method(scenario)) if method else \
        build_trial(scenario, grasps=[_grasp(scenario, d) for d in rod_depths])
    assert trial.station.plant.GetBodyByName(trial.station.object_name).is_floating_base_body()
    _, record = simulate_trial(trial)
    return record


@pytest.mark.trial
@pytest.mark.parametrize(("rod_depth", "caged"), [(0.025, True), (-0.012, False)],
                         ids=["rod_in_the_loop", "loop_above_the_rod"])
def test_hook_lifts_the_rod_only_when_it_is_in_the_loop(scenario, staple_mesh, rod_depth, caged):
    record = _pick(scenario, staple_mesh, rod_depth)
    assert record.grasp_rank == 0, record.reason
    if caged:
        assert record.success and record.held_by == "cage", record.reason
        assert record.verdict.max_clearance > 0.04
    else:
        assert not record.success and record.outcome == "not_lifted", record.reason
        assert record.verdict.max_clearance < 0.01


@pytest.mark.trial
def test_a_lift_that_came_away_empty_is_tried_again_with_another_grasp(scenario, staple_mesh):
    """With ``pick.max_retries`` 1 (gbh_plus's own), the loop closed above the rod comes away
    empty (the hand's load does not grow), the hand opens, goes home, the staple is scanned
    again and the grasp that failed is skipped: the next one cages it."""
    scenario.pick.max_retries = 1
    record = _pick(scenario, staple_mesh, -0.012, 0.025)
    assert record.success and record.held_by == "cage", record.reason
    assert record.grasp_rank == 1 and "1 earlier grasp came away empty" in record.reason
    (attempt,) = record.attempts
    assert attempt["rank"] == 0 and attempt["load"] < 0.2
    assert len(record.verdict.earlier_attempts) == 1
    assert record.verdict.earlier_attempts[0]["max_clearance"] < 0.01
    assert record.phases["retry_home"] < record.phases["rescan"] < record.phases["approach"]


@pytest.mark.trial
def test_ending_after_the_cage_test_changes_no_verdict(scenario, staple_mesh):
    """``pick.set_down: false`` ends the trial once the cage test is over: the same verdict (the
    judged phases are simulated alike), nothing set down, less simulated time."""
    full = _pick(scenario, staple_mesh, 0.025)
    scenario.pick.set_down = False
    short = _pick(scenario, staple_mesh, 0.025)
    assert short.success and short.held_by == "cage", short.reason
    for name in ("outcome", "reason", "held_by", "lifted_at", "clearance_after_hold",
                 "max_clearance", "finger_q_cage_test", "cage_test_held", "loop_closed"):
        assert getattr(short.verdict, name) == getattr(full.verdict, name), name
    assert "release" in full.phases and "lower" not in short.phases
    assert not short.verdict.released_on_table  # still in the hand
    assert short.sim_time < full.sim_time - 1.0


class _TwoTiers(GraspMethod):
    """Given grasps in two tiers: ``hooks`` (the method's own) and ``fallback``, one retry."""

    spec = MethodSpec("two_tiers", "given hooks, then given fallback grasps",
                      tiers=(Tier.GRASPS, Tier.FALLBACK), max_retries=1, beyond_paper=True)

    def __init__(self, hooks: list, fallback: list):
        self.hooks, self.fallback = hooks, fallback

    def add_systems(self, builder, *, scenario, seeds, scan) -> GraspSource:
        systems = {}
        report = add_search(builder, systems, scan, hook=False, scenario=scenario)
        ports = [builder.AddSystem(ConstantValueSource(AbstractValue.Make(list(grasps))))
                 .get_output_port() for grasps in (self.hooks, self.fallback)]
        return GraspSource(tiers=[GraspTier(Tier.GRASPS, ports[0]),
                                  GraspTier(Tier.FALLBACK, ports[1])],
                           search=report.get_output_port(), systems=systems)


@pytest.mark.trial
def test_after_an_empty_retry_the_remaining_tier_is_tried(scenario, staple_mesh):
    """Two hooks of the method's own tier close their loop above the rod (4 cm apart: the
    second is not skipped as tried) and come away empty, the first, then the retry's; with the
    retry used up, the machine goes on to the next tier (issue 42: gbh+ ended there without
    its fallback pinch), whose grasp cages the rod."""
    scenario.pick.max_retries = 1
    record = _pick(scenario, staple_mesh, method=lambda s: _TwoTiers(
        hooks=[_grasp(s, -0.012), _grasp(s, -0.012, x=0.04)],
        fallback=[_grasp(s, 0.025, x=-0.03)]))
    assert record.success and record.held_by == "cage", record.reason
    assert record.grasp_source == "fallback_grasps"
    assert [(a["source"], a["rank"]) for a in record.attempts] == [("grasps", 0), ("grasps", 1)]
    assert "2 earlier grasps came away empty" in record.reason
