"""Shape completion of a partial scan by rotational symmetry, with a confidence per point.

One view sees the front of an object; the GbH core then lacks its far side (a cup's far wall,
a pot's body behind its handle), and space no camera saw is unknown. Most containers are
near-rotational bodies with parts that break the symmetry (a handle, a spout, a bail). This
module completes the body and leaves those parts as they were seen:

1. **The axis** (:func:`fit_rotation_axis`): on a surface of revolution every normal line meets
   the axis, so the normal lines (p_i, n_i) of the scanned surface lie in a linear line complex
   of pitch 0 (Pottmann and Randrup, 1998): the axis (direction a, moment a_bar) minimises
   sum (a_bar . n_i + a . (p_i x n_i))^2 with |a| = 1, an eigenvalue problem. Points that do not
   belong to the body (the handle) are down-weighted (iteratively reweighted, Cauchy weights).
   The direction fixed to the table's normal (an upright body) is a second candidate; the one
   that explains more of what was seen (below) is kept, and none when it explains less than
   ``CompletionParams.min_explained`` (a box, a bag: nothing is completed).
2. **Votes** (:func:`symmetry_votes`): each cell of a grid over the scan's region that a camera
   saw is a vote for its ring about the axis, a bin of (r, h) (distance from the axis, height
   along it): *occupied* when a measured point lies in it, *free* when some view saw through
   it. If the object is a body of revolution, a ring is all occupied or all free; a handle is
   a minority of occupied votes among free ones.
3. **The posterior** per ring: P(occupied) = (n_occ + prior) / (n_occ + n_free + 2 prior) (a
   Beta posterior with ``prior`` pseudo-counts on each side). An unseen point is *likely
   occupied* when its ring's P(occupied) >= ``confidence``, *likely free* when P(free) >=
   ``confidence``, otherwise uncertain; a ring without votes stays at 0.5 (uncertain).
4. **The completed surface** (:attr:`SymmetryCompletion.mesh`): the contour P(occupied) =
   ``confidence`` in the (r, h) half-plane, revolved about the axis, its triangles kept only
   where no camera saw (not seen free, farther than a bin from a measured point): the far side
   of the body, to be added to the scan. A part seen once (the handle) is in the scan as seen
   and is not copied round the axis (its rings are mostly free).

Pure numpy, scipy and contourpy (matplotlib's contouring); no Drake. All in W, metres.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from gbh_drake.core.free_space import FreeSpace
from gbh_drake.core.geometry import orthonormal_basis, unit
from gbh_drake.core.lazy import lazy_module
from gbh_drake.core.params import CompletionParams

ndimage = lazy_module("scipy.ndimage")
spatial = lazy_module("scipy.spatial")
trimesh = lazy_module("trimesh")

#: At most this many grid cells vote: a larger region is sampled more coarsely.
MAX_VOTE_CELLS = 800_000
#: Iterations of the reweighted axis fit.
_AXIS_ITERATIONS = 8


@dataclass(frozen=True)
class RotationAxis:
    """A line in W: ``point`` (3,) on it, unit ``direction`` (3,); ``rms`` (m): the weighted
    root-mean-square distance-times-sine of the normal lines from it (0: a perfect surface of
    revolution)."""

    point: np.ndarray
    direction: np.ndarray
    rms: float = 0.0

    def coordinates(self, points_W: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(r, h), each (n,): distance (m) of ``points_W`` (n, 3) from the axis and height (m)
        along it from :attr:`point`."""
        d = np.asarray(points_W, dtype=float).reshape(-1, 3) - self.point
        h = d @ self.direction
        r = np.linalg.norm(d - h[:, None] * self.direction, axis=1)
        return r, h


def _line_complex_terms(points: np.ndarray, normals: np.ndarray) -> np.ndarray:
    """(n, 6) Pluecker coordinates (n, p x n) of the normal lines, points centred."""
    return np.concatenate([normals, np.cross(points, normals)], axis=1)


def _solve_axis(lines: np.ndarray, weights: np.ndarray, direction: np.ndarray | None
                ) -> tuple[np.ndarray, np.ndarray]:
    """(direction a, moment a_bar) minimising sum w (a_bar . n + a . (p x n))^2, |a| = 1
    (``direction`` given: only a_bar)."""
    M = (lines * weights[:, None]).T @ lines
    A, B, E = M[:3, :3], M[:3, 3:], M[3:, 3:]
    A_inv = np.linalg.pinv(A + 1e-12 * np.trace(A) * np.eye(3))
    if direction is None:
        S = E - B.T @ A_inv @ B
        _, vectors = np.linalg.eigh(0.5 * (S + S.T))
        a = vectors[:, 0]
    else:
        a = unit(np.asarray(direction, dtype=float))
    a_bar = -A_inv @ B @ a
    return a, a_bar - (a @ a_bar) * a  # pitch 0: a line


def fit_rotation_axis(points_W: np.ndarray, normals_W: np.ndarray,
                      direction: np.ndarray | None = None) -> RotationAxis:
    """The axis of revolution of the surface sampled at ``points_W`` (n, 3) with unit outward
    normals ``normals_W`` (n, 3) (module docstring, 1.): reweighted least squares on the line
    complex of the normal lines, Cauchy weights at 1.5 x the median residual. ``direction``
    (3,): the axis's direction is fixed (only its position is fitted). At least 6 points."""
    p = np.asarray(points_W, dtype=float).reshape(-1, 3)
    n = unit(np.asarray(normals_W, dtype=float).reshape(-1, 3))
    if len(p) < 6:
        raise ValueError(f"fit_rotation_axis: {len(p)} points, at least 6 needed")
    centre = p.mean(axis=0)
    lines = _line_complex_terms(p - centre, n)
    weights = np.ones(len(p))
    for _ in range(_AXIS_ITERATIONS):
        a, a_bar = _solve_axis(lines, weights, direction)
        residual = lines[:, :3] @ a_bar + lines[:, 3:] @ a
        scale = 1.5 * max(float(np.median(np.abs(residual))), 1e-6)
        weights = 1.0 / (1.0 + (residual / scale) ** 2)
    rms = float(np.sqrt(np.sum(weights * residual ** 2) / np.sum(weights)))
    return RotationAxis(centre + np.cross(a, a_bar), unit(a), rms)


@dataclass(frozen=True, eq=False)
class SymmetryVotes:
    """Votes of the seen grid cells per ring (r, h) about an axis (module docstring, 2.)."""

    axis: RotationAxis
    bin: float
    """m: the rings' width in r and in h."""
    h0: float
    """m: the height (along the axis, from ``axis.point``) of the lower edge of ring row 0."""
    occupied: np.ndarray
    """(R, H) cells with a measured point, per ring (r index, h index)."""
    free: np.ndarray
    """(R, H) cells some view saw through (and with no measured point), per ring."""

    @property
    def explained(self) -> float:
        """The fraction of the occupied votes that lie in rings where they are the majority:
        how much of what was seen the body of revolution explains (1: all of it; a handle's
        cells, a minority in their rings, are not explained; on a box or a bag most are not)."""
        total = self.occupied.sum()
        if total == 0:
            return 0.0
        return float(self.occupied[self.occupied >= self.free].sum() / total)

    def ring_index(self, points_W: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(i_r, i_h, inside), each (n,): the ring of each point and whether it is one of the
        voted rings."""
        r, h = self.axis.coordinates(points_W)
        i_r = np.floor(r / self.bin).astype(np.int64)
        i_h = np.floor((h - self.h0) / self.bin).astype(np.int64)
        inside = (i_r < self.occupied.shape[0]) & (i_h >= 0) & (i_h < self.occupied.shape[1])
        return np.where(inside, i_r, 0), np.where(inside, i_h, 0), inside


@dataclass(frozen=True, eq=False)
class SeenCells:
    """A grid over a box and what the cameras saw of each cell (module docstring, 2.)."""

    centres: np.ndarray
    """(n, 3) float32 cell centres (m, W)."""
    cell: float
    """m: the cells' edge."""
    occupied: np.ndarray
    """(n,) bool: a measured point lies in the cell."""
    free: np.ndarray
    """(n,) bool: some view saw the cell's centre free, and it is no neighbour of an occupied
    cell (a view that sees a surface obliquely sees the cells in front of it free within a cell
    of it, in the surface's own ring)."""


def seen_cells(measured_W: np.ndarray, observed_free: Callable[[np.ndarray], np.ndarray],
               lower_W, upper_W, cell: float, max_cells: int = MAX_VOTE_CELLS) -> SeenCells:
    """The cells of a grid of ``cell`` (m; coarser when the box [``lower_W``, ``upper_W``] (m,
    W) would need more than ``max_cells``) and what was seen of them: ``measured_W`` (n, 3)
    the measured points, ``observed_free`` ((k, 3) -> (k,) bool) what the views saw free."""
    lower = np.asarray(lower_W, dtype=float).reshape(3)
    upper = np.asarray(upper_W, dtype=float).reshape(3)
    size = np.maximum(upper - lower, 0.0)
    cell = max(float(cell), float(np.cbrt(np.prod(size) / max_cells)))
    shape = tuple(int(k) for k in np.maximum(np.ceil(size / cell).astype(int), 1))
    axes = [(lower[i] + cell * (np.arange(shape[i]) + 0.5)).astype(np.float32) for i in range(3)]
    centres = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, 3)
    occupied = np.zeros(shape, dtype=bool)
    index = np.floor((np.asarray(measured_W, dtype=float).reshape(-1, 3) - lower) / cell
                     ).astype(np.int64)
    index = index[np.all((index >= 0) & (index < shape), axis=1)]
    occupied[tuple(index.T)] = True
    near = ndimage.binary_dilation(occupied, np.ones((3, 3, 3), bool)).reshape(-1)
    free = np.zeros(len(centres), dtype=bool)
    free[~near] = np.asarray(observed_free(centres[~near]), dtype=bool)
    return SeenCells(centres, cell, occupied.reshape(-1), free)


def symmetry_votes(axis: RotationAxis, cells: SeenCells) -> SymmetryVotes:
    """The votes of the seen ``cells`` per ring (r, h) about ``axis``, rings one cell wide
    (module docstring, 2.)."""
    d = cells.centres - axis.point.astype(np.float32)
    a = axis.direction.astype(np.float32)
    h = d[:, 0] * a[0] + d[:, 1] * a[1] + d[:, 2] * a[2]
    r = np.sqrt(np.maximum(np.einsum("ij,ij->i", d, d) - h * h, 0.0))
    cell = cells.cell
    h0 = float(h.min()) - 0.5 * cell  # cell centres mid-ring along an axis of the grid
    n_r = int(np.floor(r.max() / cell)) + 1
    n_h = int(np.floor((h.max() - h0) / cell)) + 1
    ring = np.floor(r / cell).astype(np.int64) * n_h + np.minimum(
        np.floor((h - h0) / cell).astype(np.int64), n_h - 1)
    votes_occ = np.bincount(ring[cells.occupied], minlength=n_r * n_h).reshape(n_r, n_h)
    votes_free = np.bincount(ring[cells.free], minlength=n_r * n_h).reshape(n_r, n_h)
    return SymmetryVotes(axis, cell, h0, votes_occ.astype(float), votes_free.astype(float))


@dataclass(frozen=True, eq=False)
class SymmetryCompletion:
    """A scan completed by rotational symmetry (module docstring): per point, how likely it is
    occupied, and the completed surface where no camera saw."""

    votes: SymmetryVotes
    prior: float
    """Beta pseudo-counts added to each side of a ring's votes."""
    confidence: float
    """A point is likely occupied (free) when its ring's P(occupied) (P(free)) is at least this."""
    mesh: trimesh.Trimesh
    """The completed unseen surface (W, m): the contour P(occupied) = confidence revolved,
    where no camera saw; may be empty."""

    @property
    def axis(self) -> RotationAxis:
        return self.votes.axis

    def __deepcopy__(self, memo) -> SymmetryCompletion:
        """Shared, not copied: never modified (Drake copies abstract port values)."""
        return self

    def p_occupied_rings(self) -> np.ndarray:
        """(R, H) P(occupied) of every ring."""
        v = self.votes
        return (v.occupied + self.prior) / (v.occupied + v.free + 2.0 * self.prior)

    def p_occupied(self, points_W: np.ndarray) -> np.ndarray:
        """(n,) P(occupied) of the points (n, 3) by their ring; 0.5 outside the voted rings."""
        i_r, i_h, inside = self.votes.ring_index(points_W)
        return np.where(inside, self.p_occupied_rings()[i_r, i_h], 0.5)

    def likely_free(self, points_W: np.ndarray) -> np.ndarray:
        """(n,) bool: P(free) >= :attr:`confidence`."""
        return 1.0 - self.p_occupied(points_W) >= self.confidence

    def likely_occupied(self, points_W: np.ndarray) -> np.ndarray:
        """(n,) bool: P(occupied) >= :attr:`confidence`."""
        return self.p_occupied(points_W) >= self.confidence

    def on_surface(self, points_W: np.ndarray, tolerance: float = 1e-5) -> np.ndarray:
        """(n,) bool: the points (n, 3) lie on the completed surface (within ``tolerance`` m
        of :attr:`mesh`): samples of material no camera saw."""
        from gbh_drake.core.o3d import open3d
        o3d = open3d()  # lazy: see gbh_drake.core.o3d

        p = np.asarray(points_W, dtype=np.float32).reshape(-1, 3)
        if len(self.mesh.faces) == 0 or len(p) == 0:
            return np.zeros(len(p), dtype=bool)
        scene = o3d.t.geometry.RaycastingScene()
        scene.add_triangles(o3d.core.Tensor(np.asarray(self.mesh.vertices, np.float32)),
                            o3d.core.Tensor(np.asarray(self.mesh.faces, np.uint32)))
        return scene.compute_distance(o3d.core.Tensor(p)).numpy() <= tolerance


def revolved_contour(votes: SymmetryVotes, p_rings: np.ndarray, level: float,
                     max_step: float) -> trimesh.Trimesh:
    """The contour ``p_rings`` = ``level`` of a (R, H) field on the rings of ``votes``, revolved
    about their axis in steps of at most ``max_step`` (m) at its largest radius; triangles wound
    so that their normals point to where the field is below ``level`` (out of the occupied)."""
    import contourpy

    n_r, n_h = p_rings.shape
    r = (np.arange(n_r) + 0.5) * votes.bin
    h = votes.h0 + (np.arange(n_h) + 0.5) * votes.bin
    z = np.pad(p_rings, 1, constant_values=0.0)  # closes contours at the grid's edges
    r_pad = np.concatenate([[r[0] - votes.bin], r, [r[-1] + votes.bin]])
    h_pad = np.concatenate([[h[0] - votes.bin], h, [h[-1] + votes.bin]])
    lines = contourpy.contour_generator(h_pad, r_pad, z, line_type="Separate").lines(level)
    segments = [np.stack([line[:-1], line[1:]], axis=1) for line in lines if len(line) > 1]
    if not segments:
        return trimesh.Trimesh()
    seg = np.concatenate(segments)  # (S, 2, 2): (h, r) of both ends
    seg = seg[:, :, ::-1]  # (r, h)
    seg[:, :, 0] = np.maximum(seg[:, :, 0], 0.0)
    r_max = float(seg[:, :, 0].max())
    n_az = max(12, int(np.ceil(2.0 * np.pi * r_max / max_step)))
    phi = 2.0 * np.pi * np.arange(n_az + 1) / n_az
    a = votes.axis.direction
    e1, e2 = orthonormal_basis(a[None])
    e1, e2 = e1[0], e2[0]
    radial = np.cos(phi)[:, None] * e1 + np.sin(phi)[:, None] * e2  # (n_az + 1, 3)

    def point(rh, k):  # rh (S, 2), k (n_az,) -> (S, n_az, 3)
        return (votes.axis.point + rh[:, None, 1:2] * a
                + rh[:, None, 0:1] * radial[None, k])

    k0, k1 = np.arange(n_az), np.arange(1, n_az + 1)
    p00, p01 = point(seg[:, 0], k0), point(seg[:, 0], k1)
    p10, p11 = point(seg[:, 1], k0), point(seg[:, 1], k1)
    # The segment's outward side in (r, h): where the field falls below the level.
    mid = seg.mean(axis=1)
    d = seg[:, 1] - seg[:, 0]
    n2 = np.stack([d[:, 1], -d[:, 0]], axis=1)  # perpendicular to the segment in (r, h)
    n2 /= np.maximum(np.linalg.norm(n2, axis=1, keepdims=True), 1e-12)
    probe = 0.5 * votes.bin
    outward = _field_at(votes, p_rings, mid + probe * n2) < _field_at(votes, p_rings,
                                                                       mid - probe * n2)
    tri_a = np.stack([p00, p10, p11], axis=2).reshape(-1, 3, 3)
    tri_b = np.stack([p00, p11, p01], axis=2).reshape(-1, 3, 3)
    triangles = np.concatenate([tri_a, tri_b])
    # Orient: the revolved (r, h) normal n2 maps to n2_r radial + n2_h axial.
    normal_dir = (n2[:, None, 0:1] * 0.5 * (radial[None, k0] + radial[None, k1])
                  + n2[:, None, 1:2] * a)  # (S, n_az, 3)
    want = np.where(outward[:, None, None], normal_dir, -normal_dir).reshape(-1, 3)
    want = np.concatenate([want, want])
    face_n = np.cross(triangles[:, 1] - triangles[:, 0], triangles[:, 2] - triangles[:, 0])
    flip = np.einsum("ij,ij->i", face_n, want) < 0
    triangles[flip] = triangles[flip][:, ::-1]
    area = 0.5 * np.linalg.norm(face_n, axis=1)
    triangles = triangles[area > 1e-12]
    vertices = triangles.reshape(-1, 3)
    faces = np.arange(len(vertices)).reshape(-1, 3)
    mesh = trimesh.Trimesh(vertices, faces, process=False)
    mesh.merge_vertices()
    return mesh


def _field_at(votes: SymmetryVotes, field: np.ndarray, rh: np.ndarray) -> np.ndarray:
    """(n,) the ring field at (r, h) points (n, 2) (nearest ring; 0 outside)."""
    i_r = np.floor(rh[:, 0] / votes.bin).astype(np.int64)
    i_h = np.floor((rh[:, 1] - votes.h0) / votes.bin).astype(np.int64)
    inside = (i_r >= 0) & (i_r < field.shape[0]) & (i_h >= 0) & (i_h < field.shape[1])
    out = np.zeros(len(rh))
    out[inside] = field[i_r[inside], i_h[inside]]
    return out


def complete_by_symmetry(surface_W: np.ndarray, normals_W: np.ndarray, measured_W: np.ndarray,
                         free: FreeSpace, lower_W, upper_W,
                         params: CompletionParams | None = None, *, up_W=(0.0, 0.0, 1.0),
                         floor: float = -np.inf, max_axis_points: int = 4000, seed: int = 0
                         ) -> SymmetryCompletion | None:
    """A scan completed by rotational symmetry (module docstring), or None when the body of
    revolution explains less than ``params.min_explained`` of what was seen (a box, a bag).

    ``surface_W`` (n, 3) with unit outward ``normals_W`` (n, 3): points of the scanned surface
    (a scan's vertices) that fit the axis, those at most ``floor`` m high along ``up_W`` (the
    cut and cap at the table) left out; ``measured_W`` (k, 3): the measured points; ``free``:
    what the cameras saw free; the votes are taken on a grid of ``params.cell`` (m) over
    [``lower_W``, ``upper_W``] above ``floor``. Two axes are tried, the fitted one and one along
    ``up_W``; the one that explains more is kept. ``seed``: which surface points fit the axis
    when there are more than ``max_axis_points``."""
    params = params or CompletionParams()
    up = unit(np.asarray(up_W, dtype=float))
    points = np.asarray(surface_W, dtype=float).reshape(-1, 3)
    normals = np.asarray(normals_W, dtype=float).reshape(-1, 3)
    keep = points @ up > floor
    p, n = points[keep], normals[keep]
    if len(p) < 6:
        return None
    if len(p) > max_axis_points:
        pick = np.sort(np.random.default_rng(seed).choice(len(p), max_axis_points,
                                                          replace=False))
        p, n = p[pick], n[pick]
    lower = np.asarray(lower_W, dtype=float).copy()
    upper = np.asarray(upper_W, dtype=float)
    if np.isfinite(floor):  # the grid starts above the floor (here along z)
        lower[2] = max(lower[2], floor)
    cells = seen_cells(measured_W, free.observed_free, lower, upper, params.cell)
    best = None
    for direction in (None, up):
        votes = symmetry_votes(fit_rotation_axis(p, n, direction), cells)
        if best is None or votes.explained > best.explained:
            best = votes
    if best.explained < params.min_explained:
        return None
    completion = SymmetryCompletion(best, float(params.prior), float(params.confidence),
                                    trimesh.Trimesh())
    surface = revolved_contour(best, completion.p_occupied_rings(), params.confidence,
                               2.0 * best.bin)
    return dataclasses.replace(completion, mesh=_unseen_part(surface, measured_W, free,
                                                             best.bin))


@dataclass(frozen=True, eq=False)
class CompletedFreeSpace(FreeSpace):
    """What the cameras saw free, and what a completion calls free with confidence: the free
    space the GbH core gets for a completed scan (:meth:`known_free`). ``observed_free`` and
    ``saw_plane`` are the cameras' alone (the lift and the table seen through a hole ask
    them)."""

    completion: SymmetryCompletion | None = None

    @staticmethod
    def of(free: FreeSpace, completion: SymmetryCompletion | None) -> CompletedFreeSpace:
        """``free``'s views, margin and depth error, with ``completion``."""
        return CompletedFreeSpace(free.views, free.margin, free.depth_error, completion)

    def known_free(self, points_W: np.ndarray) -> np.ndarray:
        """(n,) bool: seen free (:meth:`observed_free`), or likely free by the completion
        (:meth:`SymmetryCompletion.likely_free`)."""
        free = self.observed_free(points_W)
        if self.completion is not None and not free.all():
            p = np.asarray(points_W, dtype=float).reshape(-1, 3)
            todo = np.flatnonzero(~free)
            free[todo] = self.completion.likely_free(p[todo])
        return free


def _unseen_part(surface: trimesh.Trimesh, measured_W: np.ndarray, free: FreeSpace,
                 near: float) -> trimesh.Trimesh:
    """The triangles of ``surface`` whose centroid no camera saw: not seen free and farther
    than ``near`` (m) from every measured point (n, 3)."""
    if len(surface.faces) == 0:
        return surface
    centroids = surface.triangles_center
    keep = ~free.observed_free(centroids)
    m = np.asarray(measured_W, dtype=float).reshape(-1, 3)
    if len(m) and keep.any():
        d, _ = spatial.cKDTree(m).query(centroids[keep], distance_upper_bound=near)
        idx = np.flatnonzero(keep)
        keep[idx[np.isfinite(d)]] = False
    out = surface.submesh([np.flatnonzero(keep)], append=True) if keep.any() else \
        trimesh.Trimesh()
    return out
