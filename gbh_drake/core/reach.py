"""Reach analysis (issue 18): could ANY hook grasp of this gripper hold a structure, or is it out
of reach of the gripper?

When GbH offers no grasp, either no hook pose of this gripper around the object's hanging
structures clears the table and avoids collision (*out of reach* of the gripper: the method's
limit), or one exists and the paper's candidate set (grasp_synthesis.py) missed it. This module
answers that with a dense, bounded search, judged by the pipeline's own rules.

**The poses** (:func:`reach_poses`), for each structure (c, v, H), all in W:

* the *through axis*, the rod that passes the hole (parallel: the bar, +y_G; vertical: the
  straight finger, +z_G), on near-uniform directions within ``tilt_max_deg`` of the hole axis v
  and within ``tilt_max_deg`` of the ground normal (one every ``tilt_step_deg`` or so, the two
  caps merged where they overlap; both signs of each, as the synthesis does);
* every turn about the through axis, a full circle every ``turn_step_deg`` (the synthesis'
  ``approach_rotations_deg`` stretched to 360 deg, beyond its +-90 deg range);
* positions: parallel, the bar's centre line through c and through the midpoints between c and
  ``n_contacts`` of the contact points (the caged material then centred between the rods,
  :func:`~gbh_drake.core.grasp_synthesis.parallel_grasp_poses`); vertical, the straight rod
  through those ``n_contacts`` contact points (at d1, eq. 1), through the midpoints and through
  c, the bar beyond the caged material
  (:func:`~gbh_drake.core.grasp_synthesis.vertical_grasp_poses`). The poses are built by those
  two functions, on the structure with v replaced by the through axis, so every pose is one the
  synthesis would make for a hole with that axis.

**The rules** are the pipeline's (:func:`~gbh_drake.core.pipeline.count_collisions`,
:func:`~gbh_drake.core.scoring.collision_free`) on the same points, margins and gripper solid:
N_c < p_c, N_sweep < p_sweep (closing sweep, swept boxes grown by ``sweep_margin_spacings``
spacings) and ground distance >= ``ground_clearance`` (skipped when it is negative). Not
included: the unknown-space sweep and the resampling vote (both off by default). One rule is
added: the closed loop must hold material (at least one object point inside
:func:`~gbh_drake.core.collision.closed_loop_interior_G`), else a tilted pose that misses the
material would count as a grasp of nothing.

**The order and the bound.** The paper's candidates (grasp_synthesis with the same params)
are judged first: one of them passing decides (*reachable*, and that pose is reported). Else
the dense set, with them, is judged. The ground distance (eight corners per box) costs nothing
beside a point count, so every pose's is computed first and the poses are counted in batches
from the highest above the table down. The first collision-free pose that holds material is
then the one with the best table margin of all: if it clears the table the structure is
*reachable*; if not, no pose of the set is, and its margin is the best one ("best -1.1 mm below
the clearance"). Groups of poses that cannot come within ``depth_below`` (3 cm) of the
clearance are not generated (so a best margin below -3 cm reads nan). The search stops there,
or when ``budget_s`` (wall seconds, synthesis included) or ``max_poses`` (poses counted) run
out; a search cut short before a pose above the clearance was counted is ``undecided``. The
defaults generate about 1-3 x 10^4 poses per structure; docs/reach.md has the measured seconds
(bench/bench_reach.py).
"""

from __future__ import annotations

import dataclasses
import time
from dataclasses import dataclass, field

import numpy as np

from gbh_drake.core.collision import (
    closed_loop_interior_G,
    count_open_and_sweep,
    count_points_in_boxes,
    ground_distance,
)
from gbh_drake.core.geometry import fibonacci_cap, orthonormal_basis, unit
from gbh_drake.core.grasp_synthesis import (
    parallel_grasp_poses,
    synthesize_grasps,
    vertical_grasp_poses,
)
from gbh_drake.core.gripper import HOOK_GRIPPER, HookGripperGeometry
from gbh_drake.core.object_model import ObjectModel
from gbh_drake.core.params import GbhParams
from gbh_drake.core.results import PARALLEL, VERTICAL, HangingStructure

#: Classifications of a :class:`ReachResult`.
REACHABLE, OUT_OF_REACH, UNDECIDED, NO_STRUCTURE = ("reachable", "out of reach", "undecided",
                                                    "no structure")

#: m: groups of poses whose highest pose stays more than this below the table clearance are not
#: generated (they cannot clear the table; a best margin worse than -3 cm is not reported).
DEPTH_BELOW = 0.03
#: m: farthest an object point can be from a grasp's position (vertical: q1; parallel: the bar
#: at c) and still be one of its caged points Q: sqrt(l_f^2 + (2 q_open)^2) + slice, rounded up.
SYNTHESIS_REACH = 0.12

#: Poses counted per batch (one batch of 5000 points is ~(512, 5000) float32 arrays).
_BATCH = 512


@dataclass
class ReachResult:
    """What :func:`search_reach` found. Lengths in metres, W frame."""

    classification: str
    """``reachable`` (a pose passes every rule), ``out of reach`` (no pose of the set does),
    ``undecided`` (the budget ran out first) or ``no structure`` (nothing to search around)."""
    poses: int = 0
    """Poses generated (both kinds, every structure)."""
    evaluated: int = 0
    """Poses whose points were counted (the rest were never needed, or the budget ran out)."""
    best_X_WG: np.ndarray | None = None
    """(4, 4) pose of the gripper G in W (open, at the grasp) of the collision-free pose that
    holds material with the best table margin; None if there is none."""
    best_kind: str = ""
    """``parallel`` or ``vertical``: the best pose's kind ("" if none)."""
    best_structure: int = -1
    """Index of the best pose's structure (-1 if none)."""
    best_ground_distance: float = float("nan")
    """m: the best pose's ground distance (collision.ground_distance); nan if none."""
    best_margin: float = float("nan")
    """m: best_ground_distance - ground_clearance (negative: that far short of the rule; nan
    without a collision-free pose, or when the table rule is off)."""
    seconds: float = 0.0
    """Wall seconds of the search (synthesis and counting)."""
    complete: bool = True
    """Whether the search reached its answer (False: the budget ran out, ``undecided``)."""

    @property
    def reachable(self) -> bool:
        return self.classification == REACHABLE

    def to_dict(self) -> dict:
        """Plain values (lists, floats, str) for a row."""
        d = dataclasses.asdict(self)
        d["best_X_WG"] = None if self.best_X_WG is None else np.asarray(self.best_X_WG).tolist()
        return d


@dataclass
class ReachPoses:
    """Candidate hook poses: ``X_WG`` (M, 4, 4), ``kinds`` (M,) str and ``structure`` (M,) int
    (the index of the structure each was made for)."""

    X_WG: np.ndarray = field(default_factory=lambda: np.zeros((0, 4, 4)))
    kinds: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=object))
    structure: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=int))
    cut: bool = False
    """Whether the generation stopped at its deadline (the set is partial)."""

    def __len__(self) -> int:
        return len(self.X_WG)

    def subset(self, index) -> ReachPoses:
        return ReachPoses(self.X_WG[index], self.kinds[index], self.structure[index])

    @staticmethod
    def concatenate(parts: list[ReachPoses]) -> ReachPoses:
        parts = [p for p in parts if len(p)]
        if not parts:
            return ReachPoses()
        return ReachPoses(np.concatenate([p.X_WG for p in parts]),
                          np.concatenate([p.kinds for p in parts]),
                          np.concatenate([p.structure for p in parts]))


def through_axes(v: np.ndarray, ground_normal: np.ndarray | None, tilt_max_deg: float,
                 tilt_step_deg: float) -> np.ndarray:
    """(n, 3) unit directions within ``tilt_max_deg`` of ``v`` and within it of
    ``ground_normal`` (W), about one per ``tilt_step_deg`` (a Fibonacci cap each, v and the
    ground normal themselves first), with near-duplicates (within half a step, either sign:
    the poses use both signs) dropped."""
    half = np.radians(tilt_max_deg)
    step = np.radians(max(tilt_step_deg, 1e-3))
    n = max(1, int(np.ceil(2.0 * np.pi * (1.0 - np.cos(half)) / step**2)))
    caps = [fibonacci_cap(unit(np.asarray(a, dtype=float)), half, n) if half > 0 else
            unit(np.asarray(a, dtype=float))[None] for a in (v, ground_normal) if a is not None]
    kept: list[np.ndarray] = []
    for a in np.concatenate(caps):
        if all(abs(float(a @ b)) < np.cos(0.5 * step) for b in kept):
            kept.append(a)
    return np.stack(kept)


@dataclass(frozen=True)
class DenseSet:
    """The extent of the dense set (module docstring): through axes within ``tilt_max_deg``
    (deg) of v or of the ground normal, one every ``tilt_step_deg`` or so; turns every
    ``turn_step_deg`` (deg); ``n_contacts`` contact points; groups more than ``depth_below``
    (m) below the table clearance left out."""

    tilt_max_deg: float = 60.0
    tilt_step_deg: float = 20.0
    turn_step_deg: float = 30.0
    n_contacts: int = 3
    depth_below: float = DEPTH_BELOW


@dataclass
class PoseGroup:
    """One position, through axis and kind of :func:`reach_poses`: its turns about the axis
    (and the synthesis' signs), generated on demand by :meth:`poses`. ``one``: the structure
    the synthesis' pose function is called with (c = the position, v = the axis, H the turns);
    ``points``: the object points within :data:`SYNTHESIS_REACH` of the position; ``bound``
    (m): the highest ground distance any of its poses can have (:func:`_height_bound`; +inf
    with the table rule off); ``seq``: its place in the set's fixed order."""

    kind: str
    structure: int
    one: HangingStructure
    points: np.ndarray
    bound: float
    seq: int

    def poses(self, params: GbhParams, gripper: HookGripperGeometry) -> ReachPoses:
        return _tagged(_group(self.kind, self.one, self.points, params, gripper), self.kind,
                       self.structure)


def _search_params(params: GbhParams) -> GbhParams:
    """``params`` for the dense set's pose functions. The turns are rows of H (one approach
    direction w each, normal to the through axis), not approach_rotations_deg: one vectorised
    call per position instead of one per turn. No snap to the ground normal, no extra
    direction: the through axes are enumerated by :func:`through_axes`."""
    return dataclasses.replace(params, approach_rotations_deg=[0.0], p_theta=1.0,
                               snap_tilt_max_deg=0.0)


def pose_groups(
    obj: ObjectModel,
    structures: list[HangingStructure],
    params: GbhParams,
    gripper: HookGripperGeometry = HOOK_GRIPPER,
    *,
    dense: DenseSet = DenseSet(),
    deadline: float = float("inf"),
) -> tuple[list[PoseGroup], bool]:
    """The groups of the dense set of :func:`reach_poses` (``dense``: its extent), in its
    order, without their poses; and whether the listing stopped at ``deadline`` (partial)."""
    tilt_max_deg, tilt_step_deg, turn_step_deg = (dense.tilt_max_deg, dense.tilt_step_deg,
                                                  dense.turn_step_deg)
    n_contacts, depth_below = dense.n_contacts, dense.depth_below
    groups: list[PoseGroup] = []
    turns = np.radians(np.arange(0.0, 360.0 - 1e-9, turn_step_deg))
    search = _search_params(params)
    g = unit(np.asarray(params.ground_normal, dtype=float))
    table = params.ground_clearance >= 0
    floor = params.ground_clearance - depth_below if table else -np.inf
    nowhere = np.full((1, 3), 1e3)  # a point no grasp cages: the placement without material
    for i, s in enumerate(structures):
        if len(s.H) == 0:
            continue
        H = s.H[np.unique(np.linspace(0, len(s.H) - 1, min(n_contacts, len(s.H))).astype(int))]
        # Parallel: the bar's centre line through these; vertical: the straight rod (q1).
        anchors = np.concatenate([s.c[None], 0.5 * (H + s.c)])
        rods = np.concatenate([H + params.d1 * unit(s.c - H), anchors])
        # Each position's own points: those within SYNTHESIS_REACH of it (the rest cannot be
        # caged points of its poses), found once for all its axes and turns.
        near = {kind: [obj.points[np.linalg.norm(obj.points - p, axis=1) <= SYNTHESIS_REACH]
                       for p in positions]
                for kind, positions in ((PARALLEL, anchors), (VERTICAL, rods))}
        # The bar within tilt_max of v; the straight finger within it of v or of the vertical.
        axes = {PARALLEL: through_axes(s.v, None, tilt_max_deg, tilt_step_deg),
                VERTICAL: through_axes(s.v, g, tilt_max_deg, tilt_step_deg)}
        for kind, positions in ((PARALLEL, anchors), (VERTICAL, rods)):
            if not (params.parallel_grasps if kind == PARALLEL else params.vertical_grasps):
                continue
            for a in axes[kind]:
                e1, e2 = orthonormal_basis(a[None])
                w = np.cos(turns)[:, None] * e1 + np.sin(turns)[:, None] * e2  # (R, 3), normal
                if time.perf_counter() > deadline:
                    return groups, True
                # Without material the poses at p are those at the origin moved by p (the
                # pose functions use c - H = d1 w and put the bar or q1 at c), so one call
                # bounds every position: the highest pose at p is p . g higher.
                bounds = np.full(len(positions), np.inf)
                if table:
                    at_0 = dataclasses.replace(s, c=np.zeros(3), v=a, H=-params.d1 * w)
                    bounds = _height_bound(_group(kind, at_0, nowhere, search, gripper), kind,
                                           params, gripper).max() + positions @ g
                for p, points, bound in zip(positions, near[kind], bounds, strict=True):
                    if bound < floor:
                        continue
                    # c' = p, h' = p - d1 w: the approach (parallel) or the closing axis
                    # (vertical) along w, the bar or the straight rod (q1 = h' + d1 w) at p.
                    one = dataclasses.replace(s, c=p, v=a, H=p - params.d1 * w)
                    groups.append(PoseGroup(kind, i, one, points, float(bound), len(groups)))
    return groups, False


def reach_poses(
    obj: ObjectModel,
    structures: list[HangingStructure],
    params: GbhParams,
    gripper: HookGripperGeometry = HOOK_GRIPPER,
    *,
    deadline: float = float("inf"),
    **dense,
) -> ReachPoses:
    """The dense set of parallel and vertical hook poses around ``structures`` (module
    docstring), all of it: through axes within ``tilt_max_deg`` (deg) of v or of the ground
    normal, every ``tilt_step_deg`` or so; turns about them every ``turn_step_deg`` (deg) on
    the full circle; positions through c, ``n_contacts`` contact points (evenly spread over H)
    and the midpoints between them and c. Built with the synthesis' own pose functions on
    ``obj.points`` (those within :data:`SYNTHESIS_REACH` of the positions: the rest cannot be
    caged points).

    With the table rule on, a group of poses (one position, axis and kind: its turns and both
    signs) is left out when even its highest pose (:func:`_height_bound`) stays more than
    ``depth_below`` (m) below ``ground_clearance``: no pose of it clears the table, and its
    margin would be worse than that. Generation stops (``cut``) at ``deadline`` (a
    ``time.perf_counter()`` value). :func:`search_reach` generates only the groups it needs
    (:func:`pose_groups`). ``dense``: the fields of :class:`DenseSet`."""
    groups, cut = pose_groups(obj, structures, params, gripper, dense=DenseSet(**dense),
                              deadline=deadline)
    search = _search_params(params)
    out = ReachPoses.concatenate([grp.poses(search, gripper) for grp in groups])
    out.cut = cut
    return out


def _group(kind: str, structure: HangingStructure, points: np.ndarray, params: GbhParams,
           gripper: HookGripperGeometry) -> np.ndarray:
    """(M, 4, 4) the synthesis' poses X_WG of ``kind`` for ``structure`` on ``points``."""
    if kind == PARALLEL:
        return parallel_grasp_poses(structure, gripper, points, params)[0]
    return vertical_grasp_poses(structure, points, params, gripper)[0]


def _height_bound(X_WG: np.ndarray, kind: str, params: GbhParams,
                  gripper: HookGripperGeometry) -> np.ndarray:
    """(M,) m: the highest ground distance the poses X_WG, placed without material, can have
    once the material places them: a parallel grasp slides along y_G by at most
    q_closed - rod_width/2 (the centring), a vertical one along +z_G by at most l_f (the bar
    beyond the farthest caged point, within a finger length of q1)."""
    g = unit(np.asarray(params.ground_normal, dtype=float))
    height = ground_distance(X_WG, kind, g, params.ground_height, gripper)
    if kind == PARALLEL:
        slide = (gripper.q_closed - 0.5 * gripper.rod_width) * np.abs(X_WG[:, :3, 1] @ g)
    else:
        slide = gripper.finger_length * np.maximum(X_WG[:, :3, 2] @ g, 0.0)
    return height + slide


def candidate_poses(obj: ObjectModel, structures: list[HangingStructure], params: GbhParams,
                gripper: HookGripperGeometry) -> ReachPoses:
    """The paper's candidate set (grasp_synthesis with ``params``' turns and snaps), as
    poses."""
    grasps = synthesize_grasps(structures, obj.points, params, gripper)
    if not grasps:
        return ReachPoses()
    return ReachPoses(np.stack([g.X_WG for g in grasps]),
                      np.array([str(g.kind) for g in grasps], dtype=object),
                      np.array([g.structure_index for g in grasps], dtype=int))


def _tagged(X: np.ndarray, kind: str, structure: int) -> ReachPoses:
    return ReachPoses(X, np.full(len(X), str(kind), dtype=object),
                      np.full(len(X), structure, dtype=int))


def evaluate_poses(
    obj: ObjectModel,
    poses: ReachPoses,
    params: GbhParams,
    gripper: HookGripperGeometry = HOOK_GRIPPER,
    *,
    budget_s: float = float("inf"),
    max_poses: int | None = None,
    start: float | None = None,
) -> ReachResult:
    """Judges ``poses`` by the pipeline's rules plus "the loop holds material" (module
    docstring), counting from the highest above the table down and stopping at the first pose
    that is collision-free and holds material (the best table margin of all), or when
    ``budget_s`` wall seconds since ``start`` (default: now) have passed or ``max_poses`` poses
    have been counted."""
    start = time.perf_counter() if start is None else start
    n = len(poses)
    result = ReachResult(OUT_OF_REACH, poses=n)
    if n == 0:
        result.seconds = time.perf_counter() - start
        return result
    table = params.ground_clearance >= 0
    height = ground_distance(poses.X_WG, list(poses.kinds), np.asarray(params.ground_normal),
                             params.ground_height, gripper)
    order = np.argsort(-height, kind="stable") if table else np.arange(n)
    sweep_margin = params.sweep_margin_spacings * obj.spacing
    limit = n if max_poses is None else min(n, int(max_poses))
    done = 0
    while done < limit:
        if done and time.perf_counter() - start > budget_s:
            break
        batch = order[done : min(done + _BATCH, limit)]
        done += len(batch)
        found = _first_passing(obj, poses.subset(batch), params, gripper, sweep_margin)
        if found is None:
            continue
        _set_best(result, poses, batch[found], height, params)
        break
    result.evaluated = done
    if result.best_X_WG is None and done < n:
        # Cut short: decided only if every pose not counted is below the clearance.
        rest_below = table and height[order[done]] < params.ground_clearance
        result.classification = OUT_OF_REACH if rest_below else UNDECIDED
        result.complete = bool(rest_below)
    result.seconds = time.perf_counter() - start
    return result


def _set_best(result: ReachResult, poses: ReachPoses, j: int, height: np.ndarray,
              params: GbhParams) -> None:
    """Records pose ``j`` of ``poses`` (ground distances ``height``) as ``result``'s best, and
    the class it gives: reachable if it clears the table (or the table rule is off)."""
    table = params.ground_clearance >= 0
    result.best_X_WG = poses.X_WG[j].copy()
    result.best_kind, result.best_structure = str(poses.kinds[j]), int(poses.structure[j])
    result.best_ground_distance = float(height[j])
    if table:
        result.best_margin = float(height[j] - params.ground_clearance)
    passes = not table or height[j] >= params.ground_clearance
    result.classification = REACHABLE if passes else OUT_OF_REACH


def _first_passing(obj: ObjectModel, batch: ReachPoses, params: GbhParams,
                   gripper: HookGripperGeometry, sweep_margin: float) -> int | None:
    """Index in ``batch`` of its first pose with N_c < p_c, N_sweep < p_sweep and material in
    the closed loop, or None."""
    free = np.zeros(len(batch), dtype=bool)
    for kind in dict.fromkeys(batch.kinds):
        sel = batch.kinds == kind
        n_c, n_s = count_open_and_sweep(obj.points, batch.X_WG[sel], kind,
                                        params.collision_margin, gripper,
                                        sweep_margin=sweep_margin)
        free[sel] = (n_c < params.p_c) & (n_s < params.p_sweep)
    for k in np.flatnonzero(free):
        loop = closed_loop_interior_G(batch.kinds[k], gripper)
        if count_points_in_boxes(obj.points, batch.X_WG[k][None], [[loop]])[0, 0] > 0:
            return int(k)
    return None


def search_reach(
    obj: ObjectModel,
    structures: list[HangingStructure],
    params: GbhParams,
    gripper: HookGripperGeometry = HOOK_GRIPPER,
    *,
    budget_s: float = 2.5,
    max_poses: int = 100_000,
    dense: DenseSet = DenseSet(),
) -> ReachResult:
    """Whether any hook pose of ``gripper`` around ``structures`` (of ``obj``, in W) passes
    every rule of the pipeline (module docstring): judges the paper's candidates
    (:func:`candidate_poses`), then, if none passes, them and :func:`reach_poses` with
    :func:`evaluate_poses`, in at most about ``budget_s`` wall seconds (synthesis included;
    the group or batch under way when the budget runs out is finished) and ``max_poses``
    counted poses. No structure: classification ``no structure``."""
    start = time.perf_counter()
    if not any(len(s.H) for s in structures):
        return ReachResult(NO_STRUCTURE, seconds=time.perf_counter() - start)
    # The paper's candidates first: one of them passing decides at once.
    candidates = candidate_poses(obj, structures, params, gripper)
    first = evaluate_poses(obj, candidates, params, gripper, budget_s=budget_s, start=start)
    if first.reachable:
        return first
    groups, cut = pose_groups(obj, structures, params, gripper, dense=dense,
                              deadline=start + budget_s)
    if params.ground_clearance >= 0:
        result = _evaluate_lazily(obj, candidates, groups, params, gripper, budget_s=budget_s,
                                  max_poses=max_poses, start=start)
    else:  # no table order to exploit: every pose, in the set's order
        search = _search_params(params)
        both = ReachPoses.concatenate([candidates, *(grp.poses(search, gripper)
                                                     for grp in groups)])
        result = evaluate_poses(obj, both, params, gripper, budget_s=budget_s,
                                max_poses=max_poses, start=start)
    if cut and not result.reachable:
        result.classification, result.complete = UNDECIDED, False
    return result


def _evaluate_lazily(obj: ObjectModel, candidates: ReachPoses, groups: list[PoseGroup],
                     params: GbhParams, gripper: HookGripperGeometry, *, budget_s: float,
                     max_poses: int, start: float) -> ReachResult:
    """:func:`evaluate_poses` on ``candidates`` and every group's poses (in that order), with
    the same answer, generating only the groups it needs: the groups are generated from the
    highest ``bound`` down, and a pose is counted only once its height is above the bound of
    every group not yet generated, so the poses are still counted from the highest down (ties
    in the set's order) and the first one that passes is the same. ``poses`` is then the
    number generated."""
    search = _search_params(params)
    g = np.asarray(params.ground_normal)
    order = sorted(groups, key=lambda grp: (-grp.bound, grp.seq))
    sweep_margin = params.sweep_margin_spacings * obj.spacing

    def part(poses: ReachPoses, seq: int) -> tuple[ReachPoses, np.ndarray, np.ndarray]:
        """Poses, their keys (group seq, index in group) and their ground distances."""
        key = np.stack([np.full(len(poses), seq), np.arange(len(poses))], axis=1)
        height = ground_distance(poses.X_WG, list(poses.kinds), g, params.ground_height,
                                 gripper) if len(poses) else np.zeros(0)
        return poses, key, height

    pool = part(candidates, -1)  # generated, not yet counted
    result = ReachResult(OUT_OF_REACH)
    generated, done, k = len(candidates), 0, 0
    out_of_time = False
    while True:
        poses, key, height = pool
        safe = height > (order[k].bound if k < len(order) else -np.inf)
        if k < len(order) and safe.sum() < _BATCH:
            # Not yet a batch above every ungenerated group's bound: generate the next group.
            if time.perf_counter() - start > budget_s:
                out_of_time = True
                break
            new = part(order[k].poses(search, gripper), order[k].seq)
            pool = (ReachPoses.concatenate([poses, new[0]]), np.concatenate([key, new[1]]),
                    np.concatenate([height, new[2]]))
            generated += len(new[0])
            k += 1
            continue
        if not safe.any():
            break  # every group generated, every pose counted
        idx = np.flatnonzero(safe)
        idx = idx[np.lexsort((key[idx, 1], key[idx, 0], -height[idx]))]
        found, counted = None, 0
        for b in range(0, len(idx), _BATCH):
            if (done and time.perf_counter() - start > budget_s) or done >= max_poses:
                out_of_time = True
                break
            batch = idx[b : b + min(_BATCH, max_poses - done)]
            done += len(batch)
            counted += len(batch)
            hit = _first_passing(obj, poses.subset(batch), params, gripper, sweep_margin)
            if hit is not None:
                found = batch[hit]
                break
        if found is not None:
            _set_best(result, poses, found, height, params)
            break
        keep = np.ones(len(poses), dtype=bool)
        keep[idx[:counted]] = False
        pool = (poses.subset(np.flatnonzero(keep)), key[keep], height[keep])
        if out_of_time:
            break
    result.poses, result.evaluated = generated, done
    if result.best_X_WG is None:
        # Cut short: decided only if every pose not counted is below the clearance.
        rest = [order[k].bound] if k < len(order) else []
        rest += [float(pool[2].max())] if len(pool[2]) else []
        highest = max(rest, default=-np.inf)
        if out_of_time and highest >= params.ground_clearance:
            result.classification, result.complete = UNDECIDED, False
    result.seconds = time.perf_counter() - start
    return result
