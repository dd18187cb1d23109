"""The ranked grasps of one scan in the robot's base frame B, as dataclasses: what
``gbh_drake.grasps(...)`` returns and ``gbh grasps`` and ``gbh run`` write (``document.py``).

:func:`make_result` builds it from the GbH core's results in W and the pose of B in W (the
identity for a scan given in B; a station whose arm stands elsewhere transforms).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from gbh_drake.core.gripper import HOOK_GRIPPER, HookGripperGeometry, X_B_link8
from gbh_drake.core.results import GraspCandidate, HangabilityReport, HangingStructure
from gbh_drake.scan_grasps.waypoints import Waypoints, grasp_waypoints

#: How many of the refused candidates nearest to passing are kept (drawn, written).
N_REFUSED = 3


@dataclass
class Grasp:
    """One ranked (or refused) grasp in B. Poses are (4, 4), lengths metres."""

    rank: int
    """1 for the best; 0 for a refused candidate."""
    kind: str
    """``parallel`` (the bar along the hole's axis) or ``vertical`` (the straight rod in the
    hole); how it closes: see :class:`~gbh_drake.core.results.GraspKind`."""
    score: float
    """S_total = m S_beta S_alpha."""
    terms: dict[str, float]
    """``m`` (the structure's closedness), ``s_alpha``, ``s_beta``, ``alpha_deg`` (the approach
    from straight down), ``beta_deg`` (nan for a closed loop)."""
    structure: int
    """Index of the hanging structure it hooks."""
    turn_deg: float
    """Degrees the approach is turned from the paper's pose (``approach_rotations_deg``)."""
    waypoints: Waypoints
    """G at the pre-grasp, the grasp (open), closed and lifted."""
    checks: dict[str, float]
    """``n_collisions`` (N_c), ``n_sweep_collisions``, ``ground_distance`` (m)."""
    candidate: GraspCandidate
    """The core's candidate (in the scan's frame W)."""

    @property
    def X_BG(self) -> np.ndarray:
        """The open gripper's pose at the grasp."""
        return self.waypoints.grasp

    @property
    def X_B_link8(self) -> np.ndarray:
        """The flange's pose at the grasp."""
        return X_B_link8(self.waypoints.grasp)


@dataclass
class NoGrasp:
    """Why there is no grasp: ``outcome`` is the trial's (``empty_scan``,
    ``no_hangable_structure`` or ``no_grasp_found``), ``message`` says it in words."""

    outcome: str
    message: str
    rejected_by: dict[str, int] = field(default_factory=dict)
    """Candidates each collision rule removed (``core.rejections``), for ``no_grasp_found``."""
    closest: str = ""
    """How near the closest candidate came to passing the last rule."""


@dataclass
class GraspsResult:
    """The ranked grasps of one scan, in B (see the module docstring)."""

    input_kind: str
    """``mesh``, ``point_cloud``, ``depth_images`` or ``simulation`` (``gbh run``)."""
    input_path: str
    table: object
    """The ``TablePlane`` in B (GbH's supporting surface)."""
    table_source: str
    free_space: bool
    """Whether the scan came with what the cameras saw free (the exit proof runs on it unless
    the parameters say otherwise: ``hangability.exit_proof``)."""
    params: object
    """The ``GbhParams`` used."""
    seed: int
    structures: list[HangingStructure]
    """In B, best first."""
    grasps: list[Grasp]
    """The ranked grasps, best first (empty: see ``none``)."""
    refused: list[Grasp] = field(default_factory=list)
    """The refused candidates that came closest to passing (for a look at what was refused)."""
    none: NoGrasp | None = None
    hangability: HangabilityReport | None = None
    n_candidates: int = 0
    notes: list[str] = field(default_factory=list)
    warnings: list[str] = field(default_factory=list)
    timings: dict[str, float] = field(default_factory=dict)
    scan: object = None
    """The ``ScanResult`` in B (the object's mesh, points, free space), for drawing."""
    extra: dict = field(default_factory=dict)
    """What the writer adds to the document's ``input`` (``gbh run``: the scenario)."""


def make_result(*, structures_W: list[HangingStructure], candidates_W: list[GraspCandidate],
                ranked_W: list[GraspCandidate], params, seed: int, scan_B, table_B,
                table_source: str, X_BW: np.ndarray | None = None, pick=None,
                hangability: HangabilityReport | None = None, input_kind: str = "",
                input_path: str = "", notes: list[str] | None = None,
                warnings: list[str] | None = None, unseen_B: np.ndarray | None = None,
                empty_message: str = "", gripper: HookGripperGeometry = HOOK_GRIPPER
                ) -> GraspsResult:
    """A :class:`GraspsResult` from the GbH core's outputs in W (``structures_W``,
    ``candidates_W``, ``ranked_W``) with the scan ``scan_B`` and the table ``table_B`` already
    in B, ``X_BW`` (4, 4; None: W is B); ``pick``: a ``PickConfig`` for the waypoints
    (default: the scenario's defaults)."""
    from gbh_drake.core.pick_config import PickConfig
    from gbh_drake.core.rejections import (
        closest_rejected,
        count_rejections,
        no_grasp_message,
    )

    pick = PickConfig() if pick is None else pick
    X = np.eye(4) if X_BW is None else np.asarray(X_BW, dtype=float)
    points_B = np.asarray(scan_B.mesh_W.vertices, dtype=float) if scan_B is not None else \
        np.zeros((0, 3))
    index = {id(s): i for i, s in enumerate(structures_W)}

    def grasp(rank: int, g: GraspCandidate) -> Grasp:
        way = grasp_waypoints(X @ g.X_WG, g.kind, points_B, table_B, pick, unseen_B=unseen_B,
                              gripper=gripper)
        return Grasp(rank, str(g.kind), float(g.score),
                     {"m": float(g.structure.m), "s_alpha": float(g.s_alpha),
                      "s_beta": float(g.s_beta), "alpha_deg": float(np.degrees(g.alpha)),
                      "beta_deg": float(np.degrees(g.beta))},
                     index.get(id(g.structure), int(g.structure_index)), float(g.turn_deg), way,
                     {"n_collisions": int(g.n_collisions),
                      "n_sweep_collisions": int(g.n_sweep_collisions),
                      "ground_distance": float(g.ground_distance)}, g)

    none = None
    if empty_message:
        none = NoGrasp("empty_scan", empty_message)
    elif not structures_W:
        none = NoGrasp("no_hangable_structure", no_structure_message(hangability))
    elif not ranked_W:
        rejections = count_rejections(candidates_W, params)
        none = NoGrasp("no_grasp_found", no_grasp_message(len(candidates_W), len(structures_W),
                                                          rejections),
                       dict(rejections.removed), rejections.closest)
    refused = [grasp(0, g) for g in closest_rejected(candidates_W, params, N_REFUSED)] \
        if candidates_W else []
    return GraspsResult(
        input_kind, input_path, table_B, table_source,
        scan_B is not None and scan_B.free_space is not None,
        params, int(seed), [structure_in(s, X) for s in structures_W],
        [grasp(rank + 1, g) for rank, g in enumerate(ranked_W)], refused, none, hangability,
        len(candidates_W), list(notes or []), list(warnings or []), scan=scan_B)


def no_structure_message(report: HangabilityReport | None) -> str:
    """Why there is no hanging structure, in words: what the detector saw (its report's
    summary), when it says."""
    return "no hangable structure found" + (f": {report.summary()}" if report is not None
                                            else "")


def structure_in(s: HangingStructure, X_BW: np.ndarray) -> HangingStructure:
    """The structure ``s`` (in W) in B."""
    if np.array_equal(X_BW, np.eye(4)):
        return s
    R, t = X_BW[:3, :3], X_BW[:3, 3]
    return HangingStructure(R @ s.c + t, R @ s.v, s.H @ R.T + t, s.m, R @ s.a, s.clearance,
                            R @ s.contact_point + t, s.n_rays, s.miss_directions @ R.T)
