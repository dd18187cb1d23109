"""Grasp synthesis, collision counting and scoring (paper Sec. 2.3-2.4, design.md Sec. 4)."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
import trimesh
from gbh_shapes import CUP_RADIUS, RING_R, RING_r
from scipy.spatial.transform import Rotation

from gbh_drake.core.collision import count_points_in_gripper
from gbh_drake.core.geometry import unit
from gbh_drake.core.gripper import HOOK_GRIPPER, keypoints_W
from gbh_drake.core.object_model import prepare_object
from gbh_drake.core.params import GbhParams
from gbh_drake.core.pipeline import plan_grasps
from gbh_drake.core.results import PARALLEL, VERTICAL, GraspCandidate, HangingStructure
from gbh_drake.core.scoring import (
    collision_free,
    is_copy,
    miss_resultant,
    rank_grasps,
    score_grasps,
)


def linking_number(a: np.ndarray, b: np.ndarray) -> float:
    """Gauss linking number of two closed polygons (n, 3) and (m, 3), exact for polygons
    (signed solid angles of segment pairs, Klenin & Langowski 2000)."""
    a0, a1 = a, np.roll(a, -1, axis=0)
    b0, b1 = b, np.roll(b, -1, axis=0)
    r13 = b0[None] - a0[:, None]
    r14 = b1[None] - a0[:, None]
    r23 = b0[None] - a1[:, None]
    r24 = b1[None] - a1[:, None]

    def n(u, v):
        c = np.cross(u, v)
        return c / np.maximum(np.linalg.norm(c, axis=-1, keepdims=True), 1e-15)

    n1, n2, n3, n4 = n(r13, r14), n(r14, r24), n(r24, r23), n(r23, r13)

    def asin(u, v):
        return np.arcsin(np.clip(np.sum(u * v, axis=-1), -1.0, 1.0))

    omega = asin(n1, n2) + asin(n2, n3) + asin(n3, n4) + asin(n4, n1)
    sign = np.sign(np.sum(np.cross((b1 - b0)[None], (a1 - a0)[:, None]) * r13, axis=-1))
    return float(np.sum(omega * sign) / (4.0 * np.pi))


def ring_core_circle(n: int = 200) -> np.ndarray:
    t = 2.0 * np.pi * np.arange(n) / n
    return RING_R * np.stack([np.cos(t), np.sin(t), np.zeros(n)], axis=1)


def gripper_loop_W(X_WG: np.ndarray, q: float) -> np.ndarray:
    return trimesh.transform_points(HOOK_GRIPPER.loop_polygon_G(q), X_WG)


@pytest.fixture(scope="module")
def ring_result(ring, params):
    return plan_grasps(ring, params)


@pytest.fixture(scope="module")
def mug_result(mug, params):
    return plan_grasps(mug, params)


def test_linking_number_helper_on_known_pairs():
    circle = ring_core_circle()
    square = np.array([[0.04, 0, -0.02], [0.06, 0, -0.02], [0.06, 0, 0.02], [0.04, 0, 0.02]])
    assert linking_number(circle, square) == pytest.approx(1.0, abs=1e-6) or linking_number(
        circle, square
    ) == pytest.approx(-1.0, abs=1e-6)
    assert linking_number(circle, square + [0.1, 0, 0]) == pytest.approx(0.0, abs=1e-6)


def test_ring_grasps_link_the_ring_and_shifted_ones_do_not(ring_result, params):
    ranked = ring_result.ranked
    assert len(ranked) == params.top_k
    kinds = {g.kind for g in ring_result.candidates if g.n_collisions < params.p_c}
    assert kinds == {PARALLEL, VERTICAL}
    circle = ring_core_circle()
    travel = HOOK_GRIPPER.q_open - HOOK_GRIPPER.q_closed
    for g in ring_result.candidates:
        if g.n_collisions >= params.p_c:
            continue
        # At the grasp pose (open) the ring passes through the open loop (p5 p4 p2 p3) ...
        q = HOOK_GRIPPER.q_open
        assert abs(linking_number(gripper_loop_W(g.X_WG, q), circle)) == pytest.approx(1, abs=1e-6)
        shifted = g.X_WG.copy()
        shifted[:3, 3] += g.X_WG[:3, 2] * -0.10  # 10 cm back along the approach
        assert linking_number(gripper_loop_W(shifted, q), circle) == pytest.approx(0, abs=1e-6)
        # ... and through the closed one, where the closing motion puts it (parallel: about G;
        # vertical: about the straight rod, G following the fingers along +y_G).
        X_closed = g.X_WG.copy()
        if g.kind == VERTICAL:
            X_closed[:3, 3] += travel * g.X_WG[:3, 1]
        loop = gripper_loop_W(X_closed, HOOK_GRIPPER.q_closed)
        assert abs(linking_number(loop, circle)) == pytest.approx(1, abs=1e-6)


def test_parallel_and_vertical_pose_conventions(ring_result, params):
    """The paper's poses (turn 0); the turned ones are tested below."""
    s = ring_result.structures[0]
    for g in ring_result.candidates:
        if g.turn_deg != 0:
            continue
        R = g.X_WG[:3, :3]
        np.testing.assert_allclose(R.T @ R, np.eye(3), atol=1e-9)
        assert np.linalg.det(R) == pytest.approx(1.0)
        u = (s.c - g.h) / np.linalg.norm(s.c - g.h)
        kp = keypoints_W(g.X_WG)
        if g.kind == PARALLEL:
            # c on the bar's centre line, at most the closed loop's half width from the middle
            # of the fingertips (the caged material is centred between the rods; the ring's
            # tube is symmetric, so here the shift is small).
            off = s.c - 0.5 * (kp["p2"] + kp["p3"])
            np.testing.assert_allclose(off - (off @ R[:, 1]) * R[:, 1], 0.0, atol=1e-9)
            assert abs(off @ R[:, 1]) < 1e-3
            assert abs(R[:, 1] @ s.v) == pytest.approx(1.0)  # bar n2 along +-v
            np.testing.assert_allclose(R[:, 2], u, atol=1e-9)  # approach -n1 = unit(c - h)
        else:
            # Ring lies flat: v is the ground normal, so the straight finger is exactly vertical.
            assert abs(R[:, 2] @ [0, 0, 1]) == pytest.approx(1.0)
            u_perp = u - (u @ R[:, 2]) * R[:, 2]  # u made orthogonal to the snapped finger
            np.testing.assert_allclose(R[:, 1], u_perp / np.linalg.norm(u_perp), atol=1e-9)
            # p2 lies d1 beyond h on the line through q1 along the finger.
            q1 = g.h + params.d1 * u
            off = kp["p2"] - q1
            np.testing.assert_allclose(off - (off @ R[:, 2]) * R[:, 2], 0.0, atol=1e-9)


def test_vertical_grasp_tips_clear_the_caged_material(ring_result, params):
    """The bar's inner face is cage_clearance + d2 beyond the ring's tube (radius 1 cm about the
    ring's plane) along the finger, whether the fingers point down (from above) or up: p2, on
    the bar's centre line, is half a rod further."""
    vertical = [g for g in ring_result.candidates if g.kind == VERTICAL]
    assert {np.sign(g.X_WG[2, 2]) for g in vertical} == {-1.0, 1.0}
    for g in vertical:
        p2 = keypoints_W(g.X_WG)["p2"]
        inner_face = p2 @ g.X_WG[:3, 2] - HOOK_GRIPPER.rod_width / 2
        assert inner_face == pytest.approx(RING_r + params.cage_clearance + params.d2, abs=2e-3)


def test_d2_adds_to_the_clearance(ring, params):
    base = plan_grasps(ring, params)
    one_view = plan_grasps(ring, dataclasses.replace(params, d2=0.005))
    for a, b in zip(base.candidates, one_view.candidates, strict=True):
        if a.kind == VERTICAL:
            shift = (b.X_WG[:3, 3] - a.X_WG[:3, 3]) @ a.X_WG[:3, 2]
            assert shift == pytest.approx(0.005, abs=1e-9)
        else:
            np.testing.assert_allclose(a.X_WG, b.X_WG)


@pytest.mark.parametrize(("tilt_deg", "snap_tilt_max_deg", "finger_cosines"), [
    (10.0, 45.0, {1.0}),           # the paper's rule: within 18 deg the finger is vertical
    (30.0, 0.0, {0.866}),          # the paper's rule alone: along the tilted axis
    (30.0, 45.0, {0.866, 1.0}),    # ours: both, the checks decide
    (60.0, 45.0, {0.5}),           # past the bound: along the axis only
])
def test_ground_rule_snaps_near_vertical_and_tries_both_up_to_the_bound(
        ring, params, tilt_deg, snap_tilt_max_deg, finger_cosines):
    X = np.eye(4)
    X[:3, :3] = Rotation.from_euler("x", tilt_deg, degrees=True).as_matrix()
    result = plan_grasps(ring.copy().apply_transform(X),
                         dataclasses.replace(params, snap_tilt_max_deg=snap_tilt_max_deg))
    vertical = [g for g in result.candidates if g.kind == VERTICAL]
    cosines = {round(float(abs(g.X_WG[2, 2])), 1) for g in vertical}
    assert cosines == {round(c, 1) for c in finger_cosines}


def test_every_kept_grasp_is_collision_free_by_an_independent_count(mug, mug_result, params):
    obj = prepare_object(mug, params)
    assert mug_result.ranked
    for g in mug_result.candidates:
        assert g.n_collisions == _count_reference(g.X_WG, obj.points, HOOK_GRIPPER.q_open, 0.0)
    assert all(g.n_collisions < params.p_c for g in mug_result.ranked)
    # Approaching from the cup's side (h on the cup wall) drives the hand into the cup.
    from_cup = [g for g in mug_result.candidates
                if g.kind == PARALLEL and np.linalg.norm(g.h[:2]) < CUP_RADIUS + 1e-3]
    assert from_cup and all(g.n_collisions >= params.p_c for g in from_cup)


def _count_reference(X_WG: np.ndarray, points: np.ndarray, q: float, margin: float) -> int:
    """Independent N_c: each point in G, each box of the solid model, one at a time."""
    p_G = trimesh.transform_points(points, np.linalg.inv(X_WG))
    inside = np.zeros(len(p_G), dtype=bool)
    for b in HOOK_GRIPPER.solid_boxes_G(q):
        inside |= np.all(np.abs(p_G - b.center) <= np.asarray(b.half_extents) + margin, axis=1)
    return int(inside.sum())


def test_batched_count_matches_gripper_model():
    rng = np.random.default_rng(1)
    points = rng.normal(scale=0.06, size=(3000, 3))
    X = np.tile(np.eye(4), (7, 1, 1))
    X[:, :3, :3] = Rotation.random(7, random_state=2).as_matrix()
    X[:, :3, 3] = rng.normal(scale=0.03, size=(7, 3))
    for q, margin in ((HOOK_GRIPPER.q_open, 0.0), (HOOK_GRIPPER.q_closed, 0.002)):
        counts = count_points_in_gripper(points, X, q, margin)
        np.testing.assert_array_equal(counts, [_count_reference(x, points, q, margin) for x in X])
        p_G = trimesh.transform_points(points, np.linalg.inv(X[0]))
        assert HOOK_GRIPPER.count_points_inside(p_G, q, margin) == counts[0]
        assert counts.max() > 0


def _structure(m: float, a) -> HangingStructure:
    return HangingStructure(np.zeros(3), np.array([1.0, 0, 0]), np.zeros((1, 3)), m,
                            np.asarray(a, dtype=float))


def _pose(y, z) -> np.ndarray:
    X = np.eye(4)
    X[:3, 1], X[:3, 2] = y, z
    X[:3, 0] = np.cross(y, z)
    return X


def test_scores_follow_the_paper_and_the_beta_sign_choice(params):
    hook = _structure(0.7, [0, -1, 0])  # open toward -y
    loop = _structure(1.0, [0, 0, 0])
    down, up = np.array([0, 0, -1.0]), np.array([0, 0, 1.0])
    g = [
        # Parallel, approach +z_G = -y: the material at h is on +y, opposite the opening (-y).
        GraspCandidate(_pose([1, 0, 0], [0, -1, 0]), PARALLEL, 0, hook, np.zeros(3)),
        GraspCandidate(_pose([1, 0, 0], down), PARALLEL, 0, loop, np.zeros(3)),
        GraspCandidate(_pose([0, -1, 0], down), VERTICAL, 0, hook, np.zeros(3)),
        GraspCandidate(_pose([0, 1, 0], up), VERTICAL, 0, hook, np.zeros(3)),
    ]
    score_grasps(g, params)
    # Parallel: beta uses the approach +z_G = unit(c - h) (design.md Sec. 4), here along a.
    assert g[0].beta == pytest.approx(0.0)
    assert g[0].s_beta == pytest.approx(1.0)
    assert g[0].alpha == pytest.approx(np.pi / 2)
    assert g[0].s_alpha == pytest.approx(np.exp(-(np.pi / 2) ** 2 / 0.04))
    # A closed loop (m = 1) and a top-down approach (R n1 = up) score 1; beta has no meaning.
    assert (g[1].s_beta, g[1].s_alpha, g[1].score) == pytest.approx((1.0, 1.0, 1.0))
    assert np.isnan(g[1].beta)
    # Vertical: beta uses R n2 = +y_G.
    assert g[2].beta == pytest.approx(0.0) and g[2].score == pytest.approx(0.7)
    assert g[3].beta == pytest.approx(np.pi)
    assert g[3].s_beta == pytest.approx(np.exp(-np.pi**2 / 2.0))
    assert g[3].alpha == pytest.approx(np.pi)

    for x, n in zip(g, (0, 3, 12, 9), strict=True):
        x.n_collisions, x.n_sweep_collisions, x.ground_distance, x.rod_contacts = n, 0, 1.0, 0
    ranked = rank_grasps(g, dataclasses.replace(params, top_k=2))
    assert ranked == [g[1], g[0]]  # g[2] collides (12 >= 10), g[3] scores ~0 and is cut by k


def test_equal_scores_rank_by_fewer_points_in_the_gripper(params):
    """Ours: of grasps that score alike, the one with fewer object points in the open gripper
    (more room round its rods) first; the paper's preset sorts by the score alone; a better
    score always wins over fewer points."""
    loop = _structure(1.0, [0, 0, 0])
    down = np.array([0, 0, -1.0])
    g = [GraspCandidate(_pose([1, 0, 0], down), PARALLEL, i, loop, np.zeros(3)) for i in range(3)]
    for i, x in enumerate(g):
        x.X_WG[:3, 3] = [0.1 * i, 0, 0]  # distinct poses
    score_grasps(g, params)
    g[0].score = 1.0 - 1e-9  # a rounding's difference: a tie
    g[2].score = 0.99  # a real difference
    for x, n in zip(g, (5, 1, 0), strict=True):
        x.n_collisions, x.n_sweep_collisions, x.ground_distance, x.rod_contacts = n, 0, 1.0, 0
    assert rank_grasps(g, params) == [g[1], g[0], g[2]]
    assert rank_grasps(g, GbhParams(preset="paper")) == [g[1], g[0], g[2]]


def test_pipeline_is_deterministic(mug, mug_result, params):
    again = plan_grasps(mug, params)
    assert len(again.candidates) == len(mug_result.candidates)
    for a, b in zip(again.candidates, mug_result.candidates, strict=True):
        np.testing.assert_array_equal(a.X_WG, b.X_WG)
        assert (a.kind, a.n_collisions, a.score) == (b.kind, b.n_collisions, b.score)


def test_nothing_hangable_gives_empty_results(params):
    result = plan_grasps(trimesh.creation.box((0.1, 0.06, 0.04)), params)
    assert result.structures == [] and result.candidates == [] and result.ranked == []
    assert set(result.timings) == {"sampling", "hangability", "synthesis", "collision", "scoring"}


def test_only_requested_grasp_kinds(ring, params):
    result = plan_grasps(ring, GbhParams(vertical_grasps=False))
    assert {g.kind for g in result.candidates} == {PARALLEL}


def test_cancelling_misses_give_a_neutral_beta(params):
    """m < 1 with openings on opposite sides (a = 0): beta = pi/2, not the best score."""
    two_sided = _structure(0.8, [0, 0, 0])
    g = [GraspCandidate(_pose([1, 0, 0], [0, 0, -1.0]), PARALLEL, 0, two_sided, np.zeros(3))]
    score_grasps(g, params)
    assert g[0].beta == pytest.approx(np.pi / 2)
    assert g[0].s_beta == pytest.approx(np.exp(-(np.pi / 2) ** 2 / params.gamma_beta))
    assert g[0].score < 0.8


def test_ranking_filters_then_sorts_then_cuts(mug_result, params):
    """The paper's order: collision-free grasps (our sweep and ground checks included), by
    S_total (ours: equal scores by fewer N_c), copies of a better grasp left out, the top k;
    nothing left out scores higher than the last one kept unless it fails a collision check
    or copies one kept."""
    free = [g for g in mug_result.candidates if collision_free(g, params)]
    distinct: list = []
    for g in sorted(free, key=lambda g: (-float(f"{g.score:.6g}"), g.n_collisions)):
        if not any(is_copy(g, kept, params) for kept in distinct):
            distinct.append(g)
    assert mug_result.ranked == distinct[: params.top_k]
    cut = min(g.score for g in mug_result.ranked)
    for g in mug_result.candidates:
        if g not in mug_result.ranked and g.score > cut:
            assert not collision_free(g, params) or any(is_copy(g, kept, params)
                                                        for kept in mug_result.ranked)
    for field, bad in (("n_collisions", params.p_c), ("n_sweep_collisions", params.p_sweep),
                       ("ground_distance", params.ground_clearance - 1e-4)):
        g = dataclasses.replace(mug_result.ranked[0], **{field: bad})
        assert not collision_free(g, dataclasses.replace(params, ground_clearance=0.003))


def test_closed_loops_score_s_beta_one_in_the_pipeline(ring_result):
    """A closed loop (the ring, m = 1) has no opening direction: a = 0, S_beta = 1."""
    assert ring_result.structures[0].m == 1.0
    assert np.allclose(ring_result.structures[0].a, 0.0)
    assert ring_result.ranked
    for g in ring_result.ranked:
        assert g.s_beta == 1.0 and np.isnan(g.beta)


def _two_arcs(offset: float) -> trimesh.Trimesh:
    """A ring (radius 3 cm, 4 mm wire) with two gaps on opposite sides (a 2 cm slab removed,
    ``offset`` m off centre): two arcs that hold a rod between them."""
    import manifold3d as m3d
    from gbh_shapes import _to_trimesh, _torus

    slab = m3d.Manifold.cube((0.02, 0.1, 0.02)).translate((-0.01 + offset, -0.05, -0.01))
    return _to_trimesh(_torus(0.03, 0.004) - slab)


@pytest.mark.parametrize("offset", [0.0, 0.003])
def test_cancelling_misses_give_a_neutral_beta_in_the_pipeline(params, offset):
    """Two openings on opposite sides: m < 1 and the missing rays cancel, so beta = pi/2 for
    every grasp, even when the gaps are a little uneven and the structure's normalised a is a
    unit vector (offset 3 mm)."""
    result = plan_grasps(_two_arcs(offset), params)
    (s,) = result.structures
    assert 0.5 < s.m < 1.0
    assert miss_resultant(s) < params.min_miss_resultant
    if offset:
        assert np.linalg.norm(s.a) == pytest.approx(1.0)
    assert result.ranked
    for g in result.candidates:
        assert g.beta == pytest.approx(np.pi / 2)
        assert g.s_beta == pytest.approx(np.exp(-(np.pi / 2) ** 2 / params.gamma_beta))


def test_one_opening_gives_a_beta(hook, params):
    """One opening (a hook): the misses agree, beta is the angle to a_i and varies."""
    result = plan_grasps(hook, params)
    s = result.structures[0]
    assert s.m < 1.0 and miss_resultant(s) > 0.5
    betas = {round(g.beta, 3) for g in result.candidates if g.structure is s}
    assert len(betas) > 2 and all(0.0 <= b <= np.pi for b in betas)


def test_parallel_grasps_centre_the_caged_material_between_the_rods(params):
    """A ring's structure moved 4 mm off the ring's mid-plane along its axis (c and its hit
    points: the plane of the rays is not the material's mid-plane, as on the headphones' band):
    the parallel grasps slide back along the bar until the tube is centred between the rods."""
    import gbh_shapes

    from gbh_drake.core.grasp_synthesis import parallel_anchor_G, parallel_grasp_poses

    obj = prepare_object(gbh_shapes.make_ring(), params)
    (s,) = plan_grasps(obj, params).structures
    off_plane = dataclasses.replace(s, c=s.c + 0.004 * s.v, H=s.H + 0.004 * s.v)
    X, _ = parallel_grasp_poses(off_plane, HOOK_GRIPPER, obj.points, params)
    X_fixed, _ = parallel_grasp_poses(off_plane)  # no points: c at (p2 + p3) / 2
    for a, b in zip(X, X_fixed, strict=True):
        np.testing.assert_allclose(a[:3, :3], b[:3, :3])
        assert trimesh.transform_points(parallel_anchor_G()[None], b)[0] @ s.v == pytest.approx(0.004)
        # Centred: (p2 + p3) / 2 back on the ring's mid-plane (z = 0), i.e. moved along the bar.
        mid = trimesh.transform_points(parallel_anchor_G()[None], a)[0]
        assert mid[2] == pytest.approx(0.0, abs=1e-3)
        np.testing.assert_allclose(np.cross(a[:3, 3] - b[:3, 3], a[:3, 1]), 0.0, atol=1e-12)


def test_turned_grasps_are_the_papers_turned_about_the_hole_or_the_finger(ring_result, params):
    """Beyond the paper: each grasp is also tried turned about the hole's axis through c
    (parallel: the bar stays on the axis) or about the straight finger through q1 (vertical:
    the straight rod stays in the hole); the caged point h turns with it."""
    s = ring_result.structures[0]
    turns = sorted({g.turn_deg for g in ring_result.candidates})
    assert turns == sorted(params.approach_rotations_deg) and len(turns) > 1
    by_key = {(g.kind, g.turn_deg, i % len(s.H)): g for i, g in enumerate(
        g for g in ring_result.candidates if g.structure is s)}
    for (kind, turn, j), g in by_key.items():
        if turn == 0:
            continue
        paper = by_key[(kind, 0.0, j)]
        R, R0 = g.X_WG[:3, :3], paper.X_WG[:3, :3]
        axis = R[:, 1] if kind == PARALLEL else R[:, 2]  # the bar, or the straight finger
        np.testing.assert_allclose(axis, R0[:, 1] if kind == PARALLEL else R0[:, 2], atol=1e-9)
        cos = np.clip(R[:, 2 if kind == PARALLEL else 1] @ R0[:, 2 if kind == PARALLEL else 1],
                      -1, 1)
        assert np.degrees(np.arccos(cos)) == pytest.approx(abs(turn), abs=1e-6)
        if kind == PARALLEL:  # h stays as far from c as the paper's, on the turned approach
            assert np.linalg.norm(g.h - s.c) == pytest.approx(np.linalg.norm(paper.h - s.c))
            np.testing.assert_allclose(unit(s.c - g.h), R[:, 2], atol=1e-9)


def _pose_gap(a: GraspCandidate, b: GraspCandidate) -> tuple[float, float]:
    """(m, deg) between two grasps' origins and orientations."""
    R = a.X_WG[:3, :3].T @ b.X_WG[:3, :3]
    angle = np.degrees(np.arccos(np.clip(0.5 * (np.trace(R) - 1.0), -1.0, 1.0)))
    return float(np.linalg.norm(a.X_WG[:3, 3] - b.X_WG[:3, 3])), float(angle)


def test_a_closed_handles_top_ten_are_ten_distinct_grasps(mug, mug_result, params):
    """The mug's closed handle: the turned approaches land on the neighbouring contacts, so the
    ranking without de-duplication (the paper's, preset ``paper`` keeps it) holds copies of one
    pose; with it the ten are distinct: any two differ in kind, or by at least
    ``distinct_distance`` or ``distinct_angle_deg``."""
    assert mug_result.structures[0].m == 1.0  # a closed loop
    ranked = mug_result.ranked
    assert len(ranked) == params.top_k
    for i, a in enumerate(ranked):
        for b in ranked[:i]:
            distance, angle = _pose_gap(a, b)
            assert a.kind != b.kind or distance >= params.distinct_distance \
                or angle >= params.distinct_angle_deg, (i, distance, angle)
    plain = rank_grasps(mug_result.candidates, dataclasses.replace(
        params, distinct_distance=0.0, distinct_angle_deg=0.0))
    copies = sum(any(a.kind == b.kind and max(_pose_gap(a, b)) < 1e-6 for b in plain[:i])
                 for i, a in enumerate(plain))
    assert copies > 0, "the ranking without de-duplication has no copies: the test shows nothing"
    assert GbhParams().with_preset("paper").distinct_distance == 0.0


def test_centred_d1_stands_the_straight_rod_in_the_middle_of_a_narrow_hole(params):
    """A ring with a 13 mm hole (|c - h| 6.5 mm, under the paper's d1 = 1 cm): the paper's
    vertical grasp stands the straight rod's axis 3.5 mm past the centre, 3 mm from the far
    side, so the 8 mm rod cuts into it; ``d1_centred`` stands it on the hole's axis, and more
    vertical grasps pass the collision count."""
    from gbh_shapes import _to_trimesh, _torus

    small = _to_trimesh(_torus(0.0105, 0.004))
    paper = plan_grasps(small, dataclasses.replace(params, d1_centred=False))
    centred = plan_grasps(small, dataclasses.replace(params, d1_centred=True))
    s = paper.structures[0]
    assert np.linalg.norm(s.c - paper.candidates[0].h) < params.d1  # a narrow hole
    offsets = {}
    for name, result in (("paper", paper), ("centred", centred)):
        off = []
        for g in result.candidates:
            if g.kind != VERTICAL or g.turn_deg != 0:
                continue
            z, p2 = g.X_WG[:3, 2], keypoints_W(g.X_WG)["p2"]
            d = s.c - p2  # the hole's axis is vertical; the straight rod along z
            off.append(np.linalg.norm(d - (d @ z) * z))
        offsets[name] = np.asarray(off)
    assert offsets["centred"].max() < 1.5e-3  # on the axis (c is the fitted centre)
    assert offsets["paper"].min() > 2e-3
    free = {name: sum(g.kind == VERTICAL and g.n_collisions < params.p_c for g in r.candidates)
            for name, r in (("paper", paper), ("centred", centred))}
    assert free["centred"] > free["paper"], free
