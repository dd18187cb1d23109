"""The rods' clearance (collision.count_rod_contacts): density-proof, exact for the surface,
and what N_c's point count lets through."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
import trimesh

from gbh_drake.core.collision import (
    SurfaceTriangles,
    count_open_and_sweep,
    count_rod_contacts,
    triangles_overlap_boxes,
)
from gbh_drake.core.gripper import HOOK_GRIPPER, Box
from gbh_drake.core.object_model import prepare_object
from gbh_drake.core.params import GbhParams
from gbh_drake.core.pipeline import count_collisions, plan_grasps
from gbh_drake.core.results import VERTICAL, GraspCandidate, GraspKind
from gbh_drake.core.scoring import collision_free
from gbh_drake.objects import make_object


def test_triangle_box_overlap_is_exact():
    box = [Box("b", (0.0, 0.0, 0.0), (1.0, 1.0, 1.0))]
    tri = np.array([
        [[0.5, 0.5, 0.5], [2, 0, 0], [0, 2, 0]],  # a vertex inside
        [[-3, 0, 0.5], [3, 0.2, 0.5], [0, 3, 0.5]],  # crosses the box, no vertex inside
        [[1.2, 1.2, -5], [5, 1.2, -5], [1.2, 5, 5]],  # near a vertical edge, outside
        [[3.1, 0, 0], [0, 3.1, 0], [0, 0, 3.1]],  # the plane x+y+z = 3.1 misses the corner
        [[2.9, 0, 0], [0, 2.9, 0], [0, 0, 2.9]],
    ], dtype=float)
    tri[4] *= 2.5 / 2.9  # x+y+z = 2.5 < 3: cuts the corner
    assert triangles_overlap_boxes(tri, box)[:, 0].tolist() == [True, True, False, False, True]


def _wire(start, end, radius: float) -> trimesh.Trimesh:
    return trimesh.creation.cylinder(radius=radius, segment=np.array([start, end]), sections=24)


def _scene(offset: float):
    """The frying pan's best vertical grasp's pose X_WG and kind (it closes about its straight rod,
    which stays where it is: only N_c sees it), and the pan with a 3 mm wire crossing that
    grasp's straight rod (open pose) at mid-height, normal to the gripper's plane (along x_G),
    its surface ``offset`` m beyond the rod's face (negative: through the rod)."""
    pan = make_object("frying_pan").mesh
    result = plan_grasps(pan, GbhParams(ground_clearance=-1.0, rod_clearance=0.0025), seed=0)
    grasp = next(g for g in result.ranked if g.kind == VERTICAL)  # its rods clear by 2.5 mm
    X = grasp.X_WG
    g = HOOK_GRIPPER
    r = 0.5 * g.rod_width
    # The straight rod's axis at the open pose: y_G = q_open; the wire beside it along +y_G.
    y = g.q_open + r + 0.0015 + offset if offset >= 0 else g.q_open
    a = X[:3, :3] @ np.array([-0.03, y, 0.5 * g.finger_length]) + X[:3, 3]
    b = X[:3, :3] @ np.array([0.03, y, 0.5 * g.finger_length]) + X[:3, 3]
    return X, grasp.kind, trimesh.util.concatenate([pan, _wire(a, b, 0.0015)])


def test_a_wire_through_the_rod_passes_n_c_and_not_the_rods_clearance():
    """Issue 42: a 3 mm wire across the straight rod meets a handful of 5000 samples inside
    the open gripper (N_c < p_c = 10: the paper's rule keeps the grasp); the rods' clearance
    refuses it. Without the wire the same pose is clear."""
    X, kind, mesh = _scene(-1.0)
    params = GbhParams(ground_clearance=-1.0)
    obj = prepare_object(mesh, params, 0)
    n_c, _ = count_open_and_sweep(obj.points, X[None], kind)
    assert n_c[0] < params.p_c
    tri = SurfaceTriangles.of(obj.mesh.vertices, obj.mesh.faces, 2 * obj.spacing)
    assert count_rod_contacts(obj.points, obj.spacing, tri, X[None], kind, 0.0025)[0] > 0
    mug = prepare_object(make_object("frying_pan").mesh, params, 0)
    tri = SurfaceTriangles.of(mug.mesh.vertices, mug.mesh.faces, 2 * mug.spacing)
    assert count_rod_contacts(mug.points, mug.spacing, tri, X[None], kind, 0.0025)[0] == 0


@pytest.mark.parametrize("samples", [1000, 5000])
def test_a_wire_beside_the_rod_is_judged_by_its_distance_at_any_density(samples):
    """A wire 2 mm from the rod's face: too near for a 2.5 mm clearance, clear for 1.5 mm,
    whether the surface is sampled 1000 or 5000 times (its samples 2-6 mm apart)."""
    X, kind, mesh = _scene(0.002)  # the wire's surface 2 mm from the rod's face
    params = GbhParams(ground_clearance=-1.0, n_points=samples)
    obj = prepare_object(mesh, params, 0)
    tri = SurfaceTriangles.of(obj.mesh.vertices, obj.mesh.faces, 2 * obj.spacing)
    assert count_rod_contacts(obj.points, obj.spacing, tri, X[None], kind, 0.0025)[0] > 0
    assert count_rod_contacts(obj.points, obj.spacing, tri, X[None], kind, 0.0015)[0] == 0


def test_the_pipeline_refuses_the_grasp_the_paper_keeps():
    """The grasp with the wire through its straight rod, counted as the pipeline counts: the
    paper's rules (N_c, and our closing sweep and table rules) keep it; the rods' clearance
    (preset ``robust``) refuses it, and so does, by default, the loop's material (the straight
    rod's centre line runs through the wire), each saying so among the rejections."""
    from gbh_drake.core.rejections import count_rejections

    X, kind, mesh = _scene(-1.0)
    for preset, rule in (("paper", ""), ("", "empty loop"), ("robust", "rod clearance")):
        params = GbhParams(ground_clearance=-1.0).with_preset(preset)
        obj = prepare_object(mesh, params, 0)
        structure = plan_grasps(make_object("frying_pan").mesh, params, seed=0).structures[0]
        g = GraspCandidate(X, kind, 0, structure, structure.H[0])
        count_collisions(obj, [g], params)
        assert g.n_collisions < params.p_c and g.n_sweep_collisions < params.p_sweep
        assert collision_free(g, params) is (rule == "")
        if rule:
            r = count_rejections([g], params)
            assert r.removed[rule] == 1 and r.last_rule == rule
        if rule == "rod clearance":
            assert "rods or bar come nearer" in r.closest
            assert "the rods' clearance removed 1" in r.summary()
        if rule == "empty loop":
            assert "closed loop runs through the surface" in r.closest
            assert "the loop's material removed 1" in r.summary()


def test_the_lazy_check_ranks_as_checking_more_would():
    """The rods' clearance is checked best score first until ``top_k`` *distinct* grasps are
    clear (a copy takes no place in the ranking): the ten ranked are the first ten of a
    ranking that checked until a hundred were clear, and every one of them was checked."""
    mesh = make_object("mug_classic").mesh
    lazy = plan_grasps(mesh, GbhParams(rod_clearance=0.0025, top_k=10), seed=0).ranked
    more = plan_grasps(mesh, GbhParams(rod_clearance=0.0025, top_k=100), seed=0).ranked
    assert len(lazy) == 10 and all(g.rod_contacts == 0 for g in lazy)
    assert [g.X_WG.tobytes() for g in lazy] == [g.X_WG.tobytes() for g in more[:10]]


def _rail(dx: float = 0.0) -> trimesh.Trimesh:
    """A 10 mm rail 20 mm long along y_W at z 4 cm, ``dx`` along x_W: with G = W, across the
    loop of a parallel grasp, ``dx`` off its plane."""
    r = trimesh.creation.cylinder(radius=0.005, height=0.02, sections=24)
    r.apply_transform(trimesh.geometry.align_vectors([0, 0, 1.0], [0, 1.0, 0]))
    return r.apply_translation([dx, 0.0, 0.04])


def _grasps_along_x(offsets):
    structure = plan_grasps(make_object("frying_pan").mesh, GbhParams(), seed=0).structures[0]
    out = []
    for dx in offsets:
        X = np.eye(4)
        X[0, 3] = dx
        out.append(GraspCandidate(X, GraspKind.PARALLEL, 0, structure, structure.H[0]))
    return out


def test_the_lazy_loop_check_ranks_as_checking_every_loop_would():
    """The loop's material is checked best score first (ties in their order) until ``top_k``
    grasps hold material: eleven grasps 6 mm apart across a rail, the farthest first, all
    collision-free; only the one on the rail holds it, and it alone is ranked (the paper's rules
    rank the first three, which close beside it); the ranked one was checked."""
    from gbh_drake.core.enclosure import LoopMaterial
    from gbh_drake.core.scoring import rank_grasps

    params = GbhParams(ground_clearance=-1.0, top_k=3)
    obj = prepare_object(_rail(), params, 0)
    offsets = [0.03, -0.03, 0.024, -0.024, 0.018, -0.018, 0.012, -0.012, 0.006, -0.006, 0.0]
    candidates = _grasps_along_x(offsets)
    count_collisions(obj, candidates, params)
    lazy = rank_grasps(candidates, params)
    assert [g.X_WG[0, 3] for g in lazy] == [0.0]
    assert lazy[0].loop_material == LoopMaterial.HELD
    assert [g.loop_material for g in candidates[:-1]] == [LoopMaterial.EMPTY] * 10
    off = dataclasses.replace(params, loop_must_enclose=False)
    assert [g.X_WG[0, 3] for g in rank_grasps(candidates, off)] == offsets[:3]


def test_every_grasp_ranked_on_a_mug_holds_its_handle(mug):
    from gbh_drake.core.enclosure import LoopMaterial

    result = plan_grasps(mug, GbhParams(), seed=0)
    assert result.ranked
    assert all(g.loop_material == LoopMaterial.HELD for g in result.ranked)


def test_the_pipeline_refuses_a_loop_closing_beside_the_material():
    """A rail beside the plane of a parallel grasp (G = W, 15 mm off it): the paper's rules
    keep the grasp (no point in the gripper or its sweep); the loop's material refuses it, and
    keeps the same grasp with the rail through the loop."""
    from gbh_drake.core.enclosure import LoopMaterial
    from gbh_drake.core.rejections import count_rejections

    for dx, loop, material in ((0.015, True, LoopMaterial.EMPTY), (0.015, False, None),
                               (0.0, True, LoopMaterial.HELD)):
        params = GbhParams(ground_clearance=-1.0, loop_must_enclose=loop)
        obj = prepare_object(_rail(dx), params, 0)
        g = _grasps_along_x([0.0])[0]
        count_collisions(obj, [g], params)
        assert g.n_collisions == g.n_sweep_collisions == 0
        assert collision_free(g, params) is (material != LoopMaterial.EMPTY)
        assert g.loop_material == (LoopMaterial.UNCHECKED if material is None else material)
        if material == LoopMaterial.EMPTY:
            r = count_rejections([g], params)
            assert r.removed["empty loop"] == 1
            assert "holds no material in its hole" in r.closest
