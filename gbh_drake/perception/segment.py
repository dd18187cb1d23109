"""Segmenting the object from the scene: the table plane goes, the object's cluster stays.

Points above the table (higher than ``crop_z_min``) are grouped into connected clusters on a grid
of ``cluster_cell`` cubes (cells touching by a face, an edge or a corner are connected, so points
closer than one cell always join and points two cells apart in some axis never do; cells with
fewer than ``min_cell_points`` points, e.g. depth noise above the table, are empty). The object is
the cluster nearest the reference point (the scan target, or a point already known to be on the
object) among those that are big enough, rest on the table (the robot's hand hovering above the
object does not), keep clear of the robot's base (the arm may be in view) and come near enough
to the target. Everything else (robot, other objects, noise) is dropped.

When the object's points are already known from another look (``known_W``: the first look, which
sees it from two sides, standing on the table), every allowed cluster that comes within
``KNOWN_MARGIN`` of them is the object's, whether or not its own lowest point reaches the table:
one view may see only the top of an object that stands on a part hidden from it (an upside-down
teapot on its lid) or see it split in two by an occlusion.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from gbh_drake.core.lazy import lazy_module
from gbh_drake.perception.config import ScanConfig
from gbh_drake.perception.crop import CropBox
from gbh_drake.perception.table import TablePlane

ndimage = lazy_module("scipy.ndimage")
spatial = lazy_module("scipy.spatial")

_CONNECTIVITY = np.ones((3, 3, 3), dtype=bool)
#: The views' points are read in a cube around the first look's bounding sphere: half side
#: ROI_SCALE x its radius + ROI_MARGIN (m) (``perception.scan.object_region``; the view
#: choice's completion of the first look votes in the same region).
ROI_SCALE = 1.1
ROI_MARGIN = 0.03

KNOWN_MARGIN = 0.015
"""A cluster is the already known object's if one of its points is this close (m) to a known
point (the first look's images sample the surface a few millimetres apart)."""
_KNOWN_SAMPLE = 4000
"""At most this many points of a cluster are compared with the known points."""


@dataclass
class Segmentation:
    """Which of the input points are the object, and which are at table height."""

    object_mask: np.ndarray
    """(n,) bool: the object's points (above ``crop_z_min``)."""
    low_mask: np.ndarray
    """(n,) bool: points within ``crop_z_min`` of the table plane (the table, and the object's
    lowest slice), not below it by more than a few tolerances."""
    heights: np.ndarray
    """(n,) m: height of each point above the table plane."""
    dropped: dict[str, int] = field(default_factory=dict)
    """How many clusters were dropped, by reason (``robot``, ``not on the table``,
    ``too far``, ``too small``)."""
    touches: list[str] = field(default_factory=list)
    """Faces of the bounding box that the object reaches (e.g. ``+x``, ``top``)."""

    @property
    def found(self) -> bool:
        return bool(self.object_mask.any())


def cluster_labels(p_WQ: np.ndarray, cell: float, min_cell_points: int = 1) -> np.ndarray:
    """Label (n,) of the connected cluster of each point p_WQ (n, 3), on a grid of ``cell`` (m)
    cubes connected by faces, edges and corners (scipy ``ndimage.label``). Cells holding fewer
    than ``min_cell_points`` points do not connect anything: their points take the label of a
    neighbouring cluster cell (a surface's edge), or 0 if there is none (isolated noise)."""
    if len(p_WQ) == 0:
        return np.zeros(0, dtype=np.int32)
    lower = p_WQ.min(axis=0)
    index = ((p_WQ - lower) / cell).astype(np.int64)
    shape = tuple(index.max(axis=0) + 1)
    linear = (index[:, 0] * shape[1] + index[:, 1]) * shape[2] + index[:, 2]
    occupied = np.bincount(linear, minlength=int(np.prod(shape))) >= min_cell_points
    labels, _ = ndimage.label(occupied.reshape(shape), structure=_CONNECTIVITY)
    point_labels = labels.reshape(-1)[linear]
    # Points of a sparse cell next to a cluster's cell (an edge of a surface) join it.
    sparse = np.flatnonzero(point_labels == 0)
    if len(sparse) and len(sparse) < len(p_WQ):
        near = np.zeros(len(sparse), dtype=labels.dtype)
        for offset in np.argwhere(_CONNECTIVITY) - 1:
            cell = index[sparse] + offset
            inside = np.all((cell >= 0) & (cell < shape), axis=1)
            found = np.zeros(len(sparse), dtype=labels.dtype)
            found[inside] = labels[cell[inside, 0], cell[inside, 1], cell[inside, 2]]
            near = np.maximum(near, found)
        point_labels[sparse] = near
    return point_labels


def segment_points(p_WQ: np.ndarray, table: TablePlane, config: ScanConfig, p_WT,
                   box: CropBox, *, reference=None, search_radius: float | None = None,
                   known_W: np.ndarray | None = None) -> Segmentation:
    """Segments points p_WQ (n, 3) in W (all inside ``box``) into table, object and the rest.

    The object's cluster must come within ``search_radius`` (default
    ``config.object_search_radius``) horizontally of p_WT; among those allowed, the one nearest
    ``reference`` (default p_WT) in 3-D is the object. With ``known_W`` (k, 3), the object's
    points seen before, the object is every allowed cluster within ``KNOWN_MARGIN`` of them,
    resting on the table or not (module docstring); if none is, the rule above."""
    p_WT = np.asarray(p_WT, dtype=float).reshape(3)
    reference = p_WT if reference is None else np.asarray(reference, dtype=float).reshape(3)
    radius = config.object_search_radius if search_radius is None else search_radius
    heights = table.heights(p_WQ)
    low = (heights < config.crop_z_min) & (heights > -3.0 * config.table_tolerance)
    result = Segmentation(np.zeros(len(p_WQ), dtype=bool), low, heights)
    above = np.flatnonzero(heights >= config.crop_z_min)
    if len(above) == 0:
        return result
    points = p_WQ[above]
    labels = cluster_labels(points, config.cluster_cell, config.min_cell_points)
    # Per-cluster statistics in one pass: points sorted by cluster, minima by segment.
    order = np.argsort(labels, kind="stable")
    index, starts, count = np.unique(labels[order], return_index=True, return_counts=True)
    if index[0] == 0:  # points in sparse cells: no cluster
        index, starts, count = index[1:], starts[1:], count[1:]
    if len(index) == 0:
        return result
    base = np.asarray(config.robot_base_xy, dtype=float)
    sorted_points = points[order]

    def lowest_per_cluster(values: np.ndarray) -> np.ndarray:
        return np.minimum.reduceat(values, starts)

    lowest = lowest_per_cluster(heights[above][order])
    to_target = lowest_per_cluster(np.hypot(sorted_points[:, 0] - p_WT[0],
                                            sorted_points[:, 1] - p_WT[1]))
    to_robot = lowest_per_cluster(np.hypot(sorted_points[:, 0] - base[0],
                                           sorted_points[:, 1] - base[1]))
    to_reference = lowest_per_cluster(np.linalg.norm(sorted_points - reference, axis=1))
    near_known = _near_known(sorted_points, starts, count, known_W)
    reasons = [("too small", count < config.min_cluster_points),
               ("robot", to_robot <= config.robot_clearance),
               ("not on the table", (lowest > config.support_gap) & ~near_known),
               ("too far", to_target > radius)]
    allowed = np.ones(len(index), dtype=bool)
    for reason, bad in reasons:
        result.dropped[reason] = int(np.sum(allowed & bad))
        allowed &= ~bad
    if not allowed.any():
        return result
    if (allowed & near_known).any():
        chosen = index[allowed & near_known]
    else:
        chosen = index[[np.flatnonzero(allowed)[np.argmin(to_reference[allowed])]]]
    result.object_mask[above[np.isin(labels, chosen)]] = True
    result.touches = box_faces_reached(p_WQ[result.object_mask], box, config.cluster_cell)
    return result


def _near_known(sorted_points: np.ndarray, starts: np.ndarray, count: np.ndarray,
                known_W: np.ndarray | None) -> np.ndarray:
    """(c,) bool: whether each cluster (``count`` points from ``starts`` in ``sorted_points``)
    comes within ``KNOWN_MARGIN`` of a known point (all False without ``known_W``)."""
    near = np.zeros(len(starts), dtype=bool)
    if known_W is None or len(known_W) == 0:
        return near
    tree = spatial.cKDTree(np.asarray(known_W, dtype=float).reshape(-1, 3))
    for k, (start, n) in enumerate(zip(starts, count, strict=True)):
        sample = sorted_points[start:start + n][:: max(1, int(n) // _KNOWN_SAMPLE)]
        distance, _ = tree.query(sample, distance_upper_bound=KNOWN_MARGIN)
        near[k] = bool(np.isfinite(distance).any())
    return near


def box_faces_reached(p_WQ: np.ndarray, box: CropBox, margin: float) -> list[str]:
    """Faces of ``box`` (``-x``, ``+x``, ``-y``, ``+y``, ``top``) that points p_WQ (n, 3) come
    within ``margin`` (m) of."""
    if len(p_WQ) == 0:
        return []
    lower, upper = np.asarray(box.lower_W), np.asarray(box.upper_W)
    reached = []
    for i, axis in enumerate("xy"):
        if p_WQ[:, i].min() <= lower[i] + margin:
            reached.append(f"-{axis}")
        if p_WQ[:, i].max() >= upper[i] - margin:
            reached.append(f"+{axis}")
    if p_WQ[:, 2].max() >= upper[2] - margin:
        reached.append("top")
    return reached


def bounding_sphere(p_WQ: np.ndarray, table: TablePlane) -> tuple[np.ndarray, float]:
    """(centre (3,), radius m) of a sphere around the object's points p_WQ (n, 3) and their
    footprint on the table (the object stands on it even where its bottom was not seen): the
    centre of their axis-aligned box and the farthest point's distance from it."""
    footprint = p_WQ - table.heights(p_WQ)[:, None] * table.normal_W
    points = np.vstack([p_WQ, footprint])
    centre = 0.5 * (points.min(axis=0) + points.max(axis=0))
    return centre, float(np.sqrt(np.max(np.sum((points - centre) ** 2, axis=1))))
