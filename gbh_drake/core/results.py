"""Result types of the GbH core: hanging structures (paper Sec. 2.2) and grasps (Sec. 2.3-2.4).

All positions are metres and all directions unit vectors, expressed in W: the frame the input mesh
is given in. Poses are 4x4 homogeneous numpy matrices (``X_WG``: pose of the gripper frame G of
:mod:`gbh_drake.core.gripper` in W).
"""

from __future__ import annotations

import enum
from dataclasses import dataclass, field

import numpy as np


class GraspKind(enum.StrEnum):
    """How a grasp holds the object: the paper's two hook grasps (Sec. 2.3) and the baseline's.
    A ``str`` enum: it compares equal to its value and is written as it in rows and YAML."""

    PARALLEL = "parallel"
    """The bar (n2) along +-v, the hand in the loop's plane (a hook)."""
    VERTICAL = "vertical"
    """The straight finger along v or the ground normal (a hook)."""
    ANTIPODAL = "antipodal"
    """Two straight rods, the bar folded (the antipodal baseline and fallback)."""
    SCOOP = "scoop"
    """Beyond the paper (:mod:`gbh_drake.core.scoop`): a vertical hook whose straight rod goes
    down through a hole in material lying on the table, the wedge bar sliding under the material
    at table level as the loop closes (a hook)."""

    @property
    def hooks(self) -> bool:
        """Whether the grasp closes the hook's loop (the bar deployed)."""
        return self is not GraspKind.ANTIPODAL

    @property
    def keeps_straight_rod(self) -> bool:
        """Whether the grasp closes about its straight rod (the arm follows the fingers so that
        the rod in the hole stays put): vertical grasps and scoops; the others close
        symmetrically about G."""
        return self in (GraspKind.VERTICAL, GraspKind.SCOOP)


#: The paper's grasp kinds by their names (Sec. 2.3), and the scoop's.
PARALLEL, VERTICAL, SCOOP = GraspKind.PARALLEL, GraspKind.VERTICAL, GraspKind.SCOOP


class GbhInputError(ValueError):
    """The input mesh (or parameters) cannot be processed; the message says why."""


@dataclass(eq=False)
class HangingStructure:
    """One hangable structure (paper Sec. 2.2, items 1-5), all in W.

    The through-hole test has been passed: rays from ``c`` along ``+v`` and ``-v`` both miss.
    """

    c: np.ndarray
    """(3,) hanging position c_i, metres: the free point of largest clearance."""
    v: np.ndarray
    """(3,) unit hanging direction v_i: the normal of the ray plane with most hits. Its sign is
    arbitrary (u and -u are the same plane); grasp synthesis uses both."""
    H: np.ndarray
    """(K, 3) contact points h_i^j, metres: where the rays of the chosen plane hit the mesh."""
    m: float
    """Fraction of the plane's rays that hit the mesh (1 = a closed loop around c)."""
    a: np.ndarray
    """(3,) unit mean direction of the rays that miss (where the loop is open); zeros if m = 1."""
    clearance: float = 0.0
    """Distance from c to the mesh surface, metres."""
    contact_point: np.ndarray = field(default_factory=lambda: np.zeros(3))
    """(3,) the contact candidate whose segment to the CoM gave c, metres."""
    n_rays: int = 0
    """Number of rays cast in the chosen plane (m = len(H) / n_rays)."""
    miss_directions: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)))
    """(n_rays - K, 3) unit directions of the rays from c that miss (for drawing; a is their
    normalised mean)."""
    hit_index: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=int))
    """(K,) the index of each hit point's ray among the plane's ``n_rays`` (adjacent rays are
    adjacent along the rim); empty when not known."""
    hang_drop: np.ndarray = field(default_factory=lambda: np.zeros(0))
    """(K,) metres: how much deeper the object hangs when the material at each hit point, once
    hooked, slides along the rim to where it comes to rest (:func:`~gbh_drake.core.sliding.rim_slide`;
    0 at a stable hang point); empty when not known (counted as 0)."""


@dataclass(eq=False)
class GraspCandidate:
    """One grasp of the hook gripper on a hanging structure, scored (paper Sec. 2.3-2.4)."""

    X_WG: np.ndarray
    """(4, 4) pose of the gripper frame G in W (G: palm centre, +z_G approach, +y_G closing)."""
    kind: GraspKind
    """``"parallel"`` (bar along +-v) or ``"vertical"`` (straight finger along v or ground)."""
    structure_index: int
    """Index of the structure in the detector's list."""
    structure: HangingStructure
    """The hanging structure this grasp hooks."""
    h: np.ndarray
    """(3,) the contact point h_i^j this grasp was generated from (turned with the grasp when
    ``turn_deg`` is not 0: the material the turned loop cages), metres in W."""
    turn_deg: float = 0.0
    """Degrees the grasp is turned from the paper's pose about the hole's axis (parallel) or
    the straight finger (vertical); 0: the paper's pose (``GbhParams.approach_rotations_deg``)."""
    n_collisions: int = -1
    """N_c (paper): object points inside the gripper's solid model (open) at X_WG; -1 if not
    counted."""
    n_sweep_collisions: int = -1
    """N_sweep (ours): object points that the moving parts of the gripper meet while closing
    (inside the volume they sweep from the open to the closed pose, grown by the sweep margin,
    and not inside the open model), i.e. material the loop would stop on; -1 if not counted.
    See :mod:`gbh_drake.core.collision`."""
    ground_distance: float = float("nan")
    """m: height of the lowest point of the gripper's solid model above the supporting surface,
    over the grasp pose (open), the closing sweep and the closed pose (negative: below it); nan
    if not computed."""
    rod_contacts: int = -1
    """Ours: witnesses that the object's surface comes nearer than ``GbhParams.rod_clearance``
    to the rods and the bar (open and closing; :func:`~gbh_drake.core.collision.count_rod_contacts`);
    0: clear; -1 if not checked (the check is off, an earlier rule refused the grasp, or
    ``top_k`` better-scored grasps were clear: it cannot be ranked)."""
    loop_material: int = -1
    """Ours: what the loop closed at this grasp holds of the object's surface, a
    :class:`~gbh_drake.core.enclosure.LoopMaterial` (1: material in its hole; 0: none; 2: the
    loop runs through the surface; -1: not checked, as ``rod_contacts``;
    ``GbhParams.loop_must_enclose``)."""
    alpha: float = float("nan")
    """Radians: angle between R n1 (toward the wrist) and the anti-gravity direction."""
    beta: float = float("nan")
    """Radians: angle between a_i and the direction from the held material toward c_i."""
    s_alpha: float = float("nan")
    """S_alpha = exp(-alpha^2 / gamma_alpha)."""
    s_beta: float = float("nan")
    """S_beta = 1 if m_i = 1 else exp(-beta^2 / gamma_beta)."""
    hang_drop: float = 0.0
    """m (ours): how much deeper the object hangs once the material this grasp cages slides
    along the structure's rim to where it comes to rest (the structure's ``hang_drop`` at the
    hit point nearest ``h``; :mod:`gbh_drake.core.sliding`)."""
    s_hang: float = 1.0
    """S_hang = exp(-(hang_drop / hang_slide_scale)^2) (ours; 1 with the paper's score)."""
    score: float = float("nan")
    """S_total = m_i * S_beta * S_alpha (* S_hang, ours)."""


@dataclass(eq=False)
class RefusedPosition:
    """A hanging position the detector found and refused (what it saw, for a report)."""

    c: np.ndarray
    """(3,) the position, metres in W."""
    clearance: float
    """Distance (m) from c to the surface."""
    rule: str
    """Which rule refused it (:data:`HANGABILITY_RULES`)."""
    v: np.ndarray | None = None
    """(3,) the hole's axis found at c (None when refused before the axis was searched)."""
    m: float = float("nan")
    """Fraction of the ray plane's rays that hit (nan before the axis was searched)."""


#: Why the detector refused a hanging position, in the order the rules apply:
#: ``too small``: its clearance is under ``GbhParams.min_clearance`` (nothing fits);
#: ``not a through-hole``: a ray from c along +v or -v hits the mesh (a pocket, not a hole);
#: ``exit proof``: no line through c near v leads out through space the cameras saw free
#: (``GbhParams.unknown_is_occupied``; only with a scan's free space).
HANGABILITY_RULES = ("too small", "not a through-hole", "exit proof")


@dataclass(eq=False)
class HangabilityReport:
    """What the hangability detector saw, stage by stage (paper Sec. 2.2): how many samples,
    contact candidates, clusters and hanging positions, and which rule refused each refused
    position; it says why an object has no hanging structure."""

    samples: int = 0
    """Surface samples of the object."""
    contact_candidates: int = 0
    """Samples whose outward normal is within ``contact_angle_deg`` of the direction to the
    CoM."""
    contact_angle_deg: float = float("nan")
    """The rule's angle (deg)."""
    best_contact_angle_deg: float = float("nan")
    """The smallest angle (deg) between a sample's normal and its direction to the CoM (how
    near the closest sample came, when none is a candidate)."""
    clusters: int = 0
    """Clusters of contact candidates (each gives at most ``positions_per_cluster`` hanging
    positions: one by default)."""
    merged: int = 0
    """Hanging positions merged into a coincident one with more clearance."""
    positions: int = 0
    """Hanging positions whose hole was tested (after the clearance rule and merging)."""
    exit_proof: bool = False
    """Whether the exit proof ran (a scan's free space and ``unknown_is_occupied``)."""
    structures: int = 0
    """Hanging structures kept."""
    refused: list[RefusedPosition] = field(default_factory=list)
    """Every refused position, in the order of :data:`HANGABILITY_RULES`."""

    def refused_by(self) -> dict[str, int]:
        """How many positions each rule refused (keys :data:`HANGABILITY_RULES`, in order)."""
        return {rule: sum(r.rule == rule for r in self.refused) for rule in HANGABILITY_RULES}

    def summary(self) -> str:
        """What the detector saw, in words."""
        text = (f"{self.samples} surface samples, {self.contact_candidates} contact candidates "
                f"(normal within {self.contact_angle_deg:g} deg of the direction to the centre "
                f"of mass")
        if self.contact_candidates == 0:
            text += f"; the nearest came within {self.best_contact_angle_deg:.0f} deg"
        text += f"), {self.clusters} clusters"
        counts = self.refused_by()
        if self.clusters:
            text += (f"; {counts['too small']} hanging positions too small, {self.merged} "
                     f"merged, {self.positions} tested: {counts['not a through-hole']} not a "
                     "through-hole")
            if self.exit_proof:
                text += f", {counts['exit proof']} refused by the exit proof"
            text += f", {self.structures} kept"
        if not self.exit_proof:
            text += ("; the exit proof did not run (no free space: the mesh alone says what "
                     "is a hole)")
        return text


@dataclass(eq=False)
class GbhResult:
    """Everything one run of :func:`gbh_drake.core.pipeline.plan_grasps` produced."""

    structures: list[HangingStructure]
    """Hangable structures, best (largest m) first."""
    candidates: list[GraspCandidate]
    """All synthesised grasps with N_c counted and scores computed (colliding ones included)."""
    ranked: list[GraspCandidate]
    """Collision-free grasps (N_c < p_c, N_sweep < p_sweep, at least ``ground_clearance`` above
    the supporting surface), best score first, at most ``top_k``."""
    timings: dict[str, float] = field(default_factory=dict)
    """Wall-clock seconds per stage: sampling, hangability, synthesis, collision, scoring."""
    cpu_timings: dict[str, float] = field(default_factory=dict)
    """CPU seconds of this process per stage (all threads; insensitive to other processes)."""
    hangability: HangabilityReport | None = None
    """What the detector saw and refused (:func:`~gbh_drake.core.hangability.detect_with_report`)."""
