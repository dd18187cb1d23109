"""Shared solid builders for the object set (manifold3d), all lengths in metres.

Everything here returns :class:`manifold3d.Manifold` solids (or 2-D
:class:`manifold3d.CrossSection` profiles), so the booleans that assemble an object are exact and
the result is watertight. :func:`to_trimesh` converts at the very end.

Conventions: a *profile* is a 2-D polygon ``(n, 2)`` in the ``(r, z)`` half-plane (``r >= 0``)
revolved about the object's z axis. A *loop plane* is given by an origin and two orthonormal
in-plane directions ``u`` (along the plane's first axis) and ``v``; 2-D paths in ``(u, v)``
coordinates are mapped to 3-D by :func:`plane_points`.
"""

from __future__ import annotations

import numpy as np
import trimesh
from manifold3d import CrossSection, JoinType, Manifold, Mesh, OpType

#: Segments around a full circle for bodies of revolution (a 10 cm mug's facets are ~5 mm).
REVOLVE_SEGMENTS = 64
#: Vertices on a tube's round cross-section.
TUBE_SEGMENTS = 16


# ---- conversion --------------------------------------------------------------------------------
def to_trimesh(solid: Manifold, tolerance: float = 1e-6) -> trimesh.Trimesh:
    """The solid as a trimesh (metres); edges shorter than ``tolerance`` are collapsed first."""
    if solid.status().name != "NoError":
        raise ValueError(f"invalid manifold: {solid.status()}")
    out = solid.simplify(tolerance).to_mesh()
    vertices = np.asarray(out.vert_properties, dtype=np.float64)[:, :3]
    faces = np.asarray(out.tri_verts, dtype=np.int64)
    return trimesh.Trimesh(vertices, faces, process=False)


def from_arrays(vertices: np.ndarray, faces: np.ndarray) -> Manifold:
    """A manifold from a closed triangle mesh; faces are flipped if the mesh is inside out."""
    vertices = np.asarray(vertices, dtype=np.float64)
    faces = np.asarray(faces, dtype=np.int64)
    tri = vertices[faces]
    signed_volume = np.einsum("ij,ij->i", tri[:, 0], np.cross(tri[:, 1], tri[:, 2])).sum() / 6.0
    if signed_volume < 0:
        faces = faces[:, ::-1]
    solid = Manifold(
        Mesh(
            vert_properties=np.ascontiguousarray(vertices, dtype=np.float32),
            tri_verts=np.ascontiguousarray(faces, dtype=np.uint32),
        )
    )
    if solid.status().name != "NoError" or solid.is_empty():
        raise ValueError(f"mesh is not a closed manifold: {solid.status()}")
    return solid


# ---- booleans ------------------------------------------------------------------------------------
def union(*solids: Manifold) -> Manifold:
    """Boolean union of solids."""
    return Manifold.batch_boolean(list(solids), OpType.Add)


def subtract(solid: Manifold, *tools: Manifold) -> Manifold:
    """``solid`` minus every tool."""
    return Manifold.batch_boolean([solid, *tools], OpType.Subtract)


# ---- 2-D profiles and sections ----------------------------------------------------------------
def circle_section(radius: float, n: int = TUBE_SEGMENTS) -> np.ndarray:
    """A CCW circle polygon ``(n, 2)`` of ``radius`` (a tube's round cross-section)."""
    return ellipse_section(radius, radius, n)


def ellipse_section(half_a: float, half_b: float, n: int = TUBE_SEGMENTS) -> np.ndarray:
    """A CCW ellipse polygon ``(n, 2)``: ``half_a`` along the section's first axis, ``half_b``
    along the second (for loops: first = in the loop plane, second = along the hole axis)."""
    t = 2.0 * np.pi * (np.arange(n) + 0.5) / n
    return np.column_stack([half_a * np.cos(t), half_b * np.sin(t)])


def rounded_rect_section(
    half_a: float, half_b: float, radius: float, n_corner: int = 4
) -> np.ndarray:
    """A CCW rounded rectangle ``(4 n_corner, 2)``, half sides ``half_a``/``half_b``."""
    radius = min(radius, half_a, half_b)
    corners = [(half_a, half_b), (-half_a, half_b), (-half_a, -half_b), (half_a, -half_b)]
    points = []
    for k, (cx, cy) in enumerate(corners):
        centre = np.array([cx - np.sign(cx) * radius, cy - np.sign(cy) * radius])
        t = 0.5 * np.pi * (k + np.linspace(0.0, 1.0, n_corner))
        points.append(centre + radius * np.column_stack([np.cos(t), np.sin(t)]))
    return np.vstack(points)


def _signed_area(poly: np.ndarray) -> float:
    x, y = poly[:, 0], poly[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y))


def polygon(points: np.ndarray) -> CrossSection:
    """A CrossSection from one polygon (any orientation)."""
    points = np.asarray(points, dtype=np.float64)
    if _signed_area(points) < 0:
        points = points[::-1]
    return CrossSection([points])


# ---- solids from profiles ------------------------------------------------------------------------
def revolve(profile: CrossSection | np.ndarray, segments: int = REVOLVE_SEGMENTS) -> Manifold:
    """Revolve a ``(r, z)`` profile about the z axis (full turn)."""
    cs = profile if isinstance(profile, CrossSection) else polygon(profile)
    return Manifold.revolve(cs, circular_segments=segments)


def vessel(outer: np.ndarray, wall: float, segments: int = REVOLVE_SEGMENTS):
    """An open-topped vessel of revolution: ``(shell, cavity)`` solids.

    ``outer`` is the outside profile ``(r, z)`` from ``(0, 0)`` (centre of the base) to the rim
    ``(r_rim, z_rim)``, whose last segment should be vertical or flaring. The shell is ``wall``
    thick (inner corners rounded). ``cavity`` is the inside, up to just above the rim: subtract it
    from anything attached later so that handles do not poke into the vessel.
    """
    outer = np.asarray(outer, dtype=np.float64)
    r_rim, z_rim = outer[-1]
    half = polygon(np.vstack([outer, [[0.0, z_rim]]]))
    full = half + half.mirror((1.0, 0.0))
    above = CrossSection.square((2.0 * r_rim, 1.0)).translate((-r_rim, z_rim - 1e-4))
    inner = (full + above).offset(-wall, JoinType.Round, circular_segments=24)
    # The cavity reaches just above the rim: enough to trim what pokes inside, not arches above.
    right = CrossSection.square((10.0, z_rim + 1e-3)).translate((0.0, -1e-3))
    return revolve(half - inner, segments), revolve(inner ^ right, segments)


def extrude(section: CrossSection, height: float) -> Manifold:
    """Extrude a 2-D section along +z from z = 0 to ``height``."""
    return Manifold.extrude(section, height)


def rounded_rect_xs(size_x: float, size_y: float, radius: float) -> CrossSection:
    """A rounded rectangle centred at the origin (2-D)."""
    radius = min(radius, 0.499 * min(size_x, size_y))
    core = CrossSection.square((size_x - 2 * radius, size_y - 2 * radius), center=True)
    return core.offset(radius, JoinType.Round, circular_segments=32)


# ---- paths ---------------------------------------------------------------------------------------
def arc(center: np.ndarray, radius: float, a0: float, a1: float, n: int) -> np.ndarray:
    """``n`` points on a circular arc from angle ``a0`` to ``a1`` (radians), 2-D."""
    t = np.linspace(a0, a1, n)
    return np.asarray(center) + radius * np.column_stack([np.cos(t), np.sin(t)])


def rounded_polyline(points: np.ndarray, radius: float, n_corner: int = 10) -> np.ndarray:
    """A 2-D polyline with every interior corner replaced by a tangent arc of ``radius``.

    The fillet radius is reduced at a corner where the neighbouring segments are too short.
    """
    points = np.asarray(points, dtype=np.float64)
    out = [points[0]]
    for i in range(1, len(points) - 1):
        a, b, c = points[i - 1], points[i], points[i + 1]
        d0, d1 = (a - b), (c - b)
        l0, l1 = np.linalg.norm(d0), np.linalg.norm(d1)
        d0, d1 = d0 / l0, d1 / l1
        half = 0.5 * np.arccos(np.clip(np.dot(d0, d1), -1.0, 1.0))
        if half > 0.5 * np.pi - 1e-6:
            out.append(b)
            continue
        r = min(radius, 0.49 * min(l0, l1) * np.tan(half))
        t = r / np.tan(half)
        bis = d0 + d1
        centre = b + bis / np.linalg.norm(bis) * r / np.sin(half)
        p0, p1 = b + d0 * t, b + d1 * t
        a0 = np.arctan2(*(p0 - centre)[::-1])
        a1 = np.arctan2(*(p1 - centre)[::-1])
        da = (a1 - a0 + np.pi) % (2 * np.pi) - np.pi
        out.extend(arc(centre, r, a0, a0 + da, n_corner))
    out.append(points[-1])
    return resample(np.array(out))


def resample(path: np.ndarray, max_step: float = 0.004) -> np.ndarray:
    """Insert points so that no segment of the 2-D/3-D polyline is longer than ``max_step``;
    consecutive duplicates are dropped."""
    path = np.asarray(path, dtype=np.float64)
    keep = np.r_[True, np.linalg.norm(np.diff(path, axis=0), axis=1) > 1e-9]
    path = path[keep]
    out = [path[0]]
    for a, b in zip(path[:-1], path[1:], strict=True):
        k = max(1, int(np.ceil(np.linalg.norm(b - a) / max_step)))
        out.extend(a + (b - a) * (np.arange(1, k + 1)[:, None] / k))
    return np.array(out)


def plane_points(points_uv: np.ndarray, origin, u, v) -> np.ndarray:
    """Map 2-D ``(u, v)`` coordinates to 3-D points ``origin + a u + b v``."""
    points_uv = np.asarray(points_uv, dtype=np.float64)
    return (
        np.asarray(origin, dtype=np.float64)
        + points_uv[:, :1] * np.asarray(u, dtype=np.float64)
        + points_uv[:, 1:2] * np.asarray(v, dtype=np.float64)
    )


# ---- sweeps --------------------------------------------------------------------------------------
def sweep(path: np.ndarray, section: np.ndarray, plane_normal, closed: bool = False) -> Manifold:
    """Sweep a convex 2-D ``section`` along a planar 3-D ``path`` ``(n, 3)``.

    The section's first coordinate lies in the path's plane (along the in-plane normal of the
    path), the second along ``plane_normal``. Open paths get flat end caps. The path must be
    smooth enough (turn radius larger than the section) not to self-intersect.
    """
    path = np.asarray(path, dtype=np.float64)
    if closed and np.linalg.norm(path[0] - path[-1]) < 1e-9:
        path = path[:-1]
    b = np.asarray(plane_normal, dtype=np.float64)
    b = b / np.linalg.norm(b)
    if closed:
        tangent = np.roll(path, -1, axis=0) - np.roll(path, 1, axis=0)
    else:
        tangent = np.gradient(path, axis=0)
    tangent -= np.outer(tangent @ b, b)
    tangent /= np.linalg.norm(tangent, axis=1, keepdims=True)
    normal = np.cross(tangent, b)
    n, m = len(path), len(section)
    rings = (
        path[:, None, :]
        + section[None, :, 0, None] * normal[:, None, :]
        + section[None, :, 1, None] * b[None, None, :]
    )
    vertices = rings.reshape(-1, 3)
    i = np.arange(n if closed else n - 1)[:, None]
    j = np.arange(m)[None, :]
    a = i * m + j
    bb = i * m + (j + 1) % m
    c = ((i + 1) % n) * m + (j + 1) % m
    d = ((i + 1) % n) * m + j
    faces = np.concatenate(
        [np.stack([a, bb, c], -1).reshape(-1, 3), np.stack([a, c, d], -1).reshape(-1, 3)]
    )
    if not closed:
        centres = np.array([path[0], path[-1]])
        c0, c1 = len(vertices), len(vertices) + 1
        vertices = np.vstack([vertices, centres])
        ring0 = np.arange(m)
        ring1 = (n - 1) * m + np.arange(m)
        cap0 = np.column_stack([np.full(m, c0), np.roll(ring0, -1), ring0])
        cap1 = np.column_stack([np.full(m, c1), ring1, np.roll(ring1, -1)])
        faces = np.concatenate([faces, cap0, cap1])
    return from_arrays(vertices, faces)


def tube(path: np.ndarray, radius: float, plane_normal, closed: bool = False) -> Manifold:
    """A round tube of ``radius`` along a planar path (see :func:`sweep`)."""
    return sweep(path, circle_section(radius), plane_normal, closed)


def cylinder_between(p0, p1, radius: float, segments: int = 24) -> Manifold:
    """A solid round cylinder from point ``p0`` to point ``p1``."""
    p0, p1 = np.asarray(p0, dtype=np.float64), np.asarray(p1, dtype=np.float64)
    d = p1 - p0
    length = float(np.linalg.norm(d))
    cyl = Manifold.cylinder(length, radius, radius, segments)
    return cyl.transform(_frame_z_to(d / length, p0))


def cone_between(p0, p1, r0: float, r1: float, segments: int = 24) -> Manifold:
    """A truncated cone from ``p0`` (radius ``r0``) to ``p1`` (radius ``r1``)."""
    p0, p1 = np.asarray(p0, dtype=np.float64), np.asarray(p1, dtype=np.float64)
    d = p1 - p0
    length = float(np.linalg.norm(d))
    return Manifold.cylinder(length, r0, r1, segments).transform(_frame_z_to(d / length, p0))


def _frame_z_to(z: np.ndarray, origin: np.ndarray) -> np.ndarray:
    """A 3x4 affine transform taking +z to unit vector ``z`` and the origin to ``origin``."""
    helper = np.array([1.0, 0.0, 0.0]) if abs(z[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    x = np.cross(helper, z)
    x /= np.linalg.norm(x)
    y = np.cross(z, x)
    return np.column_stack([x, y, z, origin])


def box(size, center=(0.0, 0.0, 0.0)) -> Manifold:
    """An axis-aligned box of ``size`` (3,) centred at ``center``."""
    return Manifold.cube(tuple(float(s) for s in size), center=True).translate(
        tuple(float(c) for c in center)
    )
