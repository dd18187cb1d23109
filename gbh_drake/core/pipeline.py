"""The whole GbH core in one call: mesh in W -> structures -> grasps -> ranked top-k, timed."""

from __future__ import annotations

import time

import numpy as np
import trimesh

from gbh_drake.core.collision import count_open_and_sweep, ground_distance
from gbh_drake.core.grasp_synthesis import synthesize_grasps
from gbh_drake.core.gripper import HOOK_GRIPPER, HookGripperGeometry
from gbh_drake.core.hangability import detect_hangable_structures
from gbh_drake.core.object_model import ObjectModel, prepare_object
from gbh_drake.core.params import GbhParams
from gbh_drake.core.results import GbhResult, GraspCandidate, HangingStructure
from gbh_drake.core.scoring import rank_grasps, score_grasps


def detect(mesh: trimesh.Trimesh | ObjectModel, params: GbhParams, seed: int = 0
           ) -> tuple[ObjectModel, list[HangingStructure]]:
    """Stage 1 (paper Sec. 2.2): the prepared object (samples from ``seed``, CoM, ray scene) and
    its hanging structures. Raises GbhInputError for unusable input."""
    obj = prepare_object(mesh, params, seed)
    return obj, detect_hangable_structures(obj, params, seed)


def synthesize(obj: ObjectModel, structures: list[HangingStructure], params: GbhParams,
               gripper: HookGripperGeometry = HOOK_GRIPPER) -> list[GraspCandidate]:
    """Stage 2 (Sec. 2.3): parallel and vertical grasps with N_c (open gripper at X_WG), N_sweep
    (closing motion) and the ground distance computed on the object's points."""
    candidates = synthesize_grasps(structures, obj.points, params, gripper)
    count_collisions(obj, candidates, params, gripper)
    return candidates


def count_collisions(obj: ObjectModel, candidates: list[GraspCandidate], params: GbhParams,
                     gripper: HookGripperGeometry = HOOK_GRIPPER) -> None:
    """Sets ``n_collisions`` (N_c: object points inside the open gripper), ``n_sweep_collisions``
    (points the closing motion meets) and ``ground_distance`` (how far above the supporting
    surface the gripper stays, open, closing and closed) of every candidate."""
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
    for g, n, s, d in zip(candidates, n_c, n_s, height, strict=True):
        g.n_collisions, g.n_sweep_collisions, g.ground_distance = int(n), int(s), float(d)


def score(candidates: list[GraspCandidate], params: GbhParams) -> list[GraspCandidate]:
    """Stage 3 (Sec. 2.4): scores every candidate in place; returns the collision-free top-k."""
    score_grasps(candidates, params)
    return rank_grasps(candidates, params)


def plan_grasps(
    mesh: trimesh.Trimesh | ObjectModel,
    params: GbhParams | None = None,
    gripper: HookGripperGeometry = HOOK_GRIPPER,
    seed: int = 0,
) -> GbhResult:
    """Run hangability detection, grasp synthesis, collision counting and scoring on ``mesh``
    (vertices in W, metres; ``seed``: the surface sampler's). Grasps are X_WG of the open
    gripper; ``result.ranked`` holds the collision-free top-k (open, closing and closed;
    scoring.rank_grasps). Raises GbhInputError for unusable input; nothing hangable gives empty
    lists. ``result.timings`` has the seconds of each stage."""
    params = GbhParams() if params is None else params
    clock = _StageClock()
    obj = prepare_object(mesh, params, seed)
    clock.lap("sampling")
    structures = detect_hangable_structures(obj, params, seed)
    clock.lap("hangability")
    candidates = synthesize_grasps(structures, obj.points, params, gripper)
    clock.lap("synthesis")
    count_collisions(obj, candidates, params, gripper)
    clock.lap("collision")
    ranked = score(candidates, params)
    clock.lap("scoring")
    return GbhResult(structures, candidates, ranked, clock.wall, clock.cpu)


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
