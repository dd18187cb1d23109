"""The closing motion: swept volume, closed-loop interior, and cages rather than pinches.

The reference used here is independent of gbh_drake.core.collision: it steps the fingers from
q_open to q_closed with the gripper module's own solid model (``solid_boxes_G(q)``) and moves G
as the pick script does (gbh_drake/planning/pick.py: vertical grasps keep the straight rod where
it is, so G follows the fingers along +y_G by q_open - q; parallel grasps keep G).
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
import trimesh
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from gbh_drake.core.collision import (
    closed_loop_interior_G,
    closing_boxes_G,
    count_open_and_sweep,
    count_points_in_boxes,
    swept_boxes_G,
)
from gbh_drake.core.gripper import HOOK_GRIPPER as GR
from gbh_drake.core.object_model import prepare_object
from gbh_drake.core.params import GbhParams
from gbh_drake.core.pipeline import plan_grasps
from gbh_drake.core.results import PARALLEL, VERTICAL
from gbh_drake.core.scoring import collision_free
from gbh_drake.objects import make_object

KINDS = (PARALLEL, VERTICAL)
R_ROD = 0.5 * GR.rod_width
STEP = 2.5e-4  # m of finger travel per step of the reference closing (rods are 8 mm thick)


# ---- the independent reference -------------------------------------------------------------------
def reference_boxes(kind: str, q: float) -> list[tuple[np.ndarray, np.ndarray]]:
    """(center, half_extents) of the solid model at finger position q, in the frame G of the
    grasp pose (open), moved as the pick script moves it."""
    shift = (GR.q_open - q) if kind == VERTICAL else 0.0
    return [(np.asarray(b.center) + (0.0, shift, 0.0), np.asarray(b.half_extents))
            for b in GR.solid_boxes_G(q)]


def inside(p: np.ndarray, boxes) -> np.ndarray:
    m = np.zeros(len(p), dtype=bool)
    for c, h in boxes:
        m |= np.all(np.abs(p - c) <= h, axis=1)
    return m


def openings() -> np.ndarray:
    return np.r_[np.arange(GR.q_open, GR.q_closed, -STEP), GR.q_closed]


def closing_stop(X_WG: np.ndarray, kind: str, points_W: np.ndarray) -> tuple[float, int]:
    """Where the fingers stop when closing from the grasp pose: the first finger position q at
    which the moving gripper touches an object point that was not already inside the open
    gripper, and how many it touches there; (q_closed, 0) if the loop closes."""
    p = trimesh.transform_points(points_W, np.linalg.inv(X_WG))
    ends = reference_boxes(kind, GR.q_open) + reference_boxes(kind, GR.q_closed)
    lo = np.min([c - h for c, h in ends], axis=0)
    hi = np.max([c + h for c, h in ends], axis=0)
    p = p[np.all((p >= lo) & (p <= hi), axis=1)]  # only points the moving model can reach
    already = inside(p, reference_boxes(kind, GR.q_open))
    for q in openings():
        hit = inside(p, reference_boxes(kind, q)) & ~already
        if hit.any():
            return float(q), int(hit.sum())
    return GR.q_closed, 0


def reference_interior(kind: str) -> tuple[np.ndarray, np.ndarray]:
    """(lo, hi) corners of the closed loop's hole in the grasp frame: between the closed rods'
    inner faces, from the palm (z = 0) to the bar's lower face, as thick as the rods."""
    boxes = dict(zip([b.name for b in GR.solid_boxes_G(GR.q_closed)],
                     reference_boxes(kind, GR.q_closed), strict=True))
    (cs, hs), (cl, hl), (cb, hb) = boxes["straight_rod"], boxes["l_rod"], boxes["bar"]
    lo = np.array([-R_ROD, cl[1] + hl[1], 0.0])
    hi = np.array([R_ROD, cs[1] - hs[1], cb[2] - hb[2]])
    return lo, hi


def in_interior(p_G: np.ndarray, kind: str) -> np.ndarray:
    lo, hi = reference_interior(kind)
    return np.all((p_G >= lo) & (p_G <= hi), axis=-1)


# ---- the swept volume (properties) -----------------------------------------------------------------
def _contains(outer, inner, tol=1e-12) -> bool:
    lo_o, hi_o = np.subtract(outer.center, outer.half_extents), np.add(outer.center,
                                                                       outer.half_extents)
    lo_i, hi_i = np.subtract(inner.center, inner.half_extents), np.add(inner.center,
                                                                       inner.half_extents)
    return bool(np.all(lo_o <= lo_i + tol) and np.all(hi_i <= hi_o + tol))


@settings(max_examples=60, deadline=None)
@given(kind=st.sampled_from(KINDS), t=st.floats(0.0, 1.0))
def test_swept_boxes_contain_every_box_along_the_closing(kind, t):
    q = GR.q_open - t * (GR.q_open - GR.q_closed)
    swept = swept_boxes_G(kind)
    for boxes in (closing_boxes_G(kind, q), closing_boxes_G(kind, GR.q_open),
                  closing_boxes_G(kind, GR.q_closed)):
        assert len(boxes) == len(swept)
        assert all(_contains(s, b) for s, b in zip(swept, boxes, strict=True))
    # ... and the closing boxes are the gripper's own solid model, moved as the pick moves it.
    for b, (c, h) in zip(closing_boxes_G(kind, q), reference_boxes(kind, q), strict=True):
        np.testing.assert_allclose(b.center, c, atol=1e-12)
        np.testing.assert_allclose(b.half_extents, h, atol=1e-12)


def test_closing_kinematics_match_the_pick():
    """Vertical: the straight rod stays, the L finger travels twice the finger travel.
    Parallel: the hand stays, the fingers travel symmetrically."""
    def y_of(boxes, name):
        return next(b.center[1] for b in boxes if b.name == name)

    travel = GR.q_open - GR.q_closed
    for kind, d_straight, d_l, d_hand in ((VERTICAL, 0.0, 2 * travel, travel),
                                          (PARALLEL, -travel, travel, 0.0)):
        a, b = closing_boxes_G(kind, GR.q_open), closing_boxes_G(kind, GR.q_closed)
        assert y_of(b, "straight_rod") - y_of(a, "straight_rod") == pytest.approx(d_straight)
        assert y_of(b, "l_rod") - y_of(a, "l_rod") == pytest.approx(d_l)
        assert y_of(b, "bar") - y_of(a, "bar") == pytest.approx(d_l)
        assert y_of(b, "hand") - y_of(a, "hand") == pytest.approx(d_hand)


@settings(max_examples=15, deadline=None)
@given(kind=st.sampled_from(KINDS), seed=st.integers(0, 2**16),
       margin=st.sampled_from([0.0, 1e-3]), sweep_margin=st.sampled_from([0.0, 1.5e-3]))
def test_sweep_count_matches_a_stepped_closing(kind, seed, margin, sweep_margin):
    """N_c and N_sweep against the reference: points in the open model, and points reached by
    a moving part at some opening between open and closed (in steps, grown by the sweep
    margin) but not in the open model."""
    rng = np.random.default_rng(seed)
    # Points around the rods and bar (a box a bit larger than the fingers' reach).
    points = rng.uniform([-0.01, -0.06, -0.01], [0.01, 0.06, 0.095], size=(4000, 3))
    X = np.tile(np.eye(4), (3, 1, 1))
    X[1:, :3, :3] = Rotation.random(2, random_state=seed).as_matrix()
    X[1:, :3, 3] = rng.normal(scale=0.01, size=(2, 3))
    n_open, n_sweep = count_open_and_sweep(points, X, kind, margin, sweep_margin=sweep_margin)
    moves = [not np.allclose(a[0], b[0]) for a, b in zip(
        reference_boxes(kind, GR.q_open), reference_boxes(kind, GR.q_closed), strict=True)]
    assert moves.count(True) == 3  # two fingers (parallel) or L finger and hand (vertical)
    for k in range(len(X)):
        p = trimesh.transform_points(points, np.linalg.inv(X[k]))
        already = inside(p, [(c, h + margin) for c, h in reference_boxes(kind, GR.q_open)])
        reached = np.zeros(len(p), dtype=bool)
        for q in openings():
            reached |= inside(p, [(c, h + margin + sweep_margin) for (c, h), m in zip(
                reference_boxes(kind, q), moves, strict=True) if m])
        assert n_open[k] == already.sum()
        assert n_sweep[k] == (reached & ~already).sum()
    assert n_sweep.max() > 0


def test_closed_loop_interior_is_the_hole_of_the_closed_loop():
    """The interior box touches the closed rods, the bar and the palm, and overlaps none."""
    for kind in KINDS:
        box = closed_loop_interior_G(kind)
        lo, hi = reference_interior(kind)
        np.testing.assert_allclose(np.subtract(box.center, box.half_extents), lo, atol=1e-12)
        np.testing.assert_allclose(np.add(box.center, box.half_extents), hi, atol=1e-12)
        closed = closing_boxes_G(kind, GR.q_closed)
        inner = dataclasses.replace(box, half_extents=tuple(np.subtract(box.half_extents,
                                                                        1e-6)))
        grown = dataclasses.replace(box, half_extents=tuple(np.add(box.half_extents, 1e-6)))
        counts = count_points_in_boxes(_box_grid(inner), np.eye(4)[None], [closed])
        assert counts[0, 0] == 0
        grid = _box_grid(grown)
        touched = {b.name for b in closed
                   if count_points_in_boxes(grid, np.eye(4)[None], [[b]])[0, 0] > 0}
        assert {"straight_rod", "l_rod", "bar", "hand"} <= touched


def _box_grid(box, n: int = 9) -> np.ndarray:
    axes = [np.linspace(c - h, c + h, n) for c, h in zip(box.center, box.half_extents,
                                                         strict=True)]
    return np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)


# ---- objects of the set: cages, not pinches ---------------------------------------------------------
FLAT = ("key_ring", "tape_roll", "scissors")
PARAMS = GbhParams()
RAISED = 0.05  # m: flat objects lifted off the table (ground plane z = 0 stays, and checked)


class Case:
    """One object at the report's pose (+0.55 m in x), lifted by ``dz``: its GbH result, the
    core's points, a denser independent sampling of its surface and its ground-truth holes."""

    def __init__(self, name: str, dz: float = 0.0, params: GbhParams = PARAMS):
        spec = make_object(name)
        offset = np.array([0.55, 0.0, dz])
        self.mesh = spec.mesh.copy().apply_translation(offset)
        self.result = plan_grasps(self.mesh, params)
        self.obj = prepare_object(self.mesh, params)
        self.points = self.obj.points
        self.dense = np.concatenate([
            np.asarray(self.mesh.vertices),
            np.asarray(trimesh.sample.sample_surface(self.mesh, 20000, seed=1)[0]),
        ])
        self.holes = [(p.center_O + offset, p.axis_O, 0.5 * p.clear_diameter)
                      for p in spec.hangable_parts]


_CASES: dict[tuple[str, float], Case] = {}


def case(name: str, dz: float = 0.0) -> Case:
    if (name, dz) not in _CASES:
        _CASES[(name, dz)] = Case(name, dz)
    return _CASES[(name, dz)]


def threads_a_hole(X_WG: np.ndarray, kind: str, c: Case) -> bool:
    """Whether the closed gripper's rod that should pass through a hole does: the straight rod
    (vertical grasps) or the bar (parallel grasps), as a segment of its centre line, crosses a
    ground-truth hole's plane at a point from which the straight way to the hole's centre is
    free (so the point is in the hole, whatever the hole's shape)."""
    closed = dict(zip([b.name for b in GR.solid_boxes_G(GR.q_closed)],
                      reference_boxes(kind, GR.q_closed), strict=True))
    center_G, half = closed["straight_rod" if kind == VERTICAL else "bar"]
    axis = 2 if kind == VERTICAL else 1
    a_G, b_G = center_G.copy(), center_G.copy()
    a_G[axis] -= half[axis]
    b_G[axis] += half[axis]
    a, b = trimesh.transform_points(np.stack([a_G, b_G]), X_WG)
    for center, normal, _ in c.holes:
        denom = (b - a) @ normal
        if abs(denom) < 1e-12:
            continue
        t = ((center - a) @ normal) / denom
        if not 0.0 <= t <= 1.0:
            continue
        p = a + t * (b - a)
        d = np.linalg.norm(center - p)
        if d < 1e-9 or c.obj.cast(p[None], ((center - p) / d)[None])[0] > d:
            return True
    return False


def check_cage(g, c: Case) -> None:
    """The loop of ranked grasp g closes (nothing stops the fingers before q_closed) around
    material: the hooked point h and other material lie inside the closed loop's hole, and the
    rod that goes through the hole does go through a ground-truth hole."""
    q_stop, n = closing_stop(g.X_WG, g.kind, c.dense)
    assert q_stop == GR.q_closed, (
        f"{g.kind} grasp stops at q = {1e3 * q_stop:.2f} mm on {n} points (closed: "
        f"{1e3 * GR.q_closed:.1f} mm)")
    p_G = trimesh.transform_points(c.dense, np.linalg.inv(g.X_WG))
    assert in_interior(p_G, g.kind).sum() >= 5, "no material inside the closed loop"
    h_G = trimesh.transform_points(g.h[None], np.linalg.inv(g.X_WG))
    assert in_interior(h_G, g.kind)[0], "the hooked material is not inside the closed loop"
    assert threads_a_hole(g.X_WG, g.kind, c)


@pytest.mark.parametrize("name", FLAT)
def test_flat_objects_in_free_space_get_vertical_grasps_that_close_around_them(name):
    c = case(name, RAISED)
    vertical = [g for g in c.result.ranked if g.kind == VERTICAL]
    assert vertical, f"{name}: no ranked vertical grasp"
    for g in vertical:
        check_cage(g, c)
    # Round loops: the closed gripper's centre-line loop links a circle inside the material.
    if name in ("key_ring", "tape_roll"):
        from test_grasps import linking_number

        center, axis, radius = c.holes[0]
        e1 = np.cross(axis, [1.0, 0.0, 0.0])
        e1 /= np.linalg.norm(e1)
        e2 = np.cross(axis, e1)
        t = 2 * np.pi * np.arange(200) / 200
        circle = center + (radius + 1e-3) * (np.cos(t)[:, None] * e1 + np.sin(t)[:, None] * e2)
        travel = GR.q_open - GR.q_closed
        for g in vertical:
            loop_G = GR.loop_polygon_G(GR.q_closed) + (0.0, travel, 0.0)
            assert abs(linking_number(trimesh.transform_points(loop_G, g.X_WG), circle)) == \
                pytest.approx(1.0, abs=1e-6)


@pytest.mark.parametrize("name", FLAT)
def test_the_old_vertical_placement_pinches(name):
    """The bar's centre line on q_f (the old reading of p2 = q_m with d2 = 0) puts half the bar
    in the material: the sweep check rejects it and the fingers stop before the loop closes."""
    c = case(name, RAISED)
    vertical = [g for g in c.result.ranked if g.kind == VERTICAL]
    assert vertical
    for g in vertical:
        X_old = g.X_WG.copy()
        X_old[:3, 3] -= (R_ROD + PARAMS.cage_clearance) * X_old[:3, 2]  # p2 back on q_2 + d2 z
        _, n_sweep = count_open_and_sweep(c.points, X_old[None], VERTICAL)
        assert n_sweep[0] >= PARAMS.p_sweep
        assert not collision_free(dataclasses.replace(g, X_WG=X_old, n_sweep_collisions=int(
            n_sweep[0])), PARAMS)
        assert closing_stop(X_old, VERTICAL, c.dense)[0] > GR.q_closed + 1e-3


def _reference_lowest(X_WG: np.ndarray, kind: str) -> float:
    """Lowest height (z_W) of the solid model over the closing, from stepped corners."""
    signs = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)])
    low = np.inf
    for q in openings()[::8].tolist() + [GR.q_closed]:
        for center, half in reference_boxes(kind, q):
            low = min(low, trimesh.transform_points(center + signs * half, X_WG)[:, 2].min())
    return float(low)


@pytest.mark.parametrize("name", FLAT)
def test_flat_objects_on_the_table_rank_nothing_below_the_clearance(name):
    on = case(name)
    for g in on.result.ranked:
        assert _reference_lowest(g.X_WG, g.kind) >= PARAMS.ground_clearance - 1e-9
    # Not vacuous: without the check, ranked grasps go below the clearance (under the object).
    off = plan_grasps(on.mesh, dataclasses.replace(PARAMS, ground_clearance=-1.0))
    assert any(_reference_lowest(g.X_WG, g.kind) < PARAMS.ground_clearance for g in off.ranked)


@pytest.mark.parametrize("name", FLAT)
def test_flat_objects_on_the_table_cannot_be_hooked(name):
    """The physical limit, stated: an object 5-19 mm tall lying flat can be hooked only by a bar
    under it (vertical grasps) or by rods 17 mm + half a rod on both sides of its hole's plane
    (parallel grasps: the bar along the vertical hole axis); both go through the table."""
    assert case(name).result.ranked == []


def test_mug_parallel_grasps_close_around_the_handle():
    c = case("mug_classic")
    parallel = [g for g in c.result.ranked if g.kind == PARALLEL]
    assert parallel
    for g in parallel:
        check_cage(g, c)
        assert _reference_lowest(g.X_WG, g.kind) >= PARAMS.ground_clearance


def test_the_paper_parallel_placement_pinches_the_mug_handle():
    """p_M on c (the paper's placement, taken literally with our rods): the handle's material at
    h ends under the closing straight rod."""
    c = case("mug_classic")
    p = GR.keypoints_G()
    for g in [g for g in c.result.ranked if g.kind == PARALLEL]:
        X_old = g.X_WG.copy()
        X_old[:3, 3] = g.structure.c - X_old[:3, :3] @ p["pM"]  # same axes, p_M on c
        assert count_open_and_sweep(c.points, X_old[None], PARALLEL)[1][0] >= PARAMS.p_sweep
        assert closing_stop(X_old, PARALLEL, c.dense)[0] > GR.q_closed + 1e-3


def test_the_wedge_nose_path_down_counts_as_a_sweep_collision():
    """A point the wedge's nose passes on its way down to a parallel grasp (5 cm above the
    bar, where the paper's bar tip stops short of it and no part sweeps while closing) is a
    sweep collision for the wedge gripper, nothing for the paper's."""
    from gbh_drake.core.collision import count_open_and_sweep, nose_descent_boxes_G
    from gbh_drake.core.gripper import HOOK_GRIPPER, WEDGE_GRIPPER, HookGripperGeometry

    nosed = HookGripperGeometry(bar_nose=0.008, bar_ramp=0.016)
    (column,) = nose_descent_boxes_G(nosed)
    # The paper's bar and the default wedge (its chamfer inside the bar) have no nose.
    assert nose_descent_boxes_G(HOOK_GRIPPER) == nose_descent_boxes_G(WEDGE_GRIPPER) == []
    p_G = np.array([[column.center[0], column.center[1], nosed.finger_length - 0.05]])
    X = np.eye(4)[None]
    counts = [tuple(int(v[0]) for v in count_open_and_sweep(p_G, X, "parallel", gripper=g))
              for g in (HOOK_GRIPPER, WEDGE_GRIPPER, nosed)]
    assert counts == [(0, 0), (0, 0), (0, 1)]


def test_a_wedge_centres_the_material_where_it_passes_the_nose_and_ends_in_the_loop():
    """The paper's bar centres a parallel grasp's material on G, the closed loop's middle; the
    wedge's nose narrows the way down to [nose tip, straight rod closed], so its material is
    centred there (the paper's grasps unchanged)."""
    from gbh_drake.core.grasp_synthesis import parallel_window_G
    from gbh_drake.core.gripper import HOOK_GRIPPER, WEDGE_GRIPPER, HookGripperGeometry

    assert parallel_window_G(HOOK_GRIPPER) == (0.0, -(HOOK_GRIPPER.q_closed - 0.004))
    # The default wedge's chamfer lies inside the paper's bar: the paper's window.
    assert parallel_window_G(WEDGE_GRIPPER) == parallel_window_G(HOOK_GRIPPER)
    nosed = HookGripperGeometry(bar_nose=0.008, bar_ramp=0.016)
    centre, low = parallel_window_G(nosed)
    nose_tip = -nosed.q_open + nosed.bar_length + nosed.bar_nose
    assert low == pytest.approx(nose_tip)
    assert centre == pytest.approx(0.5 * (nose_tip + nosed.q_closed - 0.004))
