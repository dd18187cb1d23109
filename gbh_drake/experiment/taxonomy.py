"""Why a trial failed, in the words a reader uses: one cause class per failed trial, derived from
its row and the row's ``record`` alone (never typed by hand), by :func:`cause_of`.

The classes (:data:`CAUSES`, in pipeline order; the report lists every one, zeros included):

- ``out of reach``, ``candidate set missed``: from a ``no_grasp_found`` row's ``reach`` field
  (the reach analysis, :mod:`gbh_drake.experiment.reach`, on the trial's scan and on the true
  mesh where the object lay). ``out of reach``: no hook pose around the true mesh's structures
  passes every rule; the gripper's limit, whatever the scan was (it also wins over ``scan
  cut/partial``: no scan would have given a grasp). ``candidate set missed``: a pose passes
  on the true mesh **and** on the trial's own scan, so the method had what it needed and its
  candidate set did not contain such a pose. When the true mesh has a pose but the scan has
  none (``out of reach``, ``no structure`` or ``undecided`` on the scan) the grasp was lost in
  the scan, not in the candidate set: ``reach`` does not decide, nor does it when the true
  mesh's search is ``undecided`` or finds no structure (GbH's structures were on a false
  part) or the analysis failed; the next rules apply.
- ``no structure``: GbH found nothing to hang the object by (``no_hangable_structure``).
- ``table clearance``, ``collision N_c``, ``closing sweep``, ``rod clearance``, ``empty
  loop``: a ``no_grasp_found`` row that ``reach`` did not decide and whose record has
  ``rejected_by`` (candidates each collision rule removed, in the order the rules apply:
  ``collision N_c``, ``closing sweep``, ``table clearance``, ``rod clearance``, ``empty loop``,
  :data:`gbh_drake.core.rejections.ALL_RULES`): the last rule with a nonzero count, the one
  that removed the last candidates.
- ``no grasp found``: the method offered no grasp (``no_grasp_found``) and neither ``reach``
  nor ``rejected_by`` says more (older rows; the antipodal sampler).
- ``IK``, ``planner``: grasps were offered and every one refused (``no_reachable_grasp``): the
  more frequent kind of refusal in ``refusals`` (keys ``reason:where``; ``ik:*`` is IK;
  ``planner:*``, ``collision:*`` and ``approach:*``, a path or approach that could not be
  planned, are planner); a tie, or no refusal recorded, counts as IK.
- ``lift too low``: held but not lifted clear of the table (``not_lifted``).
- ``touched down``: carried to the place, but it came down onto the table while held after the
  lift (``touched_down``: dragged, not carried clear; its own class, not a success).
- ``slipped during carry``: dropped after the lift began (``dropped_during_lift``,
  ``dropped_during_carry``).
- ``scan cut/partial``: ``empty_scan``, or a failure decided on the scan (no structure, no grasp,
  IK or planner) of a scan warned to reach the edge of what the cameras framed
  (:data:`EDGE_WARNINGS`); failures after a grasp was executed keep their physical cause.
- ``error``: the pipeline raised (``error``) or the trial never finished (``incomplete``).
"""

from __future__ import annotations

from collections import Counter

from gbh_drake.core.rejections import ALL_RULES

#: Every cause class, in pipeline order.
CAUSES = ("out of reach", "candidate set missed", "no structure", "table clearance",
          "collision N_c", "closing sweep", "rod clearance", "empty loop", "no grasp found",
          "IK", "planner", "lift too low",
          "touched down", "slipped during carry", "scan cut/partial", "error")

#: Classes no row can be given yet (listed with 0 so that the table's columns do not change).
RESERVED: tuple[str, ...] = ()

#: The collision rules of GbH in the order they apply (the keys of a record's ``rejected_by``).
REJECTION_RULES = ALL_RULES


#: The starts of the scan warnings that the object reaches the edge of what was framed or seen
#: (gbh_drake.perception.scan: FRAME_EDGE_WARNING, the image border, the workspace bound).
EDGE_WARNINGS = ("the object reaches the edge of the region framed by the first look",
                 "the object reaches the image border", "the object reaches the workspace bound")

#: Outcomes decided on the scan, before any grasp was executed.
_ON_THE_SCAN = ("no_hangable_structure", "no_grasp_found", "no_reachable_grasp")

_BY_OUTCOME = {
    "no_hangable_structure": "no structure",
    "no_grasp_found": "no grasp found",
    "not_lifted": "lift too low",
    "touched_down": "touched down",
    "dropped_during_lift": "slipped during carry",
    "dropped_during_carry": "slipped during carry",
    "empty_scan": "scan cut/partial",
    "error": "error",
    "incomplete": "error",
}


def cause_of(row: dict) -> str:
    """The cause class (one of :data:`CAUSES`) of a failed trial's ``row``; ``""`` for a
    success. Raises ``ValueError`` for an outcome it does not know."""
    if row.get("success"):
        return ""
    outcome = row.get("outcome", "")
    if outcome == "no_grasp_found" and (row.get("reach") or {}).get("true") == "out of reach":
        return "out of reach"  # no scan, cut or whole, would have given a grasp
    if outcome in _ON_THE_SCAN and scan_cut(row):
        return "scan cut/partial"
    if outcome == "no_grasp_found":
        return no_grasp_cause(row)
    if outcome == "no_reachable_grasp":
        return refused_by(row.get("refusals") or (row.get("record") or {}).get("refusals") or {})
    if outcome not in _BY_OUTCOME:
        raise ValueError(f"no cause class for the outcome {outcome!r} of trial "
                         f"{row.get('object')}/{row.get('method')}/{row.get('trial')}")
    return _BY_OUTCOME[outcome]


def no_grasp_cause(row: dict) -> str:
    """The class of a ``no_grasp_found`` row: its reach (out of reach on the true mesh;
    reachable on both meshes: candidate set missed), else the last rule of ``rejected_by``
    that removed candidates, else ``no grasp found`` (module docstring)."""
    reach = row.get("reach") or {}
    if reach.get("true") == "out of reach":
        return "out of reach"
    if reach.get("true") == reach.get("scan") == "reachable":
        return "candidate set missed"
    rejected = (row.get("record") or {}).get("rejected_by") or {}
    last = [rule for rule in REJECTION_RULES if int(rejected.get(rule, 0)) > 0]
    return last[-1] if last else "no grasp found"


def scan_cut(row: dict) -> bool:
    """Whether the row's scan was warned to reach the edge of what the cameras framed."""
    warnings = (row.get("record") or {}).get("scan_warnings") or []
    return any(str(w).startswith(EDGE_WARNINGS) for w in warnings)


def refused_by(refusals: dict[str, int]) -> str:
    """``IK`` or ``planner``: the more frequent kind of refusal (a tie or none: ``IK``)."""
    kinds: Counter = Counter()
    for key, n in refusals.items():
        kinds["IK" if key.split(":")[0] == "ik" else "planner"] += int(n)
    return "planner" if kinds["planner"] > kinds["IK"] else "IK"
