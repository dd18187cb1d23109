"""The reach analysis of one trial (issue 18): could any hook grasp have held the object, on the
trial's own scan and on the true mesh where it lay?

:func:`reach_of_trial` runs :func:`gbh_drake.core.reach.search_reach` twice: on the scan (the
structures GbH found on it, when given, else detected again) and on the true mesh in W at the
pose it rested in (structures detected there, same params and seed). The answer is a
:class:`TrialReach`, a row's ``reach`` field (:meth:`TrialReach.to_dict`); the taxonomy reads
it (:mod:`gbh_drake.experiment.taxonomy`).

Pure numpy/trimesh (no Drake): the worker passes the meshes.
"""

from __future__ import annotations

import time
from dataclasses import asdict, dataclass

import trimesh

from gbh_drake.core.object_model import ObjectModel
from gbh_drake.core.params import GbhParams
from gbh_drake.core.pipeline import detect
from gbh_drake.core.reach import NO_STRUCTURE, ReachResult, search_reach
from gbh_drake.core.results import GbhInputError, HangingStructure

#: Wall seconds each of the two searches may take: none. A row must not depend on the machine's
#: speed or load (a wall-clock cut made the pose counts, and could make the class, differ
#: between identical runs); the search is bounded by its pose set instead (at most
#: ``max_poses`` counted; docs/reach.md has the measured seconds).
BUDGET_S = float("inf")


@dataclass
class TrialReach:
    """A row's ``reach`` field: each mesh's classification (``reachable``, ``out of reach``,
    ``undecided``, ``no structure``), the best table margin (mm) of each, the poses tried and
    the wall seconds, both searches together."""

    scan: str
    """On the trial's scan (the structures GbH found on it)."""
    true: str
    """On the true mesh at the pose the object rested in (structures detected there)."""
    best_margin_mm: float
    """mm: the true mesh's best table margin (nan: no collision-free pose within 3 cm)."""
    scan_best_margin_mm: float
    """mm: the same on the scan."""
    poses: int
    """Poses generated, both searches."""
    seconds: float

    def to_dict(self) -> dict:
        return asdict(self)

    def row(self) -> dict:
        """A row's ``reach`` field: :meth:`to_dict` without ``seconds`` (a measurement of the
        run, not a result: the row's ``stage_times["reach"]`` has it), so that identical runs
        give identical rows."""
        out = self.to_dict()
        out.pop("seconds")
        return out


def reach_of_trial(scan_mesh: trimesh.Trimesh | ObjectModel | None,
                   true_mesh: trimesh.Trimesh | None, params: GbhParams, *, seed: int = 0,
                   scan_structures: list[HangingStructure] | None = None,
                   budget_s: float = BUDGET_S) -> TrialReach:
    """The reach of one trial: ``scan_mesh`` (W; or the ObjectModel GbH prepared from it, then
    with ``scan_structures`` its structures: not detected again) and ``true_mesh`` (the
    object's mesh in W where it rested), each searched with ``params`` (the trial's, table
    included; ``budget_s``: a wall-clock cut, none by default: rows stay deterministic);
    ``seed`` the surface sampler's. A missing or
    unusable mesh reads ``no structure``."""
    start = time.perf_counter()
    scan = _search(scan_mesh, params, seed, scan_structures, budget_s)
    true = _search(true_mesh, params, seed, None, budget_s)
    return TrialReach(scan=scan.classification, true=true.classification,
                      best_margin_mm=1e3 * true.best_margin,
                      scan_best_margin_mm=1e3 * scan.best_margin,
                      poses=scan.poses + true.poses, seconds=time.perf_counter() - start)


def _search(mesh, params: GbhParams, seed: int, structures, budget_s: float) -> ReachResult:
    if mesh is None:
        return ReachResult(NO_STRUCTURE)
    try:
        if structures is None or not isinstance(mesh, ObjectModel):
            mesh, structures = detect(mesh, params, seed)
    except GbhInputError:
        return ReachResult(NO_STRUCTURE)
    return search_reach(mesh, structures, params, budget_s=budget_s)
