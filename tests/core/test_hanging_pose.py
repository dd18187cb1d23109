"""Where a hooked object hangs: rotations, lowest points, the lift that clears the table."""

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from gbh_drake.core.gripper import HOOK_GRIPPER
from gbh_drake.core.hanging_pose import (
    hanging_lowest_height,
    hanging_rotation,
    lift_for_clearance,
    rest_on_loop,
)
from gbh_drake.core.results import PARALLEL

UP = np.array([0.0, 0.0, 1.0])
vectors = st.lists(st.floats(-1.0, 1.0), min_size=3, max_size=3).map(np.array)


@given(vectors, vectors)
def test_hanging_rotation_brings_the_com_straight_below_the_hook(com, hook):
    d = com - hook
    R = hanging_rotation(com, hook, UP)
    np.testing.assert_allclose(R @ R.T, np.eye(3), atol=1e-9)
    assert np.linalg.det(R) == pytest.approx(1.0)
    if np.linalg.norm(d) > 1e-6:
        np.testing.assert_allclose(R @ d, -np.linalg.norm(d) * UP, atol=1e-9)


def test_a_stick_hooked_at_one_end_hangs_straight_down():
    """A 30 cm horizontal stick at 5 cm height, hooked at one end: it swings to hang below."""
    x = np.linspace(0.0, 0.3, 31)
    points = np.column_stack([x, np.zeros_like(x), np.full_like(x, 0.05)])
    hook = points[0]
    com = points.mean(axis=0)
    assert hanging_lowest_height(points, com, hook) == pytest.approx(0.05 - 0.3)
    assert hanging_lowest_height(points, com, hook, swings=False) == pytest.approx(0.05)
    # Clear the table by 5 cm: the hook rises 30 cm.
    assert lift_for_clearance(points, com, hook, 0.05) == pytest.approx(0.30)
    assert lift_for_clearance(points, com, hook, 0.05, swings=False) == pytest.approx(0.0)


def test_the_lift_bounds_any_way_the_object_turns():
    """A wrong centre of mass (a scan's centroid) cannot make the lift too short: the farthest
    point from the hook bounds the hanging object's lowest point."""
    rng = np.random.default_rng(0)
    points = rng.uniform([-0.1, -0.1, 0.0], [0.1, 0.1, 0.2], (500, 3))
    hook = np.array([0.0, 0.0, 0.2])
    lift = lift_for_clearance(points, points.mean(axis=0), hook, 0.05)
    for com in rng.uniform([-0.1, -0.1, 0.0], [0.1, 0.1, 0.2], (50, 3)):
        assert hanging_lowest_height(points, com, hook) + lift >= 0.05 - 1e-9


# ---- where the hooked material rests on the loop ---------------------------------------------
G = HOOK_GRIPPER
R_DOWN = np.diag([1.0, -1.0, -1.0])  # a top-down grasp: z_G = -z_W, the bar at the bottom
BAR_HALF = 0.5 * G.rod_width


def _top_down(p_bar_W) -> np.ndarray:
    """The open grasp pose (parallel, top-down, loop in the y-z plane of W) whose bar's middle is
    at ``p_bar_W``."""
    X = np.eye(4)
    X[:3, :3] = R_DOWN
    X[:3, 3] = np.asarray(p_bar_W, dtype=float) - R_DOWN @ [0.0, 0.0, G.finger_length]
    return X


def _ring(centre, clear_radius, tube=0.006, n=72, m=8):
    """A torus with its axis along y_W, in the x-z plane (the top-down loop, in the y-z plane,
    links it), as surface points."""
    a, b = np.meshgrid(np.linspace(0, 2 * np.pi, n, endpoint=False),
                       np.linspace(0, 2 * np.pi, m, endpoint=False))
    R = clear_radius + tube
    y = tube * np.sin(b)
    x = (R + tube * np.cos(b)) * np.cos(a)
    z = (R + tube * np.cos(b)) * np.sin(a)
    return np.column_stack([x.ravel(), y.ravel(), z.ravel()]) + centre


def test_a_ring_hooked_at_its_centre_drops_by_its_clear_radius_less_the_bar():
    """A ring of 6 cm clear diameter with the bar through its centre: lifted, it sinks until its
    inner top rests on the bar's upper face, 3 cm - 4 mm, and hangs straight below."""
    centre = np.array([0.5, 0.0, 0.2])
    ring = _ring(centre, 0.03)
    rest = rest_on_loop(ring, centre, _top_down(centre), PARALLEL, hook_W=centre)
    assert rest.support == "bar"
    assert rest.caged > 0
    assert rest.drop == pytest.approx(0.03 - BAR_HALF, abs=1.5e-3)
    np.testing.assert_allclose(rest.contact_W, centre + [0.0, 0.0, BAR_HALF], atol=BAR_HALF)
    # The ring hangs from the contact: its bottom is its outer diameter (7.2 cm) below it.
    assert rest.lowest == pytest.approx(rest.contact_W[2] - 0.072, abs=1e-3)
    assert rest.lowest_any_turn <= rest.lowest + 1e-9
    # The old estimate, hanging at the centre, was too high by the drop.
    assert hanging_lowest_height(ring, centre, centre) - rest.lowest == pytest.approx(rest.drop,
                                                                                      abs=1e-3)


def test_a_mug_handle_on_the_bar_barely_drops():
    """A mug's handle whose inner face is 2 mm above the bar's upper face sinks 2 mm."""
    body = np.random.default_rng(0).uniform([-0.04, -0.04, 0.0], [0.04, 0.04, 0.095], (400, 3))
    bar = np.array([0.0, 0.06, 0.07])  # the bar's middle, inside the handle
    handle_inner = bar + [0.0, 0.0, BAR_HALF + 0.002]
    handle = np.array([handle_inner + [dx, dy, 0.0] for dx in (-0.004, 0.0, 0.004)
                       for dy in (-0.005, 0.0, 0.005)])
    points = np.vstack([body, handle])
    rest = rest_on_loop(points, body.mean(axis=0), _top_down(bar), PARALLEL, hook_W=bar)
    assert rest.support == "bar"
    assert rest.drop == pytest.approx(0.002, abs=1e-9)
    assert rest.contact_W[2] == pytest.approx(bar[2] + BAR_HALF)


def test_no_caged_material_hangs_from_the_hook_point():
    points = np.random.default_rng(1).uniform([-0.05, -0.05, 0.0], [0.05, 0.05, 0.1], (300, 3))
    hook = np.array([0.3, 0.3, 0.3])  # the loop far from the object
    rest = rest_on_loop(points, points.mean(axis=0), _top_down(hook), PARALLEL, hook_W=hook)
    assert rest.caged == 0 and rest.drop == 0.0 and rest.support == ""
    np.testing.assert_allclose(rest.contact_W, hook)
    assert rest.lowest == pytest.approx(hanging_lowest_height(points, points.mean(axis=0), hook))


def test_a_loop_lying_flat_does_not_predict_a_drop():
    """Approach horizontal and loop plane horizontal (up along x_G): material in the hole has no
    side below it; it hangs from the hook point."""
    centre = np.array([0.5, 0.0, 0.2])
    ring = _ring(np.zeros(3), 0.03) @ np.array([[1, 0, 0], [0, 0, 1], [0, 1, 0]]).T + centre
    X = np.eye(4)
    X[:3, :3] = np.array([[0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]])  # x_G = -z_W
    X[:3, 3] = centre - X[:3, :3] @ [0.0, 0.0, G.finger_length]
    rest = rest_on_loop(ring, centre, X, PARALLEL, hook_W=centre)
    assert rest.drop == 0.0 and rest.support == ""


def test_a_sideways_loop_rests_the_material_on_the_lower_rod():
    """A horizontal approach with y_G = -z_W: the straight rod is below the hole."""
    centre = np.array([0.5, 0.0, 0.2])
    X = np.eye(4)
    X[:3, :3] = np.column_stack([[0.0, 1.0, 0.0], [0.0, 0.0, -1.0], [-1.0, 0.0, 0.0]])
    X[:3, 3] = centre - X[:3, :3] @ [0.0, 0.0, 0.5 * G.finger_length]
    material = centre + np.array([[dx, 0.0, 0.0] for dx in (-0.005, 0.0, 0.005)])
    rest = rest_on_loop(material, centre, X, PARALLEL)
    assert rest.support == "straight_rod"
    straight_inner = (G.q_closed - BAR_HALF)
    assert rest.drop == pytest.approx(straight_inner, abs=1e-9)


def _standing_hanger():
    """The generated wire hanger (3.5 mm wire) standing in the air, hook up, its surface
    sampled as a scan's points, and a top-down parallel hook of its triangle's straight bottom
    bar at the middle (the bar crossing the loop's plane 6 cm below the palm)."""
    import trimesh

    from gbh_drake.core.geometry import poses_from_axes
    from gbh_drake.objects import make_object

    mesh = make_object("clothes_hanger").mesh.copy()
    mesh.apply_transform(trimesh.transformations.rotation_matrix(np.pi / 2, [1, 0, 0]))
    mesh.apply_translation([0.5, 0.0, 0.3 - mesh.bounds[0, 2]])
    points, _ = trimesh.sample.sample_surface_even(mesh, 20000, seed=0)
    bar_middle = np.array([0.5, 0.0, mesh.bounds[0, 2] + 0.0035])
    X = poses_from_axes(np.array([[0.0, 1.0, 0.0]]), np.array([[0.0, 0.0, -1.0]]),
                        np.zeros((1, 3)))[0]
    X[:3, 3] = bar_middle - X[:3, :3] @ np.array([0.0, 0.0, 0.06])
    return mesh, points, X


def test_a_wire_slides_through_the_loop_to_its_corner_and_the_lift_allows_for_it():
    """Issue 42: hooked in the middle of its straight bottom bar, the hanger's wire slides
    through the closed loop to the triangle's corner (16 cm along), and the object hangs from
    there, 15 cm deeper than from the middle. The bound over every point the wire can slide
    to (a 3.5 mm wire passes the 26 x 76 mm loop anywhere) says so; without the material
    graph, the bound is the old one, from the middle."""
    from gbh_drake.core.sliding import material_graph

    mesh, points, X = _standing_hanger()
    fixed = rest_on_loop(points, mesh.center_mass, X, PARALLEL)
    slid = rest_on_loop(points, mesh.center_mass, X, PARALLEL,
                        material=material_graph(points, 0.004))
    assert fixed.slide == 0.0 and fixed.hang_W is None
    assert slid.slide > 0.14  # half the 32 cm bar
    assert abs(slid.hang_W[0] - 0.5) > 0.14  # at a corner
    assert slid.lowest_any_turn < fixed.lowest_any_turn - 0.12
    assert slid.lowest < fixed.lowest - 0.12
    np.testing.assert_allclose(slid.contact_W, fixed.contact_W)


def test_a_mug_handle_slides_to_the_body_and_no_farther():
    """A mug hooked top-down by its handle: the handle's arm passes the loop and the material
    may slide along it, but not onto the body (its cross-section is the cup's): the slide is
    at most the handle's length and the bound moves by centimetres."""
    import trimesh

    from gbh_drake.core.params import GbhParams
    from gbh_drake.core.pipeline import plan_grasps
    from gbh_drake.core.sliding import material_graph
    from gbh_drake.objects import make_object

    mesh = make_object("mug_classic").mesh
    points, _ = trimesh.sample.sample_surface_even(mesh, 20000, seed=0)
    grasp = plan_grasps(mesh, GbhParams(), seed=0).ranked[0]
    fixed = rest_on_loop(points, mesh.center_mass, grasp.X_WG, grasp.kind)
    slid = rest_on_loop(points, mesh.center_mass, grasp.X_WG, grasp.kind,
                        material=material_graph(points, 0.004))
    assert 0.0 < slid.slide < 0.08
    assert fixed.lowest_any_turn - 0.04 < slid.lowest_any_turn <= fixed.lowest_any_turn
