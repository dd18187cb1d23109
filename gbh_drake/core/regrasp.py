"""Where to set an object down so that GbH can hook it (issue 19, ``gbh+regrasp``: its pure part).

When GbH finds a hanging structure but no hook grasp of the object as it lies (a mug resting on
its handle, out of reach of the gripper), another resting pose may offer one. Given the object's
mesh where it lies (the scan's, in W) and its resting orientations (``(R, probability)`` pairs:
R turns the mesh, as it is in W now, into that resting orientation about its own centre, e.g.
:func:`gbh_drake.objects.stability.stable_poses` of the W mesh), :func:`choose_regrasp_pose`
puts the mesh in each (the yaw about the vertical that turns it least, the centre of its
footprint at ``place_xy``, its lowest point on the table), runs the pipeline on it
(:func:`gbh_drake.core.pipeline.plan_grasps`, the same params) and returns the poses that offer
a hook grasp, best first:

0. the poses probable on their own (at least ``min_probability``) before those offered only by
   their family (below): a facet of a side the object rolls on is the pose it is set down in
   only if it rolls about the right axis (a roll's core, not a mug's handle);
1. fewest degrees to turn, in steps of :data:`TURN_STEP_DEG` (the hand turns the object with it
   while it holds a fallback pinch: the smaller the turn, the likelier the arm can do it and
   the pinch holds; turns a few degrees apart are alike: a scan's resting poses of one object
   differ by that much);
2. then the best GbH score of the pose (paper Sec. 2.4);
3. then the most probable orientation.

Orientations within ``min_turn_deg`` of the present one (the pose that offered nothing) are
skipped, and so are those whose *family* is less probable than ``min_probability``
(:func:`family_probabilities`): an object that rolls on a curved side (a tape roll or a ring
standing on its rim, a bottle on its side) rests on many facets of its hull, each improbable (a
scanned tape roll's rim: 32 facets of 0.1-0.6 % each, 5 % together), yet set down it rests on
one of them as surely as on a face; the facets are one family, whose probability is their sum.

Which pinch can turn the object into a pose? One that is a good pinch *there* (from above, the
hand clear of the table once the object stands in the new pose) and that the arm can take
*here*: :func:`pinches_for_pose` samples antipodal pinches of the object as it will stand and
keeps those that, moved back to where it lies now, keep the gripper (open, closing, closed, bar
folded) clear of the table. (A mug lying on its handle pinched from above would be held from
below once upright, its hand in the table.) Pure numpy/trimesh: the trial's systems do the
pick, the place, the re-scan and the hook.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, replace

import numpy as np

from gbh_drake.core.antipodal import sample_antipodal_grasps
from gbh_drake.core.collision import box_corners
from gbh_drake.core.gripper import HOOK_GRIPPER, HookGripperGeometry
from gbh_drake.core.lazy import lazy_module
from gbh_drake.core.params import AntipodalParams, GbhParams
from gbh_drake.core.pipeline import plan_grasps
from gbh_drake.core.results import GbhInputError

trimesh = lazy_module("trimesh")

#: Degrees: turns are compared rounded to steps of this (85 and 90 deg alike: a scan's resting
#: poses of one orientation differ by a few degrees).
TURN_STEP_DEG = 30.0
#: Degrees: resting orientations whose support faces' normals (in the mesh as it lies) are
#: chained this close are one family (:func:`family_probabilities`): one turn step, the turns
#: counted alike. A scanned tape roll's rim rests are 3-44 deg apart, all but one gap below
#: 30 deg; a box's faces are 90 deg apart, a hexagonal prism's 60.
FAMILY_LINK_DEG = TURN_STEP_DEG


@dataclass
class RegraspPose:
    """One resting pose that offers a hook grasp. Metres, degrees, W frame."""

    X_WnewWnow: np.ndarray
    """(4, 4): the rigid motion that takes the mesh from where it lies now to the new pose (apply
    it to the W mesh; the hand that holds the object makes the same motion)."""
    turn_deg: float
    """Angle of the motion's rotation."""
    probability: float
    """The resting orientation's probability (as given)."""
    grasps: int
    """Hook grasps the pipeline ranks on the mesh in the new pose."""
    best_score: float
    """The best of them's score S."""
    index: int
    """Which of the given orientations."""
    family_probability: float = float("nan")
    """The probability of its family (:func:`family_probabilities`): what ``min_probability``
    is compared with."""
    pinches: list[np.ndarray] | None = None
    """(4, 4) X_WG each, where the object lies now: pinches that hold it from above in this
    pose (:func:`pinches_for_pose`); None until asked for."""


def least_turn_yaw(R: np.ndarray) -> float:
    """rad: the yaw psi about +z for which Rz(psi) R turns least (the largest trace:
    trace(Rz R) = cos psi (R00 + R11) + sin psi (R01 - R10) + R22)."""
    return float(np.arctan2(R[0, 1] - R[1, 0], R[0, 0] + R[1, 1]))


def rotation_angle_deg(R: np.ndarray) -> float:
    """deg: the angle of the rotation R (3, 3)."""
    return float(np.degrees(np.arccos(np.clip(0.5 * (np.trace(R) - 1.0), -1.0, 1.0))))


def resting_motion(mesh_W: trimesh.Trimesh, R: np.ndarray, place_xy: Sequence[float],
                   ground_height: float = 0.0) -> np.ndarray:
    """(4, 4) the motion X_WnewWnow that turns ``mesh_W`` by Rz(least_turn_yaw) R about its
    centroid, puts the centre of its footprint (the bounding box's, in x and y) at ``place_xy``
    and its lowest vertex at ``ground_height``."""
    psi = least_turn_yaw(np.asarray(R, dtype=float))
    c, s = np.cos(psi), np.sin(psi)
    Rz = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
    X = np.eye(4)
    X[:3, :3] = Rz @ np.asarray(R, dtype=float)
    centroid = np.asarray(mesh_W.vertices).mean(axis=0)
    X[:3, 3] = centroid - X[:3, :3] @ centroid
    v = np.asarray(mesh_W.vertices) @ X[:3, :3].T + X[:3, 3]
    lo, hi = v.min(axis=0), v.max(axis=0)
    X[:2, 3] += np.asarray(place_xy, dtype=float) - 0.5 * (lo[:2] + hi[:2])
    X[2, 3] += ground_height - lo[2]
    return X


def pinch_clearance(X_WG: np.ndarray, q_lo: float, ground_height: float = 0.0,
                    gripper: HookGripperGeometry = HOOK_GRIPPER) -> np.ndarray:
    """(M,) m: how high above the table plane z = ``ground_height`` (W z up) the lowest corner of
    the bar-folded gripper stays while it closes from open to each finger at ``q_lo`` (the
    rods on the material), at poses X_WG (M, 4, 4)."""
    X = np.asarray(X_WG, dtype=float).reshape(-1, 4, 4)
    corners = np.concatenate([box_corners(gripper.solid_boxes_G(q, bar_retracted=True))
                              for q in (gripper.q_open, max(q_lo, gripper.q_closed_retracted))])
    return (np.einsum("mj,cj->mc", X[:, 2, :3], corners) + X[:, 2, 3:4]).min(axis=1) - \
        ground_height


def pinches_for_pose(mesh_W: trimesh.Trimesh, pose: RegraspPose, params: AntipodalParams,
                     *, seed: int = 0, clearance: float = 0.003) -> list[np.ndarray]:
    """Pinches (X_WG (4, 4) each, where ``mesh_W`` lies now) that hold the object from above
    once it stands in ``pose``: the antipodal sampler's best pinches of the mesh moved into the
    pose (``params``, the sampler's ``seed``; its table rule there), moved back by the pose's
    inverse motion, kept where the gripper clears the table by ``clearance`` (m) here too (the
    same pinch, from the other side: the object lies otherwise), best first. The regrasp
    approaches fully open (its pinches are poses only): ``narrow_pregrasp`` is off here."""
    M = np.asarray(pose.X_WnewWnow, dtype=float)
    try:
        grasps = sample_antipodal_grasps(mesh_W.copy().apply_transform(M),
                                         replace(params, narrow_pregrasp=False), rng=seed)
    except GbhInputError:
        return []
    back = np.linalg.inv(M)
    out = []
    for g in grasps:
        X_now = back @ g.X_WG
        if pinch_clearance(X_now[None], g.q, params.ground_height)[0] >= clearance:
            out.append(X_now)
    return out


def family_probabilities(orientations: Sequence[tuple[np.ndarray, float]]) -> np.ndarray:
    """(n,) each orientation's family probability: the sum of the probabilities of the
    orientations chained to it (single linkage) by support normals each within
    :data:`FAMILY_LINK_DEG` of the next. ``orientations``: (R (3, 3), probability) as in
    :func:`choose_regrasp_pose`; R turns the mesh as it lies into the resting orientation, so
    the face it rests on has the outward normal R^T (0, 0, -1) in the mesh as it lies. A box's
    faces are each their own family; a tessellated or scanned cylinder's side facets, or a
    ball's, chain into one (it rolls from one to the next)."""
    if len(orientations) == 0:
        return np.zeros(0)
    from scipy.sparse.csgraph import connected_components

    normals = np.array([-np.asarray(R, dtype=float)[2] for R, _ in orientations])  # R^T (-z)
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    linked = normals @ normals.T >= np.cos(np.radians(FAMILY_LINK_DEG))
    _, label = connected_components(linked, directed=False)
    probability = np.array([float(p) for _, p in orientations])
    return np.bincount(label, weights=probability)[label]


def choose_regrasp_pose(
    mesh_W: trimesh.Trimesh,
    orientations: Sequence[tuple[np.ndarray, float]],
    params: GbhParams,
    place_xy: Sequence[float],
    *,
    seed: int = 0,
    min_turn_deg: float = 15.0,
    min_probability: float = 0.02,
    max_poses: int | None = None,
) -> list[RegraspPose]:
    """The resting poses of ``mesh_W`` (vertices in W, where the object lies now) among
    ``orientations`` ((R (3, 3), probability) each, see the module docstring) in which the
    pipeline, with ``params`` and the surface sampler's ``seed``, ranks a hook grasp, best
    first (module docstring); empty if none does. An orientation is tried when its family's
    probability (:func:`family_probabilities`) is at least ``min_probability``, and comes after
    every one probable on its own when only its family is.

    ``max_poses``: only the best that many (the same as the first ``max_poses`` of the whole
    list). The pipeline then runs group by group of the order's first two keys (probable on its
    own, the turn's step), which are known before it runs, and stops after the group in which
    that many poses were found: a tape roll's 59 rim facets are not each planned when its
    first group already offers three. Raises GbhInputError for ``max_poses`` below 1."""
    if max_poses is not None and (isinstance(max_poses, bool) or not isinstance(
            max_poses, int | np.integer) or max_poses < 1):
        raise GbhInputError(f"choose_regrasp_pose: max_poses must be a whole number of at least "
                            f"1 (or None: every pose), got {max_poses!r}")
    family = family_probabilities(orientations)
    tried: list[tuple[tuple[bool, int], int, np.ndarray, float]] = []
    for i, (R, probability) in enumerate(orientations):
        if family[i] < min_probability:
            continue
        X = resting_motion(mesh_W, R, place_xy, params.ground_height)
        turn = rotation_angle_deg(X[:3, :3])
        if turn >= min_turn_deg:
            tried.append(((float(probability) < min_probability,
                           round(turn / TURN_STEP_DEG)), i, X, turn))
    tried.sort(key=lambda t: (t[0], t[1]))
    out: list[RegraspPose] = []
    for k, (group, i, X, turn) in enumerate(tried):
        try:
            result = plan_grasps(mesh_W.copy().apply_transform(X), params, seed=seed)
        except GbhInputError:
            result = None
        if result is not None and result.ranked:
            out.append(RegraspPose(X, turn, float(orientations[i][1]), len(result.ranked),
                                   float(result.ranked[0].score), i,
                                   family_probability=float(family[i])))
        group_done = k + 1 == len(tried) or tried[k + 1][0] != group
        if max_poses is not None and group_done and len(out) >= max_poses:
            break
    out.sort(key=lambda p: (p.probability < min_probability,
                            round(p.turn_deg / TURN_STEP_DEG), -p.best_score,
                            -p.probability, p.index))
    return out if max_poses is None else out[:max_poses]
