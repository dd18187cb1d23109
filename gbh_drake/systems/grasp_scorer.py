"""The ``GraspScorer`` system: candidates in, the ranked collision-free top-k out (Sec. 2.4)."""

from __future__ import annotations

import copy

from gbh_drake.core.params import GbhParams
from gbh_drake.core.pipeline import score
from gbh_drake.systems.stage import AbstractStage, params_argument


class GraspScorer(AbstractStage):
    """Scores grasps (S_total = m S_beta S_alpha), drops N_c >= p_c, keeps the best k.

    .. pydrake_system::

        name: GraspScorer
        input_ports:
        - grasp_candidates
        output_ports:
        - ranked_grasps

    ``grasp_candidates``: ``list[GraspCandidate]``; ``ranked_grasps``: the same type, best first,
    at most ``params.top_k``. The input candidates are not modified (scores go on copies).
    """

    def __init__(self, params: GbhParams | None = None):
        super().__init__("grasp_candidates", [], "ranked_grasps", [])
        self.params = params_argument(self, "params", params, GbhParams)

    def compute(self, value):
        return score([copy.copy(g) for g in value], self.params)
