"""Why GbH's candidates were refused: how many each collision rule removed, in the order the rules
apply, and how near the closest candidate came to passing the last rule that removed any.

The rules are those of :func:`gbh_drake.core.scoring.collision_free`, applied in turn to what the
previous ones left (the counts add up to the candidates that fail):

1. ``collision N_c``: at least p_c object points inside the open gripper at X_WG (the paper's);
2. ``closing sweep``: at least p_sweep points (or unseen space) in the volume the closing
   fingers and bar sweep (ours);
3. ``table clearance``: some point of the gripper (open, closing or closed) less than
   ``ground_clearance`` above the supporting surface (ours; skipped when it is negative);
4. ``rod clearance``: the rods or the bar, open or closing, nearer than ``rod_clearance`` to the
   object's surface (ours; skipped when it is negative; checked after the first three, for the
   grasps they left and only as far as the ranking needs: ``pipeline.count_collisions``);
5. ``empty loop``: the loop, closed at the grasp, holds no material in its hole or runs through
   the surface (ours, ``loop_must_enclose``; checked last, lazily as the fourth).

:data:`RULES` are the first three, the rules a record's ``rejected_by`` had before the fourth;
:data:`ALL_RULES` all five; :attr:`Rejections.removed` has the first three and those of the
last two that are checked (:func:`active_rules`).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from gbh_drake.core.enclosure import LoopMaterial
from gbh_drake.core.params import GbhParams
from gbh_drake.core.results import GraspCandidate
from gbh_drake.core.words import counted

#: The rules, in the order they apply.
RULES = ("collision N_c", "closing sweep", "table clearance")
#: Every rule, in the order they apply: :data:`RULES`, the rods' clearance, the loop's material.
ALL_RULES = (*RULES, "rod clearance", "empty loop")


def active_rules(params: GbhParams) -> tuple[str, ...]:
    """The rules of :data:`ALL_RULES` that ``params`` checks, in their order."""
    return RULES + (("rod clearance",) if params.rod_clearance >= 0 else ()) \
        + (("empty loop",) if params.loop_must_enclose else ())


@dataclass
class Rejections:
    """How the collision rules sorted a list of candidates."""

    removed: dict[str, int] = field(default_factory=dict)
    """Candidates each rule removed (keys :func:`active_rules`, in their order), of those the
    earlier rules left."""
    passed: int = 0
    """Candidates that passed every rule."""
    last_rule: str = ""
    """The last rule that removed any candidate (the one that removed the last ones); ``""``
    when none was removed."""
    closest: str = ""
    """The candidate that came closest to passing ``last_rule``, in words (``"closest: a
    vertical grasp 2.3 mm above the table, 0.7 mm short of the 3.0 mm clearance"``)."""

    def summary(self) -> str:
        """The counts in words, rule by rule (``"N_c removed 120, the closing sweep 20, the
        table clearance the last 4 (closest: ...)"``)."""
        parts = []
        for rule, n in self.removed.items():
            if n:
                verb = " removed " if not parts else " "
                last = "the last " if rule == self.last_rule and parts else ""
                parts.append(f"{_WORDS[rule]}{verb}{last}{n}")
        if not parts:
            return ""
        text = ", ".join(parts)
        return f"{text} ({self.closest})" if self.closest else text


_WORDS = {"collision N_c": "N_c", "closing sweep": "the closing sweep",
          "table clearance": "the table clearance", "rod clearance": "the rods' clearance",
          "empty loop": "the loop's material"}


def count_rejections(candidates: list[GraspCandidate], params: GbhParams) -> Rejections:
    """Sorts counted ``candidates`` (N_c, N_sweep and ground distance set, as by
    :func:`gbh_drake.core.pipeline.count_collisions`) by the rule that removed each
    (module docstring). Uncounted candidates (-1, nan) count as removed by the rule whose
    count is missing. :attr:`Rejections.removed` has the rules that are checked
    (:func:`active_rules`)."""
    rule, shortfall = removed_by(candidates, params)
    removed = {name: int(np.sum(rule == ALL_RULES.index(name))) for name in active_rules(params)}
    if not (rule >= 0).any():
        return Rejections(removed, len(candidates))
    last = int(rule.max())
    idx = np.flatnonzero(rule == last)
    best = candidates[idx[int(np.argmin(shortfall[idx]))]]
    return Rejections(removed, int(np.sum(rule < 0)), ALL_RULES[last],
                      _closest(best, ALL_RULES[last], params))


def no_grasp_message(n_candidates: int, n_structures: int, rejections: Rejections) -> str:
    """Why no candidate was ranked, in words (the trial's ``no_grasp_found`` reason)."""
    why = rejections.summary()
    return (f"no collision-free grasp among {counted(n_candidates, 'candidate')} on "
            f"{counted(n_structures, 'hanging structure')}{': ' + why if why else ''}")


def removed_by(candidates: list[GraspCandidate], params: GbhParams
               ) -> tuple[np.ndarray, np.ndarray]:
    """(rule, shortfall), each (M,): the index in :data:`ALL_RULES` of the rule that removed each
    candidate (-1: it passed every one), and how far it is from passing that rule (points at
    or over p_c or p_sweep; metres below the table clearance; inf when uncounted)."""
    n_c = np.array([g.n_collisions for g in candidates], dtype=float)
    n_s = np.array([g.n_sweep_collisions for g in candidates], dtype=float)
    height = np.array([g.ground_distance for g in candidates], dtype=float)
    rods = np.array([g.rod_contacts for g in candidates], dtype=float)
    loops = np.array([g.loop_material for g in candidates], dtype=int)
    # The rods' clearance and the loop's material: unchecked (-1) when an earlier rule refused
    # the grasp or top_k better ones were clear (pipeline.count_collisions): not refused by it.
    fails = [~((n_c >= 0) & (n_c < params.p_c)),
             ~((n_s >= 0) & (n_s < params.p_sweep)),
             np.zeros(len(candidates), bool) if params.ground_clearance < 0
             else ~(height >= params.ground_clearance),
             np.zeros(len(candidates), bool) if params.rod_clearance < 0 else rods > 0,
             (loops == LoopMaterial.EMPTY) | (loops == LoopMaterial.THROUGH)
             if params.loop_must_enclose else np.zeros(len(candidates), bool)]
    shortfalls = [np.where(n_c >= 0, n_c, np.inf), np.where(n_s >= 0, n_s, np.inf),
                  np.where(np.isnan(height), np.inf, params.ground_clearance - height),
                  np.where(rods >= 0, rods, np.inf),
                  np.where(loops == LoopMaterial.THROUGH, 1.0, 0.0)]
    rule = np.full(len(candidates), -1)
    shortfall = np.zeros(len(candidates))
    for k in range(len(ALL_RULES)):
        out = (rule < 0) & fails[k]
        rule[out], shortfall[out] = k, shortfalls[k][out]
    return rule, shortfall


def _closest(best: GraspCandidate, rule: str, params: GbhParams) -> str:
    """``best``, the candidate ``rule`` removed that came nearest to passing it, in words."""
    return f"closest: {refusal_words(best, rule, params)}"


def refusal_words(candidate: GraspCandidate, rule: str, params: GbhParams) -> str:
    """Why ``rule`` (one of :data:`RULES`) removed ``candidate``, in words (``"a vertical grasp
    2.3 mm above the table, 0.7 mm short of the 3.0 mm clearance"``)."""
    if rule == "table clearance":
        d_mm, need_mm = candidate.ground_distance * 1e3, params.ground_clearance * 1e3
        where = f"{-d_mm:.1f} mm below the table" if d_mm < 0 else \
            f"{d_mm:.1f} mm above the table"
        return (f"a {candidate.kind} grasp {where}, {need_mm - d_mm:.1f} mm short of the "
                f"{need_mm:.1f} mm clearance")
    if rule == "rod clearance":
        return (f"a {candidate.kind} grasp whose rods or bar come nearer than "
                f"{params.rod_clearance * 1e3:.1f} mm to the surface "
                f"({candidate.rod_contacts} triangles or samples)")
    if rule == "empty loop":
        through = candidate.loop_material == LoopMaterial.THROUGH
        return (f"a {candidate.kind} grasp whose closed loop "
                + ("runs through the surface" if through else "holds no material in its hole"))
    if rule == "closing sweep":
        return (f"a {candidate.kind} grasp with {candidate.n_sweep_collisions} points in its "
                f"closing sweep, p_sweep = {params.p_sweep}")
    return (f"a {candidate.kind} grasp with {candidate.n_collisions} points inside the open "
            f"gripper, p_c = {params.p_c}")


@dataclass
class Refused:
    """A refused candidate, the rule that removed it (one of :data:`RULES`) and why, in words."""

    candidate: GraspCandidate
    rule: str
    words: str


#: Metres a turn of one radian counts as in :func:`nearest_refused`'s distance between grasps
#: (10 deg ~ 9 mm: the contacts of a loop are 10 deg apart, its grasps a few mm).
ANGLE_WEIGHT = 0.05


def nearest_refused(candidates: list[GraspCandidate], params: GbhParams, X_WG: np.ndarray,
                    k: int = 3) -> list[Refused]:
    """The ``k`` refused candidates nearest to the gripper pose ``X_WG`` (4, 4, W): by the
    distance between the gripper origins (m) plus :data:`ANGLE_WEIGHT` times the angle between
    the orientations (rad), each with the rule that removed it. For showing what was refused
    around one grasp."""
    rule, _ = removed_by(candidates, params)
    refused = np.flatnonzero(rule >= 0)
    if len(refused) == 0 or k <= 0:
        return []
    X = np.asarray(X_WG, dtype=float)
    poses = np.stack([np.asarray(candidates[i].X_WG, dtype=float) for i in refused])
    distance = np.linalg.norm(poses[:, :3, 3] - X[:3, 3], axis=1)
    cos = (np.einsum("nij,ij->n", poses[:, :3, :3], X[:3, :3]) - 1.0) / 2.0
    angle = np.arccos(np.clip(cos, -1.0, 1.0))
    order = np.lexsort((refused, distance + ANGLE_WEIGHT * angle))[:k]
    return [Refused(candidates[i], ALL_RULES[rule[i]],
                    refusal_words(candidates[i], ALL_RULES[rule[i]], params))
            for i in refused[order]]


def closest_rejected(candidates: list[GraspCandidate], params: GbhParams,
                     k: int = 3) -> list[GraspCandidate]:
    """The ``k`` refused candidates that came closest to passing: those removed by a later rule
    first (they passed the earlier ones), then by how near they came to that rule (fewest
    points, or least below the table clearance). For drawing what was refused."""
    rule, shortfall = removed_by(candidates, params)
    refused = np.flatnonzero(rule >= 0)
    order = np.lexsort((refused, shortfall[refused], -rule[refused]))
    return [candidates[i] for i in refused[order[:k]]]
