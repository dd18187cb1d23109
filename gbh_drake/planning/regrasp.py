"""Plans a regrasp (beyond the paper, issue 19): pick the object with a pinch (the bar folded),
turn it into a resting pose in which GbH can hook it, set it down, let go and go home.

:func:`plan_regrasp` takes a pinch (an antipodal grasp's open pose X_WG) and a resting pose
(:class:`~gbh_drake.core.regrasp.RegraspPose`: the motion that takes the object, as it lies now,
to that pose) and returns the arm configurations of the whole pick-and-place, or a
:class:`~gbh_drake.planning.pick.Refusal`:

* ``approach``/``grasp``: the transfer and descent of :func:`~gbh_drake.planning.pick.approach_transfer`;
* ``lift``: straight up until the object, held rigidly and turned any way about the pinch,
  clears the table by ``lift_clearance`` (the farthest point of the scan or of its unseen
  space from the pinch), at least ``min_lift``, as the arm reaches;
* ``above`` and ``place``: the hand moved as the object moves (``X_WG_place = M X_WG``, M the
  resting pose's motion, turned about the vertical through the place by the first of
  :data:`PLACE_YAWS_DEG` the arm reaches), ``above`` the same height over the place as the lift;
  the move from ``lift`` to ``above`` keeps the pinch point that high (Cartesian waypoints where
  a joint move would dip, :func:`~gbh_drake.planning.pick.carry_path`) and is refused where it
  sinks below the object's reach from the pinch plus half the lift clearance (turning in the
  hand, the object would meet the table); the descent goes on
  ``place_depth`` below the predicted resting pose (the machine stops once the hand's load
  drops: the object stands);
* ``opened``, ``retreat``: the fingers open in place and the hand backs off
  (:func:`~gbh_drake.planning.pick.release_path`), then goes ``home`` (out of the cameras' way
  for the re-scan).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from pydrake.math import RigidTransform, RotationMatrix

from gbh_drake.core.gripper import BAR_RETRACTED
from gbh_drake.core.regrasp import RegraspPose, pinch_clearance
from gbh_drake.core.results import GraspKind
from gbh_drake.core.unseen import farthest_distance
from gbh_drake.planning.model import HandPose
from gbh_drake.planning.pick import (
    PickSetup,
    Refusal,
    approach_transfer,
    carry_path,
    release_path,
    shifted,
)

#: Degrees the placed object may also be turned about the vertical through the place, in the
#: order tried (its resting pose is the same; the arm may reach one and not another).
PLACE_YAWS_DEG = (0.0, 45.0, -45.0, 90.0, -90.0, 135.0, -135.0, 180.0)


@dataclass
class RegraspPlan:
    """Arm configurations (rad, 7 each) of a regrasp and what they came from."""

    rank: int
    """The pinch's rank among the offered fallback grasps."""
    pose: RegraspPose
    """The resting pose the object is set down in."""
    yaw_deg: float
    """Extra turn (deg) about the vertical through the place."""
    transfer: list[np.ndarray]
    q: dict[str, np.ndarray] = field(default_factory=dict)
    """``approach``, ``grasp``, ``lift``, ``above``, ``place``, ``opened``, ``retreat``,
    ``home``."""
    move: list[np.ndarray] = field(default_factory=list)
    """Waypoints from ``lift`` to ``above`` (the pinch point kept at the lift height)."""
    X_WG_place: np.ndarray = field(default_factory=lambda: np.eye(4))
    """(4, 4) where the gripper sets the object down."""
    place_W: np.ndarray = field(default_factory=lambda: np.zeros(3))
    """(3,) m: the centre of the object's footprint where it is set down (the re-scan's aim)."""
    lift: float = 0.0
    descent: list[np.ndarray] = field(default_factory=list)
    """The insert's waypoints, ``approach`` to ``grasp`` (:func:`~gbh_drake.planning.pick.descent_path`)."""


def plan_regrasp(setup: PickSetup, X_WG: np.ndarray, pose: RegraspPose, rank: int,
                 q_start: np.ndarray, q_home: np.ndarray) -> RegraspPlan | Refusal:
    """The regrasp with the pinch at ``X_WG`` (4, 4, open) into ``pose``, from the arm at
    ``q_start``, ending at ``q_home`` (module docstring); or why not."""
    cfg, near, g = setup.config, setup.near, setup.gripper
    kind = GraspKind.ANTIPODAL
    open_hand, held = HandPose(g.q_open, BAR_RETRACTED), HandPose(0.5 * g.rod_width, BAR_RETRACTED)
    X = RigidTransform(np.asarray(X_WG, dtype=float))

    def refuse(reason: str, where: str, detail: str = "") -> Refusal:
        return Refusal(rank, "regrasp", reason, where, detail)

    # Set down in the pose, the gripper must clear the table (it would hold the object from
    # below otherwise).
    X_set = np.asarray(pose.X_WnewWnow, dtype=float) @ X.GetAsMatrix4()
    if pinch_clearance(X_set[None], held.q)[0] < near.padding:
        return refuse("collision", "place", "the hand would meet the table holding the object "
                      "in that pose")
    q = {"grasp": near.ik(X, q_start, open_hand, restarts=3)}
    if q["grasp"] is None:
        return refuse("ik", "grasp")
    # The pinch point (between the fingertips) and how far the held object reaches from it,
    # its unseen space included (core/unseen.py: where material the cameras missed may be).
    pinch_G = np.array([0.0, 0.0, g.finger_length])
    pinch_W = X.multiply(pinch_G)
    reach = max(farthest_distance(setup.points_W, pinch_W),
                farthest_distance(setup.unseen_W, pinch_W))
    height = reach + cfg.lift_clearance  # the pinch point this high: any turn clears the table
    lift = float(np.clip(height - pinch_W[2], cfg.min_lift, cfg.max_lift))
    q["lift"] = None
    for dz in np.linspace(lift, cfg.min_lift, 4):
        q["lift"] = near.ik(shifted(X, [0.0, 0.0, dz]), q["grasp"], held)
        if q["lift"] is not None:
            lift = float(dz)
            break
    if q["lift"] is None:
        return refuse("ik", "lift")
    if not near.edge_free(q["grasp"], q["lift"], held):
        return refuse("collision", "lift")
    carry_height = pinch_W[2] + lift

    M = np.asarray(pose.X_WnewWnow, dtype=float)
    placed = setup.points_W @ M[:3, :3].T + M[:3, 3]
    place_W = np.array([*(0.5 * (placed.min(axis=0) + placed.max(axis=0)))[:2], 0.0])
    refusal = refuse("ik", "place")
    for yaw in PLACE_YAWS_DEG:
        turn = RigidTransform(place_W) @ RigidTransform(
            RotationMatrix.MakeZRotation(np.radians(yaw)), np.zeros(3)) @ \
            RigidTransform(-place_W)
        X_place = turn @ RigidTransform(M) @ X
        X_above = RigidTransform(X_place.rotation(), X_place.translation() +
                                 [0.0, 0.0, max(carry_height - X_place.multiply(pinch_G)[2],
                                                0.0)])
        q_above = near.ik(X_above, q["lift"], held, restarts=2)
        if q_above is None:
            continue
        q_place = None
        for down in (cfg.place_depth, 0.5 * cfg.place_depth, 0.0):
            q_place = near.ik(shifted(X_place, [0.0, 0.0, -down]), q_above, held)
            if q_place is not None and near.edge_free(q_above, q_place, held):
                break
            q_place = None
        if q_place is None:
            refusal = refuse("collision", "place")
            continue
        # Along the move the pinch point stays high enough for the object to turn any way
        # about it and still clear the table by half the lift clearance.
        floor = reach + 0.5 * cfg.lift_clearance
        move, low = carry_path(near, q["lift"], q_above, held, pinch_G, carry_height - 0.02,
                               check_edges=cfg.plan_paths)
        if low < floor:
            refusal = refuse("collision", "turn", f"the pinch point sinks to {low:.2f} m, the "
                             f"held object reaches {reach:.2f} m from it")
            continue
        q.update(above=q_above, place=q_place)
        q.update(release_path(near, q_place, kind, cfg, BAR_RETRACTED))
        q["home"] = np.asarray(q_home, dtype=float)
        transfer = approach_transfer(setup, X, q["grasp"], open_hand, q_start)
        if isinstance(transfer, str):
            return refuse(transfer, "transfer" if transfer == "planner" else "grasp")
        transfer, descent = transfer
        q["approach"] = transfer[-1]
        return RegraspPlan(rank, pose, float(yaw), transfer, q, move,
                           X_place.GetAsMatrix4(), place_W, lift, descent)
    return refusal

