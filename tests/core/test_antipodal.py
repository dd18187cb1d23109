"""The antipodal baseline (two rods, bar retracted) and the retracted bar's geometry."""

from __future__ import annotations

import dataclasses
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import trimesh
from hypothesis import given, settings
from hypothesis import strategies as st

from gbh_drake.core.antipodal import (
    ANTIPODAL,
    AntipodalParams,
    count_in_swept_model,
    flipped,
    plan_antipodal_grasps,
    pregrasp_openings,
    sample_antipodal_grasps,
)
from gbh_drake.core.gripper import HOOK_GRIPPER, Box
from gbh_drake.core.object_model import prepare_object
from gbh_drake.core.params import GbhParams
from gbh_drake.core.results import GbhInputError
from gbh_drake.objects import make_object

G = HOOK_GRIPPER
R_ROD = 0.5 * G.rod_width
LF, LH = G.finger_length, G.bar_length


def _on_table(mesh: trimesh.Trimesh) -> trimesh.Trimesh:
    mesh = mesh.copy()
    mesh.apply_translation([0.0, 0.0, -mesh.bounds[0, 2]])
    return mesh


def _box_mesh(size) -> trimesh.Trimesh:
    return _on_table(trimesh.creation.box(extents=size))


@pytest.fixture(scope="module")
def box_grasps():
    """A box 5 cm wide (x), 12 cm long (y), 10 cm tall on the table: only x spans fit."""
    mesh = _box_mesh((0.05, 0.12, 0.10))
    return mesh, plan_antipodal_grasps(mesh, AntipodalParams(), 0)


@pytest.fixture(scope="module")
def mug():
    return make_object("mug_classic").mesh  # body 8.2 cm across, handle toward +x, on z = 0


@pytest.fixture(scope="module")
def mug_grasps(mug):
    return plan_antipodal_grasps(mug, AntipodalParams(top_k=40), 0)


# ---- the retracted bar ---------------------------------------------------------------------------
def _contains(outer: Box, inner: Box, tol: float = 1e-12) -> bool:
    lo_o = np.subtract(outer.center, outer.half_extents)
    hi_o = np.add(outer.center, outer.half_extents)
    lo_i = np.subtract(inner.center, inner.half_extents)
    hi_i = np.add(inner.center, inner.half_extents)
    return bool(np.all(lo_o <= lo_i + tol) and np.all(hi_i <= hi_o + tol))


def test_default_solid_model_is_unchanged_by_the_new_keyword():
    for q in (G.q_closed, 0.03, G.q_open):
        assert G.solid_boxes_G(q) == G.solid_boxes_G(q, bar_retracted=False)
        bar = {b.name: b for b in G.solid_boxes_G(q)}["bar"]
        assert bar.center[1] + bar.half_extents[1] == pytest.approx(LH - q)  # tip at p1
        assert bar.center[2] == pytest.approx(LF)
    assert G.q_min() == G.q_closed and G.q_min(bar_retracted=True) == pytest.approx(R_ROD)
    with pytest.raises(ValueError):
        G.solid_boxes_G(0.01)  # below q_closed with the bar out: the bar would cross the rod
    G.solid_boxes_G(0.01, bar_retracted=True)
    with pytest.raises(ValueError):
        G.solid_boxes_G(R_ROD - 1e-4, bar_retracted=True)


def test_retracted_bar_lies_on_the_l_rods_last_bar_length():
    bar = G.retracted_bar_box()
    lo = np.subtract(bar.center, bar.half_extents)
    hi = np.add(bar.center, bar.half_extents)
    np.testing.assert_allclose(lo, [-R_ROD, -R_ROD, LF - LH], atol=1e-12)
    np.testing.assert_allclose(hi, [R_ROD, R_ROD, LF + R_ROD], atol=1e-12)
    # The joint: -pi/2 about +x_G through p3 takes the bar's direction +y_G to -z_G.
    a = G.bar_retracted_angle
    Rx = np.array([[1, 0, 0], [0, np.cos(a), -np.sin(a)], [0, np.sin(a), np.cos(a)]])
    np.testing.assert_allclose(Rx @ [0, 1, 0], [0, 0, -1], atol=1e-12)
    released = G.l_finger_boxes()[1]
    tip_released = np.array([0.0, released.center[1] + released.half_extents[1], LF])  # p1 in F
    tip_retracted = G.bar_pivot_F + Rx @ (tip_released - G.bar_pivot_F)
    np.testing.assert_allclose(tip_retracted, [0, 0, LF - LH], atol=1e-12)


@settings(max_examples=60, deadline=None)
@given(q=st.floats(min_value=R_ROD, max_value=G.q_open),
       p=st.lists(st.floats(min_value=-0.12, max_value=0.12), min_size=3, max_size=3))
def test_retracted_model_has_nothing_beyond_the_rods(q, p):
    boxes = {b.name: b for b in G.solid_boxes_G(q, bar_retracted=True)}
    assert set(boxes) == {"hand", "straight_rod", "l_rod", "bar"}
    # The bar is inside the L rod's box: no box reaches beyond the L rod's outer envelope.
    assert _contains(boxes["l_rod"], boxes["bar"])
    # So a point is in the solid model exactly when it is in the hand or one of the two rods.
    x, y, z = (np.array([v]) for v in p)
    rods = [boxes[n] for n in ("hand", "straight_rod", "l_rod")]
    expected = any(np.all(np.abs(np.subtract(p, b.center)) <= b.half_extents) for b in rods)
    assert bool(G.inside_solid_model(x, y, z, q, bar_retracted=True)[0]) == expected
    # Between the rods' inner faces (|y| < q - r) in front of the palm nothing is solid.
    if abs(p[1]) < q - R_ROD and p[2] > 1e-9:  # (the hand box is closed: z = 0 is solid)
        assert not G.inside_solid_model(x, y, z, q, bar_retracted=True)[0]


# ---- the sampler -----------------------------------------------------------------------------------
def test_box_grasps_span_the_5cm_faces_antipodally(box_grasps):
    mesh, result = box_grasps
    grasps = result.ranked
    assert len(grasps) == AntipodalParams().top_k
    for g in grasps:
        assert g.kind == ANTIPODAL and g.bar_retracted
        assert g.width == pytest.approx(0.05, abs=1e-4)
        assert g.q == pytest.approx(0.025 + R_ROD, abs=1e-4)
        np.testing.assert_allclose(np.abs(g.p_WA[0]), 0.025, atol=1e-4)
        np.testing.assert_allclose(np.abs(g.p_WB[0]), 0.025, atol=1e-4)
        assert g.n_WA @ g.n_WB == pytest.approx(-1.0, abs=1e-6)
        np.testing.assert_allclose(np.abs(g.X_WG[:3, 1]), [1, 0, 0], atol=1e-6)
        assert g.angle_A < 1e-6 and g.angle_B < 1e-6
    assert grasps[0].cost_direction == pytest.approx(-1.0)  # top-down first
    costs = [g.cost for g in grasps]
    assert costs == sorted(costs)


def test_contacts_sit_on_the_rods_pads(box_grasps, mug_grasps):
    for g in box_grasps[1].ranked + mug_grasps.ranked:
        X_GW = np.linalg.inv(g.X_WG)
        a, b = trimesh.transform_points(np.stack([g.p_WA, g.p_WB]), X_GW)
        z_pad = LF - g.contact_depth
        np.testing.assert_allclose(a, [0, -(g.q - R_ROD), z_pad], atol=1e-9)  # L rod's face
        np.testing.assert_allclose(b, [0, g.q - R_ROD, z_pad], atol=1e-9)  # straight rod's
        assert AntipodalParams().min_contact_depth - 1e-9 <= g.contact_depth <= 0.015 + 1e-9
        assert g.angle_B <= np.arctan(AntipodalParams().friction_coefficient) + 1e-9
        np.testing.assert_allclose(g.X_WG[:3, :3].T @ g.X_WG[:3, :3], np.eye(3), atol=1e-9)
        assert np.linalg.det(g.X_WG[:3, :3]) == pytest.approx(1.0)


def test_ball_wider_than_the_opening_has_no_grasp():
    big = _on_table(trimesh.creation.icosphere(subdivisions=4, radius=0.05))
    result = plan_antipodal_grasps(big, AntipodalParams(), 0)
    assert result.counts["exits"] > 0 and result.counts["fits"] == 0
    assert result.ranked == []
    # Control: a ball 5 cm across is pinched across its diameter.
    small = _on_table(trimesh.creation.icosphere(subdivisions=4, radius=0.025))
    grasps = sample_antipodal_grasps(small, AntipodalParams(), 0)
    assert grasps
    for g in grasps:
        assert g.width == pytest.approx(0.05, abs=1.5e-3)
        assert np.linalg.norm(0.5 * (g.p_WA + g.p_WB) - [0, 0, 0.025]) < 2e-3


def test_mug_grasps_hold_the_wall_or_the_handle_never_the_body_across(mug, mug_grasps):
    grasps = mug_grasps.ranked
    assert len(grasps) == 40
    max_width = 2.0 * (G.q_open - AntipodalParams().opening_margin) - G.rod_width
    mids = np.stack([0.5 * (g.p_WA + g.p_WB) for g in grasps])
    assert mug.contains(mids).all(), "the rods pinch material, not air"
    for g in grasps:
        assert 0.0 < g.width <= max_width + 1e-9
        assert g.width < 0.03  # the wall or the handle, not the 8.2 cm body across
        radius = np.linalg.norm(0.5 * (g.p_WA + g.p_WB)[:2])
        on_wall = 0.03 < radius < 0.042
        on_handle = 0.5 * (g.p_WA + g.p_WB)[0] > 0.041
        assert on_wall or on_handle
    assert grasps[0].cost_direction < -0.99  # the best comes from above


@pytest.mark.parametrize("name", ["mug_classic", "can", "kettle", "frying_pan"])
def test_no_grasp_dips_below_the_table_or_collides(name):
    mesh = make_object(name).mesh
    params = AntipodalParams(top_k=30)
    obj = prepare_object(mesh, GbhParams(n_points=params.n_points))
    grasps = sample_antipodal_grasps(obj, params, 1)
    assert grasps
    for g in grasps:
        assert g.n_collisions < params.p_c
        for q in (g.q_pregrasp, g.q):  # the open gripper and the gripper at the contacts
            assert _lowest_corner(g, q) >= params.ground_clearance - 1e-9
        assert g.ground_clearance >= params.ground_clearance - 1e-9
        # Independent count with the geometry module: open gripper and gripper at the contacts.
        p_G = trimesh.transform_points(obj.points, np.linalg.inv(g.X_WG))
        for q in (g.q_pregrasp, g.q + params.contact_tolerance):
            assert G.count_points_inside(p_G, q, bar_retracted=True) <= g.n_collisions


def test_swept_count_sees_material_between_the_open_rods_and_the_contacts():
    # A plate 5 cm wide with a post standing beside it: the top-down pinch whose rod would
    # sweep through the post is refused (the open gripper alone does not touch the post).
    plate = _box_mesh((0.05, 0.02, 0.06))
    post = trimesh.creation.box(extents=(0.004, 0.01, 0.06))
    post.apply_translation([0.0315, 0.0, 0.03])  # x in [0.0295, 0.0335]: the rod sweeps it
    points = np.concatenate([trimesh.sample.sample_surface(m, 3000, seed=0)[0]
                             for m in (plate, post)])
    X = np.eye(4)
    X[:3, :3] = [[0, 1, 0], [1, 0, 0], [0, 0, -1]]  # y_G = +x_W, z_G = -z_W
    X[:3, 3] = [0, 0, 0.05 + LF - 0.015]
    q_contact = 0.025 + R_ROD
    n_open = count_in_swept_model(points, X[None], [G.q_open], [G.q_open])[0]
    n_swept = count_in_swept_model(points, X[None], [q_contact + 1e-3], [G.q_open])[0]
    assert n_open == 0 and n_swept > 0


def test_descent_corridor_must_be_clear():
    # A stem 5 cm wide (x) and 10 cm tall with a block floating 30 cm up: at the grasp pose a
    # top-down hand clears the block, but descending from 10 cm back it hits it unless the
    # contacts are low (hand top = contact + (l_f - 1.5 cm) + hand depth + 10 cm < 30 cm).
    stem = _box_mesh((0.05, 0.02, 0.10))
    block = trimesh.creation.box(extents=(0.3, 0.3, 0.01))
    block.apply_translation([0.0, 0.0, 0.305])
    mesh = trimesh.util.concatenate([stem, block])
    top_down = {}
    for d in (0.0, 0.10):
        params = AntipodalParams(approach_distance=d, top_k=200, n_samples=600)
        grasps = sample_antipodal_grasps(mesh, params, 0)
        top_down[d] = [g for g in grasps if g.cost_direction < -0.99]
        assert top_down[d]
    hand_depth = 2.0 * G.hand_half_extents[2]
    limit = 0.30 - 0.10 - hand_depth - (LF - 0.015)
    assert max(g.p_WA[2] for g in top_down[0.0]) > limit + 0.01
    assert max(g.p_WA[2] for g in top_down[0.10]) <= limit + 1e-6


def test_same_seed_same_grasps_other_seed_others(mug):
    params = AntipodalParams(n_samples=200)
    obj = prepare_object(mug, GbhParams(n_points=params.n_points))
    a = sample_antipodal_grasps(obj, params, np.random.default_rng(7))
    b = sample_antipodal_grasps(obj, params, 7)
    c = sample_antipodal_grasps(obj, params, 8)
    assert [g.sample_index for g in a] == [g.sample_index for g in b]
    np.testing.assert_array_equal(np.stack([g.X_WG for g in a]), np.stack([g.X_WG for g in b]))
    assert [g.sample_index for g in a] != [g.sample_index for g in c]


def test_flipped_pose_is_the_same_pinch(box_grasps):
    mesh, result = box_grasps
    g = result.ranked[0]
    Xf = flipped(g.X_WG)
    np.testing.assert_allclose(Xf[:3, 1], -g.X_WG[:3, 1])
    np.testing.assert_allclose(Xf[:3, 2], g.X_WG[:3, 2])
    pts = trimesh.sample.sample_surface(mesh, 2000, seed=0)[0]
    n = count_in_swept_model(pts, np.stack([g.X_WG, Xf]), [g.q + 1e-3] * 2, [G.q_open] * 2)
    assert n[0] == n[1]


def test_low_box_backs_the_hand_off_to_clear_the_table():
    low = _box_mesh((0.05, 0.10, 0.02))
    params = AntipodalParams()
    grasps = sample_antipodal_grasps(low, params, 0)
    assert grasps, "a 2 cm high box is pinched near the fingertips"
    for g in grasps:
        assert g.contact_depth < params.contact_depth  # backed off
        assert g.ground_clearance >= params.ground_clearance - 1e-9


def test_flat_object_on_the_table_has_no_pinch():
    # The paper's observation for its baseline: nothing for a clothes hanger lying flat.
    result = plan_antipodal_grasps(make_object("clothes_hanger").mesh, AntipodalParams(), 0)
    assert result.counts["friction"] > 0 and result.ranked == []


def _lowest_corner(g, q: float) -> float:
    """m: height of the bar-retracted solid model's lowest corner at finger position ``q``."""
    signs = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)])
    corners = np.concatenate([np.asarray(b.center) + signs * b.half_extents
                              for b in G.solid_boxes_G(q, bar_retracted=True)])
    return float(trimesh.transform_points(corners, g.X_WG)[:, 2].min())


@pytest.mark.parametrize(("name", "mesh", "widths"), [
    # A ring lying flat, 13 mm tall (a torus of tube radius 6.5 mm), 4.5 cm across.
    ("ring", lambda: _on_table(trimesh.creation.torus(0.016, 0.0065)), (0.013, 0.045)),
    # A bar 10 mm thick, 2.4 cm wide and 12 cm long lying flat.
    ("bar", lambda: _box_mesh((0.024, 0.12, 0.010)), (0.024,)),
])
def test_a_thin_object_lying_flat_is_pinched_by_the_side_pass_alone(name, mesh, widths):
    """The first pass's contacts sit too low for the pads (the object is thinner than the pads'
    reach above the table); the side pass closes level on the material's extremes, its rods'
    lowest corners at the clearance or above, nothing in the swept hand."""
    mesh = mesh()
    first = plan_antipodal_grasps(mesh, AntipodalParams(), 0)
    assert first.ranked == [] and first.counts["friction"] > 0
    assert not any(k.startswith("side_") for k in first.counts)
    params = AntipodalParams(side_pass=True)
    result = plan_antipodal_grasps(mesh, params, 0)
    assert result.counts["side_collision_free"] == len(result.ranked) > 0
    obj = prepare_object(mesh, GbhParams(n_points=params.n_points), 0)
    up = np.array([0.0, 0.0, 1.0])
    for g in result.ranked:
        assert abs(g.X_WG[:3, 1] @ up) < 1e-9  # the closing axis level
        assert g.X_WG[:3, 2] @ up < -0.99  # from above
        assert min(abs(g.width - w) for w in widths) < 0.002, g.width  # on the extremes
        assert g.contact_depth < params.min_contact_depth  # below the first pass's limit
        for q in (g.q_pregrasp, g.q):
            assert _lowest_corner(g, q) >= params.ground_clearance - 1e-9
        lo = [g.q + params.contact_tolerance]
        assert count_in_swept_model(obj.points, g.X_WG[None], lo, [g.q_pregrasp], G, 0.0,
                                    params.approach_distance)[0] == g.n_collisions < params.p_c


def test_the_side_pass_runs_only_when_the_first_finds_nothing(box_grasps):
    mesh, result = box_grasps
    again = plan_antipodal_grasps(mesh, AntipodalParams(side_pass=True), 0)
    assert not any(k.startswith("side_") for k in again.counts)
    np.testing.assert_array_equal(np.stack([g.X_WG for g in again.ranked]),
                                  np.stack([g.X_WG for g in result.ranked]))


def _flat_ring() -> trimesh.Trimesh:
    """A flat ring (a washer or quoit) on the table, 8 cm across and 2.7 cm high, its wall 2.7 cm
    thick round a 2.6 cm hole: a pinch across the wall has one rod in the hole, whose far side
    is 3.95 cm from the wall's middle, inside the fully open rod (4 cm out, 8 mm thick)."""
    return _on_table(trimesh.creation.annulus(r_min=0.013, r_max=0.040, height=0.027))


def test_pregrasp_openings_run_from_fully_open_to_the_contacts_plus_the_margin():
    params = AntipodalParams()
    q = np.array([0.012, 0.03, G.q_open - params.opening_margin])
    openings = pregrasp_openings(q, params)
    assert openings.shape == (3, 3)
    np.testing.assert_allclose(openings[:, 0], G.q_open)
    np.testing.assert_allclose(openings[:, -1], q + params.opening_margin)
    assert np.all(np.diff(openings, axis=1) <= 0.0)  # widest first
    off = pregrasp_openings(q, dataclasses.replace(params, narrow_pregrasp=False))
    np.testing.assert_allclose(off, G.q_open)


def test_a_ring_lying_flat_is_pinched_with_the_hand_opened_less():
    ring = _flat_ring()
    full = plan_antipodal_grasps(ring, AntipodalParams(narrow_pregrasp=False), 0)
    narrow = plan_antipodal_grasps(ring, AntipodalParams(), 0)
    assert full.counts["ground"] > 0 and full.ranked == []  # the open rod lands on the far side
    assert narrow.ranked
    params = AntipodalParams()
    obj = prepare_object(ring, GbhParams(n_points=params.n_points))
    for g in narrow.ranked:
        assert g.q + params.opening_margin - 1e-9 <= g.q_pregrasp < G.q_open
        X = g.X_WG[None]
        lo = [g.q + params.contact_tolerance]
        assert count_in_swept_model(obj.points, X, lo, [G.q_open], G, 0.0,
                                    params.approach_distance)[0] >= params.p_c
        assert count_in_swept_model(obj.points, X, lo, [g.q_pregrasp], G, 0.0,
                                    params.approach_distance)[0] == g.n_collisions < params.p_c
        assert abs(g.width - 0.027) < 0.002  # across the wall: one rod in the hole


def test_a_scan_sized_mug_gets_a_full_top_k(mug):
    """(Its speed is measured by bench/bench_core.py, not here.)"""
    mesh = mug.subdivide().subdivide()  # ~26k triangles, like a 10-view scan
    params = AntipodalParams()
    obj = prepare_object(mesh, GbhParams(n_points=params.n_points))
    grasps = sample_antipodal_grasps(obj, params, 1)
    assert len(grasps) == params.top_k


def test_params_load_from_yaml_and_check_names_the_field():
    from pydrake.common.yaml import yaml_load_typed

    p = yaml_load_typed(schema=AntipodalParams,
                        data="{n_samples: 50, friction_coefficient: 0.5, ground_normal: [0, 1, 0]}")
    assert (p.n_samples, p.friction_coefficient, p.ground_normal) == (50, 0.5, [0.0, 1.0, 0.0])
    for f in dataclasses.fields(AntipodalParams):
        assert f.type in {float, int, bool, list[float]}, f.name
    for bad in ({"n_rolls": 0}, {"max_roll_deg": 120.0}, {"friction_coefficient": 0.0},
                {"ground_normal": [0.0, 0.0, 0.0]}):
        with pytest.raises(GbhInputError, match=next(iter(bad))):
            AntipodalParams(**bad).check()
    with pytest.raises(GbhInputError):
        sample_antipodal_grasps(trimesh.Trimesh(), AntipodalParams())


def test_antipodal_module_imports_no_pydrake():
    code = (
        "import sys\n"
        "import gbh_drake.core.antipodal\n"
        "assert not any(m.startswith('pydrake') for m in sys.modules), 'pydrake imported'\n"
    )
    subprocess.run([sys.executable, "-c", code], check=True,
                   cwd=Path(__file__).resolve().parents[2])
