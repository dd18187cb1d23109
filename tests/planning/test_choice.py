"""The plan choice alone: tiers in order, every grasp of a tier before the next, lazily."""

from dataclasses import dataclass, field

import numpy as np
import pytest

from gbh_drake.method_spec import Tier, method_spec
from gbh_drake.planning.choice import Offer, at_failed_pose, choose, tiers_after_empty_lifts


@dataclass
class Grasp:
    name: str
    X_WG: np.ndarray = field(default_factory=lambda: np.eye(4))
    kind: str = "parallel"


@dataclass
class Pose:
    name: str
    pinches: list = field(default_factory=list)


def planner(plannable: set[str], log: list):
    """plan_grasp / plan_regrasp that plan the grasps named in ``plannable`` and refuse the
    others, logging every call."""

    def plan_grasp(tier, rank, grasp):
        log.append((tier, rank, grasp.name))
        return ("plan", grasp.name) if grasp.name in plannable else ("refused", grasp.name)

    def plan_regrasp(rank, X_WG, pose):
        log.append((Tier.REGRASP, rank, pose.name))
        return ("plan", pose.name) if pose.name in plannable else ("refused", pose.name)

    return plan_grasp, plan_regrasp


def is_plan(result):
    return result[0] == "plan"


def evaluated(names, seen: list, tier: Tier):
    def grasps():
        seen.append(tier)
        return [Grasp(n) for n in names]
    return grasps


def test_every_grasp_of_a_tier_is_tried_before_the_next_tier_and_later_tiers_stay_unevaluated():
    log, seen = [], []
    plan_grasp, plan_regrasp = planner({"f1", "a2"}, log)
    offers = [Offer(Tier.GRASPS, evaluated(["a0", "a1", "a2"], seen, Tier.GRASPS)),
              Offer(Tier.FALLBACK, evaluated(["f0", "f1"], seen, Tier.FALLBACK))]
    choice = choose(offers, plan_grasp=plan_grasp, is_plan=is_plan, max_grasps=10)
    assert choice.plan == ("plan", "a2") and choice.tier is Tier.GRASPS and choice.rank == 2
    assert [r[1] for r in choice.refusals] == ["a0", "a1"]
    assert seen == [Tier.GRASPS]  # the fallback was never evaluated (it runs a sampler)
    assert len(choice.grasp_seconds) == 3 and choice.n_offered == 3


def test_the_fallback_follows_a_regrasp_and_counts_only_grasp_tiers():
    log, seen = [], []
    plan_grasp, plan_regrasp = planner({"f1"}, log)
    offers = [Offer(Tier.GRASPS, evaluated(["a0"], seen, Tier.GRASPS)),
              Offer(Tier.SCOOP, evaluated(["s0"], seen, Tier.SCOOP)),
              Offer(Tier.REGRASP, evaluated(["p0", "p1", "p2"], seen, Tier.REGRASP),
                    poses=lambda: [Pose("upright", pinches=[np.eye(4)]), Pose("side")]),
              Offer(Tier.FALLBACK, evaluated(["f0", "f1"], seen, Tier.FALLBACK))]
    choice = choose(offers, plan_grasp=plan_grasp, plan_regrasp=plan_regrasp, is_plan=is_plan,
                    max_grasps=10, max_pinches=2)
    assert choice.plan == ("plan", "f1") and choice.tier is Tier.FALLBACK and choice.rank == 1
    # Each resting pose: its own pinch first, then the tier's first two (max_pinches).
    assert [entry for entry in log if entry[0] is Tier.REGRASP] == [
        (Tier.REGRASP, 0, "upright"), (Tier.REGRASP, 1, "upright"), (Tier.REGRASP, 2, "upright"),
        (Tier.REGRASP, 0, "side"), (Tier.REGRASP, 1, "side")]
    assert choice.regrasp_note == "none of 2 resting poses x 2 pinches could be planned"
    assert choice.n_offered == 4  # a0, s0, f0, f1: a regrasp's pinches are not offered grasps
    assert [r[1] for r in choice.refusals] == ["a0", "s0", *["upright"] * 3, *["side"] * 2, "f0"]


def test_a_regrasp_plan_wins_over_the_fallback_unless_regrasping_is_used_up():
    log = []
    plan_grasp, plan_regrasp = planner({"side", "f0"}, log)
    offers = [Offer(Tier.GRASPS, lambda: []),
              Offer(Tier.REGRASP, lambda: [Grasp("p0")], poses=lambda: [Pose("side")]),
              Offer(Tier.FALLBACK, lambda: [Grasp("f0")])]
    kwargs = dict(plan_grasp=plan_grasp, plan_regrasp=plan_regrasp, is_plan=is_plan,
                  max_grasps=10, max_pinches=1)
    assert choose(offers, **kwargs).tier is Tier.REGRASP
    assert choose(offers, regrasp_allowed=False, **kwargs).tier is Tier.FALLBACK


@pytest.mark.parametrize(("poses", "pinches", "note"), [
    ([], ["p0"], "no resting pose offers a hook grasp"),
    ([Pose("side")], [], "no pinch to turn the object with"),
])
def test_a_regrasp_without_poses_or_pinches_says_why(poses, pinches, note):
    plan_grasp, plan_regrasp = planner(set(), [])
    offers = [Offer(Tier.GRASPS, lambda: []),
              Offer(Tier.REGRASP, lambda: [Grasp(n) for n in pinches], poses=lambda: poses)]
    choice = choose(offers, plan_grasp=plan_grasp, plan_regrasp=plan_regrasp, is_plan=is_plan,
                    max_grasps=10, max_pinches=3)
    assert choice.plan is None and choice.regrasp_note == note


def test_only_the_first_max_grasps_are_tried_and_skipped_ones_are_counted():
    log = []
    plan_grasp, _ = planner(set(), log)
    offers = [Offer(Tier.GRASPS, lambda: [Grasp(f"a{i}") for i in range(6)])]
    choice = choose(offers, plan_grasp=plan_grasp, is_plan=is_plan, max_grasps=4,
                    skip=lambda grasp: grasp.name == "a1")
    assert [name for _, _, name in log] == ["a0", "a2", "a3"]
    assert choice.plan is None and choice.skipped == 1 and choice.n_offered == 6


def test_an_offer_the_caller_refuses_raises():
    def check(tier, grasps):
        if any(not hasattr(g, "X_WG") for g in grasps):
            raise TypeError(f"{tier.value}: a grasp without X_WG")

    with pytest.raises(TypeError, match="grasps: a grasp without X_WG"):
        choose([Offer(Tier.GRASPS, lambda: [object()])], plan_grasp=lambda *a: None,
               is_plan=is_plan, max_grasps=10, check=check)


PLUS = method_spec("gbh_plus").tiers


@pytest.mark.parametrize(("failed", "max_retries", "left"), [
    ([], 0, PLUS),
    ([Tier.GRASPS], 0, ()),  # the paper: an empty lift ends the trial
    ([Tier.GRASPS], 1, PLUS),  # the retry: every tier again (the failed grasps skipped)
    # The retry came away empty too: on to the tiers after the hook's (the fallback pinch).
    ([Tier.GRASPS, Tier.GRASPS], 1, (Tier.SCOOP, Tier.REGRASP, Tier.TALL_SCOOP, Tier.FALLBACK)),
    ([Tier.SCOOP, Tier.SCOOP], 1, (Tier.REGRASP, Tier.TALL_SCOOP, Tier.FALLBACK)),
    ([Tier.GRASPS, Tier.GRASPS, Tier.SCOOP], 1, (Tier.REGRASP, Tier.TALL_SCOOP, Tier.FALLBACK)),
    ([Tier.GRASPS, Tier.GRASPS, Tier.TALL_SCOOP], 1, (Tier.FALLBACK,)),
    ([Tier.GRASPS, Tier.FALLBACK], 1, ()),  # nothing after the last tier
    ([Tier.GRASPS, Tier.GRASPS], 2, PLUS),
])
def test_after_empty_lifts_the_retries_then_the_remaining_tiers_are_tried(failed, max_retries,
                                                                          left):
    assert tiers_after_empty_lifts(PLUS, failed, max_retries) == left


def test_an_empty_retry_goes_on_to_the_fallback_skipping_what_was_tried():
    """gbh+ on a spray bottle: its best hook came away empty, the retry's next hook too; the
    plan after them offers the remaining tiers only, and the fallback pinch is planned."""
    failed = [Tier.GRASPS, Tier.GRASPS]
    log, seen = [], []
    plan_grasp, plan_regrasp = planner({"a2", "f0"}, log)
    tiers = tiers_after_empty_lifts(PLUS, failed, max_retries=1)
    offers = {Tier.GRASPS: Offer(Tier.GRASPS, evaluated(["a0", "a1", "a2"], seen, Tier.GRASPS)),
              Tier.SCOOP: Offer(Tier.SCOOP, evaluated([], seen, Tier.SCOOP)),
              Tier.TALL_SCOOP: Offer(Tier.TALL_SCOOP, evaluated([], seen, Tier.TALL_SCOOP)),
              Tier.REGRASP: Offer(Tier.REGRASP, evaluated(["p0"], seen, Tier.REGRASP),
                                  poses=lambda: []),
              Tier.FALLBACK: Offer(Tier.FALLBACK, evaluated(["f0"], seen, Tier.FALLBACK))}
    choice = choose([offers[t] for t in tiers], plan_grasp=plan_grasp,
                    plan_regrasp=plan_regrasp, is_plan=is_plan, max_grasps=10, max_pinches=1)
    assert choice.tier is Tier.FALLBACK and choice.plan == ("plan", "f0")
    assert Tier.GRASPS not in seen  # the hooks are not offered again (a2 would plan)


def test_unreachable_grasps_do_not_use_up_the_tries():
    """The cut by reach: a tier offers 14 grasps, the arm reaches none of the first 12. Without
    a reach check the first ``max_grasps`` (10) are planned and refused: nothing; with it, the
    12 are refused by the cheap check (kept in order, not counted) and #13 is planned."""
    names = [f"g{i}" for i in range(14)]
    reachable = {"g12", "g13"}

    def reach(tier, rank, grasp):
        return None if grasp.name in reachable else ("unreached", grasp.name)

    log = []
    plan_grasp, _ = planner(reachable, log)
    plain = choose([Offer(Tier.GRASPS, lambda: [Grasp(n) for n in names])],
                   plan_grasp=plan_grasp, is_plan=is_plan, max_grasps=10)
    assert plain.plan is None and len(log) == 10
    log.clear()
    cut = choose([Offer(Tier.GRASPS, lambda: [Grasp(n) for n in names])],
                 plan_grasp=plan_grasp, is_plan=is_plan, max_grasps=10, reach=reach)
    assert cut.plan == ("plan", "g12") and cut.rank == 12
    assert [r[1] for r in cut.refusals] == names[:12] and cut.unreached == 12
    assert log == [(Tier.GRASPS, 12, "g12")]  # only the reachable one was planned


def test_the_reach_check_still_stops_after_max_grasps_planned():
    names = [f"g{i}" for i in range(30)]
    log = []
    plan_grasp, _ = planner(set(), log)
    choice = choose([Offer(Tier.GRASPS, lambda: [Grasp(n) for n in names])],
                    plan_grasp=plan_grasp, is_plan=is_plan, max_grasps=10,
                    reach=lambda tier, rank, grasp: None if rank % 2 else ("unreached", rank))
    assert [entry[1] for entry in log] == list(range(1, 20, 2))  # ten planned, odd ranks
    assert choice.unreached == 10


def _turned(deg: float, p=(0.0, 0.0, 0.0)) -> np.ndarray:
    """A pose turned by ``deg`` about z, at ``p``."""
    a = np.radians(deg)
    X = np.eye(4)
    X[:2, :2] = [[np.cos(a), -np.sin(a)], [np.sin(a), np.cos(a)]]
    X[:3, 3] = p
    return X


def test_a_retry_with_nothing_left_goes_back_over_the_skipped_grasps_but_not_the_failed_pose():
    """gbh+ on a key ring lying flat: its scoop came away empty, and every scoop of the ring's one
    structure was skipped on the retry. Rather than ending untried, a second pass skips only the
    failed pose (and its neighbours) and plans a scoop from another side; the regrasp tier is
    not offered again."""
    log, seen = [], []
    plan_grasp, plan_regrasp = planner({"s0", "s1", "s2"}, log)
    scoops = [Grasp("s0", _turned(0.0), "scoop"), Grasp("s1", _turned(10.0, (0.005, 0, 0)),
                                                         "scoop"),
              Grasp("s2", _turned(90.0, (0.01, 0, 0)), "scoop")]
    offers = [Offer(Tier.GRASPS, lambda: []), Offer(Tier.SCOOP, lambda: scoops),
              Offer(Tier.REGRASP, evaluated(["p0"], seen, Tier.REGRASP), poses=lambda: [])]
    failed = [type("A", (), {"kind": "scoop", "p_WG": np.zeros(3), "R_WG": np.eye(3)})()]
    choice = choose(offers, plan_grasp=plan_grasp, plan_regrasp=plan_regrasp, is_plan=is_plan,
                    max_grasps=10, skip=lambda grasp: True,
                    skip_again=lambda grasp: at_failed_pose(failed, grasp, 0.02, 20.0))
    assert choice.plan == ("plan", "s2") and choice.tier is Tier.SCOOP and choice.second_pass
    assert choice.skipped == 3 and choice.n_offered == 3  # the first pass's, counted once
    assert [name for *_, name in log] == ["s2"]  # s0 (the failed pose), s1 (10 deg) skipped
    assert seen == [Tier.REGRASP]  # the regrasp was offered once, in the first pass


def test_no_second_pass_when_the_first_planned_or_skipped_nothing():
    plan_grasp, _ = planner({"a1"}, [])
    offers = [Offer(Tier.GRASPS, lambda: [Grasp("a0"), Grasp("a1")])]
    planned = choose(offers, plan_grasp=plan_grasp, is_plan=is_plan, max_grasps=10,
                     skip=lambda grasp: grasp.name == "a0", skip_again=lambda grasp: False)
    assert planned.plan == ("plan", "a1") and not planned.second_pass
    log = []
    plan_grasp, _ = planner(set(), log)
    none = choose(offers, plan_grasp=plan_grasp, is_plan=is_plan, max_grasps=10,
                  skip_again=lambda grasp: False)
    assert none.plan is None and not none.second_pass and len(log) == 2


@pytest.mark.parametrize(("p", "deg", "kind", "near"), [
    ((0.0, 0.0, 0.0), 0.0, "scoop", True),
    ((0.019, 0.0, 0.0), 19.0, "scoop", True),
    ((0.021, 0.0, 0.0), 0.0, "scoop", False),  # farther than the radius
    ((0.0, 0.0, 0.0), 21.0, "scoop", False),  # turned more than the angle
    ((0.0, 0.0, 0.0), 0.0, "antipodal", False),  # another kind
])
def test_at_failed_pose_is_position_and_turn_of_the_same_kind(p, deg, kind, near):
    failed = [type("A", (), {"kind": "scoop", "p_WG": np.zeros(3), "R_WG": np.eye(3)})()]
    assert at_failed_pose(failed, Grasp("g", _turned(deg, p), kind), 0.02, 20.0) is near
