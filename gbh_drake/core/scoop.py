"""The scoop (beyond the paper, issue 19): hook material that lies flat on the table.

A key ring, a clothes hanger or scissors lying flat leave no gap under their material for the
bar, which every hook grasp of the paper needs: no pose of the gripper clears the table
(docs/reach.md: *out of reach*, 7-17 mm short). The scoop goes under the material instead. The
straight rod goes down through the hole to the table, ``rod_gap`` inside the material's inner
edge; the L rod stands outside the material; the loop closes at table level with the wedge bar
leading (:data:`~gbh_drake.core.gripper.WEDGE_GRIPPER`: its tip chamfered, a 26.6 deg ramp
from the bottom edge to the top face). The wedge's edge slides along the table and under the
material, which rides up the ramp onto the bar while the straight rod keeps it from sliding
away; the closed loop then cages it as a vertical grasp's does. Whether it does is the
physics' call: the trial's cage test says cage or pinch.

**Poses** (:func:`scoop_poses`). For each hanging structure whose axis is within
``tilt_max_deg`` of the ground normal, and for its contact points h (where the rays from c met
the material's inner surface; at most ``max_per_structure``, evenly spread):

* u, the horizontal unit vector from c toward h (toward the material);
* z_G down (the approach), y_G = -u (the closing axis: from the L rod, outside, to the straight
  rod, in the hole), x_G = y_G x z_G;
* the straight rod's centre line half a rod plus ``rod_gap`` inside h, the rods' tips ``hover``
  above the table.

**Rules** (:func:`check_scoops`), on the object's samples, in the frame G of each pose:

* *open*: the open gripper (the wedge's solid model) holds fewer than ``p_c``
  points (the paper's N_c, GbH's threshold);
* *nothing to scoop*: the bar's path (its box, swept from the open to the closed
  pose, and the loop's corridor above it) holds fewer than ``min_scooped`` points at the bar's
  height;
* *too tall*: a point in that corridor lies higher than ``max_height`` above the table: the wedge
  lifts what it meets by its own height (one rod width), so taller material is pushed along, not
  lifted onto the bar (a tape roll's 19 mm wall);
* *pushed*: the moving parts other than the wedge (the L rod above the bar, the L rod where it
  stops, the hand) meet ``p_sweep`` points or more while closing: material they would push.

**Tall scoops** (``ranked_tall``; ``ScoopParams.tall``). Material taller than ``max_height``
(a thick ring or torus lying flat, its section 26-40 mm) may still be lifted onto the bar: the
wedge's edge slides under a round underside (the gap between a tube and the table opens from
the line it rests on) and the ramp lifts it, the straight rod in the hole holding it; the L rod
then meets the lifted material's outer side and stops there, the loop round the section (a cage
when the gap left at the bar's tip is narrower than the section: the trial's cage test). But a
square underside flush on the table (a tape roll's wall) is pushed against the straight rod and
pinched, and the scan cannot tell them apart: it loses everything within ``scan.crop_z_min``
(4 mm) of the table. So a scoop that fails only *too tall*, and whose hand meets nothing while
closing (the L rod meeting the material in the bar's column is the lifted material, not
material pushed), is offered apart, as a tier of its own that a method tries after the surer
ones (``gbh_plus``: after the regrasp, which stands a roll on its rim and hooks it).

**Score and order**: the paper's S_total = m S_beta S_alpha with a vertical grasp's terms
(:func:`gbh_drake.core.scoring.score_grasps`: the approach is top-down, S_alpha = 1; beta is
the angle between the opening a and the closing axis), best first; among equal scores (every
scoop of a closed loop scores m = 1) the one the object hangs least deep from first: lifted
from h, a flat object swings to hang with its centre of mass below h (a clothes hanger scooped
at a corner of its triangle dangles 30 cm and more, from its apex half that), and the lift must
clear that (``depth``, :func:`~gbh_drake.core.hanging_pose.hanging_lowest_height`). Pure numpy.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from gbh_drake.core.collision import chunked_box_masks, closing_displacements
from gbh_drake.core.geometry import unit
from gbh_drake.core.gripper import WEDGE_GRIPPER, Box, HookGripperGeometry
from gbh_drake.core.hanging_pose import hanging_lowest_height
from gbh_drake.core.object_model import ObjectModel
from gbh_drake.core.params import GbhParams, ScoopParams
from gbh_drake.core.results import SCOOP, GraspCandidate, HangingStructure
from gbh_drake.core.scoring import score_grasps

#: The rules of :func:`check_scoops`, in the order they apply (a candidate is removed by the
#: first it fails).
RULES = ("open", "nothing to scoop", "too tall", "pushed")


@dataclass
class ScoopResult:
    """What :func:`plan_scoops` found. ``candidates``: every scoop pose (kind ``scoop``, N_c in
    ``n_collisions``, the pushed count in ``n_sweep_collisions``, the rods' tips' height in
    ``ground_distance``), scored; ``ranked``: those that pass every rule, best first, at most
    ``top_k``; ``removed_by``: how many each rule removed (:data:`RULES` order);
    ``structures``: how many structures lie flat enough to scoop."""

    candidates: list[GraspCandidate] = field(default_factory=list)
    ranked: list[GraspCandidate] = field(default_factory=list)
    removed_by: dict[str, int] = field(default_factory=dict)
    structures: int = 0
    scooped: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=int))
    """(n,) points in each candidate's bar path at the bar's height."""
    tallest: np.ndarray = field(default_factory=lambda: np.zeros(0))
    """(n,) m: the highest point above the table in each candidate's corridor (-inf: none)."""
    passed: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=bool))
    """(n,) whether each candidate passes every rule (``ranked`` is the best ``top_k`` of them)."""
    ranked_tall: list[GraspCandidate] = field(default_factory=list)
    """Tall scoops (module docstring): the candidates that fail *too tall* and no other rule but
    the L rod's part of *pushed*, best first, at most ``top_k`` (empty unless
    ``ScoopParams.tall``)."""
    tall: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=bool))
    """(n,) whether each candidate is a tall scoop (``ranked_tall`` is the best ``top_k``)."""
    depth: np.ndarray = field(default_factory=lambda: np.zeros(0))
    """(n,) m: how far below its contact point h the object hangs from it (its lowest point
    with its centre of mass straight below h)."""

    def reason(self) -> str:
        """Why no scoop passed, in words ("" when one did)."""
        if self.ranked:
            return ""
        if self.structures == 0:
            return "no hanging structure lies flat on the table to scoop"
        removed = ", ".join(f"{rule} {n}" for rule, n in self.removed_by.items() if n)
        tall = f"; {len(self.ranked_tall)} tall scoops offered apart" if self.ranked_tall else ""
        return f"no scoop among {len(self.candidates)} poses ({removed}){tall}"


def flat_structures(structures: list[HangingStructure], params: GbhParams,
                    scoop: ScoopParams) -> list[int]:
    """Indices of the structures whose axis v is within ``tilt_max_deg`` of the ground normal."""
    up = unit(np.asarray(params.ground_normal, dtype=float))
    cos_max = np.cos(np.radians(scoop.tilt_max_deg))
    return [i for i, s in enumerate(structures) if abs(float(unit(s.v) @ up)) >= cos_max - 1e-12]


def scoop_poses(structures: list[HangingStructure], params: GbhParams, scoop: ScoopParams,
                gripper: HookGripperGeometry = WEDGE_GRIPPER) -> list[GraspCandidate]:
    """The scoop poses (module docstring) of the flat ``structures``, unscored and uncounted."""
    up = unit(np.asarray(params.ground_normal, dtype=float))
    r = 0.5 * gripper.rod_width
    tip = gripper.finger_length + r  # the rods' tips along z_G
    out = []
    for i in flat_structures(structures, params, scoop):
        s = structures[i]
        H = np.asarray(s.H, dtype=float).reshape(-1, 3)
        if len(H) > scoop.max_per_structure:
            H = H[np.linspace(0, len(H) - 1, scoop.max_per_structure).round().astype(int)]
        for h in H:
            d = h - s.c
            d -= (d @ up) * up
            if np.linalg.norm(d) < 1e-9:
                continue
            u = unit(d)
            y, z = -u, -up
            x = np.cross(y, z)
            on_table = h - (h @ up - params.ground_height) * up  # h dropped onto the table
            rod = on_table - (r + scoop.rod_gap) * u  # the straight rod's centre line
            X = np.eye(4)
            X[:3, :3] = np.column_stack([x, y, z])
            X[:3, 3] = rod - gripper.q_open * y + (tip + scoop.hover) * up
            out.append(GraspCandidate(X_WG=X, kind=SCOOP, structure_index=i, structure=s,
                                      h=np.asarray(h, dtype=float)))
    return out


def _swept(box: Box, dy: float) -> Box:
    """``box`` swept along +y_G by ``dy`` (m)."""
    c = np.asarray(box.center, dtype=float) + (0.0, 0.5 * dy, 0.0)
    h = np.asarray(box.half_extents, dtype=float) + (0.0, 0.5 * abs(dy), 0.0)
    return Box(box.name + "_swept", tuple(float(v) for v in c), tuple(float(v) for v in h))


def _at(box: Box, dy: float) -> Box:
    return Box(box.name, tuple(float(v) for v in np.asarray(box.center) + (0.0, dy, 0.0)),
               box.half_extents)


def scoop_regions_G(gripper: HookGripperGeometry = WEDGE_GRIPPER
                    ) -> tuple[list[Box], Box, list[Box]]:
    """The regions of :func:`check_scoops`, in the frame G of the scoop pose (open gripper):
    (the open solid model's boxes; the corridor: the bar's path from the open pose to
    the straight rod, from the palm down to the bar's outer face; the moving parts other than
    the wedge: the L rod above the bar swept while closing, the L rod where it stops, the hand
    swept)."""
    g = gripper
    r = 0.5 * g.rod_width
    hand_dy, _, l_dy = closing_displacements(SCOOP, g)
    open_boxes = g.solid_boxes_G(g.q_open)
    l_rod, bar = (_at(b, -g.q_open) for b in g.l_finger_boxes()[:2])
    straight = _at(g.straight_finger_boxes()[0], g.q_open)
    y_lo = bar.center[1] - bar.half_extents[1]
    y_hi = straight.center[1] - straight.half_extents[1]  # the straight rod's inner face
    bottom = g.finger_length + r
    corridor = Box("corridor", (0.0, 0.5 * (y_lo + y_hi), 0.5 * bottom),
                   (r, 0.5 * (y_hi - y_lo), 0.5 * bottom))
    top = g.finger_length - r  # the bar's inner face: the L rod above it pushes
    rod_above = Box("l_rod_above", (0.0, l_rod.center[1], 0.5 * top), (r, r, 0.5 * top))
    pushers = [_swept(rod_above, l_dy), _at(l_rod, l_dy), _swept(g.hand_box(), hand_dy)]
    return open_boxes, corridor, pushers


def check_scoops(obj: ObjectModel, candidates: list[GraspCandidate], params: GbhParams,
                 scoop: ScoopParams, gripper: HookGripperGeometry = WEDGE_GRIPPER
                 ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Counts the rules' points for every candidate, in place (``n_collisions``: N_c of the
    open gripper; ``n_sweep_collisions``: points the other moving parts meet; ``ground_distance``:
    the rods' tips above the table) and returns (N_c, scooped, tallest, pushed, pushed_by_hand),
    each (n,): scooped counts the corridor's points at the bar's height, tallest (m) is the
    highest point above the table in the corridor (-inf: none), pushed_by_hand the points in
    the hand's sweep (of those in pushed; the L rod's may meet them too)."""
    n = len(candidates)
    zeros = np.zeros(n, dtype=int)
    if n == 0:
        return zeros, zeros.copy(), np.zeros(0), zeros.copy(), zeros.copy()
    g = gripper
    up = unit(np.asarray(params.ground_normal, dtype=float))
    X = np.stack([c.X_WG for c in candidates])
    points = np.asarray(obj.points, dtype=float)
    height = points @ up - params.ground_height  # (N,) above the table
    open_boxes, corridor, pushers = scoop_regions_G(g)
    n_open, scooped, pushed, by_hand = zeros.copy(), zeros.copy(), zeros.copy(), zeros.copy()
    tallest = np.full(n, -np.inf)
    tip_height = np.array([(c.X_WG[:3, 3] @ up) - params.ground_height
                           - (g.finger_length + 0.5 * g.rod_width) for c in candidates])
    margin = params.collision_margin
    l_rod, hand = pushers[:-1], pushers[-1]  # scoop_regions_G gives the hand's sweep last
    for sl, (inside_open, in_corridor, in_l_rod, in_hand) in chunked_box_masks(
            points, X, [open_boxes, [corridor], l_rod, [hand]], [margin, 0.0, margin, margin]):
        n_open[sl] = inside_open.sum(axis=1)
        low = height[None, :] <= tip_height[sl, None] + g.rod_width
        scooped[sl] = (in_corridor & low).sum(axis=1)
        tallest[sl] = np.where(in_corridor, height[None, :], -np.inf).max(axis=1)
        pushed[sl] = ((in_l_rod | in_hand) & ~inside_open).sum(axis=1)
        by_hand[sl] = (in_hand & ~inside_open).sum(axis=1)
    for c, nc, p, d in zip(candidates, n_open, pushed, tip_height, strict=True):
        c.n_collisions, c.n_sweep_collisions, c.ground_distance = int(nc), int(p), float(d)
    return n_open, scooped, tallest, pushed, by_hand


def plan_scoops(obj: ObjectModel, structures: list[HangingStructure], params: GbhParams,
                scoop: ScoopParams | None = None, gripper: HookGripperGeometry = WEDGE_GRIPPER
                ) -> ScoopResult:
    """The scoops of ``structures`` (GbH's, on ``obj``): poses, rules and scores (module
    docstring); ``params``: GbH's (the table, N_c's p_c and margin, the score's gammas,
    ``top_k``)."""
    scoop = scoop or ScoopParams()
    candidates = scoop_poses(structures, params, scoop, gripper)
    result = ScoopResult(candidates=candidates,
                         structures=len(flat_structures(structures, params, scoop)),
                         removed_by=dict.fromkeys(RULES, 0))
    if not candidates:
        return result
    n_open, scooped, tallest, pushed, by_hand = check_scoops(obj, candidates, params, scoop,
                                                             gripper)
    score_grasps(candidates, params)
    failed = np.stack([n_open >= params.p_c, scooped < scoop.min_scooped,
                       tallest > scoop.max_height, pushed >= scoop.p_sweep])  # (rules, n)
    first = np.where(failed.any(axis=0), failed.argmax(axis=0), -1)
    result.removed_by = {rule: int(np.count_nonzero(first == k)) for k, rule in enumerate(RULES)}
    result.scooped, result.tallest = scooped, tallest
    up = unit(np.asarray(params.ground_normal, dtype=float))
    result.depth = np.array([float(c.h @ up) - hanging_lowest_height(obj.points, obj.com, c.h, up)
                             for c in candidates])
    result.passed = first < 0
    result.tall = (scoop.tall & ~failed[0] & ~failed[1] & failed[2]
                   & (by_hand < scoop.p_sweep))
    result.ranked = _best(candidates, result.passed, result.depth, params.top_k)
    result.ranked_tall = _best(candidates, result.tall, result.depth, params.top_k)
    return result


def _best(candidates: list[GraspCandidate], keep: np.ndarray, depth: np.ndarray,
          top_k: int) -> list[GraspCandidate]:
    """The kept candidates, best score first, then the one the object hangs least deep from
    (``depth``, m), at most ``top_k``."""
    order = sorted(np.flatnonzero(keep).tolist(),
                   key=lambda i: (-round(candidates[i].score, 6), round(float(depth[i]), 4), i))
    return [candidates[i] for i in order[:top_k]]
