"""A learning-free antipodal grasp baseline for the hook gripper with its bar retracted.

Why: the paper compares GbH with GraspNet (Sec. 3.1), whose weights we cannot have, and its
fairness rule mounts "two straight fingers of the same length" for the baseline. With the bar
retracted (:mod:`gbh_drake.core.gripper`: a revolute joint about ``x_G`` at the bend p3, angle
``-pi/2``, the paper's Sec. 4 proposal) the hook gripper is exactly that: two 8 mm square rods,
l_f = 8 cm long, opening up to l_w = 8 cm between their centre lines. The same sampler is the
fallback beyond the paper: GbH first; when nothing hangable is found or reachable, retract the
bar and pinch.

Frames and units: everything is in W, the frame the mesh is given in (metres, radians unless a
field says degrees). Poses ``X_WG`` (4x4) place the gripper frame G of :mod:`gbh_drake.core.
gripper`: origin at the palm centre, ``+z_G`` the approach (palm toward fingertips), ``+y_G`` the
closing axis from the L rod (retracted bar) toward the straight rod, ``x_G = y_G x z_G``. A finger
position ``q`` is one finger's joint position (its rod's centre line at ``|y_G| = q``).

The sampler (after ``GenerateAntipodalGraspCandidate`` of Russ Tedrake's ``manipulation`` course,
``clutter.py``; our own code, vectorised, no pydrake):

1. Draw ``n_samples`` of the object's Poisson-disk surface points ``A`` (outward normal ``n_A``)
   with ``rng``.
2. Closing axis along the normal: ``y_G = -n_A`` (the L rod's pad at A pushes into the object).
   Cast a ray from just inside A along ``y_G``; its exit B (outward normal ``n_B``, the hit
   face's) is the straight rod's contact. The width ``w = |AB|`` must fit: the rods' inner faces
   touch A and B at ``q = w/2 + rod_width/2``, which must be at most ``q_open - opening_margin``
   (w <= 6.6 cm with the defaults) and ``w >= min_width``.
3. Friction cone: the angle between ``n_B`` and ``+y_G`` (and between ``n_A`` and ``-y_G``, zero
   by construction) must be below ``atan(mu)``.
4. Rotate the hand about the closing axis through the contacts' midpoint C: ``n_rolls`` angles
   in ``[-max_roll_deg, +max_roll_deg]`` about the most downward approach perpendicular to
   ``y_G`` (the course tries 7 rolls in +-60 deg, centre out, and keeps the first feasible; we
   score all and rank). C is centred between the rods (the course's ``adjust_X_G``) at
   ``contact_depth`` behind the rods' tip keypoint (z_G = l_f - contact_depth: the finger pads).
5. Supporting surface: the lowest corner of the solid model, swept from the open gripper to the
   contact opening, must be at least ``ground_clearance`` above the plane ``ground_normal . p =
   ground_height``. If it is not, the hand is backed off along ``-z_G`` so that the contact
   moves toward the fingertips, but not closer than ``min_contact_depth`` to them.
6. Collision (the course rejects any point inside the gripper; GbH keeps N_c < p_c): N_c counts
   the object's points inside the bar-retracted solid model swept along the descent (the open
   gripper moving ``approach_distance`` along ``+z_G`` to X_WG) and then along the closing (each
   rod from ``q_open`` to ``contact_tolerance`` short of its contact): material the hand would
   pass through or that the rods would touch before A and B. Keep ``N_c < p_c``. With
   ``narrow_pregrasp`` (beyond the course, whose hand always opens fully; GraspNet's grasps
   carry their width) a pinch that fails fully open is counted again with the hand opened
   less, down to the contacts plus ``opening_margin`` (:func:`pregrasp_openings`): the rod
   that goes down inside a ring lying flat, or beside a handle, no longer lands on the far
   side of the hole or the body behind it. The widest clear opening is the grasp's
   ``q_pregrasp``.
7. The side pass (beyond the course; ``side_pass``, only when steps 1-6 keep nothing): an
   object lying flat and thinner than about 13 mm (scissors, a small ring) offers the first
   pass almost only its top and bottom faces, whose pinches close vertically, and its sides
   sit too low for contacts ``min_contact_depth`` behind the tips. The second pass draws A
   only among points whose normal lies within the friction cone of the table's plane, lays
   the closing axis level, and moves the contacts to where upright rod faces first meet the
   material (:func:`_widest`: the extremes along ``y_G`` within half a rod width of the
   closing plane, near the pair and across the whole opening); the contacts may come down to
   ``contact_tolerance`` above the rods' end faces. Steps 4-6 then run as before (same
   clearance, same collision count). Its counts carry a ``side_`` prefix.

The cost (lower is better), per candidate, in the course's spirit (``GraspCandidateCost``:
``cost = 20 R_WG[2, 1] - sum_points (n . x_G)^2``, where the WSG's +y is its approach and +x its
closing axis)::

    cost = weight_direction * (z_G . up)                        # in [-1, 1]: -1 straight down
         + weight_antipodal * (1 - ((n_A . y_G)^2 + (n_B . y_G)^2) / 2)   # in [0, 1]
         + weight_com * d_com                                   # metres x (1/m)

* direction: the course penalises its approach axis (WSG +y) not pointing down; ours is +z_G, so
  ``z_G . up`` (up = the ground normal), -1 for a top-down approach, 0 for a side one.
* antipodality: the course rewards ``(n . x_G)^2`` summed over the cloud's points between the
  fingers; we take the two contacts' normals (the exact contacts of the ray construction) and
  average, so the term does not grow with the sampling density.
* centre of mass (not in the course): ``d_com`` is the distance from the CoM (the volume centroid,
  or the surface centroid of an open scan) to the closing line AB: the lever arm of gravity about
  the one axis a two-pad pinch resists only by the pads' torsional friction, so a pinch far from
  the CoM lets the object swing out.
* also differs: the course checks collisions against the scene with Drake's geometry queries; we
  count points (as GbH does) and test the supporting plane analytically, and we also count the
  material swept by the descent and by the closing rods (the course checks the final pose
  only); the course keeps the first feasible roll of one sample per call, we rank every
  (sample, roll) and return the top_k. ``score = exp(-(cost + weight_direction))`` maps the cost
  to (0, 1] (1: top-down, perfectly antipodal, through the CoM); it is not GbH's S_total.
* ``prefer_hanging`` (beyond the paper, off for the baseline): the object pivots about the
  pinch axis once lifted (:mod:`gbh_drake.core.pinch`), so pinches are ranked first by how far
  its CoM would fall as it swings to rest below the axis (in steps of ``DROP_STEP``), then by
  cost: a pinch above the CoM before one beside or below it.

Execution: retract the bar (bar joint at ``gripper.bar_retracted_angle = -pi/2``), open the
fingers to ``q_pregrasp`` (``q_open``, or less with ``narrow_pregrasp``), reach ``X_WG`` along
``+z_G``, close with a force limit toward ``gripper.q_closed_retracted`` (rods touching);
contact is expected at ``q``. ``X_WG @ diag(-1, -1, 1, 1)`` (half a turn about ``z_G``) is
the same grasp with the rods swapped, and the solid model with the bar retracted is symmetric
under it: :func:`flipped` gives it, for a planner that cannot reach the first.
"""

# No ``from __future__ import annotations`` here: Drake's yaml_load_typed reads
# AntipodalParams' field types at run time and needs real types, not strings.
import time
from dataclasses import dataclass, field

import numpy as np

from gbh_drake.core.geometry import frame_coordinates, orthonormal_basis, unit
from gbh_drake.core.gripper import HOOK_GRIPPER, HookGripperGeometry
from gbh_drake.core.lazy import lazy_module
from gbh_drake.core.object_model import ObjectModel, prepare_object
from gbh_drake.core.params import AntipodalParams, GbhParams
from gbh_drake.core.pinch import DROP_STEP, swing_drops
from gbh_drake.core.results import GraspKind

trimesh = lazy_module("trimesh")

#: Grasp kind of this module (GbH's are parallel and vertical).
ANTIPODAL = GraspKind.ANTIPODAL

#: Points x poses per chunk of the collision count (bounds the (chunk, N) temporaries).
_CHUNK_POINTS = 400_000
#: m: the exit ray starts this far inside the surface at A, so that it does not hit A's face.
_RAY_START = 2e-4
#: Openings tried per pinch with ``narrow_pregrasp``: fully open, then evenly narrower down to
#: the contacts plus the opening margin (three: the widest clear one is kept).
PREGRASP_STEPS = 3


@dataclass(eq=False)
class AntipodalGrasp:
    """One pinch of the two-rod gripper (bar retracted); positions metres and directions unit
    vectors in W. A is the L rod's contact (on the -y_G side), B the straight rod's."""

    X_WG: np.ndarray
    """(4, 4) pose of the gripper frame G (palm centre, +z_G approach, +y_G closing A -> B)."""
    q: float
    """m: one finger's joint position when both rods touch (width / 2 + rod_width / 2)."""
    q_pregrasp: float
    """m: one finger's joint position for the approach (the collision count's open end)."""
    width: float
    """m: |AB|, the material's thickness between the contacts."""
    p_WA: np.ndarray
    """(3,) the L rod's contact point."""
    p_WB: np.ndarray
    """(3,) the straight rod's contact point."""
    n_WA: np.ndarray
    """(3,) outward normal at A (sampled face's)."""
    n_WB: np.ndarray
    """(3,) outward normal at B (the exit face's)."""
    contact_depth: float
    """m: how far behind the rods' tip keypoint (z_G = l_f) the contacts are."""
    angle_A: float
    """rad: angle between n_WA and -y_G (0 by construction)."""
    angle_B: float
    """rad: angle between n_WB and +y_G (at most atan(mu))."""
    com_distance: float
    """m: distance from the object's CoM to the closing line AB."""
    cost: float
    """weight_direction * cost_direction + weight_antipodal * cost_antipodal + weight_com *
    com_distance; lower is better."""
    cost_direction: float
    """z_G . up, in [-1, 1] (-1: straight down)."""
    cost_antipodal: float
    """1 - ((n_A . y_G)^2 + (n_B . y_G)^2) / 2, in [0, 1]."""
    score: float
    """exp(-(cost + weight_direction)), in (0, 1]: 1 for the ideal pinch (not GbH's S_total)."""
    n_collisions: int
    """N_c: object points inside the solid model swept along the descent (approach_distance)
    and the closing from q_pregrasp to the contacts."""
    ground_clearance: float
    """m: height of the swept solid model's lowest corner above the supporting surface."""
    sample_index: int
    """Index of A in the object's surface points."""
    kind: GraspKind = ANTIPODAL
    bar_retracted: bool = True
    """The grasp is for the gripper with its bar folded onto the L rod (always True here)."""


@dataclass(eq=False)
class AntipodalResult:
    """What one :func:`plan_antipodal_grasps` call found, with counts that say why not more."""

    ranked: list[AntipodalGrasp]
    """At most top_k collision-free grasps, lowest cost first."""
    counts: dict[str, int] = field(default_factory=dict)
    """How many survived each step: samples, exits (ray hit), fits (width), friction (cone),
    poses (x rolls), ground (surface rule), evaluated (collision counted), collision_free."""
    timings: dict[str, float] = field(default_factory=dict)
    """Wall-clock seconds: sampling (object preparation), contacts, poses, collision."""


def flipped(X_WG: np.ndarray) -> np.ndarray:
    """The same pinch with the rods swapped: ``X_WG`` turned half a turn about ``z_G``."""
    return np.asarray(X_WG, dtype=float) @ np.diag([-1.0, -1.0, 1.0, 1.0])


def sample_antipodal_grasps(
    mesh: "trimesh.Trimesh | ObjectModel",
    params: AntipodalParams | None = None,
    rng: np.random.Generator | int | None = None,
    gripper: HookGripperGeometry = HOOK_GRIPPER,
) -> list[AntipodalGrasp]:
    """The best ``params.top_k`` antipodal grasps of ``mesh`` (vertices in W, metres, or a
    prepared :class:`ObjectModel`, whose points, normals, CoM and ray scene are reused), lowest
    cost first; empty when nothing fits. ``rng``: a numpy Generator or a seed (default
    0; a seed also seeds the surface sampler of a mesh input); the same seed gives the same
    grasps. Raises GbhInputError for unusable
    input."""
    return plan_antipodal_grasps(mesh, params, rng, gripper).ranked


def plan_antipodal_grasps(
    mesh: "trimesh.Trimesh | ObjectModel",
    params: AntipodalParams | None = None,
    rng: np.random.Generator | int | None = None,
    gripper: HookGripperGeometry = HOOK_GRIPPER,
) -> AntipodalResult:
    """:func:`sample_antipodal_grasps` with the counts of each step and timings."""
    params = AntipodalParams() if params is None else params
    params.check()
    seed = 0 if rng is None else rng if isinstance(rng, int | np.integer) else None
    if seed is not None:
        rng = np.random.default_rng(int(seed))
    t0 = time.perf_counter()
    obj = mesh if isinstance(mesh, ObjectModel) else prepare_object(
        mesh, GbhParams(n_points=params.n_points), 0 if seed is None else int(seed))
    timings = {"sampling": time.perf_counter() - t0}
    counts: dict[str, int] = {}
    t = time.perf_counter()
    pairs = _contact_pairs(obj, params, rng, gripper, counts)
    timings["contacts"] = time.perf_counter() - t
    t = time.perf_counter()
    cand = _poses(obj, pairs, params, gripper, counts)
    timings["poses"] = time.perf_counter() - t
    t = time.perf_counter()
    ranked = _rank_collision_free(obj, pairs, cand, params, gripper, counts)
    timings["collision"] = time.perf_counter() - t
    if not ranked and params.side_pass:
        t = time.perf_counter()
        ranked = _side_pass(obj, params, rng, gripper, counts)
        timings["side_pass"] = time.perf_counter() - t
    return AntipodalResult(ranked, counts, timings)


def _side_pass(obj: ObjectModel, params: AntipodalParams, rng: np.random.Generator,
               gripper: HookGripperGeometry, counts: dict[str, int]) -> list[AntipodalGrasp]:
    """The second pass (module docstring, step 7): contacts drawn only among the points whose
    normal lies within the friction cone of the table's plane, and the contacts allowed down
    to the rods' end faces. Its counts are kept under ``side_`` keys."""
    up = unit(np.asarray(params.ground_normal, dtype=float))
    sin_cone = np.sin(np.arctan(params.friction_coefficient))
    pool = np.flatnonzero(np.abs(unit(obj.normals) @ up) <= sin_cone)
    side: dict[str, int] = {}
    pairs = _widest(obj, _contact_pairs(obj, params, rng, gripper, side, pool), params,
                    gripper, up, side)
    low = -0.5 * gripper.rod_width + params.contact_tolerance
    cand = _poses(obj, pairs, params, gripper, side, min_contact_depth=low)
    ranked = _rank_collision_free(obj, pairs, cand, params, gripper, side)
    counts.update({f"side_{k}": v for k, v in side.items()})
    return ranked


# ---- step 1-3: contact pairs ---------------------------------------------------------------------
def _widest(obj: ObjectModel, pairs: dict[str, np.ndarray], params: AntipodalParams,
            gripper: HookGripperGeometry, up: np.ndarray, counts: dict[str, int]
            ) -> dict[str, np.ndarray]:
    """The side pass's pairs as upright rod faces meet the material: each closing axis laid in
    the table's plane, and the contacts moved to the material's extremes along it among the
    points within half a rod width of the vertical plane through the pair (a rod face
    touches the widest part of a rounded edge, not the sampled point): within the pair's own
    width plus ``opening_margin`` of its midpoint (the local pinch), and within the open
    hand's reach (the whole object between the rods: a ring whose hole the scan closed). A
    flat face pushes along its own normal whatever the material's shape at the extreme (a
    rounded side, the cut's rim), so the contact normals become -y_G and +y_G. Kept when
    the width fits; rows: the local pinches, then the whole ones."""
    keys = ("index", "p_A", "p_B", "n_A", "n_B", "y", "width", "q", "cos_A", "cos_B")
    y = pairs["y"] - (pairs["y"] @ up)[:, None] * up
    levels = np.linalg.norm(y, axis=1) > 1e-6  # a vertical closing axis has no level one
    y[levels] = unit(y[levels])
    x = np.cross(y, up)
    half = 0.5 * gripper.rod_width
    mid = 0.5 * (pairs["p_A"] + pairs["p_B"])
    whole = gripper.q_open - half - params.opening_margin
    # The points each rod column may meet, once for both reaches (the whole one is the larger).
    near = obj.tree.query_ball_point(mid, np.sqrt(whole ** 2 + half ** 2
                                                  + gripper.finger_length ** 2))
    variants = []
    for reach in (0.5 * pairs["width"] + params.opening_margin,
                  np.full(len(y), whole)):
        out = {k: np.asarray(pairs[k]).copy() for k in keys}
        keep = levels.copy()
        for i in np.flatnonzero(keep):
            idx = np.asarray(near[i], dtype=np.int64)
            d = obj.points[idx] - mid[i]
            s = d @ y[i]
            sel = (np.abs(d @ x[i]) <= half) & (np.abs(s) <= reach[i])
            if sel.sum() < 2:
                keep[i] = False
                continue
            a, b = idx[sel][np.argmin(s[sel])], idx[sel][np.argmax(s[sel])]
            out["p_A"][i], out["p_B"][i] = obj.points[a], obj.points[b]
            out["width"][i] = float((obj.points[b] - obj.points[a]) @ y[i])
        out["y"] = y
        out["q"] = 0.5 * out["width"] + half
        out["n_A"], out["n_B"] = -y, y
        out["cos_A"] = out["cos_B"] = np.ones(len(y))
        keep &= (out["width"] >= params.min_width) & (out["q"] <= gripper.q_open
                                                      - params.opening_margin)
        variants.append({k: v[keep] for k, v in out.items()})
    merged = {k: np.concatenate([v[k] for v in variants]) for k in keys}
    counts["widest"] = len(merged["y"])
    return merged


def _contact_pairs(obj: ObjectModel, params: AntipodalParams, rng: np.random.Generator,
                   gripper: HookGripperGeometry, counts: dict[str, int],
                   pool: np.ndarray | None = None) -> dict[str, np.ndarray]:
    """Antipodal contact pairs (A, B) that fit between the rods, one row per kept sample;
    A drawn among the surface points ``pool`` (indices; default all)."""
    from gbh_drake.core.o3d import open3d
    o3d = open3d()  # lazy: see gbh_drake.core.o3d
    if pool is None:
        n = len(obj.points)
        idx = rng.choice(n, size=min(params.n_samples, n), replace=False)
    else:
        idx = np.sort(rng.choice(pool, size=min(params.n_samples, len(pool)), replace=False))
    counts["samples"] = len(idx)
    p_A = obj.points[idx]
    n_A = unit(obj.normals[idx])
    y = -n_A
    rays = np.concatenate([p_A + _RAY_START * y, y], axis=1).astype(np.float32)
    hit = obj.scene.cast_rays(o3d.core.Tensor(rays))
    t_hit = hit["t_hit"].numpy().astype(float)
    prim = hit["primitive_ids"].numpy().astype(np.int64)
    exits = np.isfinite(t_hit)
    counts["exits"] = int(exits.sum())
    width = np.where(exits, t_hit + _RAY_START, np.inf)
    r = 0.5 * gripper.rod_width
    q = 0.5 * width + r
    fits = exits & (width >= params.min_width) & (q <= gripper.q_open - params.opening_margin)
    counts["fits"] = int(fits.sum())
    face_normals = np.asarray(obj.mesh.face_normals)
    n_B = np.zeros_like(n_A)
    n_B[exits] = face_normals[prim[exits]]
    cos_A = np.sum(n_A * -y, axis=1)
    cos_B = np.sum(n_B * y, axis=1)
    cone = np.cos(np.arctan(params.friction_coefficient))
    keep = fits & (cos_A >= cone) & (cos_B >= cone)
    counts["friction"] = int(keep.sum())
    p_B = p_A + np.where(exits, width, 0.0)[:, None] * y
    return {
        "index": idx[keep], "p_A": p_A[keep], "p_B": p_B[keep], "n_A": n_A[keep],
        "n_B": n_B[keep], "y": y[keep], "width": width[keep], "q": q[keep],
        "cos_A": cos_A[keep], "cos_B": cos_B[keep],
    }


# ---- step 4-5: poses, cost, supporting surface ------------------------------------------------------
def _poses(obj: ObjectModel, pairs: dict[str, np.ndarray], params: AntipodalParams,
           gripper: HookGripperGeometry, counts: dict[str, int],
           min_contact_depth: float | None = None) -> dict[str, np.ndarray]:
    """Every (pair, roll) pose that clears the supporting surface, with its cost, lowest first.
    Rows index pairs through ``pair``. ``min_contact_depth``: instead of the params' one."""
    if min_contact_depth is None:
        min_contact_depth = params.min_contact_depth
    up = unit(np.asarray(params.ground_normal, dtype=float))
    y = pairs["y"]
    S = len(y)
    if S == 0:
        counts["poses"] = counts["ground"] = 0
        empty = np.zeros(0)
        return {"X": np.zeros((0, 4, 4)), "pair": np.zeros(0, dtype=int), "depth": empty,
                "q_lo": empty, "q_hi": empty, "cost": empty, "cost_dir": empty,
                "cost_anti": empty, "d_com": empty, "clearance": empty}
    rolls = np.deg2rad(np.linspace(-params.max_roll_deg, params.max_roll_deg, params.n_rolls)
                       if params.n_rolls > 1 else np.zeros(1))
    # Most downward approach perpendicular to the closing axis (any, if the axis is vertical).
    down = np.broadcast_to(-up, y.shape)
    z0 = down - np.sum(down * y, axis=1, keepdims=True) * y
    flat = np.linalg.norm(z0, axis=1) < 1e-6
    z0 = np.where(flat[:, None], orthonormal_basis(y)[0], z0)
    z0 = unit(z0)
    x0 = np.cross(y, z0)
    c, s = np.cos(rolls), np.sin(rolls)
    z = unit(z0[:, None, :] * c[None, :, None] + x0[:, None, :] * s[None, :, None])  # (S, R, 3)
    yy = np.broadcast_to(y[:, None, :], z.shape)
    R = np.stack([np.cross(yy, z), yy, z], axis=-1).reshape(-1, 3, 3)  # columns x, y, z
    pair = np.repeat(np.arange(S), len(rolls))
    mid = 0.5 * (pairs["p_A"] + pairs["p_B"])[pair]
    depth = np.full(len(pair), params.contact_depth)
    lf = gripper.finger_length

    # Supporting surface: lowest corner of the swept solid model, backed off along -z_G if need be.
    q_lo = np.minimum(pairs["q"][pair] + params.contact_tolerance, gripper.q_open)
    q_hi = np.full(len(pair), gripper.q_open)
    lo, hi = _swept_boxes(q_lo, q_hi, gripper, 0.0, 0.0)  # (M, B, 3) each, in G
    u_G = np.einsum("mji,j->mi", R, up)  # up in G
    z_up = R[:, :, 2] @ up  # z_G . up
    p_WG = mid - (lf - depth)[:, None] * R[:, :, 2]
    if params.check_ground:
        lowest = np.minimum(u_G[:, None, :] * lo, u_G[:, None, :] * hi).sum(axis=2).min(axis=1)
        height = lowest + p_WG @ up - params.ground_height
        short = params.ground_clearance - height  # > 0: too low by this much
        need, can = short > 0.0, z_up < -1e-6  # backing off raises the hand only if it points down
        backoff = np.where(need & can, short / np.maximum(-z_up, 1e-6), 0.0)
        max_backoff = params.contact_depth - min_contact_depth + 1e-12
        ok = ~need | (can & (backoff <= max_backoff))
        backoff = np.where(ok, backoff, 0.0)
        depth = depth - backoff
        p_WG = mid - (lf - depth)[:, None] * R[:, :, 2]
        clearance = height + backoff * (-z_up)
    else:
        ok = np.ones(len(pair), dtype=bool)
        lowest = np.minimum(u_G[:, None, :] * lo, u_G[:, None, :] * hi).sum(axis=2).min(axis=1)
        clearance = lowest + p_WG @ up - params.ground_height
    counts["poses"] = len(pair)
    counts["ground"] = int(ok.sum())

    # Cost (module docstring).
    axis_point, com = pairs["p_A"][pair], obj.com
    v = com - axis_point
    yw = R[:, :, 1]
    d_com = np.linalg.norm(v - np.sum(v * yw, axis=1, keepdims=True) * yw, axis=1)
    cost_dir = z_up
    cost_anti = 1.0 - 0.5 * (pairs["cos_A"][pair] ** 2 + pairs["cos_B"][pair] ** 2)
    cost = (params.weight_direction * cost_dir + params.weight_antipodal * cost_anti
            + params.weight_com * d_com)
    keep = np.flatnonzero(ok)
    order = keep[np.argsort(cost[keep], kind="stable")]
    if params.prefer_hanging:  # the least fall of the CoM about the pinch axis first, then cost
        drop = swing_drops(mid[order], yw[order], com, up)
        order = order[np.argsort(np.round(drop / DROP_STEP), kind="stable")]
    X = np.zeros((len(order), 4, 4))
    X[:, :3, :3] = R[order]
    X[:, :3, 3] = p_WG[order]
    X[:, 3, 3] = 1.0
    return {
        "X": X, "pair": pair[order], "depth": depth[order], "q_lo": q_lo[order],
        "q_hi": q_hi[order], "cost": cost[order], "cost_dir": cost_dir[order],
        "cost_anti": cost_anti[order], "d_com": d_com[order], "clearance": clearance[order],
    }


def _swept_boxes(q_lo: np.ndarray, q_hi: np.ndarray, gripper: HookGripperGeometry,
                 margin: float, approach: float) -> tuple[np.ndarray, np.ndarray]:
    """Lower and upper corners (M, B, 3), in G, of the bar-retracted solid model's B boxes swept
    (along y_G) while each finger moves between ``q_lo`` and ``q_hi`` (M,), grown by ``margin``,
    and extended by ``approach`` (m) along -z_G (the descent of the gripper open at q_hi).

    The boxes come from :meth:`HookGripperGeometry.solid_boxes_G`; each box's centre moves
    linearly with q (slope read off two openings), so its sweep is again a box. Extending every
    box back along -z_G over-covers only where the rods close behind the palm (z_G < 0), which
    the hand's own sweep covers: the union is exactly the descent plus the closing."""
    qa, qb = gripper.q_closed_retracted, gripper.q_open
    boxes_a = gripper.solid_boxes_G(qa, bar_retracted=True)
    boxes_b = gripper.solid_boxes_G(qb, bar_retracted=True)
    c_a = np.array([b.center for b in boxes_a], dtype=float)  # (B, 3)
    slope = (np.array([b.center for b in boxes_b], dtype=float) - c_a) / (qb - qa)
    half = np.array([b.half_extents for b in boxes_a], dtype=float) + margin
    c_lo = c_a[None] + slope[None] * (q_lo - qa)[:, None, None]  # (M, B, 3)
    c_hi = c_a[None] + slope[None] * (q_hi - qa)[:, None, None]
    lo = np.minimum(c_lo, c_hi) - half[None]
    lo[:, :, 2] -= approach
    return lo, np.maximum(c_lo, c_hi) + half[None]


# ---- step 6: collision count, lazily in cost order ---------------------------------------------------
def pregrasp_openings(q: np.ndarray, params: AntipodalParams,
                      gripper: HookGripperGeometry = HOOK_GRIPPER) -> np.ndarray:
    """(M, K) finger positions (m) to approach each pinch with, widest first: ``q_open``, then
    with ``params.narrow_pregrasp`` :data:`PREGRASP_STEPS` - 1 more, evenly down to the contact
    opening ``q`` (M,) plus ``params.opening_margin`` (the room :func:`_contact_pairs` already
    keeps between the rods and the contacts)."""
    q = np.asarray(q, dtype=float).reshape(-1)
    if not params.narrow_pregrasp:
        return np.full((len(q), 1), gripper.q_open)
    narrowest = np.minimum(q + params.opening_margin, gripper.q_open)
    t = np.linspace(0.0, 1.0, PREGRASP_STEPS)
    return gripper.q_open + (narrowest - gripper.q_open)[:, None] * t[None, :]


def _rank_collision_free(obj: ObjectModel, pairs: dict[str, np.ndarray],
                         cand: dict[str, np.ndarray], params: AntipodalParams,
                         gripper: HookGripperGeometry, counts: dict[str, int]
                         ) -> list[AntipodalGrasp]:
    """Count N_c in cost order, chunk by chunk, until top_k collision-free grasps are found (the
    cost does not depend on N_c, so this is the top_k of counting them all). Each pinch is
    counted with the hand open at each of its :func:`pregrasp_openings`, widest first, and
    keeps the widest that is clear (``cand["q_hi"]`` is set to it)."""
    points = np.asarray(obj.points, dtype=np.float32)
    M = len(cand["X"])
    step = max(8, _CHUNK_POINTS // max(len(points), 1))
    ranked: list[AntipodalGrasp] = []
    evaluated = 0
    openings = pregrasp_openings(pairs["q"][cand["pair"]], params, gripper)
    for k in range(0, M, step):
        sl = slice(k, min(k + step, M))
        n_c = np.full(sl.stop - sl.start, np.iinfo(np.int64).max)
        for j in range(openings.shape[1]):
            todo = np.flatnonzero(n_c >= params.p_c)
            if len(todo) == 0:
                break
            rows = np.arange(sl.start, sl.stop)[todo]
            n_j = count_in_swept_model(points, cand["X"][rows], cand["q_lo"][rows],
                                       openings[rows, j], gripper, params.collision_margin,
                                       params.approach_distance)
            n_c[todo] = np.minimum(n_c[todo], n_j)
            clear = todo[n_j < params.p_c]
            cand["q_hi"][sl.start + clear] = openings[sl.start + clear, j]
        evaluated = sl.stop
        for j in np.flatnonzero(n_c < params.p_c):
            ranked.append(_grasp(pairs, cand, k + int(j), int(n_c[j]), params))
            if len(ranked) == params.top_k:
                break
        if len(ranked) == params.top_k:
            break
    counts["evaluated"] = evaluated
    counts["collision_free"] = len(ranked)
    return ranked


def count_in_swept_model(points_W: np.ndarray, X_WG: np.ndarray, q_lo: np.ndarray,
                         q_hi: np.ndarray, gripper: HookGripperGeometry = HOOK_GRIPPER,
                         margin: float = 0.0, approach: float = 0.0) -> np.ndarray:
    """N_c (M,) int: how many of ``points_W`` (N, 3, metres in W) lie inside the bar-retracted
    solid model (boxes grown by ``margin``) swept while the fingers move between ``q_lo`` and
    ``q_hi`` (M,) at each pose ``X_WG`` (M, 4, 4), and while the gripper, open at ``q_hi``,
    descends to it along +z_G from ``approach`` metres back."""
    X = np.asarray(X_WG, dtype=np.float32).reshape(-1, 4, 4)
    p = np.asarray(points_W, dtype=np.float32).reshape(-1, 3)
    if len(X) == 0 or len(p) == 0:
        return np.zeros(len(X), dtype=int)
    lo, hi = _swept_boxes(np.asarray(q_lo, float).reshape(-1), np.asarray(q_hi, float).reshape(-1),
                          gripper, margin, approach)
    lo, hi = lo.astype(np.float32), hi.astype(np.float32)
    x, y, z = frame_coordinates(X, p)
    inside = np.zeros(x.shape, dtype=bool)
    for b in range(lo.shape[1]):
        box = (x >= lo[:, b, 0:1]) & (x <= hi[:, b, 0:1])
        box &= (z >= lo[:, b, 2:3]) & (z <= hi[:, b, 2:3])
        box &= (y >= lo[:, b, 1:2]) & (y <= hi[:, b, 1:2])
        inside |= box
    return inside.sum(axis=1)


def _grasp(pairs: dict[str, np.ndarray], cand: dict[str, np.ndarray], i: int, n_c: int,
           params: AntipodalParams) -> AntipodalGrasp:
    s = int(cand["pair"][i])
    cost = float(cand["cost"][i])
    return AntipodalGrasp(
        X_WG=cand["X"][i].copy(),
        q=float(pairs["q"][s]),
        q_pregrasp=float(cand["q_hi"][i]),
        width=float(pairs["width"][s]),
        p_WA=pairs["p_A"][s].copy(),
        p_WB=pairs["p_B"][s].copy(),
        n_WA=pairs["n_A"][s].copy(),
        n_WB=pairs["n_B"][s].copy(),
        contact_depth=float(cand["depth"][i]),
        angle_A=float(np.arccos(np.clip(pairs["cos_A"][s], -1.0, 1.0))),
        angle_B=float(np.arccos(np.clip(pairs["cos_B"][s], -1.0, 1.0))),
        com_distance=float(cand["d_com"][i]),
        cost=cost,
        cost_direction=float(cand["cost_dir"][i]),
        cost_antipodal=float(cand["cost_anti"][i]),
        score=float(np.exp(-max(cost + params.weight_direction, 0.0))),
        n_collisions=n_c,
        ground_clearance=float(cand["clearance"][i]),
        sample_index=int(pairs["index"][s]),
    )
