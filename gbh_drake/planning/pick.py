"""Plans one pick: approach, insert, close, lift until clear, carry, lower, release, retreat.

:func:`plan_pick` turns a grasp (the open gripper's pose X_WG) into arm configurations for each
waypoint, solved by IK on the planning model (no free body), checks the segments for collisions
and plans the transfer from the robot's measured configuration to the approach pose by
RRT-Connect around the scanned object's convex hull. It returns a :class:`PickPlan`, or a
:class:`Refusal` that says why this grasp cannot be executed (IK infeasible at which waypoint,
which segment collides, the planner gave up).

Closing: parallel grasps close symmetrically about G (p_M, where the bar's tip meets the
straight rod, stays at the hole's centre); vertical grasps close about the straight rod (the arm
moves G along +y_G by each finger's travel, so the rod placed in the hole is not pushed into the
material). The lift comes from the scan: the object, hanging from the hook point with its CoM
below it, must clear the table by ``lift_clearance``.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from pydrake.math import RigidTransform, RotationMatrix

from gbh_drake.core.gripper import HOOK_GRIPPER
from gbh_drake.core.hanging_pose import hanging_lowest_height, lift_for_clearance
from gbh_drake.core.results import PARALLEL, VERTICAL, GraspKind
from gbh_drake.planning.model import HandPose, PlanningModel
from gbh_drake.planning.rrt import plan_rrt_connect
from gbh_drake.scenario.schema import PickConfig

#: Steps (m) by which the approach pose backs off until it is clear of the object's hull.
APPROACH_STEP = 0.05
#: Turns (rad) of the hand about the vertical tried for the carry, in order.
CARRY_YAWS = np.radians([0.0, 30.0, -30.0, 60.0, -60.0, 90.0, -90.0, 180.0])


@dataclass
class Refusal:
    """Why the grasp of rank ``rank`` was not executed: ``reason`` is one of ``ik``,
    ``collision``, ``planner``, ``approach``; ``where`` names the waypoint or segment."""

    rank: int
    kind: str
    reason: str
    where: str = ""

    def text(self) -> str:
        what = {"ik": "no IK solution at", "collision": "collision in",
                "planner": "RRT-Connect gave up on", "approach": "no clear approach for"}
        return f"grasp #{self.rank + 1} ({self.kind}): {what[self.reason]} {self.where}".strip()

    @property
    def key(self) -> str:
        """A short counting key, e.g. ``ik:lift``."""
        return f"{self.reason}:{self.where}" if self.where else self.reason


@dataclass
class PickPlan:
    """Arm configurations (rad, 7 each) of one planned pick and what they were computed from."""

    rank: int
    kind: str
    bar: float
    """Bar angle (rad) for the whole pick (0: deployed hook; -pi/2: folded, two straight rods)."""
    transfer: list[np.ndarray]
    """From the start configuration to ``approach`` (RRT-Connect waypoints, ends included)."""
    q: dict[str, np.ndarray] = field(default_factory=dict)
    """``approach``, ``grasp``, ``closed``, ``lift``, ``carry``, ``place``, then the release's
    ``opened``, ``down``, ``slide`` and ``retreat`` (:func:`release_path`)."""
    lift: float = 0.0
    """How far (m) the gripper rises after closing."""
    hook_W: np.ndarray = field(default_factory=lambda: np.zeros(3))
    """The point (W, m) the object hangs from when closed, before the lift."""
    place_W: np.ndarray = field(default_factory=lambda: np.zeros(3))
    """Where (W, m) the hook point is when the object is released."""
    keep_straight_rod: bool = False


@dataclass
class PickSetup:
    """What planning a pick needs besides the grasp: the planning models (``near``: table and
    robot, padding = the grasp's ground clearance, for the segments near the grasp; ``far``:
    also the scanned object's hull, for the transfer), the scan's points and their centroid
    (W, m), the pick parameters and the planner's seed."""

    near: PlanningModel
    far: PlanningModel | None
    points_W: np.ndarray
    com_W: np.ndarray
    config: PickConfig
    seed: int = 0


def plan_pick(setup: PickSetup, X_WG: np.ndarray, kind: str, rank: int, q_start: np.ndarray,
              bar: float = 0.0) -> PickPlan | Refusal:
    """The plan that picks with the open gripper at ``X_WG`` (4, 4) starting from the arm at
    ``q_start`` (7,), or the reason it cannot (see the module docstring). ``bar`` (rad): the
    bar's angle during the pick. Without ``setup.far`` the transfer is a straight move."""
    cfg = setup.config
    g = HOOK_GRIPPER
    X_WG = RigidTransform(np.asarray(X_WG))
    R = X_WG.rotation()
    approach_W, closing_W = R.col(2), R.col(1)  # +z_G: palm -> tips; +y_G: L rod -> straight rod
    keep_straight_rod = kind == VERTICAL
    hook = GraspKind(kind).hooks
    q_closed = g.q_closed if hook else 0.5 * g.rod_width
    open_hand, closed_hand = HandPose(g.q_open, bar), HandPose(q_closed, bar)
    shift = (g.q_open - g.q_closed) if keep_straight_rod else 0.0
    X_closed = RigidTransform(R, X_WG.translation() + shift * closing_W)

    def refuse(reason: str, where: str = "") -> Refusal:
        return Refusal(rank, kind, reason, where)

    def ik(X: RigidTransform, seed, hand: HandPose, restarts: int = 0):
        # Waypoints after the grasp follow from the previous one (no restarts: a restart could
        # land in another arm configuration and swing the arm while it holds the object).
        return setup.near.ik(X, seed, hand, restarts=restarts)

    q: dict[str, np.ndarray] = {}
    q["grasp"] = ik(X_WG, q_start, open_hand, restarts=3)
    if q["grasp"] is None:
        return refuse("ik", "grasp")
    q["closed"] = ik(X_closed, q["grasp"], closed_hand)
    if q["closed"] is None:
        return refuse("ik", "closed")

    # Lift until the hanging object clears the table (from the scan), as far as the arm reaches.
    # The object hangs on the bar's middle (hooks) or is held between the rods' pads.
    hook_W = X_closed.translation() + g.finger_length * approach_W
    need = lift_for_clearance(setup.points_W, setup.com_W, hook_W, cfg.lift_clearance,
                              swings=hook)
    lift = float(np.clip(need, cfg.min_lift, cfg.max_lift))
    q["lift"] = None
    for dz in np.linspace(lift, max(cfg.min_lift, 0.5 * lift), 4):
        q["lift"] = ik(_shifted(X_closed, [0.0, 0.0, dz]), q["closed"], closed_hand)
        if q["lift"] is not None:
            lift = float(dz)
            break
    if q["lift"] is None:
        return refuse("ik", "lift")

    # Carry: the hanging object's CoM (or, held rigidly, its hook offset) over the place. Where
    # the arm cannot reach that with the grasp's orientation, the hand also turns about the
    # vertical through the hook point (the object hangs the same way).
    com_offset = np.zeros(2) if hook else (hook_W - setup.com_W)[:2]
    target_xy = np.asarray(cfg.place_position[:2], dtype=float) + com_offset
    q["carry"], X_carry = None, None
    for yaw in CARRY_YAWS:
        R_turn = RotationMatrix.MakeZRotation(yaw)
        X_carry = RigidTransform(R_turn.multiply(X_closed.rotation()),
                                 [*target_xy, hook_W[2] + lift]) @ \
            RigidTransform(X_closed.inverse().multiply(hook_W)).inverse()
        q["carry"] = ik(X_carry, q["lift"], closed_hand)
        if q["carry"] is not None:
            break
    if q["carry"] is None:
        return refuse("ik", "carry")
    # Lower: at most until the object's estimated lowest point is place_depth under the table
    # (the machine stops once the hand's load drops), less where the hand would meet the table.
    low = hanging_lowest_height(setup.points_W, setup.com_W, hook_W, swings=hook) + lift
    q["place"] = None
    for down in np.linspace(low + cfg.place_depth, max(0.0, low - cfg.place_depth), 4):
        q_place = ik(_shifted(X_carry, [0.0, 0.0, -max(down, 0.0)]), q["carry"], closed_hand)
        if q_place is not None and (not cfg.plan_paths or
                                    setup.near.edge_free(q["carry"], q_place, closed_hand)):
            q["place"] = q_place
            break
    if q["place"] is None:
        return refuse("ik", "place")
    q.update(release_path(setup.near, q["place"], kind, cfg, bar))

    if cfg.plan_paths:
        segments = (("descend", q["grasp"], q["closed"], open_hand),
                    ("close", q["closed"], q["closed"], closed_hand),
                    ("lift", q["closed"], q["lift"], closed_hand),
                    ("carry", q["lift"], q["carry"], closed_hand))
        for name, a, b, hand in segments:
            if not setup.near.edge_free(a, b, hand):
                return refuse("collision", name)

    # The approach pose, backed off until clear of the object's hull, and the transfer to it.
    distances = np.arange(cfg.approach_distance, cfg.max_approach_distance + 1e-9, APPROACH_STEP)
    transfer, blocked = None, "approach"
    for distance in distances if setup.far is not None else distances[:1]:
        q_approach = ik(_shifted(X_WG, -distance * approach_W), q["grasp"], open_hand,
                        restarts=1)
        if q_approach is None:
            blocked = "approach"
            continue
        if setup.far is None:
            transfer = [np.asarray(q_start, dtype=float), q_approach]
            break
        if not setup.near.edge_free(q_approach, q["grasp"], open_hand):
            continue
        if not setup.far.free(q_approach, open_hand):
            continue
        transfer = plan_rrt_connect(setup.far, q_start, q_approach, open_hand, seed=setup.seed,
                                    max_iterations=cfg.planner_iterations)
        if transfer is not None:
            break
        blocked = "planner"
    if transfer is None:
        return refuse(blocked, "transfer" if blocked == "planner" else "grasp")
    q["approach"] = transfer[-1]
    place_W = setup.near.X_WG(q["place"], closed_hand).multiply(
        X_closed.inverse().multiply(hook_W))  # the hook point at the release
    return PickPlan(rank, kind, bar, transfer, q, lift, np.asarray(hook_W), np.asarray(place_W),
                    keep_straight_rod)


def release_path(model: PlanningModel, q_place: np.ndarray, kind: str, cfg: PickConfig,
                 bar: float = 0.0) -> dict[str, np.ndarray]:
    """How the gripper lets go at ``q_place`` (closed), the reverse of how it went in:

    * ``opened``: where the arm is once the fingers are open: a vertical grasp opens about its
      straight rod (the arm moves G along -y_G as each finger travels, so the rod stays in the
      hole and the bar leaves from under the material); the others open in place;
    * ``down``: a parallel grasp goes on along +z_G by up to ``release_depth`` (the bar leaves
      the material it was under; less if the hand would meet the table);
    * ``slide``: then along -y_G by ``release_shift`` (the bar comes out of the hole tip first);
    * ``retreat``: every grasp backs out along -z_G by ``retreat_distance``, or straight up where
      the arm cannot. A move without IK or with a collision is skipped (the arm stays)."""
    g = HOOK_GRIPPER
    closed_hand, open_hand = HandPose(g.q_closed, bar), HandPose(g.q_open, bar)
    X = model.X_WG(q_place, closed_hand)
    R = X.rotation()

    def step(q_from, X_from, moves, hand=open_hand):
        """The first of ``moves`` (W offsets) with an IK solution and a free edge."""
        for d_W in moves:
            X_to = _shifted(X_from, d_W)
            q = model.ik(X_to, q_from, hand)
            if q is not None and model.edge_free(q_from, q, hand):
                return q, X_to
        return q_from, X_from

    q = {"opened": q_place}
    if kind == VERTICAL:
        q["opened"], X = step(q_place, X, [-(g.q_open - g.q_closed) * R.col(1)])
    q["down"], q["slide"] = q["opened"], q["opened"]
    if kind == PARALLEL:
        q["down"], X = step(q["opened"], X, [f * cfg.release_depth * R.col(2)
                                             for f in (1.0, 0.5, 0.25)])
        q["slide"], X = step(q["down"], X, [-cfg.release_shift * R.col(1)])
    q["retreat"], _ = step(q["slide"], X, [-cfg.retreat_distance * R.col(2),
                                           [0.0, 0.0, cfg.retreat_distance]])
    return q


def _shifted(X: RigidTransform, d_W) -> RigidTransform:
    return RigidTransform(X.rotation(), X.translation() + np.asarray(d_W, dtype=float))
