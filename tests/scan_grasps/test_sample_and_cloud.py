"""The sample views (tests/scan_grasps/data/mug_views: the mug as a simulated 16-bit sensor saw
it, 10 views and a first look, written by tools/make_sample_views.py) and the same scan as a point
cloud: both through ``gbh grasps``, both hook the mug's handle."""

import numpy as np
import pytest

import gbh_drake
from gbh_drake import REPO_ROOT
from gbh_drake.core.params import GbhParams
from gbh_drake.scan_grasps.inputs import NO_FREE_SPACE, load_input

pytestmark = pytest.mark.sim

SAMPLE = REPO_ROOT / "tests" / "scan_grasps" / "data" / "mug_views"
#: The sample mug's handle: its true centre in B (mug_classic's hangable part at (0.55, 0, 2 mm),
#: yaw 30 deg; the hole is 4 cm across).
HANDLE_B = np.array([0.6027, 0.0304, 0.0519])


@pytest.fixture(scope="module")
def sample():
    return gbh_drake.grasps(SAMPLE)


def test_the_sample_views_hook_the_handle(sample):
    assert sample.input_kind == "depth_images" and sample.free_space
    assert sample.scan.table.source == "verified" or sample.table_source == "given"
    assert 10 < len(sample.grasps) <= GbhParams().top_k and sample.hangability.exit_proof
    c = sample.structures[sample.grasps[0].structure].c
    assert np.linalg.norm(c - HANDLE_B) < 0.01
    assert sample.grasps[0].terms["alpha_deg"] < 20.0  # from above


def _with_masks(folder, key: str, chosen) -> None:
    """The sample views copied into ``folder``, each with a mask ``key`` of the pixels whose
    points p_B (n, 3) ``chosen`` (p_B) marks."""
    import shutil

    import yaml

    from gbh_drake.perception.depth import points_C
    from gbh_drake.scan_grasps.views import read_views, write_png

    v = read_views(SAMPLE).views
    data = yaml.safe_load((SAMPLE / "views.yaml").read_text())
    for i, (depth, X) in enumerate(zip(v.depths, v.X_BCs, strict=True)):
        p_C = points_C(np.where(np.isfinite(depth), depth, 0.0), v.intrinsics).reshape(3, -1).T
        write_png(folder / f"{key}_{i}.png", chosen(p_C @ X[:3, :3].T + X[:3, 3]).reshape(
            depth.shape))
        data["views"][i][key] = f"{key}_{i}.png"
    for name in {*(x["depth"] for x in data["views"]), *(x["depth"] for x in
                                                         data["first_look"]["views"])}:
        shutil.copy(SAMPLE / name, folder / name)
    (folder / "views.yaml").write_text(yaml.safe_dump(data))


def test_masks_keep_the_object_and_nothing_else(tmp_path, sample):
    """Each view with a mask of the object's pixels (here: the pixels whose points lie within
    2 cm of the scan's mesh): the same object, the same best grasp."""
    from scipy.spatial import cKDTree

    tree = cKDTree(sample.scan.mesh_W.vertices)
    _with_masks(tmp_path, "mask",
                lambda p_B: tree.query(p_B, distance_upper_bound=0.02)[0] < 0.02)
    masked = gbh_drake.grasps(tmp_path)
    assert len(masked.scan.mesh_W.faces) == pytest.approx(len(sample.scan.mesh_W.faces), rel=0.02)
    np.testing.assert_allclose(masked.grasps[0].X_BG[:3, 3], sample.grasps[0].X_BG[:3, 3],
                               atol=0.005)


def test_robot_masks_are_no_measurement_of_the_object_but_of_free_space(tmp_path, sample):
    """Each view with a ``robot_mask`` (the self filter's pixels: here, as if the robot's hand
    hung over the mug, the pixels that see anything above 5 cm): nothing above is fused (the
    mug is 9.8 cm tall), and those pixels' depths still give the free space."""
    _with_masks(tmp_path, "robot_mask", lambda p_B: p_B[:, 2] > 0.05)
    filtered = gbh_drake.grasps(tmp_path)
    assert sample.scan.mesh_W.vertices[:, 2].max() > 0.09
    assert filtered.scan.mesh_W.vertices[:, 2].max() < 0.05 + 0.0025  # a voxel
    views = filtered.scan.free_space.views[:10]  # the views' own (the first look's follow)
    np.testing.assert_array_equal(np.stack([w.depth for w in views]),
                                  np.stack([w.depth for w in sample.scan.free_space.views[:10]]))


def test_a_point_cloud_is_fused_and_says_so(tmp_path, sample):
    """The sample's measured points (the mug and the table round it) as an .npy cloud: table
    fitted, the mug segmented and fused, no free space; its handle is hooked."""
    scan = load_input(SAMPLE).scan
    from gbh_drake.perception.crop import CropBox
    from gbh_drake.perception.fusion import view_points

    box = CropBox((0.45, -0.12, -0.02), (0.72, 0.15, 0.2))
    cloud = view_points([v.depth for v in scan.free_space.views[:10]], scan.intrinsics,
                        scan.X_WCs, box).p_WQ[::4]
    np.save(tmp_path / "cloud.npy", cloud)
    r = gbh_drake.grasps(tmp_path / "cloud.npy")
    assert r.input_kind == "point_cloud" and not r.free_space
    assert NO_FREE_SPACE in r.notes and any("fused" in n for n in r.notes)
    assert r.table_source in ("verified", "fitted")
    assert r.grasps, r.none
    c = r.structures[r.grasps[0].structure].c
    assert np.linalg.norm(c - HANDLE_B) < 0.015


def test_a_table_in_words_has_no_negative_zero():
    from gbh_drake.perception.table import TablePlane
    from gbh_drake.scan_grasps.table import plane_text

    assert plane_text(TablePlane.horizontal(-0.00001)) == "z = 0.0000 m"
    assert plane_text(TablePlane.horizontal(0.0123456)) == "z = 0.0123 m"
    tilted = TablePlane(np.array([0.0, -0.6, 0.8]), -0.00001)
    assert plane_text(tilted) == "[0.0, -0.6, 0.8] . p = 0.0000 m"
