"""How a chosen grasp is planned and executed (the scenario's ``pick:``): :class:`PickConfig`.

On the ground floor, beside :mod:`gbh_drake.core.params`, and free of Drake: ``gbh grasps``
reads it for its waypoints (the lift height) without loading the scenario's schema, which
:mod:`gbh_drake.scenario.schema` re-exports it from. Lengths in metres, forces in newtons,
times in seconds; W is the world (z up, the table top the plane z = 0).
"""

from dataclasses import dataclass

from gbh_drake.core.ranges import Int, Items, NonNeg, Pos, Range, Relation, ranged


@dataclass
class PickConfig:
    """How a chosen grasp is planned and executed: approach, insert, close, lift until clear,
    carry to ``place_position``, cage test, lower, release, retreat."""

    approach_distance: float = ranged(0.10, Pos(0.5, "m"))
    """Pre-grasp offset (m) back along the approach direction (-z_G)."""
    max_approach_distance: float = ranged(0.25, Pos(0.5, "m"),
                                          relations=(
        Relation(">=", "approach_distance", "the pre-grasp pose backs off from approach_distance "
                                            "up to this"),))
    """The pre-grasp pose backs off in 5 cm steps up to this distance (m) until the gripper is
    clear of the scanned object's convex hull."""
    precise_insert: bool = True
    """The grasp, closed and descent poses solved to 0.1 mm and 0.001 rad (the IK's usual 1 mm
    and 0.01 rad only where that fails) and the insert through waypoints every 2 cm on the
    approach line (docs/robustness.md). False: the usual tolerance and one joint move from the
    pre-grasp pose, as before 2026-12-04 (the executed hand 1-3 mm off the plan)."""
    lift_clearance: float = ranged(0.05, NonNeg(0.5, "m"), relations=(
        Relation("<", "max_lift", "the object's lowest point rises no more than the gripper: "
                                  "the clearance could never be reached"),))
    """After the lift, the object's lowest point (estimated from the scan, hanging from the
    grasp) is at least this far (m) above the table."""
    min_lift: float = ranged(0.10, Pos(1.0, "m"), relations=(
        Relation("<=", "max_lift", "the gripper rises at least min_lift, at most max_lift"),))
    """The gripper rises at least this much (m)."""
    slide_lift: bool = False
    """Beyond the paper, opt-in: the lift allows for the hooked material sliding through the
    closed loop along material thin enough to pass it (a wire hanger's side, a long handle's
    bar) to where the object hangs deepest (:func:`~gbh_drake.core.hanging_pose.rest_on_loop`);
    false (the default until both experiments are re-run with it, docs/robustness.md): it hangs
    from where the material first meets the loop."""
    max_lift: float = ranged(0.40, Pos(1.0, "m"))
    """The gripper rises at most this much (m); lower when the arm cannot reach higher."""
    place_position: list[float] = ranged(lambda: [0.40, 0.30], Items(2, what="coordinates (x, y in m)"))
    """Where (x, y in W, m) the object is carried, lowered and released."""
    place_depth: float = ranged(0.03, NonNeg(0.2, "m"))
    """The gripper is lowered until the hand's load drops (the object stands on the table: a
    hook that still carries the object would drag it along as it opens), at most until the
    object's estimated lowest point is this far (m) below the table top."""
    unloaded_fraction: float = ranged(0.4, Range(0.0, 1.0, lo_open=True, hi_open=True))
    """The object counts as set down when the hand's vertical load falls below this fraction of
    what it was while carried (as Franka senses its external force)."""
    unload_depth: float = ranged(0.006, NonNeg(0.05, "m"))
    """Once set down, the gripper goes on down this far (m) so that the hook hangs free in the
    hole before the fingers open (a bar pressed against the material would drag it along)."""
    unloaded_band: float = ranged(0.15, Range(0.0, 1.0, lo_open=True, hi_open=True))
    """After the cage test, the hand's vertical load counts as near zero (the object's weight
    off the hand) within this fraction of the load it carried while held still over the place
    (or within twice that load's noise then, or 0.2 N, whichever is more). LOWER counts the
    object as set down only once the load has stayed in that band for ``unloaded_dwell``
    (a load that merely fell, the hook still bearing part of it, or one pressing the object
    down, does not count); RELEASE and RETREAT stop when it rises above the band (the bar is
    lifting the object again)."""
    unloaded_dwell: float = ranged(0.05, NonNeg(1.0, "s"))
    """How long (s) the load must stay in the near-zero band before the object counts as set
    down, or above it before the bar counts as lifting the object again (a swing of the hanging
    object, a bounce on the table, passes quicker; the machine looks every 10 ms). A load below
    the band for 20 ms (the hand pressing the object down) never counts as set down (LOWER goes
    on down ``unload_depth`` at most), and stops a hand going back down to withdraw."""
    relift_tries: int = ranged(2, Int(0, 5, "each try goes down, opens and withdraws anew"))
    """How often RELEASE and RETREAT, when the bar lifts the object again (the load rises above
    the near-zero band), stop, go back down ``relift_drop``, open, and withdraw the bar out of
    the hole along the way it went in before going up. Once more (0: the first time), the hand
    goes back down ``relift_drop``, opens and stops there: the object is left standing in the
    open hand, never carried off."""
    relift_drop: float = ranged(0.01, NonNeg(0.05, "m"))
    """How far (m) the hand goes back down (in W) when the bar lifted the object again, for
    each try (the n-th try goes n times as far), so that the object stands again."""
    withdraw_shift: float = ranged(0.025, NonNeg(0.08, "m"))
    """How far (m) a parallel hook grasp withdraws its bar out of the hole along -y_G (the
    bar's axis, the way it went in) after the bar lifted the object again, before it goes up.
    In all, from where the fingers opened (the release's ``slide`` counts toward it). The
    default is about one finger's opening travel (2.3 cm for the paper's gripper): the bar's
    tip, which opening moved back by that travel, then lies about 5 cm back from where it
    closed the loop (its 3 cm are out of the hole), and the straight rod stands about where
    it stood closed (it does not push the material in the loop)."""
    cage_test_force: float = ranged(2.0, NonNeg(1000.0, "N"))
    """Grasp force (N) during the cage test after the carry: with the squeeze relaxed to this
    force, a caged object keeps hanging on the closed loop and a pinched one slides out."""
    cage_test_time: float = ranged(1.0, NonNeg(30.0, "s"))
    """Duration (s) of the cage test."""
    hold_time: float = ranged(0.5, NonNeg(30.0, "s"))
    """Time (s) the object is held still at the place position, full grasp force, before the
    cage test."""
    release_depth: float = ranged(0.02, NonNeg(0.05, "m"))
    """After opening, a parallel hook grasp goes this far (m) on along +z_G (less where the hand
    would come closer to the table than the grasp clearance), so that the bar leaves the
    material it was under, ..."""
    release_shift: float = ranged(0.015, NonNeg(0.05, "m"))
    """... then slides this far (m) along -y_G (toward the L rod's side), so that the bar comes
    out of the hole tip first before the gripper backs off. (A vertical grasp opens about its
    straight rod instead, the reverse of its closing: the bar leaves from under the material.)"""
    retreat_distance: float = ranged(0.10, NonNeg(0.5, "m"))
    """After releasing, the gripper backs off this far (m) along -z_G."""
    plan_paths: bool = True
    """Plan the transfer by RRT-Connect and collision-check every segment (False: IK only,
    straight joint-space moves)."""
    planner_iterations: int = ranged(3000, Int(1, 100_000))
    """RRT-Connect iterations before a transfer is given up."""
    max_grasps: int = ranged(10, Int(1, 100))
    """At most this many ranked grasps are tried, in order, before 'no reachable grasp' (with
    ``reach_check``, of those the arm reaches)."""
    reach_check: bool = True
    """Beyond the paper: before a grasp is planned, the IK of its grasp pose from the measured
    arm (the planner's first step) decides whether the arm reaches it; one it does not is
    refused without counting toward ``max_grasps``, so the best ``max_grasps`` *reachable* of
    the ranked grasps are planned (GbH ranks ``gbh.top_k``: 40, preset ``paper`` 10). With no
    more grasps offered than ``max_grasps`` (the defaults: 10 and 10) it refuses exactly what
    planning would (the same IK call, seeded by the pose), so it changes no verdict; it does
    when a tier offers more. False: the first ``max_grasps``, reachable or not."""
    set_down: bool | None = None
    """After the cage test, lower the object onto the table at ``place_position``, open and
    retreat (omitted or true); false: the trial ends once the cage test is over, the object
    still in the hand. The verdict is final then (success at the end of the hold, cage or pinch
    at the end of the cage test), so false changes no verdict, only ``released_on_table``, and
    saves about a quarter of an experiment's simulated time (README, Figures)."""
    max_retries: int | None = ranged(None, Int(0, 3, "each retry is a re-scan and a new plan",
                                               optional=True))
    """After a lift that came away empty (the hand's load did not grow), the hand opens, goes
    home, the object is scanned again and the pick planned anew, the grasps near the failed one
    skipped: at most this many times (beyond the paper); once they are used up, a further empty
    lift goes on to the method's tiers after the failed grasp's (a fallback pinch after two
    empty hooks), until none is left. Omitted: the method's own (``gbh_plus`` 1; the paper's
    methods make one attempt, 0: an empty lift ends the trial)."""
