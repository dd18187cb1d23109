"""Collision checking by point counting (paper Sec. 2.3) and our checks of the closing motion.

* N_c (paper): object points inside the gripper's solid model (hand, rods and bar boxes of
  :class:`HookGripperGeometry`, in G) at the grasp pose, open. The paper keeps N_c < p_c.
* N_sweep (ours): object points that the moving parts of the gripper reach while it closes
  (their swept volume, the closed pose included, grown by a margin of a fraction of the sample
  spacing, since material can cut into a box between samples) and that are not inside the open
  model. The paper checks the open pose only; a grasp whose closing meets material stops on it
  (a pinch) instead of closing its loop around it (a cage), so the closing motion is checked
  as well. The caged material, inside the closed loop's hole (:func:`closed_loop_interior_G`),
  is outside every swept box; it counts only if it comes within the margin of a moving part.
* unknown space in the sweep (ours, with a scan's free space, ``GbhParams.unknown_is_occupied``):
  a one-view scan lacks the material the camera did not see, so the closing motion can "meet
  nothing" in a place no camera saw. :func:`count_unknown_in_sweep` counts the points of a grid
  filling the moving parts' swept volume (outside the open model, as N_sweep) that no camera
  saw free, that lie above the supporting surface and away from the scanned surface (whose own
  noise band is not free either and is N_sweep's business); they are added to N_sweep.
* ground distance (ours): the height of the lowest point of the solid model above the supporting
  plane, over the open pose, the closing sweep and the closed pose.
* the rods' clearance (ours, ``GbhParams.rod_clearance``): the rods and the bar, at the open pose
  and swept while closing (:func:`rod_boxes_G`), must stay that far from the object's *surface*,
  tested so that no part of any thickness is missed between samples
  (:func:`count_rod_contacts`): N_c's allowance of ``p_c`` points lets an 8 mm rod cross a
  3-5 mm wire or a thin handle arm (a few samples), and the executed hand is off the plan by
  the IK's tolerance.

The closing motion of each kind (what the pick planner executes, gbh_drake/planning/pick.py),
in the frame G of the grasp pose X_WG, with travel = q_open - q_closed:

* parallel: the fingers close symmetrically about G: the straight finger moves by -travel along
  y_G, the L finger by +travel, the hand stays; (p2 + p3)/2 and p_M stay where they were (the
  grasp puts c near (p2 + p3)/2, grasp_synthesis);
* vertical: the arm moves G along +y_G by travel while the fingers close, so the straight rod
  stays put, the L finger moves by +2 travel and the hand by +travel.

The solid model is made of boxes that translate along y_G, so the volume a box sweeps is that
box extended along y_G by its displacement (exact, not a bound), and its corners at the open and
the closed pose are the corners of the swept box.

Counting is batched: the G coordinates of every point for a chunk of poses are computed as
(chunk, N) arrays (broadcast multiply-adds, :func:`frame_coordinates`), and the box tests run on
those arrays; interval tests shared by several boxes (e.g. all rods have the same x extent) are
computed once.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from gbh_drake.core.free_space import FreeSpace
from gbh_drake.core.geometry import frame_coordinates
from gbh_drake.core.gripper import HOOK_GRIPPER, Box, HookGripperGeometry
from gbh_drake.core.lazy import lazy_module
from gbh_drake.core.results import PARALLEL, GraspKind

spatial = lazy_module("scipy.spatial")

#: Points x poses processed per chunk (bounds the temporary (chunk, N) arrays to ~50 MB).
_CHUNK_POINTS = 2_000_000


# ---- the closing motion ------------------------------------------------------------------------
def closing_displacements(kind: str, gripper: HookGripperGeometry = HOOK_GRIPPER
                          ) -> tuple[float, float, float]:
    """(hand, straight finger, L finger) displacements along y_G (metres) from the open grasp
    pose to the closed gripper, in the frame G of the grasp pose, for a grasp ``kind``."""
    travel = gripper.q_open - gripper.q_closed
    if kind == PARALLEL:
        return 0.0, -travel, travel
    if kind in (GraspKind.VERTICAL, GraspKind.SCOOP):  # about the straight rod
        return travel, 0.0, 2.0 * travel
    raise ValueError(f"unknown grasp kind {kind!r}")


def _moving_boxes(gripper: HookGripperGeometry) -> list[tuple[Box, int]]:
    """Boxes of the open gripper in G, each with the index (0 hand, 1 straight, 2 L finger) of
    the body it belongs to."""
    q = gripper.q_open
    out = [(gripper.hand_box(), 0)]
    for b in gripper.straight_finger_boxes():
        out.append((_shifted(b, q), 1))
    for b in gripper.l_finger_boxes():
        out.append((_shifted(b, -q), 2))
    return out


def _shifted(b: Box, dy: float) -> Box:
    c = np.asarray(b.center, dtype=float) + (0.0, dy, 0.0)
    return Box(b.name, tuple(float(v) for v in c), b.half_extents)


def closing_boxes_G(kind: str, q: float, gripper: HookGripperGeometry = HOOK_GRIPPER
                    ) -> list[Box]:
    """The solid model, in the frame G of the grasp pose (open gripper), when the fingers have
    closed to finger position ``q`` (q_open: the grasp pose; q_closed: closed) along the closing
    motion of ``kind``."""
    q = gripper.check_opening(q)
    t = (gripper.q_open - q) / (gripper.q_open - gripper.q_closed)
    d = closing_displacements(kind, gripper)
    return [_shifted(b, t * d[body]) for b, body in _moving_boxes(gripper)]


def swept_boxes_G(kind: str, gripper: HookGripperGeometry = HOOK_GRIPPER) -> list[Box]:
    """The volume the solid model sweeps from the grasp pose (open) to the closed gripper, as
    boxes in the frame G of the grasp pose: each box extended along y_G by its displacement.
    Contains the open and the closed solid model."""
    d = closing_displacements(kind, gripper)
    out = []
    for b, body in _moving_boxes(gripper):
        dy = d[body]
        c = np.asarray(b.center, dtype=float) + (0.0, 0.5 * dy, 0.0)
        h = np.asarray(b.half_extents, dtype=float) + (0.0, 0.5 * abs(dy), 0.0)
        out.append(Box(b.name + "_swept", tuple(float(v) for v in c),
                       tuple(float(v) for v in h)))
    return out


def moving_swept_boxes_G(kind: str, gripper: HookGripperGeometry = HOOK_GRIPPER) -> list[Box]:
    """The boxes of :func:`swept_boxes_G` of the bodies that move while closing (the straight
    finger stays for vertical grasps, the hand for parallel ones): what the closing motion can
    run into. Static bodies are the open model's, which N_c checks."""
    d = closing_displacements(kind, gripper)
    return [s for s, (_, body) in zip(swept_boxes_G(kind, gripper), _moving_boxes(gripper),
                                      strict=True) if d[body] != 0.0]


#: m: how far back along -z_G the open gripper comes from (``PickConfig.approach_distance``):
#: the wedge's nose sweeps that column on its way down.
NOSE_DESCENT = 0.10


def nose_descent_boxes_G(gripper: HookGripperGeometry = HOOK_GRIPPER,
                         descent: float = NOSE_DESCENT) -> list[Box]:
    """The column the wedge bar's nose sweeps as the open gripper comes down ``descent`` (m)
    along +z_G to the grasp pose, in G (empty for the paper's square bar). A hook grasp's bar
    goes down through the hole beside the material that will be caged; the nose, 8 mm past the
    bar's tip, narrows that way by as much, so what the paper's bar passes the nose may push
    (counted in N_sweep with the closing motion: none is allowed, as on the loop's path; N_c's
    allowance of ``p_c`` points is the paper's, for its gripper)."""
    if gripper.bar_nose <= 0.0:
        return []
    nose = next(b for b in gripper.l_finger_boxes() if b.name == "bar_nose")
    top = nose.center[2] - nose.half_extents[2] - descent
    bottom = nose.center[2] + nose.half_extents[2]
    return [Box("bar_nose_descent", (nose.center[0], nose.center[1] - gripper.q_open,
                                     0.5 * (top + bottom)),
                (nose.half_extents[0], nose.half_extents[1], 0.5 * (bottom - top)))]


def closed_loop_interior_G(kind: str, gripper: HookGripperGeometry = HOOK_GRIPPER) -> Box:
    """The hole of the closed loop, in the frame G of the grasp pose: between the palm (z = 0)
    and the bar's inner face (z = l_f - rod_width/2), between the two rods' inner faces (y), as
    thick as the rods (x). Material that crosses this box when the gripper is closed is caged."""
    r = 0.5 * gripper.rod_width
    _, d_straight, d_l = closing_displacements(kind, gripper)
    y_straight = gripper.q_open + d_straight
    y_l = -gripper.q_open + d_l
    lo, hi = y_l + r, y_straight - r
    z_top = gripper.finger_length - r
    return Box("loop_interior", (0.0, 0.5 * (lo + hi), 0.5 * z_top),
               (r, 0.5 * (hi - lo), 0.5 * z_top))


# ---- counting -------------------------------------------------------------------------------------
def _box_union_masks(x: np.ndarray, y: np.ndarray, z: np.ndarray, box_sets: list[list[Box]],
                     margins: list[float]) -> list[np.ndarray]:
    """For each list of boxes, the mask of the points (G coordinates ``x, y, z``, arrays of one
    shape) inside their union, boxes grown by that list's margin. Interval tests shared by
    several boxes are computed once."""
    cache: dict[tuple[int, float, float], np.ndarray] = {}
    coords = (x, y, z)

    def interval(axis: int, c: float, h: float) -> np.ndarray:
        key = (axis, c, h)
        if key not in cache:
            cache[key] = np.abs(coords[axis] - c) <= h  # Python floats keep float32 float32
        return cache[key]

    out = []
    for boxes, margin in zip(box_sets, margins, strict=True):
        inside = np.zeros(np.shape(x), dtype=bool)
        for b in boxes:
            cx, cy, cz = (float(v) for v in b.center)
            hx, hy, hz = (float(v) + margin for v in b.half_extents)
            inside |= interval(2, cz, hz) & interval(0, cx, hx) & interval(1, cy, hy)
        out.append(inside)
    return out


def chunked_box_masks(points_W: np.ndarray, X_WG: np.ndarray, box_sets: list[list[Box]],
                   margins: list[float]):
    """Yields (slice of the poses, [mask (chunk, N) per box set]) over chunks of ``X_WG``."""
    # float32 halves the memory traffic; its ~1e-7 relative error is far below any tolerance.
    X = np.asarray(X_WG, dtype=np.float32).reshape(-1, 4, 4)
    p = np.asarray(points_W, dtype=np.float32).reshape(-1, 3)
    step = max(1, _CHUNK_POINTS // max(len(p), 1))
    for k in range(0, len(X), step):
        x, y, z = frame_coordinates(X[k : k + step], p)
        yield slice(k, k + step), _box_union_masks(x, y, z, box_sets, margins)


def count_points_in_boxes(points_W: np.ndarray, X_WG: np.ndarray, box_sets: list[list[Box]],
                          margin: float = 0.0) -> np.ndarray:
    """(S, M) int: for each of the S lists of boxes (in G), how many of ``points_W`` (N, 3,
    metres in W) lie inside their union (boxes grown by ``margin``) at each pose ``X_WG``
    (M, 4, 4)."""
    M = len(np.reshape(X_WG, (-1, 4, 4)))
    counts = np.zeros((len(box_sets), M), dtype=int)
    if len(np.reshape(points_W, (-1, 3))):
        for sl, masks in chunked_box_masks(points_W, X_WG, box_sets, [margin] * len(box_sets)):
            for s, mask in enumerate(masks):
                counts[s, sl] = mask.sum(axis=1)
    return counts


def count_points_in_gripper(
    points_W: np.ndarray,
    X_WG: np.ndarray,
    q: float | None = None,
    margin: float = 0.0,
    gripper: HookGripperGeometry = HOOK_GRIPPER,
) -> np.ndarray:
    """N_c (M,) int: how many of ``points_W`` (N, 3, metres in W) lie inside the gripper's solid
    model (boxes grown by ``margin`` metres) at each pose ``X_WG`` (M, 4, 4) with finger position
    ``q`` (metres; default fully open)."""
    return count_points_in_boxes(points_W, X_WG, [gripper.solid_boxes_G(q)], margin)[0]


def count_open_and_sweep(points_W: np.ndarray, X_WG: np.ndarray, kind: str, margin: float = 0.0,
                         gripper: HookGripperGeometry = HOOK_GRIPPER, sweep_margin: float = 0.0
                         ) -> tuple[np.ndarray, np.ndarray]:
    """(N_c, N_sweep), each (M,) int, for grasps of one ``kind`` at poses ``X_WG`` (M, 4, 4).

    N_c (paper): the points inside the open solid model, boxes grown by ``margin``.
    N_sweep: the points that the moving parts reach while closing (:func:`moving_swept_boxes_G`,
    the closed pose included, and a wedge bar's nose on its way down,
    :func:`nose_descent_boxes_G`; grown by ``margin + sweep_margin``) and that are not already
    counted in N_c. ``sweep_margin`` (m) makes up for the sampling: a surface can cut into a
    box between two samples, up to about half their spacing deep, unseen by the count."""
    open_boxes = closing_boxes_G(kind, gripper.q_open, gripper)
    moving = moving_swept_boxes_G(kind, gripper) + nose_descent_boxes_G(gripper)
    n_open = np.zeros(len(np.reshape(X_WG, (-1, 4, 4))), dtype=int)
    n_sweep = np.zeros_like(n_open)
    if len(np.reshape(points_W, (-1, 3))):
        for sl, (inside_open, swept) in chunked_box_masks(points_W, X_WG, [open_boxes, moving],
                                                       [margin, margin + sweep_margin]):
            n_open[sl] = inside_open.sum(axis=1)
            n_sweep[sl] = (swept & ~inside_open).sum(axis=1)
    return n_open, n_sweep


# ---- the rods' clearance ---------------------------------------------------------------------
#: Every surface point lies within this many sample spacings of a sample (the Poisson-disk
#: sampling's covering radius, measured at most 1.6 on the generated objects: a mug, a pot, a
#: wire hanger, a key ring, 300k dense surface points each).
COVERING_SPACINGS = 2.0


def rod_boxes_G(kind: str, gripper: HookGripperGeometry = HOOK_GRIPPER) -> list[Box]:
    """The rods and the bar (not the hand) of a grasp of ``kind``, in the frame G of the grasp
    pose: the open model's, and the volumes the moving ones sweep while closing (the closed
    pose included)."""
    open_boxes = [b for b in closing_boxes_G(kind, gripper.q_open, gripper) if b.name != "hand"]
    swept = [b for b in moving_swept_boxes_G(kind, gripper) if b.name != "hand_swept"]
    return open_boxes + swept


@dataclass
class SurfaceTriangles:
    """An object's triangles (W) for the exact tests of :func:`count_rod_contacts`: their
    vertices (T, 3, 3), a k-d tree of the centroids of the small ones (circumradius at most
    ``small``, m) and the indices of the others (always tested)."""

    vertices: np.ndarray
    tree: object
    small_index: np.ndarray
    large_index: np.ndarray
    small: float
    lo: np.ndarray
    """(T, 3) the triangles' bounding boxes' lower corners (W)."""
    hi: np.ndarray
    """(T, 3) and their upper corners."""

    @classmethod
    def of(cls, vertices: np.ndarray, faces: np.ndarray, small: float) -> SurfaceTriangles:
        tri = np.asarray(vertices, dtype=float)[np.asarray(faces, dtype=int)]
        centroid = tri.mean(axis=1)
        radius = np.linalg.norm(tri - centroid[:, None], axis=2).max(axis=1)
        is_small = radius <= small
        return cls(tri, spatial.cKDTree(centroid[is_small]), np.flatnonzero(is_small),
                   np.flatnonzero(~is_small), small, tri.min(axis=1), tri.max(axis=1))

    def near(self, points: np.ndarray, radius: float, lo: np.ndarray, hi: np.ndarray
             ) -> np.ndarray:
        """Indices of the triangles that may come within ``radius`` of any of ``points`` (k, 3)
        and whose bounding box meets the box [``lo``, ``hi``] (W): small ones whose centroid
        does, and the large ones."""
        hits = self.tree.query_ball_point(np.asarray(points, dtype=float), radius + self.small)
        small = np.unique(np.concatenate([np.asarray(h, dtype=int) for h in hits])) \
            if len(hits) else np.zeros(0, dtype=int)
        idx = np.concatenate([self.small_index[small], self.large_index])
        meets = (self.lo[idx] <= hi).all(axis=1) & (self.hi[idx] >= lo).all(axis=1)
        return idx[meets]


def triangles_overlap_boxes(tri: np.ndarray, boxes: list[Box]) -> np.ndarray:
    """(T, B) bool: whether each triangle ``tri`` (T, 3, 3) meets each box (axis-aligned in the
    triangles' frame), exactly: the separating-axis test (the boxes' three axes, the triangle's
    normal and the nine cross products of their edges; Akenine-Moller 2001)."""
    tri = np.asarray(tri, dtype=float).reshape(-1, 3, 3)
    c = np.array([b.center for b in boxes], dtype=float)  # (B, 3)
    h = np.array([b.half_extents for b in boxes], dtype=float)  # (B, 3)
    v = tri[:, None] - c[None, :, None]  # (T, B, 3 vertices, 3)
    ok = np.ones(v.shape[:2], dtype=bool)
    # The boxes' axes: the triangle's extent against the box's.
    ok &= (v.min(axis=2) <= h).all(axis=2) & (v.max(axis=2) >= -h).all(axis=2)
    e = np.roll(tri, -1, axis=1) - tri  # (T, 3 edges, 3)
    axes = [np.cross(e[:, 0], e[:, 1])]  # the triangle's normal
    axes += [np.cross(np.eye(3)[i], e[:, j]) for i in range(3) for j in range(3)]
    for a in axes:  # (T, 3)
        proj = np.einsum("tbkd,td->tbk", v, a)  # (T, B, 3)
        r = np.abs(a) @ h.T  # (T, B)
        ok &= (proj.min(axis=2) <= r) & (proj.max(axis=2) >= -r)
    return ok


def count_rod_contacts(points_W: np.ndarray, spacing: float, triangles: SurfaceTriangles,
                       X_WG: np.ndarray, kind: str, clearance: float,
                       gripper: HookGripperGeometry = HOOK_GRIPPER) -> np.ndarray:
    """(M,) int, 0 when the object's surface stays at least ``clearance`` (m, per axis: the
    boxes grown by it) from the rods and the bar (:func:`rod_boxes_G`) of each grasp at
    ``X_WG`` (M, 4, 4); else how many witnesses say it does not. ``points_W`` (N, 3) are the
    surface's samples (every surface point within :data:`COVERING_SPACINGS` ``spacing`` of
    one) and ``triangles`` the surface itself.

    Exact and density-proof, in two steps: samples inside the grown boxes are witnesses; where
    there are none but some sample lies within the covering radius of the grown boxes, the
    triangles near those samples are tested against the grown boxes exactly
    (:func:`triangles_overlap_boxes`), each one that meets them a witness. (Material in a grown
    box lies within the covering radius of a sample, which then lies that near the box.) A
    grasp with no sample that near is clear. So a wire thinner than the samples' spacing is
    not missed."""
    X = np.asarray(X_WG, dtype=float).reshape(-1, 4, 4)
    out = np.zeros(len(X), dtype=int)
    p = np.asarray(points_W, dtype=float).reshape(-1, 3)
    if len(X) == 0 or len(p) == 0:
        return out
    boxes = rod_boxes_G(kind, gripper)
    reach = COVERING_SPACINGS * spacing
    grown = [Box(b.name, b.center, tuple(x + clearance for x in b.half_extents)) for b in boxes]
    corners_G = box_corners(grown)
    for sl, (inside, near) in chunked_box_masks(p, X, [boxes, boxes],
                                                [clearance, clearance + reach]):
        out[sl] = inside.sum(axis=1)
        for r in np.flatnonzero((out[sl] == 0) & near.any(axis=1)):
            m = sl.start + r
            corners = corners_G @ X[m, :3, :3].T + X[m, :3, 3]
            idx = triangles.near(p[near[r]], reach, corners.min(axis=0), corners.max(axis=0))
            if len(idx) == 0:
                continue
            tri_G = (triangles.vertices[idx] - X[m, :3, 3]) @ X[m, :3, :3]
            out[m] = int(triangles_overlap_boxes(tri_G, grown).any(axis=1).sum())
    return out


# ---- unknown space ---------------------------------------------------------------------------
def box_grid(boxes: list[Box], spacing: float, margin: float = 0.0) -> np.ndarray:
    """(n, 3) points filling each box (grown by ``margin``) on a grid of at most ``spacing``
    (m) per axis, its faces included (a box thinner than ``spacing`` still gets two layers)."""
    parts = []
    for b in boxes:
        c = np.asarray(b.center, dtype=float)
        h = np.asarray(b.half_extents, dtype=float) + margin
        axes = [np.linspace(c[k] - h[k], c[k] + h[k], max(2, int(np.ceil(2 * h[k] / spacing)) + 1))
                for k in range(3)]
        parts.append(np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3))
    return np.concatenate(parts) if parts else np.zeros((0, 3))


def sweep_grid_G(kind: str, spacing: float, margin: float = 0.0, sweep_margin: float = 0.0,
                 gripper: HookGripperGeometry = HOOK_GRIPPER) -> np.ndarray:
    """(n, 3) grid points (G, m) of the volume the moving parts sweep while closing
    (:func:`moving_swept_boxes_G` grown by ``margin + sweep_margin``) outside the open solid
    model (grown by ``margin``): where N_sweep counts object points."""
    grid = box_grid(moving_swept_boxes_G(kind, gripper), spacing, margin + sweep_margin)
    x, y, z = (grid[:, k] for k in range(3))
    inside_open, = _box_union_masks(x, y, z, [closing_boxes_G(kind, gripper.q_open, gripper)],
                                    [margin])
    return grid[~inside_open]


def count_unknown_in_sweep(free: FreeSpace, X_WG: np.ndarray, grid_G: np.ndarray,
                           ground_normal: np.ndarray, ground_height: float,
                           surface_distance=None, surface_band: float = 0.0) -> np.ndarray:
    """(M,) int: for each pose X_WG (M, 4, 4), how many of the points ``grid_G`` (n, 3, in G)
    lie in space not known free (``free.known_free``: no camera saw it free, nor did a
    completion call it free with confidence), more than ``free.margin`` above the supporting
    plane (``ground_normal . p = ground_height``, W: the
    table's own noise band is not free) and, when ``surface_distance`` (a function of (k, 3)
    points in W giving their distance to the scanned surface, m) is given, farther than
    ``surface_band`` from the scanned surface."""
    X = np.asarray(X_WG, dtype=float).reshape(-1, 4, 4)
    counts = np.zeros(len(X), dtype=int)
    if len(X) == 0 or len(grid_G) == 0:
        return counts
    n = np.asarray(ground_normal, dtype=float)
    n = n / np.linalg.norm(n)
    p = (np.einsum("mij,nj->mni", X[:, :3, :3], grid_G) + X[:, None, :3, 3]).reshape(-1, 3)
    pose = np.repeat(np.arange(len(X)), len(grid_G))
    keep = p @ n > ground_height + free.margin
    p, pose = p[keep], pose[keep]
    unknown = ~free.known_free(p)
    p, pose = p[unknown], pose[unknown]
    if surface_distance is not None and len(p):
        far = surface_distance(p) > surface_band
        pose = pose[far]
    return np.bincount(pose, minlength=len(X))


# ---- the supporting surface -----------------------------------------------------------------
def box_corners(boxes: list[Box]) -> np.ndarray:
    """(8 B, 3) corners of the boxes, in their frame (metres)."""
    signs = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)])
    return np.concatenate([np.asarray(b.center) + signs * np.asarray(b.half_extents)
                           for b in boxes])


def solid_model_corners_G(q: float | None = None,
                          gripper: HookGripperGeometry = HOOK_GRIPPER) -> np.ndarray:
    """(8 B, 3) corners of the solid model's B boxes in G (metres) at finger position ``q``."""
    return box_corners(gripper.solid_boxes_G(q))


def ground_distance(X_WG: np.ndarray, kinds: list[str] | str, ground_normal: np.ndarray,
                    ground_height: float, gripper: HookGripperGeometry = HOOK_GRIPPER
                    ) -> np.ndarray:
    """(M,) metres: height above the plane ``ground_normal . p = ground_height`` (W) of the
    lowest point of the solid model over the grasp pose (open), the closing sweep and the closed
    pose, for grasps of ``kinds`` (one per pose, or one for all) at poses X_WG (M, 4, 4).
    Negative: the gripper goes that deep below the plane. (The swept boxes are convex and
    contain every intermediate pose, so their lowest corner is the lowest point.)"""
    X = np.asarray(X_WG, dtype=float).reshape(-1, 4, 4)
    kinds = [kinds] * len(X) if isinstance(kinds, str) else list(kinds)
    n = np.asarray(ground_normal, dtype=float)
    n = n / np.linalg.norm(n)
    out = np.zeros(len(X))
    for kind in set(kinds):
        sel = np.array([k == kind for k in kinds])
        corners = box_corners(swept_boxes_G(kind, gripper))
        # Height of each corner along n: n . (R p + t) = (R^T n) . p + n . t
        heights = (np.einsum("mij,i,cj->mc", X[sel, :3, :3], n, corners)
                   + (X[sel, :3, 3] @ n)[:, None])
        out[sel] = heights.min(axis=1) - ground_height
    return out
