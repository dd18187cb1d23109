"""Whether the hook's loop encloses an object's material: the cage test's geometry (issue 42).

The hook gripper cages what passes through its loop: palm, straight rod, bar, L rod
(:mod:`gbh_drake.core.gripper`). Closed (the bar's tip on the straight rod) the loop is a ring:
material through its hole stays in the hand by the loop's shape, whatever the fingers'
squeeze. Whether a held object was caged or pinched is therefore a question about the loop at
the measured finger positions and the object's surface where it is, answered here without
physics:

* **the loop** (:func:`loop_polygon`): a closed polygon in the loop's plane (x_G = 0) through
  the inside of the gripper's solids: across the hand a rod's half width behind the palm, up
  the straight rod's centre line, across to the bar's tip-most point (the square bar's tip
  face, the wedge's sharp edge), back along the bar to the bend p3 and down the L rod. With
  the fingers apart by more than their closed position the closure from the bar's tip to the
  straight rod crosses the **gap** between them;
* **crossed**: the loop passes through the material: it lies in the gap between the bar's tip
  and the straight rod, where the fingers would close (a cup's wall with the straight rod
  inside the cup, a wire ring pinched at the bar's tip). The material holds the fingers apart:
  a pinch, however long the object stayed;
* **inside** and **thickness**: the material's sections by the loop's plane that lie inside the
  loop (its hole), and the thinnest of them (the least width of a section's convex hull):
  material thinner than the gap could slip out through it;
* **linked** (the topological test, recorded): the loop, not crossing the material, links it:
  some closed curve on the object's surface crosses the disc the loop spans a nonzero number
  of times, counted with sign (the linking number; a mug's handle through the loop crosses it
  once, a bead lying in the hole crosses down and back up: 0). By Alexander duality that is
  exactly when the loop cannot be slipped off the solid by any motion. Computed on the surface
  mesh's edge graph: the edges that cross the disc are cut, the rest split the vertices into
  pieces, and each cut edge joins its piece below the disc to its piece above; the loop links
  the material iff no height per piece makes every cut edge climb by one (then a cycle with a
  nonzero count exists). Exact for the mesh, whatever its resolution; the mesh must share its
  vertices between faces (merge them first).

The loop **encloses** the material (a cage) iff material lies in its hole, the loop does not
pass through it, and its gap is narrower than that material (closed, the gap is 0). Linking is
not required: a rod on two legs hung on the closed bar (a hanger's hook, a staple) is held by the
loop's shape, not by the squeeze, though the loop could be slid off its ends; linking says
more (no motion at all frees it) and is recorded beside. Pure numpy/scipy: the monitor
(:class:`~gbh_drake.systems.cage_monitor.CageMonitor`) calls :func:`loop_enclosure` with the
object's mesh posed in G at the end of the cage test.

**Before the grasp** the same geometry asks whether a planned hook can cage at all
(:func:`planned_loop_material`, GbH's ``loop_must_enclose`` rule): the loop closed at the grasp
(:func:`~gbh_drake.core.grasp_synthesis.closed_gripper`) must hold the scanned surface in its
hole and not run through it. A hook whose closed loop holds nothing lifts nothing: a turned
grasp whose plane passes beside a headband or a teapot's handle, a rod beside the material
instead of round it.
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import IntEnum

import numpy as np

from gbh_drake.core.gripper import HOOK_GRIPPER, HookGripperGeometry

#: Parallel tolerance of the segment-triangle test (Moller-Trumbore), unitless.
_EPS = 1e-12
#: m: a gap below this is the rounding of the finger positions' sum: closed.
_ZERO_GAP = 1e-9


@dataclass(frozen=True)
class LoopEnclosure:
    """What the loop (at the measured fingers) encloses of the material. Metres."""

    linked: bool
    """The loop links the material (a curve on its surface crosses the loop's disc a nonzero
    net number of times); False when the loop crosses the material."""
    crossed: bool
    """The loop passes through the material (it lies in the gap between the bar's tip and the
    straight rod, or deeper in the gripper)."""
    gap: float
    """From the bar's tip to the straight rod's inner face (0: the loop is closed)."""
    thickness: float
    """The thinnest section of the material by the loop's plane inside the loop (inf: no
    material in the hole, or the loop crosses it)."""

    @property
    def inside(self) -> bool:
        """Material lies in the loop's hole (and the loop does not cross it)."""
        return bool(np.isfinite(self.thickness))

    @property
    def encloses(self) -> bool:
        """Material in the hole, the loop not through it, the gap narrower: caged."""
        return not self.crossed and self.inside and self.gap < self.thickness

    def text(self) -> str:
        """A few words for a verdict's reason."""
        if self.crossed:
            return (f"the material lies between the bar's tip and the straight rod (a "
                    f"{1000 * self.gap:.1f} mm gap)")
        if not self.inside:
            return "no material passes through the loop"
        if self.gap >= self.thickness:
            return (f"the loop's {1000 * self.gap:.1f} mm gap is wider than the material in "
                    f"it ({1000 * self.thickness:.1f} mm)")
        return ("its material passes through the loop, which "
                + ("links it" if self.linked else "does not link it")
                + (f"; a {1000 * self.gap:.1f} mm gap, the material "
                   f"{1000 * self.thickness:.1f} mm" if round(1000 * self.gap, 1) > 0 else ""))


def bar_tip_pivot(gripper: HookGripperGeometry = HOOK_GRIPPER) -> np.ndarray:
    """(2,) the bar's tip-most point in its pivot frame's (y, z) (the bend p3 at the origin):
    the middle of its profile's vertices farthest along +y (the square bar's tip face's centre,
    the wedge's sharp edge)."""
    profile = gripper.bar_profile_pivot()
    far = profile[np.isclose(profile[:, 0], profile[:, 0].max())]
    return far.mean(axis=0)


def loop_polygon(q_straight: float, q_l: float, bar_angle: float = 0.0,
                 gripper: HookGripperGeometry = HOOK_GRIPPER) -> tuple[np.ndarray, float]:
    """The loop at finger positions ``q_straight``, ``q_l`` (m, each finger's joint) and the
    bar at ``bar_angle`` (rad about +x_G through p3): its polygon (5, 3) in G, in the plane
    x_G = 0 (palm side of the L rod, palm side of the straight rod, the straight rod at the
    tip's height, the bar's tip-most point, the bend p3), and the gap (m) between the bar's
    tip and the straight rod's inner face (0 when closed)."""
    r, lf = 0.5 * gripper.rod_width, gripper.finger_length
    c, s = np.cos(bar_angle), np.sin(bar_angle)
    y, z = bar_tip_pivot(gripper)
    tip = np.array([0.0, -q_l + c * y - s * z, lf + s * y + c * z])
    z_rod = min(tip[2], lf + r)  # the straight rod ends a rod's half width past p2
    polygon = np.array([[0.0, -q_l, -r], [0.0, q_straight, -r], [0.0, q_straight, z_rod], tip,
                        [0.0, -q_l, lf]])
    gap = q_straight - r - tip[1]
    return polygon, float(gap) if gap > _ZERO_GAP else 0.0


def mesh_edges(faces: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The unique edges (e, 2) of triangles ``faces`` (f, 3) and, per face, the indices (f, 3)
    of its edges in that list."""
    f = np.asarray(faces, dtype=np.int64).reshape(-1, 3)
    pairs = np.sort(np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]]), axis=1)
    edges, inverse = np.unique(pairs, axis=0, return_inverse=True)
    return edges, inverse.reshape(3, -1).T


def segments_cross_triangles(a: np.ndarray, b: np.ndarray, triangles: np.ndarray) -> bool:
    """Whether any segment ``a[i]``-``b[i]`` ((k, 3) each) meets any of ``triangles``
    (t, 3, 3) (Moller-Trumbore, ends included)."""
    if len(triangles) == 0 or len(a) == 0:
        return False
    v0, e1, e2 = triangles[:, 0], triangles[:, 1] - triangles[:, 0], \
        triangles[:, 2] - triangles[:, 0]
    for p, q in zip(np.asarray(a, dtype=float), np.asarray(b, dtype=float), strict=True):
        d = q - p
        h = np.cross(d, e2)
        det = np.einsum("ij,ij->i", e1, h)
        ok = np.abs(det) > _EPS
        inv = np.where(ok, 1.0 / np.where(ok, det, 1.0), 0.0)
        s = p - v0
        u = inv * np.einsum("ij,ij->i", s, h)
        qv = np.cross(s, e1)
        v = inv * (qv @ d)
        t = inv * np.einsum("ij,ij->i", e2, qv)
        hit = ok & (u >= 0) & (v >= 0) & (u + v <= 1) & (t >= 0) & (t <= 1)
        if hit.any():
            return True
    return False


def plane_crossings_yz(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """(k, 2) the (y, z) where the segments ``a[i]``-``b[i]`` ((k, 3) each, their ends on
    either side of the plane x = 0) cross that plane."""
    w = (a[:, 0] / (a[:, 0] - b[:, 0]))[:, None]
    return (a + w * (b - a))[:, 1:]


def inside_polygon(points: np.ndarray, polygon: np.ndarray) -> np.ndarray:
    """Mask (n,) of 2D ``points`` (n, 2) inside the closed ``polygon`` (k, 2) (even-odd rule)."""
    p = np.asarray(points, dtype=float).reshape(-1, 2)
    inside = np.zeros(len(p), dtype=bool)
    for (y0, z0), (y1, z1) in zip(polygon, np.roll(polygon, -1, axis=0), strict=True):
        straddles = (z0 > p[:, 1]) != (z1 > p[:, 1])
        with np.errstate(divide="ignore", invalid="ignore"):
            y_cross = y0 + (p[:, 1] - z0) * (y1 - y0) / (z1 - z0)
        inside ^= straddles & (p[:, 0] < y_cross)
    return inside


def least_width(points: np.ndarray) -> float:
    """The least width (m) of the convex hull of 2D ``points`` (n, 2): the smallest extent over
    the hull's edge normals (0 for fewer than 3 points or collinear ones)."""
    p = np.unique(np.asarray(points, dtype=float).reshape(-1, 2), axis=0)
    if len(p) < 3:
        return 0.0
    from scipy.spatial import ConvexHull, QhullError

    try:
        hull = p[ConvexHull(p).vertices]
    except QhullError:
        return 0.0
    edges = np.roll(hull, -1, axis=0) - hull
    normals = np.stack([-edges[:, 1], edges[:, 0]], axis=1)
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    extent = hull @ normals.T
    return float((extent.max(axis=0) - extent.min(axis=0)).min())


def _linked(n_vertices: int, edges: np.ndarray, cut: np.ndarray, below: np.ndarray) -> bool:
    """Whether the edge graph has a cycle that crosses the disc a nonzero net number of times:
    ``cut`` marks the edges crossing the disc, ``below`` (e, 2) which of each edge's ends lies
    below it (on x_G < 0)."""
    if not cut.any():
        return False
    from scipy import sparse
    from scipy.sparse.csgraph import connected_components

    keep = edges[~cut]
    graph = sparse.coo_matrix((np.ones(len(keep)), (keep[:, 0], keep[:, 1])),
                              shape=(n_vertices, n_vertices))
    _, piece = connected_components(graph, directed=False)
    crossing = edges[cut]
    low = np.where(below[cut, 0], crossing[:, 0], crossing[:, 1])
    high = np.where(below[cut, 0], crossing[:, 1], crossing[:, 0])
    # Heights per piece: each cut edge climbs one from its low piece to its high piece.
    steps: dict[int, list[tuple[int, int]]] = {}
    for a, b in zip(piece[low], piece[high], strict=True):
        if a == b:
            return True  # a cycle through this edge alone crosses the disc once
        steps.setdefault(int(a), []).append((int(b), 1))
        steps.setdefault(int(b), []).append((int(a), -1))
    height: dict[int, int] = {}
    for start in steps:
        if start in height:
            continue
        height[start] = 0
        stack = [start]
        while stack:
            a = stack.pop()
            for b, step in steps[a]:
                if b not in height:
                    height[b] = height[a] + step
                    stack.append(b)
                elif height[b] != height[a] + step:
                    return True
    return False


class LoopMaterial(IntEnum):
    """What a planned hook's closed loop holds of the scanned surface
    (:func:`planned_loop_material`; ``GraspCandidate.loop_material``)."""

    UNCHECKED = -1
    """Not checked (the rule is off, an earlier rule refused the grasp, or ``top_k`` better
    grasps passed: it cannot be ranked)."""
    EMPTY = 0
    """No surface passes through the loop's hole: the loop closes beside the material."""
    HELD = 1
    """The surface passes through the hole and the loop runs clear of it: a cage, if the
    material stays where the scan has it."""
    THROUGH = 2
    """The loop (a rod's or the bar's centre line, or the palm) runs through the surface."""


def planned_loop_material(triangles_G: np.ndarray, q: float,
                          gripper: HookGripperGeometry = HOOK_GRIPPER) -> LoopMaterial:
    """What the loop closed at finger position ``q`` (m, both fingers; the bar deployed) holds
    of the surface triangles ``triangles_G`` (t, 3, 3, metres, in the closed gripper's frame
    G): :class:`LoopMaterial` (module docstring). Only the triangles that straddle the loop's
    plane x_G = 0 within the loop's extent count (a caller may pass only those near it)."""
    tri = np.asarray(triangles_G, dtype=float).reshape(-1, 3, 3)
    polygon, _ = loop_polygon(q, q, 0.0, gripper)
    lo, hi = tri.min(axis=1), tri.max(axis=1)
    near = (lo[:, 0] <= 0.0) & (hi[:, 0] >= 0.0)
    near &= (hi[:, 1] >= polygon[:, 1].min()) & (lo[:, 1] <= polygon[:, 1].max())
    near &= (hi[:, 2] >= polygon[:, 2].min()) & (lo[:, 2] <= polygon[:, 2].max())
    tri = tri[near]
    if segments_cross_triangles(polygon, np.roll(polygon, -1, axis=0), tri):
        return LoopMaterial.THROUGH
    a = tri.reshape(-1, 3)  # each triangle's edges (v0 v1, v1 v2, v2 v0)
    b = np.roll(tri, -1, axis=1).reshape(-1, 3)
    straddle = (a[:, 0] < 0.0) != (b[:, 0] < 0.0)
    held = inside_polygon(plane_crossings_yz(a[straddle], b[straddle]), polygon[:, 1:]).any()
    return LoopMaterial.HELD if held else LoopMaterial.EMPTY


def loop_reach(q: float, gripper: HookGripperGeometry = HOOK_GRIPPER) -> tuple[np.ndarray, float]:
    """The centre (3,) in G and radius (m) of a ball holding the loop closed at ``q``: a
    triangle wholly farther from the centre than that cannot meet the loop or its hole."""
    polygon, _ = loop_polygon(q, q, 0.0, gripper)
    centre = 0.5 * (polygon.min(axis=0) + polygon.max(axis=0))
    return centre, float(np.linalg.norm(polygon - centre, axis=1).max())


def loop_enclosure(p_GV: np.ndarray, faces: np.ndarray, q_straight: float, q_l: float,
                   bar_angle: float = 0.0, gripper: HookGripperGeometry = HOOK_GRIPPER, *,
                   edges: tuple[np.ndarray, np.ndarray] | None = None) -> LoopEnclosure:
    """What the loop at finger positions ``q_straight``, ``q_l`` (m) and ``bar_angle`` (rad)
    encloses of the surface mesh with vertices ``p_GV`` (n, 3, in G, metres; shared between
    faces) and ``faces`` (f, 3) (module docstring). ``edges``: :func:`mesh_edges` of ``faces``,
    when the caller has them (the mesh moves, its edges do not)."""
    p = np.asarray(p_GV, dtype=float).reshape(-1, 3)
    f = np.asarray(faces, dtype=np.int64).reshape(-1, 3)
    polygon, gap = loop_polygon(q_straight, q_l, bar_angle, gripper)
    crossed = segments_cross_triangles(polygon, np.roll(polygon, -1, axis=0), p[f])
    if crossed:
        return LoopEnclosure(False, True, gap, float("inf"))
    edge_list, face_edges = mesh_edges(f) if edges is None else edges
    x = p[:, 0]
    below = x[edge_list] < 0.0
    straddle = below[:, 0] != below[:, 1]
    i = np.flatnonzero(straddle)
    a, b = edge_list[i, 0], edge_list[i, 1]
    cross_yz = plane_crossings_yz(p[a], p[b])
    in_disc = inside_polygon(cross_yz, polygon[:, 1:])
    cut = np.zeros(len(edge_list), dtype=bool)
    cut[i[in_disc]] = True
    linked = _linked(len(p), edge_list, cut, below)
    return LoopEnclosure(linked, False, gap, _thickness(face_edges, straddle, i, cross_yz,
                                                       in_disc))


def _thickness(face_edges: np.ndarray, straddle: np.ndarray, crossing: np.ndarray,
               cross_yz: np.ndarray, in_disc: np.ndarray) -> float:
    """The least width of the sections (by the loop's plane) that lie inside the loop: the
    crossing edges joined through the faces they share are one section each."""
    if not in_disc.any():
        return float("inf")
    from scipy import sparse
    from scipy.sparse.csgraph import connected_components

    index = np.full(len(straddle), -1)
    index[crossing] = np.arange(len(crossing))
    cut_faces = face_edges[straddle[face_edges].sum(axis=1) == 2]
    ends = index[cut_faces]
    ends = np.sort(ends, axis=1)[:, 1:]  # the two crossing edges of each cut face (-1 first)
    n = len(crossing)
    graph = sparse.coo_matrix((np.ones(len(ends)), (ends[:, 0], ends[:, 1])), shape=(n, n))
    _, section = connected_components(graph, directed=False)
    widths = [least_width(cross_yz[section == k]) for k in np.unique(section[in_disc])]
    return float(min(widths))
