"""Unknown space is not free space: ``core.free_space`` on hand-built depth images, and the GbH
core's through-hole test and closing sweep with a synthetic one-view scan."""

from __future__ import annotations

import dataclasses
import functools

import numpy as np
import pytest
import trimesh

from gbh_drake.core.free_space import FreeSpace
from gbh_drake.core.hangability import detect_hangable_structures
from gbh_drake.core.params import GbhParams

W, H, F = 64, 48, 60.0
CX, CY = W / 2 - 0.5, H / 2 - 0.5


def camera_X_CW(eye, target, up=(0.0, 0.0, 1.0)) -> np.ndarray:
    """X_CW (4, 4) of a camera at ``eye`` looking at ``target`` (+z_C forward, +y_C down)."""
    eye, target = np.asarray(eye, float), np.asarray(target, float)
    z = target - eye
    z /= np.linalg.norm(z)
    x = np.cross(z, up)
    if np.linalg.norm(x) < 1e-9:
        x = np.cross(z, (0.0, 1.0, 0.0))
    x /= np.linalg.norm(x)
    y = np.cross(z, x)
    R_WC = np.stack([x, y, z], axis=1)
    X = np.eye(4)
    X[:3, :3] = R_WC.T
    X[:3, 3] = -R_WC.T @ eye
    return X


def rendered_depth(mesh: trimesh.Trimesh, X_CW: np.ndarray, w: int = W, h: int = H,
                   f: float = F) -> np.ndarray:
    """Depth image (h, w) of ``mesh`` (inf where nothing is hit), Drake's pixel convention."""
    v, u = np.mgrid[0:h, 0:w]
    cx, cy = w / 2 - 0.5, h / 2 - 0.5
    d_C = np.stack([(u + 0.5 - cx) / f, (v + 0.5 - cy) / f, np.ones_like(u, float)], -1)
    X_WC = np.linalg.inv(X_CW)
    d_W = d_C.reshape(-1, 3) @ X_WC[:3, :3].T
    o_W = np.broadcast_to(X_WC[:3, 3], d_W.shape)
    loc, ray, _ = mesh.ray.intersects_location(o_W, d_W / np.linalg.norm(d_W, axis=1)[:, None],
                                               multiple_hits=False)
    depth = np.full(len(d_W), np.inf, np.float32)
    z = ((loc - X_WC[:3, 3]) @ X_WC[:3, :3])[:, 2]
    np.minimum.at(depth, ray, z.astype(np.float32))
    return depth.reshape(h, w)


def test_observed_free_on_a_hand_built_image():
    """One camera at the origin looking along +z_W (X_CW = identity): a wall at 1 m over the
    left half of the image, no return (inf) on the right half, a dropout (0) pixel."""
    depth = np.full((H, W), np.inf, np.float32)
    depth[:, : W // 2] = 1.0
    depth[10, 5] = 0.0
    fs = FreeSpace.from_depth_images([depth], F, F, CX, CY, [np.eye(4)], margin=0.01,
                                     depth_max=2.0)
    left = np.array([-0.1, 0.0, 0.0])  # pixel column ~26 at z = 1 of the left half
    pts = np.array([left + (0, 0, 0.5), left + (0, 0, 0.985), left + (0, 0, 0.995),
                    left + (0, 0, 1.2),  # behind the wall: unknown
                    (0.1, 0.0, 1.5), (0.1, 0.0, 2.5),  # right half: free up to depth_max only
                    (0.0, 0.0, -0.5),  # behind the camera
                    (10.0, 0.0, 1.0)])  # outside the image
    assert fs.observed_free(pts).tolist() == [True, True, False, False, True, False, False,
                                              False]
    assert fs.observed_free(pts[:3], margin=0.001).tolist() == [True, True, True]
    # No depth_max: a pixel with no return proves nothing; a dropout pixel neither.
    blind = FreeSpace.from_depth_images([depth], F, F, CX, CY, [np.eye(4)], margin=0.01)
    assert not blind.observed_free(pts[4:5]).any()
    u, v = 5, 10
    p_drop = np.array([(u + 0.5 - CX) / F, (v + 0.5 - CY) / F, 1.0]) * 0.5
    assert not fs.observed_free(p_drop[None]).any()


def test_a_second_view_frees_what_the_first_did_not_see():
    box = trimesh.creation.box((0.1, 0.1, 0.1))
    X1 = camera_X_CW((0.0, -0.6, 0.0), (0.0, 0.0, 0.0))
    X2 = camera_X_CW((0.0, 0.6, 0.0), (0.0, 0.0, 0.0))
    behind = np.array([[0.0, 0.1, 0.0]])  # behind the box from camera 1, in front for 2
    one = FreeSpace.from_depth_images([rendered_depth(box, X1)], F, F, CX, CY, [X1], 0.005, 3.0)
    two = FreeSpace.from_depth_images([rendered_depth(box, X) for X in (X1, X2)], F, F, CX, CY,
                                      [X1, X2], 0.005, 3.0)
    assert not one.observed_free(behind).any()
    assert two.observed_free(behind).all()
    assert not two.observed_free(np.zeros((1, 3))).any()  # inside the box


def test_views_joined_keep_their_own_margins():
    """``with_views``: what either free space saw is free, each view judged at its own margin
    (a far, coarse view's larger one), and an explicit margin overrides them all."""
    box = trimesh.creation.box((0.1, 0.1, 0.1))
    X1 = camera_X_CW((0.0, -0.6, 0.0), (0.0, 0.0, 0.0))
    X2 = camera_X_CW((0.0, 0.6, 0.0), (0.0, 0.0, 0.0))
    near = FreeSpace.from_depth_images([rendered_depth(box, X1)], F, F, CX, CY, [X1], 0.005, 3.0)
    far = FreeSpace.from_depth_images([rendered_depth(box, X2)], F, F, CX, CY, [X2], 0.03, 3.0)
    both = near.with_views(far)
    assert [v.margin for v in both.views] == [0.005, 0.03] and both.margin == 0.005
    behind = np.array([[0.0, 0.1, 0.0]])  # seen free by the second view only
    skin = np.array([[0.0, 0.07, 0.0]])  # 2 cm in front of the box for view 2: within its 3 cm
    front = np.array([[0.0, -0.07, 0.0]])  # 2 cm in front for view 1: beyond its 5 mm
    assert both.observed_free(np.concatenate([behind, skin, front])).tolist() == \
        [True, False, True]
    assert both.observed_free(skin, margin=0.005).all()
    assert not near.observed_free(behind).any()


def front_of(mesh: trimesh.Trimesh, X_CW: np.ndarray) -> trimesh.Trimesh:
    """The faces of ``mesh`` the camera sees (a one-view scan without its hidden side)."""
    X_WC = np.linalg.inv(X_CW)
    eye = X_WC[:3, 3]
    centers = mesh.triangles_center
    dirs = centers - eye
    dist = np.linalg.norm(dirs, axis=1)
    dirs /= dist[:, None]
    tri, ray = mesh.ray.intersects_id(np.broadcast_to(eye, dirs.shape), dirs,
                                      multiple_hits=False, return_locations=False)
    seen = np.zeros(len(mesh.faces), bool)
    seen[tri[tri == np.arange(len(mesh.faces))[ray]]] = True
    facing = np.einsum("ij,ij->i", mesh.face_normals, -dirs) > 0
    out = mesh.submesh([np.flatnonzero(seen & facing)], append=True)
    return out


@pytest.fixture(scope="module")
def params() -> GbhParams:
    return GbhParams(ground_clearance=-1.0, unknown_is_occupied=True)


def test_a_torus_seen_through_its_hole_keeps_its_structure(params):
    ring = trimesh.creation.torus(0.03, 0.008, major_sections=64, minor_sections=24)
    X = camera_X_CW((0.02, 0.0, 0.6), (0.0, 0.0, 0.0), up=(0.0, 1.0, 0.0))
    fs = FreeSpace.from_depth_images([rendered_depth(ring, X, 160, 120, 150.0)], 150.0, 150.0,
                                     79.5, 59.5, [X], 0.0025, 3.0)
    scan = front_of(ring, X)
    found = detect_hangable_structures(scan, params, free_space=fs)
    assert found and abs(found[0].v[2]) > 0.9
    assert np.linalg.norm(found[0].c[:2]) < 0.01


def test_a_hole_no_camera_saw_through_is_no_hole(params):
    """A ring seen edge-on from the side: its hole is hidden behind the ring's near side (and
    the cup behind it would hide it too). Without the free space the whole ring is a through
    hole; with it, the rays through c run in unseen space and the structure is refused."""
    ring = trimesh.creation.torus(0.03, 0.008, major_sections=64, minor_sections=24)
    X = camera_X_CW((0.6, 0.0, 0.0), (0.0, 0.0, 0.0))
    depth = rendered_depth(ring, X, 160, 120, 150.0)
    fs = FreeSpace.from_depth_images([depth], 150.0, 150.0, 79.5, 59.5, [X], 0.0025, 3.0)
    found_without = detect_hangable_structures(ring, params)
    assert found_without and abs(found_without[0].v[2]) > 0.9
    assert not any(abs(s.v[2]) > 0.9 and np.linalg.norm(s.c[:2]) < 0.01
                   for s in detect_hangable_structures(ring, params, free_space=fs))
    paper = dataclasses.replace(params, unknown_is_occupied=False)
    assert detect_hangable_structures(ring, paper, free_space=fs)


def _ring_free_space(eye, *, table_z: float | None = None):
    """A torus (axis z, centre at the origin) and the free space of one camera at ``eye``
    looking at it, over a table at ``table_z`` when given."""
    ring = trimesh.creation.torus(0.03, 0.008, major_sections=64, minor_sections=24)
    scene = ring
    if table_z is not None:
        table = trimesh.creation.box((0.6, 0.6, 0.02))
        table.apply_translation((0.0, 0.0, table_z - 0.01))
        scene = trimesh.util.concatenate([ring, table])
    X = camera_X_CW(eye, (0.0, 0.0, 0.0), up=(0.0, 1.0, 0.0) if eye[0] == 0 else (0, 0, 1))
    depth = rendered_depth(scene, X, 160, 120, 150.0)
    return ring, X, FreeSpace.from_depth_images([depth], 150.0, 150.0, 79.5, 59.5, [X], 0.0025,
                                                3.0)


@pytest.mark.parametrize(("eye", "angle", "proven"), [
    ((0.45, 0.0, 0.38), 60.0, True),  # seen 50 deg off the ring's axis
    ((0.3, 0.0, 0.52), 60.0, True),  # 30 deg off
    ((0.5, 0.0, 0.2), 60.0, False),  # 68 deg off: no line within 60 deg was seen free
    ((0.5, 0.0, 0.2), 75.0, True),  # ... one within 75 deg was
])
def test_a_hole_is_proven_by_a_line_seen_free_within_the_angle_of_its_axis(params, eye, angle,
                                                                            proven):
    """One camera sees through the ring's hole along its own line of sight: the hole is proven
    when that line lies within ``through_proof_angle_deg`` of the hole's axis."""
    ring, X, fs = _ring_free_space(eye)
    q = dataclasses.replace(params, through_proof_angle_deg=angle)
    found = detect_hangable_structures(front_of(ring, X), q, free_space=fs)
    assert any(abs(s.v[2]) > 0.9 and np.linalg.norm(s.c[:2]) < 0.01 for s in found) == proven


def test_a_ring_lying_on_the_table_is_closed_by_the_table_for_the_local_proof(params):
    """Seen from above, a ring lying flat has its hole seen free down to the table. For the
    local proof (``through_proof_exit: false``) every line through its hole within 60 deg of
    the axis runs into the table band: the table closes the hole (no bar can pass under
    material that lies on the table). The axis rule, which skips the table band, and the exit
    proof, which follows the line down to the table the camera saw through the hole, call it
    a hole (the grasps' table clearance then refuses what cannot pass under it)."""
    bottom = -0.008
    ring, X, fs = _ring_free_space((0.0, 0.02, 0.6), table_z=bottom)
    on_table = dataclasses.replace(params, ground_height=bottom)
    scan = front_of(ring, X)
    local = dataclasses.replace(on_table, through_proof_exit=False)
    assert not any(abs(s.v[2]) > 0.9 for s in
                   detect_hangable_structures(scan, local, free_space=fs))
    axis = dataclasses.replace(local, through_proof_angle_deg=0.0)
    assert any(abs(s.v[2]) > 0.9 for s in detect_hangable_structures(scan, axis, free_space=fs))
    assert any(abs(s.v[2]) > 0.9 for s in
               detect_hangable_structures(scan, on_table, free_space=fs))


def test_saw_plane_tells_the_table_from_a_floor_standing_on_it():
    """A camera above a table (z = 0) with a 6 mm plate on part of it: a point above the bare
    table saw the table; one above the plate saw the plate, not the table; one under the plate
    was not seen free at all."""
    table = trimesh.creation.box((0.6, 0.6, 0.02))
    table.apply_translation((0.0, 0.0, -0.01))
    plate = trimesh.creation.box((0.1, 0.2, 0.006))
    plate.apply_translation((0.1, 0.0, 0.003))
    X = camera_X_CW((0.0, -0.05, 0.5), (0.0, 0.0, 0.0), up=(0.0, 1.0, 0.0))
    depth = rendered_depth(trimesh.util.concatenate([table, plate]), X, 160, 120, 150.0)
    fs = FreeSpace.from_depth_images([depth], 150.0, 150.0, 79.5, 59.5, [X], 0.0025, 3.0)
    pts = np.array([(-0.1, 0.0, 0.02), (0.1, 0.0, 0.02), (0.1, 0.0, 0.004)])
    assert fs.saw_plane(pts, (0.0, 0.0, 1.0), 0.0, 0.001).tolist() == [True, False, False]
    assert fs.saw_plane(pts[1:2], (0.0, 0.0, 1.0), 0.006, 0.001).all()  # the plate's own top
    # A noisy sensor's depth error widens the tolerance: 6 mm of noise hides the plate.
    noisy = FreeSpace.from_depth_images([depth], 150.0, 150.0, 79.5, 59.5, [X], 0.0025, 3.0,
                                        depth_error=0.006)
    assert noisy.saw_plane(pts, (0.0, 0.0, 1.0), 0.0, 0.001).tolist() == [True, True, False]


@pytest.mark.parametrize("floor_plate", [False, True])
def test_the_exit_proof_ends_at_the_table_only_where_the_table_was_seen(params, floor_plate):
    """A ring lying flat 2.2 cm above a table, seen from above through its hole: the proof line
    runs down through the hole to the table band; it leads out only if the camera saw the table
    itself there. A 6 mm plate under the ring (a bucket's floor, which the scan's cut removes
    with the table) is not the table: the line ends in it, and the hole is refused."""
    ring = trimesh.creation.torus(0.03, 0.008, major_sections=64, minor_sections=24)
    table_z = -0.03
    table = trimesh.creation.box((0.6, 0.6, 0.02))
    table.apply_translation((0.0, 0.0, table_z - 0.01))
    parts = [ring, table]
    if floor_plate:
        plate = trimesh.creation.box((0.12, 0.12, 0.006))
        plate.apply_translation((0.0, 0.0, table_z + 0.003))
        parts.append(plate)
    X = camera_X_CW((0.0, 0.02, 0.6), (0.0, 0.0, 0.0), up=(0.0, 1.0, 0.0))
    depth = rendered_depth(trimesh.util.concatenate(parts), X, 160, 120, 150.0)
    fs = FreeSpace.from_depth_images([depth], 150.0, 150.0, 79.5, 59.5, [X], 0.0025, 3.0)
    q = dataclasses.replace(params, ground_clearance=0.0, ground_height=table_z,
                            through_proof_exit=True)
    found = detect_hangable_structures(front_of(ring, X), q, free_space=fs)
    assert any(abs(s.v[2]) > 0.9 and np.linalg.norm(s.c[:2]) < 0.01 for s in found) \
        == (not floor_plate)


def test_an_eroded_view_does_not_see_past_a_thin_rod_beside_its_pixel():
    """A wall at 1 m and a one-pixel-wide rod at 0.5 m in front of it (one camera at the origin
    looking along +z_W): a point 0.7 m out in the rod's neighbour pixel is seen free by that
    pixel's one ray; eroded by one pixel (``FreeSpace.eroded``), it is free only where every
    neighbour's ray passed it too, so not there, while a point far from the rod stays free.
    ``coarser_than`` erodes only the views whose pixel is wider than the given footprint."""
    depth = np.full((H, W), 1.0, np.float32)
    u_rod = W // 2
    depth[:, u_rod] = 0.5
    fs = FreeSpace.from_depth_images([depth], F, F, CX, CY, [np.eye(4)], margin=0.01,
                                     depth_max=2.0)
    beside = np.array([(u_rod + 1 + 0.5 - CX) / F, 0.0, 1.0]) * 0.7  # the next pixel, at 0.7 m
    far = np.array([(5 + 0.5 - CX) / F, 0.0, 1.0]) * 0.7
    pts = np.stack([beside, far])
    assert fs.observed_free(pts).tolist() == [True, True]
    assert fs.eroded().observed_free(pts).tolist() == [False, True]
    footprint = fs.views[0].footprint(beside)
    assert footprint == pytest.approx(0.7 / F)
    assert fs.eroded(coarser_than=(beside, 2 * footprint)).observed_free(pts).tolist() == \
        [True, True]  # the view is finer than asked: left as it is
    assert fs.eroded(coarser_than=(beside, 0.5 * footprint)).observed_free(pts).tolist() == \
        [False, True]
    # A pixel with no depth (NaN) makes its neighbours unknown too.
    holey = depth.copy()
    holey[0, 5] = np.nan
    near_nan = np.array([(6 + 0.5 - CX) / F, (0 + 0.5 - CY) / F, 1.0]) * 0.7
    fs2 = FreeSpace.from_depth_images([holey], F, F, CX, CY, [np.eye(4)], margin=0.01,
                                      depth_max=2.0)
    assert fs2.observed_free(near_nan[None]).all()
    assert not fs2.eroded().observed_free(near_nan[None]).any()


@functools.cache
def _mug_with_a_lost_wall(radius: float = 0.04, hole: float = 0.014):
    """A cylinder (radius ``radius``, 9 cm tall, about the origin) with a handle (the outer half
    of a torus of major radius ``hole``, tube 5 mm, axis y) on its +x side; the scan (the true
    mesh less the wall faces behind the handle: a gap a TSDF can leave there) and the free
    space of five views of the true object."""
    body = trimesh.creation.cylinder(radius=radius, height=0.09, sections=64)
    handle = trimesh.creation.torus(hole, 0.005, major_sections=48, minor_sections=16)
    handle.apply_transform(trimesh.transformations.rotation_matrix(np.pi / 2, [1, 0, 0]))
    handle.apply_translation([radius + 0.006, 0.0, 0.0])
    handle = handle.submesh([np.flatnonzero(handle.triangles_center[:, 0] > radius - 0.001)],
                            append=True)
    truth = trimesh.util.concatenate([body, handle])
    tc = body.triangles_center
    wall = body.submesh([np.flatnonzero(~((tc[:, 0] > 0.7 * radius) & (abs(tc[:, 2]) < 0.02)))],
                        append=True)
    scan = trimesh.util.concatenate([wall, handle])
    eyes = [(0.5, 0.3, 0.3), (0.5, -0.3, 0.3), (0.1, 0.0, 0.6), (0.3, 0.5, 0.0), (0.3, -0.5, 0.0)]
    Xs = [camera_X_CW(e, (0.02, 0.0, 0.0)) for e in eyes]
    fs = FreeSpace.from_depth_images([rendered_depth(truth, X, 120, 90, 112.5) for X in Xs],
                                     112.5, 112.5, 59.5, 44.5, Xs, 0.0025, 3.0)
    return scan, fs


@pytest.mark.parametrize("radius,hole", [(0.04, 0.014), (0.05, 0.018)])
def test_a_handle_whose_wall_the_scan_lost_keeps_its_structure(params, radius, hole):
    """The handle's contacts' segments toward the CoM pass through the gap into the body's
    unseen inside, whose free ball is larger than the handle's: searched to the mesh, the
    cluster's position lies in the cavity and is refused (not a through-hole), the handle is
    lost; searched only while the cameras saw it free (``hang_segment_seen``), the position
    is in the handle's hole, and the hole is proven."""
    from gbh_drake.core.hangability import detect_with_report

    scan, fs = _mug_with_a_lost_wall(radius, hole)

    def handles(flag: bool):
        found, report = detect_with_report(
            scan, dataclasses.replace(params, hang_segment_seen=flag), free_space=fs)
        return [s for s in found if radius < s.c[0] < radius + 2 * hole], report

    lost, report = handles(False)
    assert not lost and report.refused_by()["not a through-hole"] >= 1
    assert any(np.linalg.norm(r.c[:2]) < radius for r in report.refused)  # in the cavity
    kept, _ = handles(True)
    assert len(kept) == 1 and abs(kept[0].v[1]) > 0.9  # the handle's axis, y


def test_the_seen_prefix_ends_where_a_segment_leaves_seen_free_space(params):
    """From the handle's far side toward the body's centre: seen free through the handle's
    hole, unseen from the wall on (the scan's gap does not free it); samples before the first
    seen-free one (the contact's own margin) are kept, a segment never seen free is kept whole,
    and with no supporting surface nothing is taken as the table's band."""
    from gbh_drake.core.hangability import seen_prefix
    from gbh_drake.core.object_model import prepare_object

    scan, fs = _mug_with_a_lost_wall(0.04, 0.014)
    obj = prepare_object(scan, params, 0, fs)
    t = np.linspace(0.0, 0.05, 41)
    through_gap = np.array([0.0548, 0.0, 0.0]) + t[:, None] * np.array([-1.0, 0.0, 0.0])
    inside = np.array([0.0, 0.0, 0.03]) + t[:, None] * np.array([0.0, 0.0, -1.0])
    mask = seen_prefix(obj, fs, np.stack([through_gap, inside]), params)
    last = np.flatnonzero(mask[0]).max()
    assert mask[0, : last + 1].all() and not mask[0, last + 1:].any()
    assert 0.04 - 0.0025 <= through_gap[last, 0] <= 0.04 + 0.005  # at the wall the scan lost
    assert mask[1].all()  # inside the body: never seen free, kept whole
