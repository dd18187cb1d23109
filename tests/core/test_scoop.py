"""The scoop of material lying flat (core/scoop.py, pure): poses, rules, order."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
import trimesh
from gbh_shapes import _to_trimesh, _torus
from hypothesis import given, settings
from hypothesis import strategies as st

from gbh_drake.core.gripper import WEDGE_GRIPPER
from gbh_drake.core.params import GbhParams, ScoopParams
from gbh_drake.core.pipeline import detect
from gbh_drake.core.results import SCOOP
from gbh_drake.core.scoop import RULES, plan_scoops, scoop_regions_G
from gbh_drake.objects import make_object

PARAMS = GbhParams()


def on_table(mesh: trimesh.Trimesh, x=0.55, y=0.0, yaw=0.0) -> trimesh.Trimesh:
    mesh = mesh.copy()
    mesh.apply_transform(trimesh.transformations.rotation_matrix(yaw, [0, 0, 1]))
    mesh.apply_translation([x, y, -mesh.bounds[0][2]])
    return mesh


def scoops_of(mesh, params=PARAMS, scoop=None):
    obj, structures = detect(mesh, params, 0)
    return obj, structures, plan_scoops(obj, structures, params, scoop)


def rod_and_l_rod_W(X_WG):
    """Where the open gripper's straight rod and L rod stand on the table (x, y in W)."""
    q = WEDGE_GRIPPER.q_open
    return X_WG[:2, 3] + q * X_WG[:2, 1], X_WG[:2, 3] - q * X_WG[:2, 1]


def test_a_key_ring_lying_flat_is_scooped_with_the_rod_in_its_hole():
    mesh = on_table(make_object("key_ring").mesh)
    obj, structures, result = scoops_of(mesh)
    assert result.ranked and all(g.kind == SCOOP for g in result.ranked)
    ring = make_object("key_ring").hangable_parts[0]
    center = ring.center_O[:2] + [0.55, 0.0]
    on_ring = [g for g in result.ranked if np.linalg.norm(g.structure.c[:2] - center) < 0.01]
    assert on_ring and on_ring[0] is result.ranked[0]
    for g in on_ring:
        rod, l_rod = rod_and_l_rod_W(g.X_WG)
        # The straight rod stands inside the ring's hole, the L rod outside the ring.
        assert np.linalg.norm(rod - center) < 0.5 * ring.clear_diameter - 0.004
        assert np.linalg.norm(l_rod - center) > 0.5 * ring.clear_diameter + 0.005
        # Top-down, the rods' tips just above the table.
        np.testing.assert_allclose(g.X_WG[:3, 2], [0, 0, -1], atol=1e-9)
        assert g.ground_distance == pytest.approx(ScoopParams().hover, abs=1e-9)
        assert g.n_collisions < PARAMS.p_c and g.n_sweep_collisions < ScoopParams().p_sweep


def test_a_tape_roll_lying_flat_is_too_tall_to_scoop_and_offered_apart():
    """Its 19 mm wall is taller than the wedge: no scoop passes; but a round underside would be
    lifted and the scan cannot tell, so its scoops are offered apart, as tall scoops."""
    _, _, result = scoops_of(on_table(make_object("tape_roll").mesh))
    assert result.structures >= 1 and result.candidates and not result.ranked
    assert result.removed_by["too tall"] == len(result.candidates)
    assert "too tall" in result.reason() and "tall scoops offered apart" in result.reason()
    assert result.ranked_tall and set(map(id, result.ranked_tall)) <= {
        id(result.candidates[i]) for i in np.flatnonzero(result.tall)}
    assert not scoops_of(on_table(make_object("tape_roll").mesh),
                         scoop=ScoopParams(tall=False))[2].ranked_tall


@pytest.mark.parametrize("tube", [0.013, 0.02])
def test_a_thick_torus_lying_flat_gets_tall_scoops_from_inside_its_hole(tube):
    """A torus whose tube (26 or 40 mm thick) is taller than the wedge: every scoop is too tall,
    the L rod meets the tube above the bar (the lifted material), the hand nothing: tall scoops,
    the straight rod in the hole and the L rod outside, top-down, best first."""
    radius = 0.027 + tube
    mesh = on_table(_to_trimesh(_torus(radius, tube)))
    _, _, result = scoops_of(mesh)
    assert not result.ranked and result.removed_by["too tall"] == len(result.candidates)
    assert result.ranked_tall, result.reason()
    assert len(result.ranked_tall) == min(PARAMS.top_k, int(result.tall.sum()))
    scores = [g.score for g in result.ranked_tall]
    assert scores == sorted(scores, reverse=True)
    for g in result.ranked_tall:
        rod, l_rod = rod_and_l_rod_W(g.X_WG)
        assert np.linalg.norm(rod - [0.55, 0.0]) < radius - tube
        assert np.linalg.norm(l_rod - [0.55, 0.0]) > radius + tube
        np.testing.assert_allclose(g.X_WG[:3, 2], [0, 0, -1], atol=1e-9)
        assert g.n_collisions < PARAMS.p_c
        # The L rod, closing, meets the tube above the bar: pushed, were it not the lifted tube.
        assert g.n_sweep_collisions >= ScoopParams().p_sweep


def test_a_tall_scoop_whose_hand_would_push_material_is_not_offered():
    """A pipe standing on its end (5 cm tall: tall scoops), and material where one scoop's hand,
    following the fingers, sweeps while closing (clear of the open gripper): that scoop (and the
    neighbours whose hands pass there too) is no longer offered, the others are."""
    pipe = on_table(trimesh.creation.annulus(r_min=0.02, r_max=0.03, height=0.05, sections=64))
    obj, structures, result = scoops_of(pipe)
    assert result.ranked_tall and not result.ranked
    k = result.candidates.index(result.ranked_tall[0])
    X = result.candidates[k].X_WG
    hand = scoop_regions_G(WEDGE_GRIPPER)[2][-1]
    # Points at the far end of the hand's sweep (+y_G), where the open hand is not.
    p_G = np.asarray(hand.center) + [0.0, hand.half_extents[1] - 0.002, 0.0]
    extra = (p_G + np.linspace(-0.002, 0.002, 3)[:, None]) @ X[:3, :3].T + X[:3, 3]
    pushed = dataclasses.replace(obj, points=np.vstack([obj.points, extra]),
                                 normals=np.vstack([obj.normals, np.tile([0, 0, 1.0], (3, 1))]))
    again = plan_scoops(pushed, structures, PARAMS)
    assert not again.tall[k] and 0 < again.tall.sum() < result.tall.sum()


def test_an_upright_mug_has_nothing_flat_to_scoop():
    _, structures, result = scoops_of(on_table(make_object("mug_classic").mesh))
    assert structures and result.structures == 0 and not result.candidates
    assert result.reason() == "no hanging structure lies flat on the table to scoop"


def test_a_hanger_is_scooped_where_it_hangs_least_deep_first():
    """Every scoop of the hanger's closed triangle scores 1: the one it hangs least deep from
    comes first (near the apex, not at a far corner)."""
    mesh = on_table(make_object("clothes_hanger").mesh)
    _, _, result = scoops_of(mesh)
    passing = np.flatnonzero(result.passed)
    best = result.candidates.index(result.ranked[0])
    same_score = [i for i in passing
                  if result.candidates[i].score == pytest.approx(result.ranked[0].score)]
    assert result.depth[best] == pytest.approx(min(result.depth[same_score]))
    assert result.depth[best] < 0.2 < max(result.depth[same_score])


def test_the_rules_remove_in_order_and_count_every_pose():
    _, _, result = scoops_of(on_table(make_object("scissors").mesh))
    assert list(result.removed_by) == list(RULES)
    assert sum(result.removed_by.values()) + result.passed.sum() == len(result.candidates)
    assert set(map(id, result.ranked)) <= {id(result.candidates[i])
                                           for i in np.flatnonzero(result.passed)}


def test_the_corridor_runs_from_the_open_bar_to_the_straight_rod():
    open_boxes, corridor, pushers = scoop_regions_G(WEDGE_GRIPPER)
    g = WEDGE_GRIPPER
    r = 0.5 * g.rod_width
    lo = corridor.center[1] - corridor.half_extents[1]
    hi = corridor.center[1] + corridor.half_extents[1]
    assert lo == pytest.approx(-g.q_open - r) and hi == pytest.approx(g.q_open - r)
    assert corridor.center[2] + corridor.half_extents[2] == pytest.approx(g.finger_length + r)
    assert {b.name for b in open_boxes} >= {"bar", "straight_rod", "l_rod"}
    assert len(pushers) == 3


@settings(max_examples=12, deadline=None)
@given(radius=st.floats(0.018, 0.03), wire=st.floats(0.002, 0.0035),
       yaw=st.floats(-np.pi, np.pi), x=st.floats(0.45, 0.62), y=st.floats(-0.15, 0.15))
def test_any_ring_lying_flat_is_scooped_from_inside_its_hole(radius, wire, yaw, x, y):
    """A torus lying flat (wire 4-7 mm thick, hole 2.9-5.6 cm across), anywhere on the table:
    scooped, every scoop's straight rod in the hole and its L rod outside the ring."""
    mesh = on_table(_to_trimesh(_torus(radius, wire)), x, y, yaw)
    _, structures, result = scoops_of(mesh)
    assert result.ranked, result.reason()
    for g in result.ranked:
        rod, l_rod = rod_and_l_rod_W(g.X_WG)
        assert np.linalg.norm(rod - [x, y]) < radius - wire - 0.0035
        assert np.linalg.norm(l_rod - [x, y]) > radius + wire


@settings(max_examples=8, deadline=None)
@given(tube=st.floats(0.0075, 0.02), hole=st.floats(0.012, 0.03), yaw=st.floats(-np.pi, np.pi),
       x=st.floats(0.45, 0.62), y=st.floats(-0.15, 0.15))
def test_any_thick_ring_lying_flat_gets_tall_scoops_from_inside_its_hole(tube, hole, yaw, x, y):
    """A torus lying flat whose tube (15-40 mm thick) stands taller than the wedge, its hole 2.4-6
    cm across, anywhere on the table: no scoop, tall scoops, each with the straight rod in the
    hole and the L rod outside the ring."""
    radius = hole + tube
    mesh = on_table(_to_trimesh(_torus(radius, tube)), x, y, yaw)
    _, _, result = scoops_of(mesh)
    assert not result.ranked and result.ranked_tall, result.reason()
    for g in result.ranked_tall:
        rod, l_rod = rod_and_l_rod_W(g.X_WG)
        assert np.linalg.norm(rod - [x, y]) < hole
        assert np.linalg.norm(l_rod - [x, y]) > radius + tube
