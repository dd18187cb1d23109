"""The whole GbH core in one call: mesh in W -> structures -> grasps -> ranked top-k, timed."""

from __future__ import annotations

import dataclasses
import time

import numpy as np

from gbh_drake.core.arguments import argument_problem, require
from gbh_drake.core.collision import (
    COVERING_SPACINGS,
    SurfaceTriangles,
    count_open_and_sweep,
    count_rod_contacts,
    count_unknown_in_sweep,
    ground_distance,
    sweep_grid_G,
)
from gbh_drake.core.enclosure import LoopMaterial, loop_reach, planned_loop_material
from gbh_drake.core.free_space import FreeSpace
from gbh_drake.core.grasp_synthesis import closed_gripper, synthesize_grasps
from gbh_drake.core.gripper import HOOK_GRIPPER, HookGripperGeometry
from gbh_drake.core.hangability import (
    active_free_space,
    detect_with_report,
    unknown_floor,
)
from gbh_drake.core.lazy import lazy_module
from gbh_drake.core.object_model import ObjectModel, poisson_disk_samples, prepare_object
from gbh_drake.core.params import GbhParams
from gbh_drake.core.results import (
    GbhInputError,
    GbhResult,
    GraspCandidate,
    HangabilityReport,
    HangingStructure,
)
from gbh_drake.core.scoring import is_copy, rank_grasps, ranking_order, score_grasps

trimesh = lazy_module("trimesh")


def detect(mesh: trimesh.Trimesh | ObjectModel, params: GbhParams, seed: int = 0,
           free_space: FreeSpace | None = None) -> tuple[ObjectModel, list[HangingStructure]]:
    """Stage 1 (paper Sec. 2.2): the prepared object (samples from ``seed``, CoM, ray scene,
    ``free_space``: what the cameras saw free, if known) and its hanging structures. Raises
    GbhInputError for unusable input."""
    obj, structures, _ = detect_reported(mesh, params, seed, free_space)
    return obj, structures


def detect_reported(mesh: trimesh.Trimesh | ObjectModel, params: GbhParams, seed: int = 0,
                    free_space: FreeSpace | None = None
                    ) -> tuple[ObjectModel, list[HangingStructure], HangabilityReport]:
    """:func:`detect` and what the detector saw and refused on the way (the
    :class:`~gbh_drake.core.results.HangabilityReport`: the same computation, kept)."""
    _check_arguments("detect", params, seed, free_space)
    obj = prepare_object(mesh, params, seed, free_space)
    structures, report = detect_with_report(obj, params, seed)
    return obj, structures, report


def synthesize(obj: ObjectModel, structures: list[HangingStructure], params: GbhParams,
               gripper: HookGripperGeometry = HOOK_GRIPPER, free_space: FreeSpace | None = None
               ) -> list[GraspCandidate]:
    """Stage 2 (Sec. 2.3): parallel and vertical grasps with N_c (open gripper at X_WG), N_sweep
    (closing motion) and the ground distance computed on the object's points (and N_sweep on
    the unknown space too, see :func:`count_collisions`). ``free_space``: what the cameras saw
    free, when ``obj`` does not hold it already."""
    if free_space is not None and free_space is not obj.free_space:
        obj = dataclasses.replace(obj, free_space=free_space)
    candidates = synthesize_grasps(structures, obj.points, params, gripper)
    count_collisions(obj, candidates, params, gripper)
    return candidates


def count_collisions(obj: ObjectModel, candidates: list[GraspCandidate], params: GbhParams,
                     gripper: HookGripperGeometry = HOOK_GRIPPER) -> None:
    """Sets ``n_collisions`` (N_c: object points inside the open gripper), ``n_sweep_collisions``
    (points the closing motion meets) and ``ground_distance`` (how far above the supporting
    surface the gripper stays, open, closing and closed) of every candidate, and, with
    ``params.rod_clearance`` >= 0, ``rod_contacts`` of those that pass those rules (the rods and
    the bar too near the surface, ``collision.count_rod_contacts``).

    With the object's free space (``obj.free_space``) and ``params.unknown_is_occupied``, the
    unknown points of the closing sweep (``collision.count_unknown_in_sweep``: a grid of the
    swept volume at the larger of the sample spacing and the free space's margin, at most half
    a rod width so every rod's cross-section holds grid points) are added to N_sweep, for the
    candidates that pass every other check (the others are rejected already; their N_sweep
    counts object points only). Grid points below ``hangability.unknown_floor`` or within the
    free space's margin of the scanned surface are not counted: that band is the surface's own
    (no camera sees it free, the object's samples stand for it)."""
    if not candidates:
        return
    X = np.stack([g.X_WG for g in candidates])
    kinds = [g.kind for g in candidates]
    n_c = np.zeros(len(candidates), dtype=int)
    n_s = np.zeros(len(candidates), dtype=int)
    for kind in dict.fromkeys(kinds):
        sel = np.array([k == kind for k in kinds])
        n_c[sel], n_s[sel] = count_open_and_sweep(
            obj.points, X[sel], kind, params.collision_margin, gripper,
            sweep_margin=params.sweep_margin_spacings * obj.spacing)
    height = ground_distance(X, kinds, np.asarray(params.ground_normal), params.ground_height,
                             gripper)
    free = active_free_space(obj, params)
    unknown = np.zeros(len(X), dtype=int)
    if free is not None and params.unknown_sweep:
        unknown = _unknown_in_sweep(obj, free, X, kinds, n_c, n_s, height, params, gripper)
        n_s += unknown
    if params.sampling_votes > 1:
        _vote(obj, X, kinds, n_c, n_s, unknown, params, gripper)
    rods = np.full(len(X), -1)
    loops = np.full(len(X), int(LoopMaterial.UNCHECKED))
    if params.rod_clearance >= 0 or params.loop_must_enclose:
        passing = (n_c < params.p_c) & (n_s < params.p_sweep)
        if params.ground_clearance >= 0:
            passing &= height >= params.ground_clearance
        rods, loops = _lazy_rules(obj, candidates, X, kinds, passing, params, gripper)
    for g, n, s, d, r, lm in zip(candidates, n_c, n_s, height, rods, loops, strict=True):
        g.n_collisions, g.n_sweep_collisions, g.ground_distance = int(n), int(s), float(d)
        g.rod_contacts, g.loop_material = int(r), int(lm)


#: Candidates whose lazy rules (the rods' clearance, the loop's material) are checked at a
#: time, best score first.
_ROD_CHUNK = 32


def _lazy_rules(obj: ObjectModel, candidates: list[GraspCandidate], X: np.ndarray,
                kinds: list[str], passing: np.ndarray, params: GbhParams,
                gripper: HookGripperGeometry) -> tuple[np.ndarray, np.ndarray]:
    """(rod_contacts, loop_material), each (M,), of the candidates that pass the other rules
    (``passing``), checked in the ranking's order
    (:func:`~gbh_drake.core.scoring.ranking_order`) until ``top_k`` distinct ones pass both
    (:func:`~gbh_drake.core.scoring.is_copy`: a copy takes no place in the ranking): the rest
    cannot enter the ranked list and stay unchecked (-1; the rejection counts take them as
    passed). A rule that is off (``rod_clearance`` < 0, ``loop_must_enclose`` False) stays
    unchecked."""
    rods = np.full(len(X), -1)
    loops = np.full(len(X), int(LoopMaterial.UNCHECKED))
    todo = np.flatnonzero(passing)
    if len(todo) == 0:
        return rods, loops
    score_grasps(candidates, params)
    todo = todo[ranking_order([candidates[i] for i in todo], params)]
    triangles = SurfaceTriangles.of(obj.mesh.vertices, obj.mesh.faces,
                                    COVERING_SPACINGS * obj.spacing) \
        if params.rod_clearance >= 0 else None
    surface = _Surface.of(obj.mesh) if params.loop_must_enclose else None
    ranked: list[GraspCandidate] = []  # the clear ones the ranking keeps (distinct), so far
    for start in range(0, len(todo), _ROD_CHUNK):
        chunk = todo[start:start + _ROD_CHUNK]
        if triangles is not None:
            for kind in dict.fromkeys(kinds[i] for i in chunk):
                sel = chunk[[kinds[i] == kind for i in chunk]]
                rods[sel] = count_rod_contacts(obj.points, obj.spacing, triangles, X[sel], kind,
                                               params.rod_clearance, gripper)
        for i in chunk[rods[chunk] <= 0]:  # in score order, as rank_grasps takes them
            if len(ranked) >= params.top_k or any(is_copy(candidates[i], kept, params)
                                                  for kept in ranked):
                continue  # it cannot be ranked: its loop stays unchecked
            if surface is not None:
                loops[i] = surface.loop_material(X[i], kinds[i], gripper)
                if loops[i] != LoopMaterial.HELD:
                    continue
            ranked.append(candidates[i])
        if len(ranked) >= params.top_k:
            break
    return rods, loops


@dataclasses.dataclass(frozen=True)
class _Surface:
    """An object's triangles (t, 3, 3, W), their centroids (t, 3) and each one's distance from
    its centroid to its farthest corner (t,, m): what :meth:`loop_material` crops by."""

    triangles: np.ndarray
    centroids: np.ndarray
    spread: np.ndarray

    @classmethod
    def of(cls, mesh: trimesh.Trimesh) -> _Surface:
        tri = np.asarray(mesh.vertices, dtype=float)[np.asarray(mesh.faces)]
        centroids = tri.mean(axis=1)
        return cls(tri, centroids, np.linalg.norm(tri - centroids[:, None], axis=2).max(axis=1))

    def loop_material(self, X_WG: np.ndarray, kind: str, gripper: HookGripperGeometry) -> int:
        """:func:`~gbh_drake.core.enclosure.planned_loop_material` of the grasp ``kind`` open
        at ``X_WG``, the loop closed where the grasp closes it."""
        X_closed, q = closed_gripper(X_WG, kind, gripper)
        R, p = X_closed[:3, :3], X_closed[:3, 3]
        centre_G, radius = loop_reach(q, gripper)
        # Only triangles that may straddle the loop's plane (x_G = 0) within its ball.
        near = np.abs((self.centroids - p) @ R[:, 0]) <= self.spread
        near[near] = np.linalg.norm(self.centroids[near] - (p + R @ centre_G), axis=1) \
            <= radius + self.spread[near]
        return int(planned_loop_material((self.triangles[near] - p) @ R, q, gripper))


def _vote(obj: ObjectModel, X: np.ndarray, kinds: list[str], n_c: np.ndarray, n_s: np.ndarray,
          unknown: np.ndarray, params: GbhParams, gripper: HookGripperGeometry) -> None:
    """The resampling vote (``GbhParams.sampling_votes``), in place: candidates near a
    threshold are counted again on other samplings of the surface (seeds derived from the
    trial's); each keeps the counts of the median vote by pass/fail (a majority that passes
    keeps its lowest passing counts, else its lowest failing ones)."""
    near = (n_c < 2 * params.p_c) & (n_s - unknown < 2 * params.p_sweep + 2)
    idx = np.flatnonzero(near)
    if len(idx) == 0:
        return
    seed = obj.sampling[0] if obj.sampling else 0
    votes_c, votes_s = [n_c[idx]], [n_s[idx]]
    for k in range(1, params.sampling_votes):
        points, _, spacing = poisson_disk_samples(obj.mesh, params.n_points,
                                                  params.oversampling,
                                                  _vote_seed(seed, k))
        c_k = np.zeros(len(idx), dtype=int)
        s_k = np.zeros(len(idx), dtype=int)
        for kind in dict.fromkeys(kinds[i] for i in idx):
            sel = np.array([kinds[i] == kind for i in idx])
            c_k[sel], s_k[sel] = count_open_and_sweep(
                points, X[idx[sel]], kind, params.collision_margin, gripper,
                sweep_margin=params.sweep_margin_spacings * spacing)
        votes_c.append(c_k)
        votes_s.append(s_k + unknown[idx])
    c, s = np.stack(votes_c), np.stack(votes_s)  # (votes, n)
    passes = (c < params.p_c) & (s < params.p_sweep)
    majority = passes.sum(axis=0) * 2 > params.sampling_votes
    for j, i in enumerate(idx):
        pick = np.flatnonzero(passes[:, j] == majority[j])
        best = pick[np.argmin(c[pick, j] + s[pick, j])]
        n_c[i], n_s[i] = c[best, j], s[best, j]


def _vote_seed(seed: int, k: int) -> int:
    """The k-th vote's sampling seed, derived from the trial's ``seed``."""
    return int(np.random.SeedSequence([int(seed), 7919, k]).generate_state(1)[0])


def _unknown_in_sweep(obj: ObjectModel, free: FreeSpace, X: np.ndarray, kinds: list[str],
                      n_c: np.ndarray, n_s: np.ndarray, height: np.ndarray, params: GbhParams,
                      gripper: HookGripperGeometry) -> np.ndarray:
    """(M,) unknown points in the closing sweep of the candidates that pass the other checks."""
    out = np.zeros(len(X), dtype=int)
    passing = (n_c < params.p_c) & (n_s < params.p_sweep)
    if params.ground_clearance >= 0:
        passing &= height >= params.ground_clearance
    spacing = min(max(obj.spacing, free.margin), 0.5 * gripper.rod_width)
    for kind in dict.fromkeys(kinds):
        sel = np.flatnonzero(passing & np.array([k == kind for k in kinds]))
        if len(sel) == 0:
            continue
        grid = sweep_grid_G(kind, spacing, params.collision_margin,
                            params.sweep_margin_spacings * obj.spacing, gripper)
        out[sel] = count_unknown_in_sweep(free, X[sel], grid, np.asarray(params.ground_normal),
                                          unknown_floor(obj, free, params) - free.margin,
                                          obj.distance, free.margin)
    return out


def score(candidates: list[GraspCandidate], params: GbhParams) -> list[GraspCandidate]:
    """Stage 3 (Sec. 2.4): scores every candidate in place; returns the collision-free top-k."""
    score_grasps(candidates, params)
    return rank_grasps(candidates, params)


def plan_grasps(
    mesh: trimesh.Trimesh | ObjectModel,
    params: GbhParams | None = None,
    gripper: HookGripperGeometry = HOOK_GRIPPER,
    seed: int = 0,
    free_space: FreeSpace | None = None,
) -> GbhResult:
    """Run hangability detection, grasp synthesis, collision counting and scoring on ``mesh``
    (vertices in W, metres; ``seed``: the surface sampler's). Grasps are X_WG of the open
    gripper; ``result.ranked`` holds the collision-free top-k (open, closing and closed;
    scoring.rank_grasps). Raises GbhInputError for unusable input; nothing hangable gives empty
    lists (``result.hangability`` says what the detector saw and refused). ``result.timings``
    has the seconds of each stage. ``free_space``: what the cameras saw free (a scan's
    ``ScanResult.free_space``); with ``params.unknown_is_occupied`` unseen space is possibly
    occupied (through-hole rays, closing sweep)."""
    params = GbhParams() if params is None else params
    _check_arguments("plan_grasps", params, seed, free_space)
    require("plan_grasps", "gripper", gripper, HookGripperGeometry,
            "a HookGripperGeometry (gbh_drake.core.gripper.HOOK_GRIPPER)", GbhInputError)
    clock = _StageClock()
    obj = prepare_object(mesh, params, seed, free_space)
    clock.lap("sampling")
    structures, report = detect_with_report(obj, params, seed)
    clock.lap("hangability")
    candidates = synthesize_grasps(structures, obj.points, params, gripper)
    clock.lap("synthesis")
    count_collisions(obj, candidates, params, gripper)
    clock.lap("collision")
    ranked = score(candidates, params)
    clock.lap("scoring")
    return GbhResult(structures, candidates, ranked, clock.wall, clock.cpu, report)


def _check_arguments(function: str, params, seed, free_space) -> None:
    """GbhInputError naming the argument of ``function`` that is of the wrong type."""
    require(function, "params", params, GbhParams, "a GbhParams (gbh_drake.core.params)",
            GbhInputError)
    if not (isinstance(seed, int | np.integer) and not isinstance(seed, bool)
            and 0 <= seed < 2**64):
        raise GbhInputError(argument_problem(function, "seed", "an integer in [0, 2^64)", seed))
    require(function, "free_space", free_space, (FreeSpace, type(None)),
            "a FreeSpace (a scan's ScanResult.free_space) or None", GbhInputError)


class _StageClock:
    """Wall-clock and process CPU seconds between successive ``lap(name)`` calls."""

    def __init__(self) -> None:
        self.wall: dict[str, float] = {}
        self.cpu: dict[str, float] = {}
        self._t = (time.perf_counter(), time.process_time())

    def lap(self, name: str) -> None:
        now = (time.perf_counter(), time.process_time())
        self.wall[name] = now[0] - self._t[0]
        self.cpu[name] = now[1] - self._t[1]
        self._t = now
