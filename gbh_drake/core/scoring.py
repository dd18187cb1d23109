"""Grasp evaluation (paper Sec. 2.4): S_total = m_i * S_beta * S_alpha, ranking and top-k.

* alpha: angle between R n1 (n1 = -z_G, from the fingertips toward the wrist) and the
  anti-gravity direction; S_alpha = exp(-alpha^2 / gamma_alpha). A top-down approach has
  R n1 = up, alpha = 0, S_alpha = 1.
* beta: angle between a_i (mean direction of the rays that miss: where the loop around c_i is
  open) and the direction from the held material toward c_i, u = unit(c_i - h); small beta means
  the material held is opposite the opening. S_beta = 1 if m_i = 1, else exp(-beta^2/gamma_beta).

  Sign choice (design.md Sec. 4): for vertical grasps u is R n2 (= +y_G), as in the paper. For
  parallel grasps u is the approach +z_G = -R n1, not the paper's R n1: with n1 pointing to the
  wrist, the paper's sign would reward holding the material on the open side.
"""

from __future__ import annotations

import numpy as np

from gbh_drake.core.geometry import angle_between, unit
from gbh_drake.core.params import GbhParams
from gbh_drake.core.results import PARALLEL, GraspCandidate


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
    a = np.stack([g.structure.a for g in candidates])
    m = np.array([g.structure.m for g in candidates])
    alpha = angle_between(n1, up[None])
    # When m < 1 but the missed rays cancel out (|a| small: openings on opposite sides), no
    # side is safer than another: beta is taken as pi/2, neither rewarded nor best.
    beta = np.where(np.linalg.norm(a, axis=1) > 0.5, angle_between(a, toward_c), np.pi / 2)
    s_alpha = np.exp(-(alpha**2) / params.gamma_alpha)
    s_beta = np.where(m >= 1.0, 1.0, np.exp(-(beta**2) / params.gamma_beta))
    score = m * s_beta * s_alpha
    for g, al, be, sa, sb, s in zip(candidates, alpha, beta, s_alpha, s_beta, score, strict=True):
        g.alpha, g.beta, g.s_alpha, g.s_beta, g.score = (float(x) for x in (al, be, sa, sb, s))


def rank_grasps(candidates: list[GraspCandidate], params: GbhParams) -> list[GraspCandidate]:
    """The collision-free candidates (0 <= N_c < p_c, and not deeper than ``ground_margin`` below
    the supporting surface), best S_total first, at most ``top_k``.

    Ties keep the synthesis order (stable sort), so the ranking is deterministic.
    """
    free = [
        g for g in candidates
        if 0 <= g.n_collisions < params.p_c
        and not (params.ground_margin >= 0 and g.ground_penetration > params.ground_margin)
    ]
    order = np.argsort([-g.score for g in free], kind="stable")
    return [free[i] for i in order[: params.top_k]]
