"""Hangability detection on known shapes (paper Sec. 2.2, design.md Sec. 3)."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
import trimesh
from gbh_shapes import CUP_RADIUS, HANDLE_CENTER, RING_R, RING_r
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from gbh_drake.core.hangability import (
    cluster_points,
    contact_candidates,
    detect_hangable_structures,
    hanging_directions,
    hanging_positions,
    through_hole,
)
from gbh_drake.core.object_model import prepare_object
from gbh_drake.core.params import GbhParams
from gbh_drake.core.results import GbhInputError

COS_3_DEG = np.cos(np.radians(3.0))


def test_ring_one_structure_at_hole_centre_along_axis(ring, params):
    (s,) = detect_hangable_structures(ring, params)
    assert np.linalg.norm(s.c) < 2e-3
    assert abs(s.v @ [0, 0, 1]) > COS_3_DEG
    assert s.m == 1.0 and len(s.H) == params.n_rays_per_plane
    assert np.allclose(s.a, 0.0)
    assert s.clearance == pytest.approx(RING_R - RING_r, abs=1.5e-3)
    # Every hit point is on the ring's inner equator.
    assert np.allclose(np.linalg.norm(s.H[:, :2], axis=1), RING_R - RING_r, atol=1.5e-3)


def test_mug_handle_found_and_cup_mouth_rejected_by_through_hole_test(mug, params):
    structures = detect_hangable_structures(mug, params)
    assert len(structures) == 1
    (s,) = structures
    # c in the handle's hole: between the cup wall and the handle, at the handle's height.
    assert CUP_RADIUS < s.c[0] < HANDLE_CENTER[0] + 0.02
    assert abs(s.c[1]) < 2e-3 and abs(s.c[2] - HANDLE_CENTER[2]) < 0.01
    assert abs(s.v @ [0, 1, 0]) > COS_3_DEG  # normal to the handle's (xz) plane
    assert s.m == 1.0

    # The cup's mouth: a hanging position on the cup's axis exists, its direction is the axis,
    # and only the through-hole test removes it (the ray along -z hits the bottom).
    obj = prepare_object(mug, params)
    idx = contact_candidates(obj, params)
    labels = cluster_points(obj.points[idx], params.cluster_radius * obj.spacing, 2)
    c, _, _ = hanging_positions(obj, idx[labels >= 0], labels[labels >= 0], params)
    in_cup = np.linalg.norm(c[:, :2], axis=1) < CUP_RADIUS
    assert in_cup.sum() == 1
    v, _, _ = hanging_directions(obj, c[in_cup], params)
    assert abs(v[0] @ [0, 0, 1]) > COS_3_DEG
    assert not through_hole(obj, c[in_cup], v)[0]


def test_open_hook_found_with_partial_loop(hook, params):
    (s,) = detect_hangable_structures(hook, params)
    assert abs(s.v @ [0, 0, 1]) > COS_3_DEG
    assert 0.4 < s.m < 0.9
    assert s.a @ [0, -1, 0] > 0.99  # the loop is open toward -y
    assert len(s.H) == round(s.m * s.n_rays)


@pytest.mark.parametrize(
    "make",
    [
        lambda: trimesh.creation.box((0.10, 0.06, 0.04)),
        lambda: trimesh.creation.icosphere(3, 0.05),
        pytest.param(None, id="bottle"),
    ],
    ids=["box", "sphere", "bottle"],
)
def test_shapes_without_hangable_structure_give_empty_list(make, bottle, params):
    mesh = bottle if make is None else make()
    assert detect_hangable_structures(mesh, params) == []


@pytest.mark.parametrize(
    ("mesh", "message"),
    [
        (trimesh.Trimesh(np.zeros((0, 3)), np.zeros((0, 3), dtype=int)), "empty"),
        (trimesh.Trimesh([[0, 0, 0], [1, 0, 0], [np.nan, 1, 0]], [[0, 1, 2]], process=False),
         "NaN"),
        (trimesh.Trimesh([[0, 0, 0], [1, 0, 0], [2, 0, 0]], [[0, 1, 2]], process=False),
         "zero surface area"),
        ("not a mesh", "trimesh.Trimesh"),
    ],
    ids=["empty", "nan", "degenerate", "wrong-type"],
)
def test_degenerate_input_raises_clear_error(mesh, message, params):
    with pytest.raises(GbhInputError, match=message):
        detect_hangable_structures(mesh, params)


def test_open_mesh_is_best_effort_or_rejected_on_request(ring, params):
    open_ring = ring.copy()
    open_ring.update_faces(np.arange(len(ring.faces)) % 50 != 0)  # punch holes in the surface
    assert not open_ring.is_watertight
    obj = prepare_object(open_ring, params)
    assert not obj.watertight
    assert np.linalg.norm(obj.com) < 2e-3  # surface centroid of a symmetric ring
    (s,) = detect_hangable_structures(obj, params)
    assert abs(s.v @ [0, 0, 1]) > COS_3_DEG
    with pytest.raises(GbhInputError, match="watertight"):
        prepare_object(open_ring, GbhParams(require_watertight=True))


def test_inside_out_mesh_gets_outward_normals(ring, params):
    flipped = ring.copy()
    flipped.invert()
    (s,) = detect_hangable_structures(flipped, params)
    assert np.linalg.norm(s.c) < 2e-3


def test_same_mesh_and_seed_give_identical_structures(mug, params):
    a = detect_hangable_structures(mug, params)
    b = detect_hangable_structures(mug, params)
    assert len(a) == len(b) > 0
    for sa, sb in zip(a, b, strict=True):
        for f in ("c", "v", "H", "a"):
            np.testing.assert_array_equal(getattr(sa, f), getattr(sb, f))
        assert sa.m == sb.m


@settings(max_examples=4, deadline=None, derandomize=True)
@given(
    rotvec=st.tuples(*[st.floats(-np.pi, np.pi)] * 3),
    shift=st.tuples(*[st.floats(-0.5, 0.5)] * 3),
)
def test_structures_move_with_the_object(mug, params, rotvec, shift):
    (s0,) = detect_hangable_structures(mug, params)
    X = np.eye(4)
    X[:3, :3] = Rotation.from_rotvec(rotvec).as_matrix()
    X[:3, 3] = shift
    (s1,) = detect_hangable_structures(mug.copy().apply_transform(X), params)
    np.testing.assert_allclose(s1.c, X[:3, :3] @ s0.c + X[:3, 3], atol=2e-3)
    assert abs(s1.v @ (X[:3, :3] @ s0.v)) > COS_3_DEG
    assert s1.m == s0.m


def test_a_cluster_keeps_every_handle_position():
    """Issue 42: a square-handled mug lying on its side (its most probable rest). Single
    linkage puts the handle's contact points in one cluster with the body's; its one position
    (the paper's, the member of largest approximate clearance) lies in the handle's corner,
    where no grasp fits. Several positions per cluster, by non-maximum suppression, keep one
    in the handle's hole: hook grasps on the handle are ranked again."""
    from gbh_drake.core.pipeline import plan_grasps
    from gbh_drake.objects import make_object
    from gbh_drake.objects.stability import stable_poses

    spec = make_object("mug_square_handle")
    pose = stable_poses(spec.mesh).poses[0]
    mesh = spec.mesh.copy()
    T = np.eye(4)
    T[:3, :3] = pose.R
    mesh.apply_transform(T)
    mesh.apply_translation([0.5, 0.0, -mesh.bounds[0, 2]])
    (part,) = spec.hangable_parts
    centre = pose.R @ part.center_O + [0.5, 0.0, -spec.mesh.copy().apply_transform(T).bounds[0, 2]]

    def on_handle(g) -> bool:
        return np.linalg.norm(g.structure.c - centre) <= 0.5 * part.clear_diameter + 0.02

    one = plan_grasps(mesh, GbhParams(), seed=0)  # the default: the paper's one
    several = plan_grasps(mesh, GbhParams(positions_per_cluster=4), seed=0)
    assert not any(on_handle(g) for g in one.ranked)
    assert len(several.structures) > len(one.structures)
    assert several.ranked and on_handle(several.ranked[0])
    assert GbhParams().with_preset("paper").positions_per_cluster == 1
    assert GbhParams(preset="robust").positions_per_cluster == 4


@pytest.mark.parametrize("shape", ["ring", "mug", "hook", "bottle"])
def test_the_cluster_fallback_keeps_every_structure_that_stands(shape, params, request):
    """``cluster_fallback`` only adds: a cluster whose chosen position stands keeps it, so
    every structure found without the fallback is found with it, the same (and the bottle,
    with nothing to hang by, stays empty)."""
    mesh = request.getfixturevalue(shape)
    without = detect_hangable_structures(mesh, dataclasses.replace(params,
                                                                   cluster_fallback=False))
    with_it = detect_hangable_structures(mesh, dataclasses.replace(params,
                                                                   cluster_fallback=True))
    for s in without:
        assert any(np.allclose(s.c, t.c) and np.allclose(s.v, t.v) for t in with_it)
    if shape == "bottle":
        assert with_it == []


@pytest.mark.parametrize("radius_spacings", [30.0, 100.0])
def test_a_cluster_whose_position_is_refused_tries_its_next_member(mug, params, radius_spacings):
    """Single linkage at a radius that chains the handle's contacts to the cup's into one
    cluster: its one position, the largest ball, is the cup's mouth, refused (the bottom closes
    it), and the handle is lost. With ``cluster_fallback`` the cluster tries its members'
    positions outside that ball, largest first, and the handle's hole stands; the mouth stays
    among the refused. On by default; the ``paper`` preset gives the cluster up."""
    from gbh_drake.core.hangability import detect_with_report

    assert GbhParams().cluster_fallback and not GbhParams(preset="paper").cluster_fallback
    chained = dataclasses.replace(params, cluster_radius=radius_spacings, cluster_fallback=False)
    lost, before = detect_with_report(mug, chained)
    assert lost == [] and before.clusters == 1 and before.refused_by()["not a through-hole"] == 1
    (s,), after = detect_with_report(mug, dataclasses.replace(chained, cluster_fallback=True))
    assert CUP_RADIUS < s.c[0] < HANDLE_CENTER[0] + 0.02 and abs(s.v @ [0, 1, 0]) > COS_3_DEG
    assert after.positions == 2 and after.refused_by()["not a through-hole"] == 1
    assert np.linalg.norm(after.refused[0].c[:2]) < CUP_RADIUS  # the mouth, on the cup's axis
