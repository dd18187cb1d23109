"""What the cameras saw free: space carving from depth images, pure numpy (no Drake, no Open3D).

A one-view scan is only the front of an object: the material the camera did not see is absent
from the fused mesh and from its samples, so a ray through unseen material "misses" and a closing
gripper "meets nothing" there (the paper's "holes on the cup wall" with one view). A
:class:`FreeSpace` keeps, per view, the depth image, the pinhole intrinsics and the camera pose;
:meth:`FreeSpace.observed_free` says which points some camera saw through (space carving): the
point projects into that view's image, lies in front of the camera and at least ``margin``
nearer than the depth measured at its pixel, so the pixel's ray passed it and hit something
behind it. Every other point is unknown, possibly occupied.

Depth values (``DepthView.depth``, float32 metres):

* finite and > 0: the ray hit a surface at this depth; the space in front of it is free;
* NaN: nothing known (no return, dropout, too near, or pixels of a sensor whose "no return"
  may hide a surface). Use :meth:`FreeSpace.from_depth_images` to convert raw images: there a
  pixel with ``inf`` (Drake writes inf where nothing was hit within the depth range) proves the
  ray free up to ``depth_max`` when ``depth_max`` is given, and proves nothing otherwise; 0
  (too near, or a dropped pixel of the noise model) proves nothing.

Pixel convention (Drake's ``CameraInfo``, as ``perception.camera.CameraIntrinsics``): pixel
(u, v) covers [u, u + 1) x [v, v + 1) of the continuous image coordinates (fx x / z + cx,
fy y / z + cy), its centre at (u + 0.5, v + 0.5).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True, eq=False)
class DepthView:
    """One camera's depth image (what is free along each pixel's ray), intrinsics and pose."""

    depth: np.ndarray
    """(height, width) float32, metres along +z_C: the ray is free up to this depth; NaN:
    nothing known along the ray."""
    fx: float
    fy: float
    cx: float
    cy: float
    """Focal lengths and principal point, pixels (Drake's convention, module docstring)."""
    width: int
    height: int
    X_CW: np.ndarray
    """(4, 4) pose of W in the camera frame C (C: +z along the optical axis, +x right, +y down)."""
    margin: float | None = None
    """This view's own margin (m) for :meth:`FreeSpace.observed_free` (a view taken from
    farther away, or with coarser pixels, than the others); None: the FreeSpace's."""

    def footprint(self, point_W) -> float:
        """m: how wide this view's pixel is at ``point_W`` (3,): its depth over the focal length."""
        p = np.asarray(point_W, dtype=float).reshape(3)
        z = float(self.X_CW[2, :3] @ p + self.X_CW[2, 3])
        return abs(z) / min(self.fx, self.fy)

    def free_mask(self, points_W: np.ndarray, margin: float) -> np.ndarray:
        """(n,) bool: the points (n, 3) this view saw free (in the image, in front of the camera
        and at least ``margin`` metres nearer than the depth at their pixel)."""
        p = np.asarray(points_W, dtype=np.float32).reshape(-1, 3)
        R = self.X_CW[:3, :3].astype(np.float32)
        t = self.X_CW[:3, 3].astype(np.float32)
        x = p[:, 0] * R[0, 0] + p[:, 1] * R[0, 1] + p[:, 2] * R[0, 2] + t[0]
        y = p[:, 0] * R[1, 0] + p[:, 1] * R[1, 1] + p[:, 2] * R[1, 2] + t[1]
        z = p[:, 0] * R[2, 0] + p[:, 1] * R[2, 1] + p[:, 2] * R[2, 2] + t[2]
        front = z > 1e-6
        zs = np.where(front, z, np.float32(1.0))
        u = np.floor(np.float32(self.fx) * x / zs + np.float32(self.cx))
        v = np.floor(np.float32(self.fy) * y / zs + np.float32(self.cy))
        ok = front & (u >= 0) & (u < self.width) & (v >= 0) & (v < self.height)
        out = np.zeros(len(p), dtype=bool)
        i = np.flatnonzero(ok)
        d = self.depth[v[i].astype(np.intp), u[i].astype(np.intp)]
        with np.errstate(invalid="ignore"):
            out[i] = z[i] <= d - np.float32(margin)  # NaN: False
        return out


@dataclass(frozen=True, eq=False)
class FreeSpace:
    """The space some camera saw free (space carving), for the GbH core's checks."""

    views: tuple[DepthView, ...]
    margin: float
    """Default margin (m) of :meth:`observed_free`: how much nearer than the measured depth a
    point must be to count as seen free. It covers the depth noise and the TSDF's
    discretisation, so that the fused surface's own points are never "seen free" (the scan
    derives it: ``perception.scan.free_space_margin``)."""
    depth_error: float = 0.0
    """How far (m) a measured depth may lie from the surface it hit (the sensor's noise bound;
    0 for a noise-free simulated camera): :meth:`saw_plane` widens its tolerance by it (the
    scan derives it: ``perception.scan.depth_error``)."""

    def __deepcopy__(self, memo) -> FreeSpace:
        """Shared, not copied: never modified (Drake copies abstract port values)."""
        return self

    @staticmethod
    def from_depth_images(depths: Sequence[np.ndarray], fx: float, fy: float, cx: float,
                          cy: float, X_CWs: Sequence[np.ndarray], margin: float,
                          depth_max: float | None = None,
                          depth_error: float = 0.0) -> FreeSpace:
        """From raw depth images (h, w) (m; 0, NaN or negative: no measurement; inf: nothing
        hit within the sensor's range) taken with one pinhole model from poses X_CW (4, 4).

        ``depth_max``: the sensor's far limit (m) when an ``inf`` pixel is known to mean "no
        surface up to depth_max" (a simulated camera: Drake's renderer writes inf where nothing
        was hit in range); the ray is then free up to depth_max. ``None``: inf proves nothing
        (a real sensor also returns nothing from black, specular or grazing surfaces).
        ``depth_error``: :attr:`depth_error`."""
        views = []
        for depth, X_CW in zip(depths, X_CWs, strict=True):
            d = np.asarray(depth, dtype=np.float32)
            with np.errstate(invalid="ignore"):
                measured = np.isfinite(d) & (d > 0)
                far = np.isposinf(d)
            free = np.where(measured, d, np.float32(np.nan))
            if depth_max is not None:
                free = np.where(far, np.float32(depth_max), free)
            h, w = d.shape
            views.append(DepthView(free.astype(np.float32), float(fx), float(fy), float(cx),
                                   float(cy), int(w), int(h),
                                   np.asarray(X_CW, dtype=float).reshape(4, 4).copy()))
        return FreeSpace(tuple(views), float(margin), float(depth_error))

    def with_views(self, other: FreeSpace) -> FreeSpace:
        """This free space and ``other``'s views (each keeping its margin): what all of them saw
        free."""
        own = tuple(v if v.margin is not None else dataclasses.replace(v, margin=self.margin)
                    for v in self.views)
        more = tuple(v if v.margin is not None else dataclasses.replace(v, margin=other.margin)
                     for v in other.views)
        return FreeSpace(own + more, self.margin, max(self.depth_error, other.depth_error))

    def eroded(self, pixels: int = 1, coarser_than: tuple | None = None) -> FreeSpace:
        """A copy whose every pixel holds the least depth of its (2 ``pixels`` + 1)^2
        neighbourhood (NaN, nothing known, if any of them is): a point is then seen free only
        if the rays of its pixel's neighbours passed it too. A pixel's one ray can pass beside a
        thin rim or wall that covers part of the pixel (a first look's pixel is 5 mm wide at
        0.8 m), which would make the whole pixel's column "free" through it.
        ``coarser_than`` (p_W (3,), footprint m): only the views whose pixels are wider than
        that at the point p_W (:meth:`DepthView.footprint`) are eroded."""
        from scipy.ndimage import minimum_filter

        size = 2 * int(pixels) + 1
        views = []
        for view in self.views:
            if coarser_than is not None and view.footprint(coarser_than[0]) <= coarser_than[1]:
                views.append(view)
                continue
            depth = np.where(np.isnan(view.depth), -np.inf, view.depth).astype(np.float32)
            depth = minimum_filter(depth, size=size, mode="nearest")
            views.append(dataclasses.replace(
                view, depth=np.where(np.isneginf(depth), np.float32(np.nan), depth)))
        return dataclasses.replace(self, views=tuple(views))

    def view_margin(self, view: DepthView) -> float:
        """The margin (m) ``view`` is asked with: its own, else this free space's."""
        return self.margin if view.margin is None else view.margin

    def saw_plane(self, points_W: np.ndarray, normal, height: float,
                  tolerance: float) -> np.ndarray:
        """(n,) bool: the points (n, 3, m, in W) through which some view saw the plane
        ``normal . p = height`` (W; a table): the point is in that view's image and seen free
        (:meth:`observed_free`'s test at the view's margin), and the surface its pixel measured
        (the pixel's own ray out to its depth) lies within ``tolerance`` (m) + :attr:`depth_error`
        of the plane: the plane itself, not something standing on it (a container's floor a
        millimetre or two up)."""
        p = np.asarray(points_W, dtype=float).reshape(-1, 3)
        n = np.asarray(normal, dtype=float)
        n = n / np.linalg.norm(n)
        tolerance = float(tolerance) + self.depth_error
        seen = np.zeros(len(p), dtype=bool)
        for view in self.views:
            todo = np.flatnonzero(~seen)
            if len(todo) == 0:
                break
            free = view.free_mask(p[todo], self.view_margin(view))
            i = todo[free]
            if len(i) == 0:
                continue
            R, t = view.X_CW[:3, :3], view.X_CW[:3, 3]
            p_C = p[i] @ R.T + t
            u = np.clip(np.floor(view.fx * p_C[:, 0] / p_C[:, 2] + view.cx), 0, view.width - 1)
            w = np.clip(np.floor(view.fy * p_C[:, 1] / p_C[:, 2] + view.cy), 0, view.height - 1)
            d = view.depth[w.astype(np.intp), u.astype(np.intp)].astype(float)
            ray_C = np.stack([(u + 0.5 - view.cx) / view.fx, (w + 0.5 - view.cy) / view.fy,
                              np.ones_like(u)], axis=1)  # the pixel centre's ray, z = 1
            q_W = (ray_C * d[:, None] - t) @ R  # the point it measured; X_WC = X_CW^-1
            seen[i] = np.abs(q_W @ n - height) <= tolerance
        return seen

    def known_free(self, points_W: np.ndarray) -> np.ndarray:
        """(n,) bool: the points (n, 3, m, in W) the GbH core may take as free (the
        through-hole proof, the unknown space of the closing sweep): here the points a camera
        saw free (:meth:`observed_free`); a completed scan's free space
        (:class:`gbh_drake.core.completion.CompletedFreeSpace`) adds the unseen points its
        completion calls free with confidence. The lift's unseen space asks
        :meth:`observed_free` alone."""
        return self.observed_free(points_W)

    def observed_free(self, points_W: np.ndarray, margin: float | None = None) -> np.ndarray:
        """(n,) bool: the points (n, 3, m, in W) at least one view saw free: in its image, in
        front of the camera and at least ``margin`` (m; default: the view's own
        :attr:`DepthView.margin`, else :attr:`margin`) nearer than the depth at their pixel.
        Each view tests only the points the previous ones did not free."""
        p = np.asarray(points_W, dtype=np.float32).reshape(-1, 3)
        free = np.zeros(len(p), dtype=bool)
        todo = np.arange(len(p))
        for view in self.views:
            if len(todo) == 0:
                break
            hit = view.free_mask(p[todo], self.view_margin(view) if margin is None
                                 else float(margin))
            free[todo[hit]] = True
            todo = todo[~hit]
        return free
