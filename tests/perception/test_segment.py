"""Segmenting points: clusters on a grid, the object nearest the target, the robot and floating
parts and noise dropped."""

import numpy as np
import pytest

from gbh_drake.perception.config import ScanConfig
from gbh_drake.perception.crop import CropBox
from gbh_drake.perception.segment import (
    bounding_sphere,
    box_faces_reached,
    cluster_labels,
    segment_points,
)
from gbh_drake.perception.table import TablePlane

TABLE = TablePlane.horizontal(0.0, "verified")


def blob(lower, upper, spacing=0.002):
    """Points on the surface of the box [lower, upper] (m), ``spacing`` apart, as a depth camera
    samples a surface (several per 5 mm cell)."""
    lower, upper = np.asarray(lower, float), np.asarray(upper, float)
    axes = [np.arange(lower[i], upper[i] + 1e-9, spacing) for i in range(3)]
    points = []
    for i in range(3):
        j, k = [a for a in range(3) if a != i]
        grid = np.stack(np.meshgrid(axes[j], axes[k], indexing="ij"), axis=-1).reshape(-1, 2)
        for value in (lower[i], upper[i]):
            face = np.empty((len(grid), 3))
            face[:, i], face[:, j], face[:, k] = value, grid[:, 0], grid[:, 1]
            points.append(face)
    return np.vstack(points)


@pytest.mark.parametrize("gap, clusters", [(0.003, 1), (0.011, 2)])
def test_clusters_join_within_a_cell_and_split_two_cells_apart(gap, clusters):
    a = blob([0, 0, 0], [0.05, 0.05, 0.05])
    b = blob([0.05 + gap, 0, 0], [0.1, 0.05, 0.05])
    labels = cluster_labels(np.vstack([a, b]), 0.005)
    assert len(np.unique(labels)) == clusters


def test_sparse_cells_are_noise():
    p = np.vstack([blob([0, 0, 0], [0.05, 0.05, 0.05]), [[0.2, 0.2, 0.2]]])
    labels = cluster_labels(p, 0.005, min_cell_points=3)
    assert labels[-1] == 0 and np.all(labels[:-1] > 0)


def scene_points():
    """Table, an object at the target, the robot's base and arm, its hand hovering above the
    object, another object far away, isolated noise above the table."""
    rng = np.random.default_rng(3)
    table = np.column_stack([rng.uniform(0.0, 1.1, 40000), rng.uniform(-0.5, 0.5, 40000),
                             rng.normal(0.0, 0.0003, 40000)])
    parts = {
        "object": blob([0.5, -0.05, 0.0], [0.6, 0.05, 0.2]),
        "robot": blob([-0.08, -0.08, 0.0], [0.08, 0.08, 0.5]),
        "hand": blob([0.45, -0.05, 0.25], [0.55, 0.05, 0.35]),
        "far": blob([0.9, 0.3, 0.0], [0.95, 0.35, 0.1]),
        "noise": np.column_stack([rng.uniform(0.1, 1.0, 30), rng.uniform(-0.4, 0.4, 30),
                                  np.full(30, 0.006)]),
    }
    return table, parts


def test_object_is_segmented_from_table_robot_hand_and_others():
    table, parts = scene_points()
    p = np.vstack([table, *parts.values()])
    box = CropBox((-0.05, -0.6, -0.05), (1.15, 0.6, 0.6))
    seg = segment_points(p, TABLE, ScanConfig(), [0.55, 0.0, 0.06], box)
    start = len(table)
    split = np.split(seg.object_mask[start:], np.cumsum([len(v) for v in parts.values()])[:-1])
    masks = dict(zip(parts, split, strict=True))
    # All of the object but its lowest 4 mm, which go with the table; nothing of the rest but
    # a noise point that happened to fall next to it.
    assert np.array_equal(masks["object"], parts["object"][:, 2] >= 0.004)
    assert not seg.object_mask[:start].any()
    assert not any(masks[k].any() for k in ("robot", "hand", "far"))
    assert masks["noise"].sum() <= 1
    assert seg.low_mask[:len(table)].all()
    assert seg.dropped["robot"] == 1 and seg.dropped["not on the table"] == 1
    assert seg.dropped["too far"] == 1
    assert seg.touches == []


def test_nothing_near_the_target_is_no_object():
    table, parts = scene_points()
    p = np.vstack([table, parts["robot"], parts["hand"], parts["far"]])
    box = CropBox((-0.05, -0.6, -0.05), (1.15, 0.6, 0.6))
    seg = segment_points(p, TABLE, ScanConfig(), [0.5, 0.0, 0.06], box)
    assert not seg.found


def test_what_a_look_saw_before_keeps_parts_that_do_not_reach_the_table():
    """One view sees an upside-down teapot's body floating 4 cm above the table (what it stands
    on is hidden) and its handle apart: both touch what the first look saw, so both are the
    object; the hand hovering above (not near the known points) is still dropped."""
    table, parts = scene_points()
    body = blob([0.5, -0.05, 0.04], [0.6, 0.05, 0.12])
    handle = blob([0.615, -0.01, 0.06], [0.63, 0.01, 0.1])
    p = np.vstack([table, body, handle, parts["hand"]])
    box = CropBox((-0.05, -0.6, -0.05), (1.15, 0.6, 0.6))
    seg = segment_points(p, TABLE, ScanConfig(), [0.55, 0.0, 0.06], box)
    assert not seg.found and seg.dropped["not on the table"] == 3  # without a first look
    known = np.vstack([blob([0.5, -0.05, 0.0], [0.6, 0.05, 0.12], 0.01),
                       blob([0.615, -0.01, 0.06], [0.63, 0.01, 0.1], 0.01)])
    seg = segment_points(p, TABLE, ScanConfig(), [0.55, 0.0, 0.06], box, known_W=known)
    n_table, n_body, n_handle = len(table), len(body), len(handle)
    assert seg.object_mask[n_table:n_table + n_body + n_handle].all()
    assert not seg.object_mask[:n_table].any()
    assert not seg.object_mask[n_table + n_body + n_handle:].any()  # the hand
    assert seg.dropped["not on the table"] == 1


def test_faces_reached_and_bounding_sphere():
    p = blob([0.5, -0.05, 0.0], [0.6, 0.05, 0.2])
    box = CropBox((0.3, -0.04, -0.1), (0.8, 0.3, 0.2))
    assert box_faces_reached(p, box, 0.005) == ["-y", "top"]
    centre, radius = bounding_sphere(p + [0, 0, 0.05], TABLE)  # footprint included
    np.testing.assert_allclose(centre, [0.55, 0.0, 0.125], atol=2e-3)
    assert radius == pytest.approx(np.linalg.norm([0.05, 0.05, 0.125]), abs=3e-3)
