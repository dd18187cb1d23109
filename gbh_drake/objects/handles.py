"""Handle loops: the shared builder for every handle, bail and strap of the set (metres).

A handle is a convex cross-section swept along a smooth planar path. The path is given as a few
control points in a *loop plane* (origin ``o``, in-plane directions ``u`` and ``v``) whose corners
are rounded with a fillet radius: large fillets give a round "C", small ones a "D" or a square
handle. The hole axis of the loop is ``u x v``. The path's two ends should lie inside the body the
handle is attached to, so that the union closes the loop; subtracting the body's cavity afterwards
trims whatever pokes inside.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from manifold3d import Manifold

from gbh_drake.objects.primitives import plane_points, rounded_polyline, sweep


@dataclass(frozen=True)
class LoopPlane:
    """A plane for loop paths: ``origin`` (3,), ``u`` and ``v`` (3,) orthonormal, frame O."""

    origin: tuple[float, float, float] = (0.0, 0.0, 0.0)
    u: tuple[float, float, float] = (1.0, 0.0, 0.0)
    v: tuple[float, float, float] = (0.0, 0.0, 1.0)

    @property
    def normal(self) -> np.ndarray:
        """The hole axis of loops in this plane, ``u x v``."""
        return np.cross(self.u, self.v)

    def to_3d(self, points_uv) -> np.ndarray:
        """``(n, 2)`` plane coordinates to ``(n, 3)`` points in frame O."""
        return plane_points(np.atleast_2d(points_uv), self.origin, self.u, self.v)


#: The x-z plane through the origin: loops around the y axis (mug handles, arches, bails).
XZ = LoopPlane()
#: The x-y plane through the origin: flat loops around the z axis.
XY = LoopPlane(v=(0.0, 1.0, 0.0))


def handle_loop(
    plane: LoopPlane, control_uv, section: np.ndarray, fillet: float
) -> Manifold:
    """Sweep ``section`` (first coordinate in the plane, second along the hole axis) along the
    control polyline ``control_uv`` ``(k, 2)`` with corners rounded by ``fillet`` (m)."""
    path = rounded_polyline(np.asarray(control_uv, dtype=np.float64), fillet)
    return sweep(plane.to_3d(path), section, plane.normal)


def side_handle(
    plane: LoopPlane,
    wall_top: tuple[float, float],
    wall_bottom: tuple[float, float],
    reach: float,
    section: np.ndarray,
    fillet: float,
    rise: float = 0.0,
    inset: float = 0.004,
) -> tuple[Manifold, np.ndarray]:
    """A mug-style handle leaving a wall at two points and bulging out by ``reach`` along ``u``.

    ``wall_top``/``wall_bottom`` are the ``(u, v)`` points on the outer wall where the handle's
    centre line meets it; the ends are sunk ``inset`` into the wall. ``rise`` lifts the outer top
    corner. Returns the solid and a first guess of the hole centre (3,), frame O.
    """
    (ut, vt), (ub, vb) = wall_top, wall_bottom
    u_out = max(ut, ub) + reach
    control = [(ut - inset, vt), (u_out, vt + rise), (u_out, vb), (ub - inset, vb)]
    solid = handle_loop(plane, control, section, fillet)
    inner_edge = u_out - np.abs(section[:, 0]).max()
    guess = plane.to_3d([(0.5 * (0.5 * (ut + ub) + inner_edge), 0.5 * (vt + vb))])[0]
    return solid, guess


def arch_handle(
    plane: LoopPlane,
    half_span: float,
    v_feet: float,
    v_top: float,
    section: np.ndarray,
    fillet: float,
    top_half_span: float | None = None,
) -> Manifold:
    """An arch (bail, top handle, strap) with feet at ``u = +-half_span``, ``v = v_feet`` rising
    to ``v = v_top``; ``top_half_span`` narrows or widens the top corners (default: straight)."""
    top = half_span if top_half_span is None else top_half_span
    control = [(-half_span, v_feet), (-top, v_top), (top, v_top), (half_span, v_feet)]
    return handle_loop(plane, control, section, fillet)
