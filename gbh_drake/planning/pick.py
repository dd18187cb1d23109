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
material). The lift comes from the scan: once lifted, the caged material sinks onto the loop's
lower side (the bar's upper face for a top-down hook, :func:`~gbh_drake.core.hanging_pose.rest_on_loop`)
and the object hangs from there with its CoM below it; its lowest point must clear the table
by ``lift_clearance``. The lift aims at the bound for any way the object turns, and goes no
lower than the prediction with the CoM below the contact; where the arm cannot reach that, it
lifts as high as it reaches, the carry rises on to the need at the place where the arm reaches
that there, and the plan says so (:attr:`PickPlan.notes`, :attr:`PickPlan.lift_short`).
A pinch is not a rigid hold: the object pivots about the pinch axis (the closing axis through
the contacts, :mod:`gbh_drake.core.pinch`), so its lift is planned the same way, with the CoM
below the axis (the prediction) and any turn about it (the bound).
Unknown space is not free space: the bound for any turn also keeps the unseen space connected
to the scan (``PickSetup.unseen_W``, :mod:`gbh_drake.core.unseen`) off the table, so that the
part of the object a single view did not see does not drag (:attr:`PickPlan.lift_unseen`).

The carry from the lift to the place keeps the hook point at the lift height: the straight
joint-space move is checked by forward kinematics, and where it dips the carry goes through
Cartesian waypoints at the lift height (IK, :func:`carry_path`); where that finds no IK at the
lift height on the way, the hand's other turns about the vertical at the place
(:data:`CARRY_YAWS`, each a carry configuration of its own) are tried for one that keeps it,
else the one that dips least; :attr:`PickPlan.carry_low` records how low the hook point goes.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field

import numpy as np
from pydrake.common.eigen_geometry import Quaternion
from pydrake.math import RigidTransform, RotationMatrix

from gbh_drake.core.gripper import HOOK_GRIPPER, HookGripperGeometry
from gbh_drake.core.hanging_pose import LoopRest, hanging_lowest_height, rest_on_loop
from gbh_drake.core.params import AntipodalParams
from gbh_drake.core.pick_config import PickConfig
from gbh_drake.core.pinch import PinchSwing, lowest_any_turn, pinch_swing
from gbh_drake.core.results import PARALLEL, GraspKind
from gbh_drake.core.sliding import MaterialGraph, material_graph
from gbh_drake.core.unseen import farthest_distance
from gbh_drake.planning.model import HandPose, PlanningModel
from gbh_drake.planning.rrt import plan_rrt_connect

#: Steps (m) by which the approach pose backs off until it is clear of the object's hull.
APPROACH_STEP = 0.05
#: Turns (rad) of the hand about the vertical tried for the carry, in order.
CARRY_YAWS = np.radians([0.0, 30.0, -30.0, 60.0, -60.0, 90.0, -90.0, 180.0])
#: m: where a pinch holds the object when the grasp does not say (its contacts' midpoint):
#: this far short of the rods' tips (the antipodal sampler's default ``contact_depth``).
PINCH_DEPTH = AntipodalParams().contact_depth
#: A lift short of the need is searched to this resolution (m) for the most the arm reaches.
LIFT_RESOLUTION = 0.01
#: The carry may let the hook point sink this far (m) below the lift height before it is planned
#: through Cartesian waypoints (about the IK's tolerance and a joint-space move's sag).
CARRY_TOLERANCE = 0.005
#: Spacing (m) of the carry's Cartesian waypoints, horizontally, where the joint move dips.
CARRY_STEP = 0.05
#: IK restarts for a carry waypoint (a restart may change the arm's branch: the segments to it
#: are height-checked and split like any other).
CARRY_IK_RESTARTS = 2
#: How much higher (m) a carry waypoint may go where the arm does not reach it at the lift height.
CARRY_RISES = (0.03, 0.06, 0.10)
#: Joint-space spacing (rad, max-norm) of the configurations whose hook height is checked.
CARRY_CHECK_STEP = 0.02
#: The voxel (in rod widths) the scan's points are thinned to for where hooked material slides:
#: half a rod, so a wire of a few millimetres stays one line of points.
SLIDE_VOXEL = 0.5
#: A slide longer than this (m) is said in the plan's notes.
SLIDE_NOTE = 0.01
#: The plan's note when the arm cannot lower the object at the place (no set-down planned).
NO_SET_DOWN = ("no set-down: the arm cannot lower the object at the place; the trial ends "
               "holding it after the cage test")
#: IK restarts for the grasp pose (from the measured arm; the reach check's too).
GRASP_IK_RESTARTS = 3
#: IK tolerances (m, rad) of the poses where the rods meet the object: the grasp, the closed
#: pose and the descent's waypoints (:func:`precise_ik`): a tenth of the usual ones (1 mm,
#: 0.01 rad), whose slack SNOPT spends to the bound (the solution sits at the tolerance box's
#: corner: 1.7 mm and 0.57 deg off, 1.2-3 mm at the rods' tips, against an 8 mm rod's 1.5 mm
#: clearance in an 11 mm slot).
TIGHT_IK = (1e-4, 1e-3)
#: Spacing (m) of the descent's waypoints from the approach pose to the grasp along the approach
#: axis (:func:`descent_path`): one joint move over the 10 cm bows off the line by up to 4 mm;
#: the sag of a joint move grows with the square of its length, so over 2 cm it is ~0.2 mm.
INSERT_STEP = 0.02


@dataclass
class Refusal:
    """Why the grasp of rank ``rank`` was not executed: ``reason`` is one of ``ik``,
    ``collision``, ``planner``, ``approach``; ``where`` names the waypoint or segment."""

    rank: int
    kind: str
    reason: str
    where: str = ""
    detail: str = ""
    """More on why, e.g. how high the lift had to be."""

    def text(self) -> str:
        what = {"ik": "no IK solution at", "collision": "collision in",
                "planner": "RRT-Connect gave up on", "approach": "no clear approach for"}
        text = f"grasp #{self.rank + 1} ({self.kind}): {what[self.reason]} {self.where}".strip()
        return f"{text} ({self.detail})" if self.detail else text

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
    ``opened``, ``down``, ``slide`` and ``retreat`` (:func:`release_path`); without ``place``
    and the release's when the arm cannot lower the object at the place (:attr:`sets_down`)."""
    lift: float = 0.0
    """How far (m) the gripper rises after closing."""
    hook_W: np.ndarray = field(default_factory=lambda: np.zeros(3))
    """The point (W, m) the object hangs from when closed, before the lift."""
    place_W: np.ndarray = field(default_factory=lambda: np.zeros(3))
    """Where (W, m) the hook point is when the object is released (without a set-down: at the
    carry's end)."""
    keep_straight_rod: bool = False
    carry: list[np.ndarray] = field(default_factory=list)
    """The carry's waypoints (rad, 7 each), ``lift`` to ``carry``: the two ends, or Cartesian
    waypoints at the lift height where the straight joint move would dip (:func:`carry_path`)."""
    descent: list[np.ndarray] = field(default_factory=list)
    """The insert's waypoints (rad, 7 each), ``approach`` to ``grasp``, every
    :data:`INSERT_STEP` along the approach axis (:func:`descent_path`)."""
    carry_low: float = float("nan")
    """The lowest height (W z, m) of the hook point along the carry (checked by forward
    kinematics every :data:`CARRY_CHECK_STEP` rad); the lift height is ``hook_W[2] + lift``."""
    lift_needed: float = float("nan")
    """The lift (m) the hanging object needs by the prediction (CoM below its rest on the loop)."""
    lift_unseen: float = float("nan")
    """The lift (m) that keeps the unseen space next to the scan ``lift_clearance`` above the
    table however the object turns (:func:`unseen_lift`); nan without unseen space."""
    drop: float = 0.0
    """How far (m) the object is predicted to sink onto the loop once lifted."""
    slide: float = 0.0
    """How far (m) the hooked material may slide through the closed loop along material thin
    enough to pass it (``pick.slide_lift``; :attr:`~gbh_drake.core.hanging_pose.LoopRest.slide`):
    the lift bounds the object hanging from any point it reaches."""
    support: str = ""
    """The loop's side the object is predicted to rest on (``bar``, ...; "": the hook point)."""
    notes: list[str] = field(default_factory=list)
    """What the plan could not do as it should: a lift short of the need, a carry that dips."""
    opening: float = float("nan")
    """m: one finger's position for the approach and the insert (the gripper's ``q_open``, or
    a pinch's narrower ``q_pregrasp``); nan in a plan made without it: ``q_open``."""

    @property
    def sets_down(self) -> bool:
        """Whether the plan can set the object down after the cage test (the arm lowers it at
        the place); without, the trial ends holding it, as with ``pick.set_down`` false."""
        return "place" in self.q

    @property
    def lift_short(self) -> float:
        """How far (m) the lift falls short of :attr:`lift_needed` (0 when it does not)."""
        return float(max(0.0, self.lift_needed - self.lift)) if np.isfinite(self.lift_needed) \
            else 0.0

    @property
    def carry_dip(self) -> float:
        """How far (m) the hook point sinks below the lift height along the carry."""
        return float(self.hook_W[2] + self.lift - self.carry_low)


@dataclass
class PickSetup:
    """What planning a pick needs besides the grasp: the planning models (``near``: table and
    robot, padding = the grasp's ground clearance, for the segments near the grasp; ``far``:
    also the scanned object's hull, for the transfer; ``table_level``: no table and no padding,
    for the segments of a scoop, whose rods go down to the table), the scan's points and their
    centroid (W, m), the pick parameters, the planner's seed and the hook gripper's geometry
    (the variant the station runs)."""

    near: PlanningModel
    far: PlanningModel | None
    points_W: np.ndarray
    com_W: np.ndarray
    config: PickConfig
    seed: int = 0
    table_level: PlanningModel | None = None
    unseen_W: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    """(m, 3) centres of the grid cells no camera saw free that connect to the scan
    (:func:`gbh_drake.core.unseen.unseen_cells`): where unseen material may be."""
    gripper: HookGripperGeometry = HOOK_GRIPPER
    _material: MaterialGraph | None = field(default=None, repr=False)

    def material(self) -> MaterialGraph:
        """The scan's points as a material graph (:func:`~gbh_drake.core.sliding.material_graph`
        at :data:`SLIDE_VOXEL`), made once: where hooked material can slide to."""
        if self._material is None:
            self._material = material_graph(self.points_W, SLIDE_VOXEL * self.gripper.rod_width)
        return self._material


def reach_refusal(setup: PickSetup, X_WG: np.ndarray, kind: str, rank: int,
                  q_start: np.ndarray, bar: float = 0.0) -> Refusal | None:
    """The cheap reach check of the plan choice (:func:`~gbh_drake.planning.choice.choose`'s
    ``reach``): None when the arm reaches the open gripper at ``X_WG`` from ``q_start`` (the
    IK :func:`plan_pick` solves first, the same call), else the refusal it would give."""
    hand = HandPose(setup.gripper.q_open, bar)
    if setup.near.ik(RigidTransform(np.asarray(X_WG)), q_start, hand,
                     restarts=GRASP_IK_RESTARTS) is None:
        return Refusal(rank, kind, "ik", "grasp")
    return None


def plan_pick(setup: PickSetup, X_WG: np.ndarray, kind: str, rank: int, q_start: np.ndarray,
              bar: float = 0.0, min_lift: float = 0.0, *, tight: bool = False,
              pinch_W: np.ndarray | None = None, opening: float | None = None
              ) -> PickPlan | Refusal:
    """The plan that picks with the open gripper at ``X_WG`` (4, 4) starting from the arm at
    ``q_start`` (7,), or the reason it cannot (see the module docstring). ``bar`` (rad): the
    bar's angle during the pick; ``min_lift`` (m): a lift this grasp needs at least, besides
    the config's ``min_lift``; ``pinch_W`` (3,): for a pinch, a point on its axis where the
    object is (the contacts' midpoint; default: between the rods' tips, :data:`PINCH_DEPTH`
    short of them); ``opening`` (m): each finger's position for the approach and the insert
    (default the gripper's ``q_open``; a pinch's ``q_pregrasp``). Without ``setup.far`` the
    transfer is a straight move.

    The grasp and closed poses are solved to :data:`TIGHT_IK` (:func:`precise_ik`), where
    that fails to the IK's usual tolerance (1 mm, 0.01 rad); when the close near the table
    then collides, they are solved again ``tight`` (no loose fallback) before the grasp is
    refused: the IK's slack, up to 2-3 mm at the fingertips, is as large as the grasp's table
    clearance (3 mm) less the planner's padding."""
    cfg = setup.config
    if min_lift > cfg.min_lift:
        cfg = dataclasses.replace(cfg, min_lift=min(min_lift, cfg.max_lift))
    g = setup.gripper
    X_WG = RigidTransform(np.asarray(X_WG))
    R = X_WG.rotation()
    approach_W, closing_W = R.col(2), R.col(1)  # +z_G: palm -> tips; +y_G: L rod -> straight rod
    keep_straight_rod = GraspKind(kind).keeps_straight_rod
    hook = GraspKind(kind).hooks
    # A scoop's rods go down to the table: its segments near the grasp are checked without the
    # grasp clearance's padding (the press below the grasp pose is contact by design).
    check = setup.table_level if kind == GraspKind.SCOOP and setup.table_level is not None \
        else setup.near
    q_closed = g.q_closed if hook else 0.5 * g.rod_width
    opening = g.q_open if opening is None else float(np.clip(opening, q_closed, g.q_open))
    open_hand, closed_hand = HandPose(opening, bar), HandPose(q_closed, bar)
    shift = (opening - g.q_closed) if keep_straight_rod else 0.0
    X_closed = RigidTransform(R, X_WG.translation() + shift * closing_W)

    def refuse(reason: str, where: str = "", detail: str = "") -> Refusal:
        return Refusal(rank, kind, reason, where, detail)

    def ik(X: RigidTransform, seed, hand: HandPose, restarts: int = 0, precise: bool = False):
        # Waypoints after the grasp follow from the previous one (no restarts: a restart could
        # land in another arm configuration and swing the arm while it holds the object).
        tolerances = dict(zip(("position_tolerance", "angle_tolerance"), TIGHT_IK,
                              strict=True)) if precise else {}
        return setup.near.ik(X, seed, hand, restarts=restarts, **tolerances)

    def at_grasp(X: RigidTransform, seed, hand: HandPose, restarts: int = 0):
        # The grasp and closed poses: to TIGHT_IK (loose where that fails, unless ``tight``),
        # or with ``precise_insert`` off as the other waypoints (tight only when ``tight``).
        if cfg.precise_insert:
            return precise_ik(setup.near, X, seed, hand, restarts, loose=not tight)
        return ik(X, seed, hand, restarts=restarts, precise=tight)

    q: dict[str, np.ndarray] = {}
    q["grasp"] = at_grasp(X_WG, q_start, open_hand, GRASP_IK_RESTARTS)
    if q["grasp"] is None:
        return refuse("ik", "grasp")
    q["closed"] = at_grasp(X_closed, q["grasp"], closed_hand)
    if q["closed"] is None:
        return refuse("ik", "closed")

    # Lift until the hanging object clears the table (from the scan), as far as the arm reaches.
    # Hooks: the caged material sinks onto the loop and the object hangs from there; pinches
    # hold it between the rods' pads as it is.
    hook_W = X_closed.translation() + g.finger_length * approach_W
    notes: list[str] = []
    X_loop = X_WG
    if kind == GraspKind.SCOOP:
        # The scooped material rides up the wedge onto the bar: relative to the loop it ends
        # one rod width higher than the scan saw it, so it is caged by the loop one rod width
        # lower (the predicted contact is then that much low: the lift errs high).
        X_loop = shifted(X_WG, g.rod_width * approach_W)
    material = setup.material() if hook and cfg.slide_lift and len(setup.points_W) >= 4 \
        else None
    rest = rest_on_loop(setup.points_W, setup.com_W, X_loop.GetAsMatrix4(), kind,
                        hook_W=hook_W, material=material, gripper=g) if hook else None
    swing = None
    if rest is not None and rest.slide > SLIDE_NOTE:
        notes.append(f"the hooked material may slide {rest.slide:.3f} m through the loop "
                     f"({rest.slide_points} scan points thin enough to pass it): the lift "
                     f"bounds the object hanging from the deepest of them")
    if rest is not None:
        need_any = cfg.lift_clearance - rest.lowest_any_turn
        need = cfg.lift_clearance - rest.lowest
    else:
        # A pinch: the object pivots about the pinch axis (core/pinch.py), as a hooked one
        # about its hook point: its CoM below the axis (the need), any turn (the bound).
        if pinch_W is None:
            pinch_W = X_closed.multiply([0.0, 0.0, g.finger_length - PINCH_DEPTH])
        swing = pinch_swing(setup.points_W, setup.com_W, pinch_W, closing_W)
        need_any = cfg.lift_clearance - swing.lowest_any_turn
        need = cfg.lift_clearance - swing.lowest
    need_unseen = unseen_lift(setup.unseen_W, rest, cfg.lift_clearance, swing)
    if need_unseen > need_any:
        notes.append(f"the lift allows for unseen space: {need_unseen:.3f} m keeps it clear, "
                     f"{need_any:.3f} m the scan")
    top = float(np.clip(max(need_any, need_unseen), cfg.min_lift, cfg.max_lift))
    floor = float(np.clip(need, cfg.min_lift, top))
    # From the bound for any turn down to the prediction; below it only with a note.
    tries = list(np.linspace(top, floor, 4))
    tries += [dz for dz in np.linspace(floor, max(cfg.min_lift, 0.5 * top), 3)[1:] if dz < floor]
    q["lift"], lift, failed = None, top, top
    for dz in tries:
        q["lift"] = ik(shifted(X_closed, [0.0, 0.0, dz]), q["closed"], closed_hand)
        if q["lift"] is not None:
            lift = float(dz)
            break
        failed = float(dz)
    if q["lift"] is not None and lift < floor:
        # Short of the need: as high as the arm reaches (bisection between the heights tried).
        while failed - lift > LIFT_RESOLUTION:
            dz = 0.5 * (lift + failed)
            q_up = ik(shifted(X_closed, [0.0, 0.0, dz]), q["closed"], closed_hand)
            if q_up is None:
                failed = dz
            else:
                q["lift"], lift = q_up, dz
    if q["lift"] is None:
        return refuse("ik", "lift", f"the hanging object needs a {need:.2f} m lift, the arm "
                      f"reaches none down to {tries[-1]:.2f} m")
    if need > lift + 1e-6:
        notes.append(f"lift {lift:.3f} m, short of the {need:.3f} m the hanging object needs "
                     f"({'the most lift allowed' if need > cfg.max_lift else 'the arm reaches no higher'})")

    # Carry: the hanging object's CoM (or, pinched, where it swings to) over the place. Where
    # the arm cannot reach that with the grasp's orientation, the hand also turns about the
    # vertical through the hook point (the object hangs the same way).
    com_offset = np.zeros(2) if hook else (hook_W - swing.com_W)[:2]
    target_xy = np.asarray(cfg.place_position[:2], dtype=float) + com_offset
    # A lift short of the need rises on to it at the place where the arm reaches that. Of the
    # hand's turns about the vertical, the first whose carry keeps the lift height; if none
    # does, the one whose carry dips least (the first where they tie).
    hook_G = X_closed.inverse().multiply(hook_W)
    min_height = hook_W[2] + lift - CARRY_TOLERANCE
    best: tuple | None = None  # (carry_low, q_carry, X_carry, path)
    rises = [need - lift, 0.0] if need > lift + LIFT_RESOLUTION else [0.0]
    for rise in rises:
        for yaw in CARRY_YAWS:
            R_turn = RotationMatrix.MakeZRotation(yaw)
            X_turned = RigidTransform(R_turn.multiply(X_closed.rotation()),
                                      [*target_xy, hook_W[2] + lift + rise]) @ \
                RigidTransform(hook_G).inverse()
            q_turned = ik(X_turned, q["lift"], closed_hand)
            if q_turned is None:
                continue
            path, low = carry_path(setup.near, q["lift"], q_turned, closed_hand, hook_G,
                                   min_height, check_edges=cfg.plan_paths)
            if best is None or low > best[0]:
                best = (low, q_turned, X_turned, path)
            if low >= min_height:
                break
        if best is not None:
            if rise > 0.0:
                notes.append(f"the carry rises {rise:.3f} m on to the need at the place")
            break
    if best is None:
        return refuse("ik", "carry")
    carry_low, q["carry"], X_carry, carry = best
    if carry_low < min_height:
        notes.append(f"the carry dips {hook_W[2] + lift - carry_low:.3f} m below the lift height "
                     "(no IK at the lift height along the way)")
    # Lower: at most until the object's estimated lowest point is place_depth under the table
    # (the machine stops once the hand's load drops), less where the hand would meet the table.
    # (The higher of the estimates hanging at the hook point and sunk onto the loop: lowering
    # stops once the object stands, so going too deep costs nothing.)
    carry_height = X_carry.multiply(X_closed.inverse().multiply(hook_W))[2]
    low = (hanging_lowest_height(setup.points_W, setup.com_W, hook_W, swings=hook)
           if swing is None else swing.lowest) + carry_height - hook_W[2]
    q["place"] = None
    for down in np.linspace(low + cfg.place_depth, max(0.0, low - cfg.place_depth), 4):
        q_place = ik(shifted(X_carry, [0.0, 0.0, -max(down, 0.0)]), q["carry"], closed_hand)
        if q_place is not None and (not cfg.plan_paths or
                                    setup.near.edge_free(q["carry"], q_place, closed_hand)):
            q["place"] = q_place
            break
    if q["place"] is None:
        # The set-down comes after the verdict (the cage test ends it): a pick whose object
        # the arm cannot lower at the place is still a pick and carry. It ends holding it.
        del q["place"]
        notes.append(NO_SET_DOWN)
    else:
        q.update(release_path(setup.near, q["place"], kind, cfg, bar))

    if cfg.plan_paths:
        # "descend": from the grasp pose to the closed one as the hand closes (a vertical grasp's
        # arm moves along +y_G while its fingers close, so the straight rod stays where it is:
        # the fingers close with the arm, not open all the way).
        segments = (("descend", q["grasp"], q["closed"], open_hand, closed_hand),
                    ("close", q["closed"], q["closed"], closed_hand, closed_hand),
                    ("lift", q["closed"], q["lift"], closed_hand, closed_hand),
                    *(("carry", a, b, closed_hand, closed_hand)
                      for a, b in zip(carry[:-1], carry[1:], strict=True)))
        for name, a, b, hand, hand_b in segments:
            if not (check if name in ("descend", "close", "lift") else setup.near).edge_free(
                    a, b, hand, hand_b):
                if name in ("descend", "close") and not tight:
                    again = plan_pick(setup, X_WG.GetAsMatrix4(), kind, rank, q_start, bar,
                                      min_lift, tight=True, pinch_W=pinch_W,
                                      opening=opening)
                    if isinstance(again, PickPlan):
                        return again
                return refuse("collision", name)

    transfer = approach_transfer(setup, X_WG, q["grasp"], open_hand, q_start, check)
    if isinstance(transfer, str):
        return refuse(transfer, "transfer" if transfer == "planner" else "grasp")
    transfer, descent = transfer
    q["approach"] = transfer[-1]
    place_W = setup.near.X_WG(q.get("place", q["carry"]), closed_hand).multiply(
        X_closed.inverse().multiply(hook_W))  # the hook point at the release (or the carry's end)
    return PickPlan(rank, kind, bar, transfer, q, lift, np.asarray(hook_W), np.asarray(place_W),
                    keep_straight_rod, carry=carry, descent=descent, carry_low=carry_low,
                    lift_needed=need,
                    lift_unseen=need_unseen if len(setup.unseen_W) else float("nan"),
                    drop=rest.drop if rest else 0.0, support=rest.support if rest else "",
                    slide=rest.slide if rest else 0.0,
                    notes=notes, opening=opening)


def unseen_lift(unseen_W: np.ndarray, rest: LoopRest | None, clearance: float,
                swing: PinchSwing | None = None) -> float:
    """The lift (m) after which the unseen space ``unseen_W`` (m, 3) is ``clearance`` above the
    table (W z = 0), as the scan's points must be: a hooked object (``rest``: how it rests on
    the loop) hangs from its contact and may turn any way about it, so the farthest unseen cell
    from the contact bounds how low it reaches (and, where the hooked material may slide, the
    farthest from the worst hang point brought to the contact, ``rest.hang_W``); a pinched one
    (``swing``) turns about the pinch axis, each cell at its distance from the axis; held rigidly
    (neither), the lowest cell rises with the hand. -inf without unseen space."""
    u = np.asarray(unseen_W, dtype=float).reshape(-1, 3)
    if len(u) == 0:
        return float("-inf")
    if rest is None and swing is not None:
        return float(clearance - lowest_any_turn(u, swing.point_W, swing.axis_W))
    if rest is None:
        return float(clearance - u[:, 2].min())
    sunk = u - np.array([0.0, 0.0, rest.drop])  # the object sinks onto the loop first
    reach = farthest_distance(sunk, rest.contact_W)
    if rest.hang_W is not None:
        reach = max(reach, farthest_distance(u, rest.hang_W))
    return float(clearance - (float(rest.contact_W[2]) - reach))


def precise_ik(model: PlanningModel, X: RigidTransform, seed, hand: HandPose, restarts: int = 0,
               *, loose: bool = True) -> np.ndarray | None:
    """Arm joint positions (7,) that put G at ``X`` to :data:`TIGHT_IK`; where that fails and
    ``loose``, to the IK's usual tolerance; None when neither reaches it."""
    q = model.ik(X, seed, hand, restarts=restarts, position_tolerance=TIGHT_IK[0],
                 angle_tolerance=TIGHT_IK[1])
    if q is None and loose:
        q = model.ik(X, seed, hand, restarts=restarts)
    return q


def descent_path(model: PlanningModel, X_WG: RigidTransform, q_grasp: np.ndarray,
                 distance: float, hand: HandPose, precise: bool = True) -> list[np.ndarray] | None:
    """The insert's waypoints (rad, 7 each) from the pre-grasp pose ``distance`` (m) back along
    -z_G to the grasp at ``X_WG`` (arm at ``q_grasp``), every :data:`INSERT_STEP` on that line,
    each solved by :func:`precise_ik` from the one after it (no restarts: one arm branch, no
    swing between them); None where a waypoint has no IK. Not ``precise``
    (``pick.precise_insert`` false): the pre-grasp pose to the usual tolerance (one restart)
    and the grasp, one joint move."""
    approach_W = X_WG.rotation().col(2)
    if not precise:
        q = model.ik(shifted(X_WG, -distance * approach_W), q_grasp, hand, restarts=1)
        return None if q is None else [q, np.asarray(q_grasp, dtype=float)]
    steps = max(1, int(np.ceil(distance / INSERT_STEP - 1e-9)))
    path = [np.asarray(q_grasp, dtype=float)]
    for d in np.linspace(0.0, distance, steps + 1)[1:]:
        q = precise_ik(model, shifted(X_WG, -d * approach_W), path[-1], hand)
        if q is None:
            return None
        path.append(q)
    return path[::-1]


def approach_transfer(setup: PickSetup, X_WG: RigidTransform, q_grasp: np.ndarray,
                      open_hand: HandPose, q_start: np.ndarray, check: PlanningModel | None = None
                      ) -> tuple[list[np.ndarray], list[np.ndarray]] | str:
    """The transfer from ``q_start`` to the approach pose of the grasp at ``X_WG`` (arm at
    ``q_grasp`` there) and the descent from there to the grasp (:func:`descent_path`): the
    pre-grasp pose backed off along -z_G from ``approach_distance`` in :data:`APPROACH_STEP`
    steps until it is clear of the object's hull (``setup.far``) and its descent is free
    (``check``, default ``setup.near``), reached by RRT-Connect (a straight move without
    ``setup.far``). Returns the transfer's waypoints (``q_start`` first, the approach last)
    and the descent's (the approach first, ``q_grasp`` last), or why there are none:
    ``approach`` (no clear, reachable pre-grasp pose) or ``planner``."""
    cfg = setup.config
    check = check or setup.near
    distances = np.arange(cfg.approach_distance, cfg.max_approach_distance + 1e-9, APPROACH_STEP)
    blocked = "approach"
    for distance in distances if setup.far is not None else distances[:1]:
        descent = descent_path(setup.near, X_WG, q_grasp, float(distance), open_hand,
                               cfg.precise_insert)
        if descent is None:
            blocked = "approach"
            continue
        q_approach = descent[0]
        if setup.far is None:
            return [np.asarray(q_start, dtype=float), q_approach], descent
        if not all(check.edge_free(a, b, open_hand)
                   for a, b in zip(descent[:-1], descent[1:], strict=True)):
            continue
        if not setup.far.free(q_approach, open_hand):
            continue
        transfer = plan_rrt_connect(setup.far, q_start, q_approach, open_hand, seed=setup.seed,
                                    max_iterations=cfg.planner_iterations)
        if transfer is not None:
            return transfer, descent
        blocked = "planner"
    return blocked


def hook_heights(model: PlanningModel, q_a, q_b, hand: HandPose, hook_G,
                 step: float = CARRY_CHECK_STEP) -> np.ndarray:
    """Heights (W z, m) of the point ``hook_G`` (3,, in G) along the straight joint move from
    ``q_a`` to ``q_b`` (both ends included), every ``step`` rad (max-norm) at most."""
    q_a, q_b = np.asarray(q_a, dtype=float), np.asarray(q_b, dtype=float)
    n = max(2, int(np.ceil(np.abs(q_b - q_a).max() / step)) + 1)
    return np.array([model.X_WG(q_a + s * (q_b - q_a), hand).multiply(hook_G)[2]
                     for s in np.linspace(0.0, 1.0, n)])


def carry_path(model: PlanningModel, q_lift, q_carry, hand: HandPose, hook_G,
               min_height: float, *, check_edges: bool = True, depth: int = 2
               ) -> tuple[list[np.ndarray], float]:
    """Waypoints (rad, 7 each) from ``q_lift`` to ``q_carry`` along which the hook point
    ``hook_G`` (in G) stays at ``min_height`` (W z, m) or above, and the lowest height it
    reaches along them (forward kinematics, :func:`hook_heights`).

    The straight joint move when it stays high enough; otherwise Cartesian waypoints every
    :data:`CARRY_STEP` of the hook point's horizontal travel, at the height of the ends (the
    lower one, at least ``min_height``; higher where the arm reaches no lower), the hand
    turning from the one orientation to the other (slerp), each solved by IK from the one
    before; a segment between them that still dips is split again (``depth`` times at most).
    Where IK fails (or, with ``check_edges``, an edge collides), the straight move is kept: the
    caller sees how low it goes."""
    q_lift, q_carry = np.asarray(q_lift, dtype=float), np.asarray(q_carry, dtype=float)
    straight = [q_lift, q_carry]
    low = float(hook_heights(model, q_lift, q_carry, hand, hook_G).min())
    if low >= min_height:
        return straight, low
    X_a, X_b = model.X_WG(q_lift, hand), model.X_WG(q_carry, hand)
    path = _cartesian_carry(model, q_lift, q_carry, X_a, X_b, hand, hook_G, min_height, depth)
    if path is None or (check_edges and not all(
            model.edge_free(a, b, hand) for a, b in zip(path[:-1], path[1:], strict=True))):
        return straight, low
    return path, float(min(hook_heights(model, a, b, hand, hook_G).min()
                           for a, b in zip(path[:-1], path[1:], strict=True)))


def _cartesian_carry(model: PlanningModel, q_a, q_b, X_a: RigidTransform, X_b: RigidTransform,
                     hand: HandPose, hook_G, min_height: float, depth: int
                     ) -> list[np.ndarray] | None:
    """Waypoints from ``q_a`` (G at ``X_a``) to ``q_b`` (``X_b``) with the hook point moving
    straight between its two positions, kept at or above ``min_height`` (see :func:`carry_path`)."""
    h_a, h_b = X_a.multiply(hook_G), X_b.multiply(hook_G)
    height = max(min(h_a[2], h_b[2]), min_height)
    quat_a, quat_b = X_a.rotation().ToQuaternion(), X_b.rotation().ToQuaternion()
    n = max(2, int(np.ceil(np.linalg.norm((h_b - h_a)[:2]) / CARRY_STEP)))
    path = [np.asarray(q_a, dtype=float)]
    poses = [X_a]
    for s in np.linspace(0.0, 1.0, n + 1)[1:-1]:
        R = RotationMatrix(Quaternion(quat_a.slerp(s, quat_b).wxyz()))
        hook = h_a + s * (h_b - h_a)
        hook[2] = height
        q, X = _ik_at_or_above(model, R, hook, hook_G, path[-1], hand)
        if q is None:
            return None
        path.append(q)
        poses.append(X)
    path.append(np.asarray(q_b, dtype=float))
    poses.append(X_b)
    if depth <= 0:
        return path
    out = [path[0]]
    for (qa, qb), (Xa, Xb) in zip(zip(path[:-1], path[1:], strict=True),
                                  zip(poses[:-1], poses[1:], strict=True), strict=True):
        if hook_heights(model, qa, qb, hand, hook_G).min() < min_height - 1e-9 and \
                np.linalg.norm((Xb.multiply(hook_G) - Xa.multiply(hook_G))[:2]) > 0.2 * CARRY_STEP:
            sub = _split(model, qa, qb, Xa, Xb, hand, hook_G, min_height, depth - 1)
            if sub is None:
                return None
            out.extend(sub[1:])
        else:
            out.append(qb)
    return out


def _ik_at_or_above(model, R: RotationMatrix, hook_W, hook_G, q_seed, hand: HandPose):
    """IK for the hand at orientation ``R`` with the hook point at ``hook_W``, or higher by up
    to :data:`CARRY_RISES` where the arm does not reach it: (q, X_WG), or (None, None)."""
    for rise in (0.0, *CARRY_RISES):
        X = RigidTransform(R, np.asarray(hook_W) + [0.0, 0.0, rise] - R.multiply(hook_G))
        q = model.ik(X, q_seed, hand, restarts=CARRY_IK_RESTARTS)
        if q is not None:
            return q, X
    return None, None


def _split(model, q_a, q_b, X_a, X_b, hand, hook_G, min_height, depth):
    """One segment's midpoint waypoint (at the segment's height), recursively."""
    h_a, h_b = X_a.multiply(hook_G), X_b.multiply(hook_G)
    R = RotationMatrix(Quaternion(X_a.rotation().ToQuaternion().slerp(
        0.5, X_b.rotation().ToQuaternion()).wxyz()))
    hook = 0.5 * (h_a + h_b)
    hook[2] = max(min(h_a[2], h_b[2]), min_height)
    q_m, X_m = _ik_at_or_above(model, R, hook, hook_G, q_a, hand)
    if q_m is None:
        return None
    out = [np.asarray(q_a, dtype=float)]
    for qa, qb, Xa, Xb in ((q_a, q_m, X_a, X_m), (q_m, q_b, X_m, X_b)):
        if depth > 0 and hook_heights(model, qa, qb, hand, hook_G).min() < min_height - 1e-9:
            sub = _split(model, qa, qb, Xa, Xb, hand, hook_G, min_height, depth - 1)
            if sub is None:
                return None
            out.extend(sub[1:])
        else:
            out.append(np.asarray(qb, dtype=float))
    return out


#: Fractions of a release move tried in turn, the whole first, where the arm cannot make it all.
BACKOFF_FRACTIONS = (1.0, 0.5, 0.25)


def release_path(model: PlanningModel, q_place: np.ndarray, kind: str, cfg: PickConfig,
                 bar: float = 0.0, gripper: HookGripperGeometry = HOOK_GRIPPER
                 ) -> dict[str, np.ndarray]:
    """How the gripper lets go at ``q_place`` (closed), the reverse of how it went in:

    * ``opened``: where the arm is once the fingers are open: a vertical grasp opens about its
      straight rod (the arm moves G along -y_G as each finger travels, so the rod stays in the
      hole and the bar leaves from under the material); the others open in place;
    * ``down``: a parallel grasp goes on along +z_G by up to ``release_depth`` (the bar leaves
      the material it was under; less if the hand would meet the table);
    * ``slide``: then along -y_G by ``release_shift`` (the bar comes out of the hole tip first);
    * ``retreat``: every grasp backs out along -z_G by ``retreat_distance``, or by half or a
      quarter of it where the arm cannot (a rod in a hole leaves it the way it went in: straight
      up, it would lift the object by the hole), or straight up where it cannot at all. A move
      without IK or with a collision is skipped (the arm stays).
    ``gripper``: the hook gripper's geometry."""
    g = gripper
    closed_hand, open_hand = HandPose(g.q_closed, bar), HandPose(g.q_open, bar)
    X = model.X_WG(q_place, closed_hand)
    R = X.rotation()

    def step(q_from, X_from, moves):
        return first_free_move(model, q_from, X_from, moves, open_hand)

    q = {"opened": q_place}
    if GraspKind(kind).keeps_straight_rod:
        q["opened"], X = step(q_place, X, [-(g.q_open - g.q_closed) * R.col(1)])
    q["down"], q["slide"] = q["opened"], q["opened"]
    if kind == PARALLEL:
        q["down"], X = step(q["opened"], X, [f * cfg.release_depth * R.col(2)
                                             for f in BACKOFF_FRACTIONS])
        q["slide"], X = step(q["down"], X, [-cfg.release_shift * R.col(1)])
    q["retreat"], _ = step(q["slide"], X, [*(-f * cfg.retreat_distance * R.col(2)
                                             for f in BACKOFF_FRACTIONS),
                                           [0.0, 0.0, cfg.retreat_distance]])
    return q


def withdraw_path(model: PlanningModel, q_from: np.ndarray, cfg: PickConfig, bar: float = 0.0,
                  gripper: HookGripperGeometry = HOOK_GRIPPER, *, drop: float = 0.0,
                  shift: float = 0.0) -> dict[str, np.ndarray]:
    """How an open hook withdraws from ``q_from`` after its bar lifted the object it was letting
    go of (the hand's load rose again), without lifting it once more:

    * ``lowered``: ``drop`` (m) down in W, so that the object stands again and the bar hangs
      free under the material (less, a half or a quarter, where the hand would meet the table;
      not at all where it cannot);
    * ``out``: then along -y_G by ``shift`` (m): the bar's axis, the way a parallel grasp's bar
      went into the hole (the caller gives what is left of its ``withdraw_shift``; a grasp that
      keeps its straight rod in the hole is given what is left of its opening's own move, the
      rod's axis being z_G, the retreat's);
    * ``retreat``: along -z_G by ``retreat_distance`` (a half or a quarter of it where the arm
      cannot), or straight up where it cannot at all: out of the hole the way it went in.

    Each move without IK or with a collision is skipped (the arm stays), as in
    :func:`release_path`. ``gripper``: the hook gripper's geometry (the hand is open)."""
    hand = HandPose(gripper.q_open, bar)
    X = model.X_WG(q_from, hand)
    R = X.rotation()

    def step(q0, X0, moves):
        return first_free_move(model, q0, X0, moves, hand)

    q = {}
    q["lowered"], X = step(q_from, X, [[0.0, 0.0, -f * drop] for f in BACKOFF_FRACTIONS]
                           if drop > 0 else [])
    q["out"], X = step(q["lowered"], X, [-f * shift * R.col(1) for f in BACKOFF_FRACTIONS]
                       if shift > 0 else [])
    q["retreat"], _ = step(q["out"], X, [*(-f * cfg.retreat_distance * R.col(2)
                                           for f in BACKOFF_FRACTIONS),
                                         [0.0, 0.0, cfg.retreat_distance]])
    return q


def first_free_move(model: PlanningModel, q_from: np.ndarray, X_from: RigidTransform, moves,
                    hand: HandPose) -> tuple[np.ndarray, RigidTransform]:
    """(q, X_WG) after the first of ``moves`` (offsets in W, m) of the gripper at ``X_from``
    (the arm at ``q_from``) with an IK solution and a collision-free edge; ``(q_from, X_from)``
    (the arm stays) when none has."""
    for d_W in moves:
        X_to = shifted(X_from, d_W)
        q = model.ik(X_to, q_from, hand)
        if q is not None and model.edge_free(q_from, q, hand):
            return q, X_to
    return q_from, X_from


def withdrawn_along(X_from: RigidTransform, X_to: RigidTransform) -> float:
    """How far (m) the gripper has moved along -y_G (``X_from``'s) from ``X_from`` to ``X_to``:
    how much of a withdrawal along the bar's axis is done."""
    d = np.asarray(X_to.translation()) - np.asarray(X_from.translation())
    return float(-d @ X_from.rotation().col(1))


def shifted(X: RigidTransform, d_W) -> RigidTransform:
    return RigidTransform(X.rotation(), X.translation() + np.asarray(d_W, dtype=float))
