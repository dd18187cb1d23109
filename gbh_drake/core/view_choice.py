"""Which single view sees the candidate holes best: a next-best-view score, pure numpy/Open3D.

A one-view scan finds a hanging structure when its view sees the loop's material and sees
*through* the hole (the exit proof, ``GbhParams.through_proof_exit``, needs a line through c
within ``through_proof_angle_deg`` of the hole's axis seen free out of the object). Given a
coarse model of the object (the first look's) and its candidate structures (GbH's hangability
stage on that model, unseen space not held against them), :func:`hole_view_scores` scores each
candidate camera position p_WC:

    score(p_WC) = sum over structures s of  m_s * cos_s * through_s * seen_s

* ``cos_s`` = |cos| of the angle between the line of sight to c_s and the hole's axis v_s,
  0 beyond ``max_angle_deg`` (the view cannot prove the hole along its own line of sight);
* ``through_s`` = 1 when the line of sight reaches c_s unblocked by the model and leaves the
  model beyond c_s (the view sees through the hole), else 0;
* ``seen_s`` = the fraction of the structure's hit points H_s (the loop's material round c_s)
  the camera sees unblocked (within ``tolerance`` of the first surface on their line of sight);
* m_s, the structure's fraction of closed loop (the paper's m), weighs a closed handle over an
  open hook.

The structures the first look offers are already proven by it (its free space goes with every
scan), so a second proof along the chosen view's own line of sight is not what the grasp lacks:
it lacks the material its loop closes round. The one view is the only surface GbH's collision
counts see; material it does not see is where the loop may close on the object (a headband
seen from 40 deg off its axis was scanned half its 24 mm deep along the arms, and the closing
bar met the unseen half). :func:`material_view_scores` scores what a view sees of the material
round each hole, as the first look's model has it, instead:

    score(p_WC) = sum over structures s of  m_s * seen_s

* ``seen_s`` = the fraction of the model's surface samples within ``clearance_s + reach`` of c_s
  (the material the gripper's loop closes round: ``reach`` is how far a rod through the hole
  runs either side of c, ``GbhParams.through_proof_length``) that the camera sees unblocked.
"""

from __future__ import annotations

import numpy as np

from gbh_drake.core.object_model import ObjectModel
from gbh_drake.core.results import HangingStructure


def hole_view_scores(model: ObjectModel, structures: list[HangingStructure], p_WC: np.ndarray,
                     max_angle_deg: float = 60.0, tolerance: float = 0.003) -> np.ndarray:
    """(k,) scores (module docstring) of the camera positions ``p_WC`` (k, 3, m, W) for the
    ``structures`` of ``model`` (W); all 0 without structures. ``tolerance`` (m): how far
    behind the first surface on a line of sight a point may lie and still count as seen."""
    cams = np.asarray(p_WC, dtype=float).reshape(-1, 3)
    scores = np.zeros(len(cams))
    if not structures or len(cams) == 0:
        return scores
    cos_max = np.cos(np.radians(max_angle_deg))
    for s in structures:
        to_c = s.c[None] - cams  # (k, 3)
        dist_c = np.linalg.norm(to_c, axis=1)
        d = to_c / dist_c[:, None]
        cos = np.abs(d @ s.v)
        aligned = cos >= cos_max
        # The line of sight reaches c and goes on out of the model.
        reach = model.cast(cams, d) >= dist_c - 0.5 * max(s.clearance, tolerance)
        beyond = ~np.isfinite(model.cast(np.broadcast_to(s.c, cams.shape).copy(), d))
        through = aligned & reach & beyond
        if not through.any() or len(s.H) == 0:
            continue
        seen = _seen_fraction(model, cams, s.H, tolerance)  # the loop's material seen
        scores += np.where(through, s.m * cos * seen, 0.0)
    return scores


def _seen_fraction(model: ObjectModel, cams: np.ndarray, targets: np.ndarray,
                   tolerance: float) -> np.ndarray:
    """(k,) the fraction of ``targets`` (n, 3, W) each camera of ``cams`` (k, 3) sees: the first
    surface on the line of sight lies no more than ``tolerance`` (m) before the target."""
    k, n = len(cams), len(targets)
    origins = np.repeat(cams, n, axis=0)
    ray = np.tile(targets, (k, 1)) - origins
    length = np.linalg.norm(ray, axis=1)
    first = model.cast(origins, ray / length[:, None])
    return (first >= length - tolerance).reshape(k, n).mean(axis=1)


def material_view_scores(model: ObjectModel, structures: list[HangingStructure], p_WC: np.ndarray,
                         reach: float = 0.025, tolerance: float = 0.003) -> np.ndarray:
    """(k,) scores (the module docstring's second score) of the camera positions
    ``p_WC`` (k, 3, m, W): how much of the material round each of ``structures``' holes
    (``model``'s samples within the hole's clearance + ``reach`` (m) of c) each camera sees,
    weighed by m; all 0 without structures. ``tolerance`` as in :func:`hole_view_scores`."""
    cams = np.asarray(p_WC, dtype=float).reshape(-1, 3)
    scores = np.zeros(len(cams))
    if len(cams) == 0:
        return scores
    points = np.asarray(model.points, dtype=float)
    for s in structures:
        near = points[np.linalg.norm(points - s.c, axis=1) <= s.clearance + reach]
        if len(near):
            scores += s.m * _seen_fraction(model, cams, near, tolerance)
    return scores
