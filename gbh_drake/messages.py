"""The messages the trial's systems pass each other: plain dataclasses and enums, no Drake.

The pick-and-carry machine's :class:`PickStatus` (its :class:`Mode` and the :class:`Attempt` s
that came away empty), the monitor's :class:`Verdict` (an :class:`Outcome`, :class:`HeldBy`) and
a method's :class:`GraspSearch` (why it offered no grasp). The systems, the records, the
experiment's report and the tests import them from here; importing this module loads no Drake.
"""

from __future__ import annotations

import enum
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from gbh_drake.planning.pick import PickPlan, Refusal
    from gbh_drake.planning.regrasp import RegraspPlan



class Mode(enum.Enum):
    SETTLE = "settle"
    PLAN = "plan"
    # A regrasp (pick with a pinch, set down anew, re-scan), before the pick that is judged.
    REGRASP_APPROACH = "regrasp_approach"
    REGRASP_INSERT = "regrasp_insert"
    REGRASP_CLOSE = "regrasp_close"
    REGRASP_LIFT = "regrasp_lift"
    REGRASP_TURN = "regrasp_turn"
    REGRASP_LOWER = "regrasp_lower"
    REGRASP_RELEASE = "regrasp_release"
    REGRASP_RETREAT = "regrasp_retreat"
    REGRASP_HOME = "regrasp_home"
    RESCAN = "rescan"
    # A retry after a lift that came away empty: open, go home, re-scan, plan again.
    RETRY_RELEASE = "retry_release"
    RETRY_HOME = "retry_home"
    APPROACH = "approach"
    INSERT = "insert"
    CLOSE = "close"
    LIFT = "lift"
    CARRY = "carry"
    HOLD = "hold"
    CAGE_TEST = "cage_test"
    LOWER = "lower"
    RELEASE = "release"
    RETREAT = "retreat"
    DONE = "done"
    NO_GRASP = "no_grasp"
    NO_REACHABLE_GRASP = "no_reachable_grasp"


#: Modes in which the machine has stopped for good.
FINAL_MODES = (Mode.DONE, Mode.NO_GRASP, Mode.NO_REACHABLE_GRASP)


@dataclass
class Attempt:
    """An executed grasp that came away empty (a retry followed). W frame, metres, newtons."""

    kind: str
    rank: int
    score: float
    source: str
    """The input port the grasp came from."""
    p_WG: np.ndarray
    """(3,) the open gripper's origin at the grasp."""
    c_W: np.ndarray | None
    """(3,) the centre c of the hanging structure it hooked (None: a grasp without one)."""
    load: float
    """What the lift added to the hand's vertical load (below the machine's
    :data:`~gbh_drake.systems.pick_and_carry.EMPTY_LOAD`)."""
    time: float
    """Simulated time (s) the lift ended."""
    R_WG: np.ndarray | None = None
    """(3, 3) the open gripper's orientation at the grasp (None: not known)."""

    def as_dict(self) -> dict:
        """Plain numbers and lists (a record's ``attempts`` entry)."""
        return {"kind": self.kind, "rank": int(self.rank), "score": float(self.score),
                "source": self.source, "p_WG": np.asarray(self.p_WG, dtype=float).tolist(),
                "R_WG": None if self.R_WG is None else
                np.asarray(self.R_WG, dtype=float).tolist(),
                "c_W": None if self.c_W is None else np.asarray(self.c_W, dtype=float).tolist(),
                "load": float(self.load), "time": float(self.time)}


@dataclass
class PickStatus:
    """What the machine is doing and has done (the ``status`` output)."""

    mode: Mode = Mode.SETTLE
    phase_start: dict[str, float] = field(default_factory=dict)
    """Simulated time (s) at which each mode was entered, by mode value."""
    n_grasps: int = 0
    """How many grasps were offered (primary and fallback)."""
    plan: PickPlan | None = None
    """The plan being executed (None until PLAN succeeds)."""
    score: float = float("nan")
    """The executed grasp's score."""
    fallback: bool = False
    """Whether the executed grasp came from ``fallback_grasps``."""
    source: str = ""
    """The input port the executed grasp came from (``grasps``, ``scoop_grasps``,
    ``tall_scoop_grasps``, ``fallback_grasps``; "" until one is planned)."""
    refusals: list[Refusal] = field(default_factory=list)
    """Every grasp that was tried and could not be planned, with its reason."""
    plan_seconds: float = 0.0
    """Wall seconds spent in PLAN (the grasps' evaluation included)."""
    grasp_seconds: list[float] = field(default_factory=list)
    """Wall seconds planning each grasp tried, in order."""
    grasps_seconds: float = 0.0
    """Wall seconds the grasps' evaluation took (GbH or the antipodal sampler on the scan)."""
    regrasps: list[RegraspPlan] = field(default_factory=list)
    """The regrasps executed (each a pick-and-place into a resting pose, then a re-scan)."""
    regrasp_note: str = ""
    """Why a regrasp the method offered was not executed ("" if it was, or none was offered)."""
    grasp_X_WG: np.ndarray | None = None
    """(4, 4) the executed grasp's open-gripper pose in W (None until one is planned)."""
    grasp_c_W: np.ndarray | None = None
    """(3,) the centre of the hanging structure it hooks (None: none, or not planned yet)."""
    attempts: list[Attempt] = field(default_factory=list)
    """Executed grasps whose lift came away empty, each followed by a retry (beyond the paper)."""
    skipped: int = 0
    """Grasps skipped on retries for lying within the machine's
    :data:`~gbh_drake.systems.pick_and_carry.TRIED_RADIUS` of a failed one."""
    set_down_notes: list[str] = field(default_factory=list)
    """What the set-down sensed and did beyond its plan (after the cage test): where LOWER
    counted the object as down (or the hand as pressing it), and each time RELEASE or RETREAT
    found the bar lifting it again and withdrew (simulated times, loads in N)."""
    second_passes: int = 0
    """Retries whose plan, nothing else being left, went back over the skipped grasps and
    skipped only those at a failed grasp's own pose (:func:`~gbh_drake.planning.choice.choose`'s
    ``skip_again``)."""

    @property
    def phase(self) -> str:
        return self.mode.value

    @property
    def finished(self) -> bool:
        return self.mode in FINAL_MODES




class Outcome(enum.StrEnum):
    """What a trial came to: decided here, by the monitor, and copied by every record and row
    (a ``str`` enum: it compares equal to, and is written as, its value)."""

    SUCCESS = "success"
    """Lifted and carried over the place without falling, clear of the table while held."""
    TOUCHED_DOWN = "touched_down"
    """Lifted and carried over the place without falling, but after the lift it came down onto
    the table while the hand held it (the table bore it for a moment: dragged, not carried
    clear). Its own class, not a success (issue 42)."""
    NOT_LIFTED = "not_lifted"
    DROPPED_DURING_LIFT = "dropped_during_lift"
    DROPPED_DURING_CARRY = "dropped_during_carry"
    NO_REACHABLE_GRASP = "no_reachable_grasp"
    """Grasps were offered; none could be planned."""
    NO_HANGABLE_STRUCTURE = "no_hangable_structure"
    """GbH found nothing to hang the object by (a result, not an error)."""
    NO_GRASP_FOUND = "no_grasp_found"
    """The method offered no grasp (GbH: no candidate passed its rules)."""
    EMPTY_SCAN = "empty_scan"
    """The scan holds no object."""
    INCOMPLETE = "incomplete"
    """The machine has not finished (the verdict while it runs, or a trial cut off)."""
    ERROR = "error"
    """The pipeline raised (an experiment's row of a broken trial; never a monitor verdict)."""


class HeldBy(enum.StrEnum):
    """How a carried object was held (decided by the cage test)."""

    NONE = ""
    CAGE = "cage"
    PINCH = "pinch"



@dataclass
class GraspSearch:
    """Why a method offered no grasp (the monitor's ``grasp_search`` input): the outcome
    (``empty_scan``, ``no_hangable_structure`` or ``no_grasp_found``) and its reason in words.
    Made by the method's :class:`~gbh_drake.systems.grasp_search.GraspSearchReport`."""

    outcome: Outcome = Outcome.NO_GRASP_FOUND
    reason: str = "no grasp to try"
    rejected_by: dict[str, int] = field(default_factory=dict)
    """GbH's candidates each collision rule removed, in the order the rules apply
    (:func:`gbh_drake.core.rejections.count_rejections`); empty without GbH candidates."""



@dataclass
class Verdict:
    """What happened to the object. Lengths in metres, forces in newtons, times in seconds."""

    outcome: Outcome = Outcome.INCOMPLETE
    """The :class:`Outcome` (``incomplete`` while the machine has not finished)."""
    success: bool = False
    reason: str = "the pick has not finished"
    held_by: HeldBy = HeldBy.NONE
    """``cage`` or ``pinch`` when the object was carried, else empty."""
    lifted_at: float = float("nan")
    """Time when the object's lowest point first reached ``lifted_height``."""
    dropped_at: float = float("nan")
    dropped_phase: str = ""
    sank_at: float = float("nan")
    sank_phase: str = ""
    """When and in which phase the lifted object came back down onto the table while a gripper
    body still touched it (dragged, not dropped; "" if it did not)."""
    max_clearance: float = 0.0
    """Highest lowest point above the table while carried."""
    clearance_after_hold: float = float("nan")
    """Lowest point above the table at the end of the hold (full force)."""
    touching: dict[str, list[str]] = field(default_factory=dict)
    """Gripper bodies that touched the object in each phase."""
    table_touch_while_carried: bool = False
    """Whether the object touched the table during the lift or carry after being lifted."""
    touched_down_at: float = float("nan")
    touched_down_phase: str = ""
    """When and in which phase (lift, carry, hold) the object, lifted and still touched by a
    gripper body, first touched the table ("" if it did not: the outcome ``touched_down``)."""
    min_clearance_after_lift: float = float("nan")
    """Lowest height (m) its lowest point came back down to, below the highest it had reached,
    after it was lifted and until the end of the hold (the lift's own rise through
    ``lifted_height`` excluded; nan: never lifted, or it never came down); ``min_clearance_phase``:
    the phase it was in then (lift, carry or hold)."""
    min_clearance_phase: str = ""
    squeeze_force: float = float("nan")
    """Mean squeeze force of the fingers during the carry and hold (N)."""
    finger_q_cage_test: float = float("nan")
    """Mean finger position at the end of the cage test (m; closed loop: q_closed)."""
    cage_test_held: bool = False
    """Whether the object was still held at the end of the cage test."""
    loop_closed: bool = False
    """Whether both fingers ended the cage test within ``closed_tolerance`` of their closed
    position (recorded; the cage is decided by ``loop_encloses``)."""
    bar_deployed: bool = True
    """Whether the bar was out (a hook) during the cage test; folded: two straight rods."""
    loop_encloses: bool = False
    """Whether the loop (palm, rods, bar at the fingers measured at the end of the cage test)
    enclosed the object's material (:func:`gbh_drake.core.enclosure.loop_enclosure`): it links
    the material, does not pass through it, and its gap is narrower than the material."""
    loop_linked: bool = False
    """Whether the loop linked the object's material (the topological test)."""
    material_in_gap: bool = False
    """Whether the loop passed through the material: it lay between the bar's tip and the
    straight rod, where the fingers close (a pinch, however long it stayed)."""
    loop_gap: float = float("nan")
    """m: from the bar's tip to the straight rod's inner face at the end of the cage test (0:
    closed; nan: not judged, e.g. the bar folded)."""
    material_thickness: float = float("nan")
    """m: the thinnest section of the material inside the loop (inf: none there)."""
    settled_at: list[float] = field(default_factory=list)
    """The object's position (W) when planning began (after settling, when it was scanned)."""
    planned_poses: list[list[float]] = field(default_factory=list)
    """The object's pose (W: x, y, z m, roll, pitch, yaw rad) each time planning began: once,
    or once more after each regrasp (where it was set down anew and scanned again)."""
    released_at: list[float] = field(default_factory=list)
    """The object's position (W) at the end, after release."""
    released_pose: list[float] = field(default_factory=list)
    """The object's pose at the end (W: x, y, z m, roll, pitch, yaw rad)."""
    released_on_table: bool = False
    """Whether the object lies on the table, free of the gripper, at the end."""
    released_standing: bool = False
    """Whether the object rests on the table at the end, free of the gripper or not (a hand
    that could not withdraw without lifting it stops round it: ``pick.relift_tries``)."""
    earlier_attempts: list[dict] = field(default_factory=list)
    """For each executed grasp whose lift came away empty (a retry followed): the lift's
    record as it stood then (``lifted_at``, ``dropped_at``, ``dropped_phase``,
    ``max_clearance``, ``touching``); the fields above are the last attempt's."""




def verdict_final(mode: Mode) -> bool:
    """Whether the verdict is final once the machine is in ``mode``: it has stopped, or the
    cage test is over (later phases set the object down; they judge nothing)."""
    order = [m.value for m in Mode]
    return mode in FINAL_MODES or order.index(mode.value) > order.index(Mode.CAGE_TEST.value)
