"""Grasp evaluation (paper Sec. 2.4): S_total = m_i * S_beta * S_alpha, ranking and top-k.

The order is the paper's: grasp generation keeps the collision-free grasps (Sec. 2.3, N_c < p_c),
they are scored S_total = m_i S_beta S_alpha, ranked from high to low, the ten best are taken
(Sec. 3.1: "Ten predicted poses with the highest S_total value are selected and ranked"), and the
motion planner then tries them in that order and executes the first it can reach (that loop is
gbh_drake/run.py's). Our own collision checks (the closing sweep and the supporting surface,
collision.py) belong to the same "collision-free" filter, so they are applied before ranking:
a grasp they reject never takes one of the ten places. Beyond the paper, the ten are distinct:
a copy of a better grasp (the same kind within ``distinct_distance`` and
``distinct_angle_deg``, :func:`is_copy`; the turned approaches land on the neighbouring
contacts) takes no place (the ``paper`` preset ranks as the paper does, copies included).

:func:`collision_free` is that filter:

* N_c < p_c (paper): fewer than p_c object points inside the open gripper at the grasp pose;
* N_sweep < p_sweep (ours): the closing motion (the parts that move from the open to the
  closed pose, the closed pose included: both fingers of a parallel grasp; the L finger and the
  hand of a vertical grasp, whose straight rod stays) meets fewer than p_sweep object points
  besides those already counted in N_c, with the swept boxes grown by
  ``sweep_margin_spacings`` sample spacings. Points inside the closed loop's interior (between
  palm, rods and bar) are the caged material and are not in the swept volume, so they never
  count; points where the rods or the bar go are material the loop would stop on, a pinch
  instead of a cage. p_sweep = 1 by default: none;
* ground distance >= ground_clearance (ours, skipped when ground_clearance < 0): the solid model,
  open, sweeping and closed, stays that far above the supporting surface; the planner pads the
  table by the same number near the grasp;
* no rod contact (ours, skipped when rod_clearance < 0): the rods and the bar, open and closing,
  stay ``rod_clearance`` from the object's surface, however thin the material
  (:func:`~gbh_drake.core.collision.count_rod_contacts`).
* the loop holds material (ours, skipped when loop_must_enclose is False): closed at the grasp,
  the loop has the object's surface in its hole and runs clear of it
  (:func:`~gbh_drake.core.enclosure.planned_loop_material`).

The score terms:

* alpha: angle between R n1 (n1 = -z_G, from the fingertips toward the wrist) and the
  anti-gravity direction; S_alpha = exp(-alpha^2 / gamma_alpha). A top-down approach has
  R n1 = up, alpha = 0, S_alpha = 1.
* beta: angle between a_i (mean direction of the rays that miss: where the loop around c_i is
  open) and the direction from the held material toward c_i, u = unit(c_i - h); small beta means
  the material held is opposite the opening. S_beta = 1 if m_i = 1 (a closed loop has no
  opening, a_i = 0 and beta is not used; beta is recorded as nan), else exp(-beta^2/gamma_beta).

  When m_i < 1 but the missing rays' directions cancel (openings on opposite sides: the mean of
  their unit directions is shorter than ``min_miss_resultant``), there is no opening direction:
  beta is pi/2, neither rewarded nor the best. The length is taken from the structure's
  ``miss_directions`` (its ``a`` is normalised, so it no longer says how well the misses
  agree), or from ``a`` when a structure carries no miss directions.

  Sign choice (design.md Sec. 4): for vertical grasps u is R n2 (= +y_G), as in the paper. For
  parallel grasps u is the approach +z_G = -R n1, not the paper's R n1: with n1 pointing to the
  wrist, the paper's sign would reward holding the material on the open side.

* S_hang (ours; ``hang_slide_scale`` > 0): exp(-(d / hang_slide_scale)^2), d = the grasp's
  ``hang_drop``: how much deeper the object hangs once the caged material slides along the rim
  to where it rests (:mod:`gbh_drake.core.sliding`). The paper scores where the gripper is,
  not where the object will hang from: a straight wire's middle (where the paper's contact
  rule puts h) lets the material slide to the wire's end. S_total = m S_beta S_alpha S_hang.
"""

from __future__ import annotations

import numpy as np

from gbh_drake.core.enclosure import LoopMaterial
from gbh_drake.core.geometry import angle_between, rotation_angle, unit
from gbh_drake.core.params import GbhParams
from gbh_drake.core.results import PARALLEL, GraspCandidate, HangingStructure


def miss_resultant(structure: HangingStructure) -> float:
    """Length in [0, 1] of the mean of the unit directions of the rays that missed: about 1 for
    one narrow opening, 0 when openings on opposite sides cancel (and for m = 1: no misses)."""
    d = np.asarray(structure.miss_directions, dtype=float).reshape(-1, 3)
    if len(d):
        return float(np.linalg.norm(unit(d).mean(axis=0)))
    return float(np.linalg.norm(structure.a))


def score_grasps(candidates: list[GraspCandidate], params: GbhParams) -> None:
    """Fill alpha, beta, s_alpha, s_beta and score of every candidate, in place (vectorised)."""
    if not candidates:
        return
    up = unit(np.asarray(params.ground_normal, dtype=float))
    R = np.stack([g.X_WG[:3, :3] for g in candidates])
    n1 = -R[:, :, 2]  # R n1, n1 = -z_G
    # Direction from the caged material toward c_i: +z_G (parallel) or +y_G = R n2 (vertical).
    parallel = np.array([g.kind == PARALLEL for g in candidates])
    toward_c = np.where(parallel[:, None], R[:, :, 2], R[:, :, 1])
    structures = {id(g.structure): g.structure for g in candidates}
    resultant = {k: miss_resultant(s) for k, s in structures.items()}
    a = unit(np.stack([g.structure.a for g in candidates]))
    rho = np.array([resultant[id(g.structure)] for g in candidates])
    m = np.array([g.structure.m for g in candidates])
    closed = m >= 1.0
    alpha = angle_between(n1, up[None])
    beta = np.where(rho >= params.min_miss_resultant, angle_between(a, toward_c), np.pi / 2)
    beta = np.where(closed, np.nan, beta)
    s_alpha = np.exp(-(alpha**2) / params.gamma_alpha)
    s_beta = np.where(closed, 1.0, np.exp(-(np.nan_to_num(beta) ** 2) / params.gamma_beta))
    drop = np.array([g.hang_drop for g in candidates], dtype=float)
    s_hang = np.exp(-((drop / params.hang_slide_scale) ** 2)) if params.hang_slide_scale > 0 \
        else np.ones(len(candidates))
    score = m * s_beta * s_alpha * s_hang
    for g, al, be, sa, sb, sh, s in zip(candidates, alpha, beta, s_alpha, s_beta, s_hang, score,
                                        strict=True):
        g.alpha, g.beta, g.s_alpha, g.s_beta, g.s_hang, g.score = \
            (float(x) for x in (al, be, sa, sb, sh, s))


def collision_free(g: GraspCandidate, params: GbhParams) -> bool:
    """Whether ``g`` passes every collision check (module docstring): N_c < p_c (paper),
    N_sweep < p_sweep, unless ground_clearance < 0, ground distance >= ground_clearance,
    unless rod_clearance < 0, no rod contact found, and, with loop_must_enclose, the closed
    loop holds material. Uncounted candidates (-1, nan) do not pass the counts and the table;
    the rods' clearance and the loop's material are checked lazily (only for grasps that may
    be ranked, best score first, ``pipeline.count_collisions``), so an unchecked grasp (-1) is
    not refused by them (the ranking is the same as if every grasp were checked)."""
    return (0 <= g.n_collisions < params.p_c
            and 0 <= g.n_sweep_collisions < params.p_sweep
            and (params.ground_clearance < 0
                 or bool(g.ground_distance >= params.ground_clearance))
            and (params.rod_clearance < 0 or g.rod_contacts <= 0)
            and (not params.loop_must_enclose
                 or g.loop_material in (LoopMaterial.UNCHECKED, LoopMaterial.HELD)))


def rank_grasps(candidates: list[GraspCandidate], params: GbhParams) -> list[GraspCandidate]:
    """The collision-free candidates (:func:`collision_free`), best S_total first, distinct
    (:func:`is_copy`: a copy of a better one takes no place), at most ``top_k``: the paper's
    ten, in the order the planner tries them.

    The order is :func:`ranking_order`'s, so the ranking is deterministic.
    """
    free = [g for g in candidates if collision_free(g, params)]
    order = ranking_order(free, params)
    ranked: list[GraspCandidate] = []
    for i in order:
        if len(ranked) == params.top_k:
            break
        if not any(is_copy(free[i], kept, params) for kept in ranked):
            ranked.append(free[i])
    return ranked


def ranking_order(candidates: list[GraspCandidate], params: GbhParams) -> np.ndarray:
    """Indices of ``candidates``, best first: S_total descending; with
    ``params.ties_by_collisions``, scores equal to 6 significant digits by fewer N_c
    (``n_collisions``) first; remaining ties (all ties, without it: the paper's order) in the
    order the candidates were made."""
    if not params.ties_by_collisions:
        return np.argsort([-g.score for g in candidates], kind="stable")
    score = np.array([float(f"{g.score:.6g}") for g in candidates], dtype=float)
    n_c = np.array([g.n_collisions for g in candidates], dtype=float)
    return np.lexsort((np.arange(len(candidates)), n_c, -score))


def is_copy(g: GraspCandidate, other: GraspCandidate, params: GbhParams) -> bool:
    """Whether ``g`` is a copy of ``other`` for the ranking: the same kind, origins closer than
    ``distinct_distance`` (m) and orientations less than ``distinct_angle_deg`` apart (the
    angle of R_WG^T R_WG'). Both tolerances 0: never (the paper's ranking)."""
    if g.kind != other.kind:
        return False
    if np.linalg.norm(g.X_WG[:3, 3] - other.X_WG[:3, 3]) >= params.distinct_distance:
        return False
    return rotation_angle(g.X_WG[:3, :3], other.X_WG[:3, :3]) < params.distinct_angle_deg
