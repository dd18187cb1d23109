"""The unseen space next to a scan (``core.unseen``): a box on a table seen by one camera has a
shadow behind it that the unseen cells cover; a second camera on the other side closes it; cells
that do not connect to the scan are dropped; and the lift that keeps them clear (planning)."""

from __future__ import annotations

import numpy as np
import trimesh

from gbh_drake.core.free_space import FreeSpace
from gbh_drake.core.unseen import farthest_distance, unseen_cells
from tests.core.test_free_space import camera_X_CW, rendered_depth

BOX = trimesh.creation.box((0.1, 0.1, 0.1), trimesh.transformations.translation_matrix(
    (0.0, 0.0, 0.05)))
TABLE = trimesh.creation.box((2.0, 2.0, 0.02), trimesh.transformations.translation_matrix(
    (0.0, 0.0, -0.01)))
SCENE = trimesh.util.concatenate([BOX, TABLE])
LOWER, UPPER = (-0.15, -0.15, 0.005), (0.15, 0.15, 0.2)


def free_of(*eyes) -> FreeSpace:
    X = [camera_X_CW(eye, (0.0, 0.0, 0.05)) for eye in eyes]
    return FreeSpace.from_depth_images([rendered_depth(SCENE, x, 160, 120, 150.0) for x in X],
                                       150.0, 150.0, 79.5, 59.5, X, margin=0.004)


def front_points(eye) -> np.ndarray:
    """The box's faces a camera at ``eye`` (towards -x, above) sees: its -x face and its top."""
    p, _ = trimesh.sample.sample_surface_even(BOX, 3000, seed=0)
    return p[(p[:, 0] <= -0.0499) | (p[:, 2] >= 0.0999)]


EYE_FRONT, EYE_BACK = (-0.5, 0.0, 0.5), (0.5, 0.0, 0.5)


def test_one_view_leaves_the_shadow_behind_the_box_unseen():
    cells = unseen_cells(front_points(EYE_FRONT), free_of(EYE_FRONT).observed_free, LOWER, UPPER)
    assert len(cells)
    # The box itself (its inside) and the shadow behind it, down to the table, are unseen:
    assert cells[:, 0].max() > 0.1
    # nothing in front of the box, which the camera saw through:
    assert cells[:, 0].min() > -0.06
    # the farthest unseen cell from the box's front top edge is beyond the box's far corner
    pivot = (-0.05, 0.0, 0.1)
    assert farthest_distance(cells, pivot) > farthest_distance(BOX.vertices, pivot) + 0.02


def test_a_view_from_the_other_side_closes_the_shadow():
    cells = unseen_cells(front_points(EYE_FRONT), free_of(EYE_FRONT, EYE_BACK).observed_free,
                         LOWER, UPPER)
    assert len(cells)
    # What is left is the box's inside (and a cell's rounding of its faces).
    assert np.all(np.abs(cells[:, :2]) <= 0.05 + 0.005)
    assert cells[:, 2].max() <= 0.1 + 0.005


def test_cells_that_do_not_connect_to_the_scan_are_dropped():
    # Nothing seen free at all: every cell is unseen, all of them connected to the points.
    every = unseen_cells(front_points(EYE_FRONT), lambda p: np.zeros(len(p), bool), LOWER, UPPER)
    assert len(every) == 60 * 60 * 39  # the whole box, 5 mm cells
    # Free but for two separate blocks: only the one holding the points is kept.
    def two_blocks(p):
        a = np.all(np.abs(p - (0.0, 0.0, 0.05)) <= 0.06, axis=1)
        b = np.all(np.abs(p - (0.0, 0.12, 0.15)) <= 0.02, axis=1)
        return ~(a | b)
    kept = unseen_cells(front_points(EYE_FRONT), two_blocks, LOWER, UPPER)
    assert len(kept) and kept[:, 1].max() <= 0.065


def test_no_points_or_no_box_no_cells():
    free = free_of(EYE_FRONT).observed_free
    assert unseen_cells(np.zeros((0, 3)), free, LOWER, UPPER).shape == (0, 3)
    assert unseen_cells(front_points(EYE_FRONT), free, UPPER, LOWER).shape == (0, 3)
    assert unseen_cells(front_points(EYE_FRONT) + 5.0, free, LOWER, UPPER).shape == (0, 3)
