"""Cutting the mesh at the table and closing its bottom, except where the table was seen
through it."""

import numpy as np
import open3d as o3d
import pytest
import trimesh

from gbh_drake.perception.cap import bottom_boundary, cap_bottom, cut_at_height
from gbh_drake.perception.config import ScanConfig
from gbh_drake.perception.quality import raycasting_scene
from gbh_drake.perception.table import TablePlane

TABLE = TablePlane.horizontal(0.0, "verified")
CONFIG = ScanConfig()


def tube(r_in, r_out, height, bottom=0.0):
    """A thick-walled tube standing on the table (an annulus extruded), open at both ends'
    inside: a ring, a tape roll, or a cup without its floor. Watertight."""
    ring = trimesh.creation.annulus(r_min=r_in, r_max=r_out, height=height - bottom,
                                    sections=64)
    ring.apply_translation([0.0, 0.0, 0.5 * (height + bottom)])
    return ring


def hits(mesh, origins, direction):
    rays = np.hstack([origins, np.tile(direction, (len(origins), 1))]).astype(np.float32)
    return np.isfinite(raycasting_scene(mesh).cast_rays(o3d.core.Tensor(rays))["t_hit"].numpy())


def test_cut_is_exact_and_keeps_the_winding():
    sphere = trimesh.creation.icosphere(subdivisions=4, radius=0.05)
    sphere.apply_translation([0.0, 0.0, 0.04])
    cut = cut_at_height(sphere, TABLE, 0.004)
    assert cut.vertices[:, 2].min() == pytest.approx(0.004, abs=1e-12)
    assert cut.is_winding_consistent
    centroid = sphere.centroid
    outward = np.einsum("ij,ij->i", cut.face_normals, cut.triangles_center - centroid)
    assert np.all(outward > 0)
    edges, on_plane = bottom_boundary(cut, TABLE, 0.004, 0.02)
    assert len(edges) > 0 and on_plane.all()


def table_ring(r_min, r_max, n=4000, seed=0):
    """Depth points on the table (z = 0) in the annulus r_min..r_max around the origin."""
    rng = np.random.default_rng(seed)
    r = np.sqrt(rng.uniform(r_min ** 2, r_max ** 2, n))
    a = rng.uniform(0.0, 2 * np.pi, n)
    return np.column_stack([r * np.cos(a), r * np.sin(a), np.zeros(n)])


@pytest.mark.parametrize("seen_inside, is_open", [(False, False), (True, True)])
def test_enclosed_region_is_capped_unless_the_table_was_seen_through_it(seen_inside, is_open):
    """A tube cut at 4 mm: its inside is closed from below, unless depth points saw the table
    there (a key ring's hole)."""
    mesh = cut_at_height(tube(0.03, 0.036, 0.05), TABLE, CONFIG.crop_z_min)
    low = table_ring(0.04, 0.08)  # the table around the tube: always seen
    if seen_inside:
        low = np.vstack([low, table_ring(0.0, 0.029, seed=1)])
    capped, report = cap_bottom(mesh, TABLE, CONFIG, low)
    assert report.open_holes == int(is_open) and report.capped_regions == int(not is_open)
    inside = np.array([[0.0, 0.0, 0.02], [0.01, -0.01, 0.02]])
    assert hits(capped, inside, [0, 0, -1]).any() != is_open
    # The wall's own section is closed either way; nothing is added outside the tube.
    assert hits(capped, [[0.033, 0.0, 0.02]], [0, 0, -1]).all()
    assert not hits(capped, [[0.045, 0.0, 0.02]], [0, 0, -1]).any()
    assert capped.bounds[1, 0] < 0.0375


def test_floor_seen_a_few_millimetres_up_is_not_the_table():
    """Points seen 3 mm up inside (a bag's floor, below the cut) are no evidence of a hole."""
    mesh = cut_at_height(tube(0.03, 0.036, 0.05), TABLE, CONFIG.crop_z_min)
    floor = table_ring(0.0, 0.029, seed=1) + [0.0, 0.0, 0.003]
    _, report = cap_bottom(mesh, TABLE, CONFIG, np.vstack([table_ring(0.04, 0.08), floor]))
    assert report.capped_regions == 1 and report.open_holes == 0


def test_unseen_foot_gets_a_skirt_down_to_the_cap():
    """A tube whose scanned wall ends 1.2 cm up (a bevelled foot the cameras never saw): capped
    at the cut, with a skirt from the wall down to it, so rays cannot slip in sideways."""
    mesh = trimesh.creation.cylinder(radius=0.04, height=0.1, sections=64)
    mesh.apply_translation([0.0, 0.0, 0.062])
    mesh.update_faces(mesh.face_normals[:, 2] > -0.5)  # no bottom disk: open from 1.2 cm down
    mesh.remove_unreferenced_vertices()
    capped, report = cap_bottom(mesh, TABLE, CONFIG, table_ring(0.045, 0.08))
    assert report.capped_regions == 1
    assert hits(capped, [[0.0, 0.0, 0.05]], [0, 0, -1]).all()
    assert hits(capped, [[0.0, 0.0, 0.007]], [1, 0, 0]).all()  # the skirt, below the wall
    assert capped.bounds[0, 2] == pytest.approx(CONFIG.crop_z_min, abs=1e-9)


def test_handle_underside_near_the_table_is_not_capped():
    """An open boundary near the table that encloses nothing (e.g. the unseen underside of a
    low handle, here a thin open strip) gets no cap: no flap on the table."""
    strip = trimesh.Trimesh([[0, 0, 0.015], [0.06, 0, 0.015], [0.06, 0.004, 0.015],
                             [0, 0.004, 0.015]], [[0, 1, 2], [0, 2, 3]])
    capped, report = cap_bottom(strip, TABLE, CONFIG, table_ring(0.0, 0.1))
    assert report.faces == 0 and len(capped.faces) == 2
