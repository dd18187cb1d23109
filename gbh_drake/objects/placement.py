"""Put any mesh into a resting frame O: lowest point on z = 0, x and y centred.

Pure numpy/trimesh/scipy. A mesh file comes in its own frame F (any origin, any orientation,
metres after ``scale``). :func:`rest_on_table` returns the mesh in a frame O in which it rests on
the plane z = 0 (its lowest point exactly at z = 0) with x, y centred on its footprint (or on the
centre of mass, or on the bounding box), and the transform ``X_OF`` (4, 4; p_O = X_OF p_F) that
was applied, so that ground truth given in F (a hole's centre and axis) moves with it::

    placed = rest_on_table(mesh_F, com=com_F)
    center_O = placed.X_OF[:3, :3] @ center_F + placed.X_OF[:3, 3]
    axis_O = placed.X_OF[:3, :3] @ axis_F

Orientation: ``"keep"`` (default) keeps F's z as up (the scenario's convention: a mesh file's z
is up) and says, in ``placed.stable`` and ``placed.warnings``, whether the object would stand as
given or topple; ``"nearest_stable"`` turns it onto the stable pose nearest to F's upright
(levels a scan whose base is a little tilted; tips over a mesh that would fall); and
``"most_probable"`` onto its most probable stable pose (see
:mod:`gbh_drake.objects.stability`).

:func:`lift_to_table` corrects any pose ``X_WO`` so that the mesh's lowest point is at a given
height: use it for explicit poses (a scenario's roll and pitch) so the object never starts inside
the table.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import trimesh
from scipy.spatial import ConvexHull, QhullError

from gbh_drake.objects.stability import StablePose, stable_poses

CENTERS = ("footprint", "com", "bbox")
ORIENTATIONS = ("keep", "nearest_stable", "most_probable")
CONTACT_TOL = 1e-3
"""m: vertices within this of the lowest point (or 5 % of the height, if less) form the
footprint."""
STABLE_MARGIN_DEG = 1.0
"""A pose kept as given counts as stable when tipping it by this (deg) does not topple it."""
SETTLE_DEG = 5.0
"""An unstable pose kept as given within this (deg) of a stable one "settles"; beyond, it
"tips over" (the wording of the warning)."""


@dataclass(frozen=True)
class Placement:
    """A mesh put into its resting frame O.

    ``mesh``: the mesh in O (a copy). ``X_OF`` (4, 4): the rigid transform applied, p_O =
    X_OF p_F. ``com_O`` (3,): centre of mass in O (uniform density unless one was given).
    ``footprint_O`` (k, 2): the footprint's convex polygon in O's x-y plane (points within the
    contact tolerance of z = 0). ``tilt_margin_deg``: how far (deg) the object can be tipped
    about the nearest footprint edge before it topples (negative: it topples as placed).
    ``stable``: ``tilt_margin_deg >= STABLE_MARGIN_DEG``. ``settle_deg``: for an unstable
    ``"keep"``, the angle (deg) to the nearest stable pose it will fall onto. ``pose``: the
    stable pose used (for the non-"keep" orientations). ``warnings``: lines without the source's
    name.
    """

    mesh: trimesh.Trimesh
    X_OF: np.ndarray
    com_O: np.ndarray
    footprint_O: np.ndarray
    tilt_margin_deg: float
    stable: bool
    settle_deg: float = 0.0
    pose: StablePose | None = None
    warnings: list[str] = field(default_factory=list)

    def to_O(self, points_F) -> np.ndarray:
        """Points (..., 3) from F to O."""
        p = np.asarray(points_F, dtype=np.float64)
        return p @ self.X_OF[:3, :3].T + self.X_OF[:3, 3]


def rest_on_table(
    mesh: trimesh.Trimesh,
    *,
    com=None,
    center: str = "footprint",
    orientation: str = "keep",
    contact_tol: float = CONTACT_TOL,
) -> Placement:
    """``mesh`` (frame F, m) moved to its resting frame O; see the module docstring.

    ``com`` (3,): centre of mass in F (default: uniform density, exact or voxel fill).
    ``center``: what is put on O's z axis: ``"footprint"`` (the area centroid of the footprint
    polygon; the middle of a line or point contact), ``"com"`` (the centre of mass's projection)
    or ``"bbox"`` (the bounding box's centre). ``orientation``: ``"keep"``, ``"nearest_stable"``
    or ``"most_probable"``.
    """
    if center not in CENTERS:
        raise ValueError(f"center must be one of {CENTERS}, got {center!r}")
    if orientation not in ORIENTATIONS:
        raise ValueError(f"orientation must be one of {ORIENTATIONS}, got {orientation!r}")
    vertices = np.asarray(mesh.vertices, dtype=np.float64)
    if len(vertices) == 0 or not np.all(np.isfinite(vertices)):
        raise ValueError("mesh has no vertices or non-finite ones")
    if com is None:
        from gbh_drake.objects.mass import mass_properties_detailed

        com = mass_properties_detailed(mesh, 1.0).com
    com = np.asarray(com, dtype=np.float64).reshape(3)
    pose = None
    R = np.eye(3)
    if orientation != "keep":
        poses = stable_poses(mesh, com)
        pose = poses.poses[0] if orientation == "most_probable" else poses.nearest()
        R = pose.R
    rotated = vertices @ R.T
    com_r = R @ com
    z_low = float(rotated[:, 2].min())
    height = float(rotated[:, 2].max()) - z_low
    tol = min(contact_tol, 0.05 * height) if height > 0 else contact_tol
    contact = rotated[rotated[:, 2] <= z_low + tol, :2]
    polygon = _convex_polygon(contact)
    if center == "footprint":
        xy = _polygon_centroid(polygon)
    elif center == "com":
        xy = com_r[:2]
    else:
        xy = 0.5 * (rotated[:, :2].min(axis=0) + rotated[:, :2].max(axis=0))
    X_OF = np.eye(4)
    X_OF[:3, :3] = R
    X_OF[:3, 3] = (-xy[0], -xy[1], -z_low)
    margin = _tilt_margin(polygon, com_r[:2], com_r[2] - z_low)
    stable = margin >= STABLE_MARGIN_DEG
    warnings = []
    settle = 0.0
    if not stable and orientation == "keep":
        nearest = stable_poses(mesh, com).nearest()
        settle = float(np.degrees(np.arccos(np.clip(-nearest.normal_O[2], -1.0, 1.0))))
        if settle <= SETTLE_DEG:
            warnings.append(
                f"rests {settle:.1f} deg off its nearest stable face (z up as given): it will "
                f"settle onto it when released; orientation: nearest_stable levels it")
        else:
            warnings.append(
                f"not stable as given (z up): it will tip over when released, {settle:.0f} deg "
                f"onto its nearest stable face; rest it on that face with orientation: "
                f"nearest_stable (glTF files are y-up)")
    out = mesh.copy()
    out.apply_transform(X_OF)
    com_O = X_OF[:3, :3] @ com + X_OF[:3, 3]
    footprint = polygon - xy
    for a in (X_OF, com_O, footprint):
        a.setflags(write=False)
    return Placement(out, X_OF, com_O, footprint, margin, bool(stable), settle, pose, warnings)


def lift_to_table(mesh: trimesh.Trimesh, X_WO, z_table: float = 0.0) -> np.ndarray:
    """``X_WO`` (4, 4) with its z translation changed so that the lowest point of ``mesh``
    (frame O) is at ``z_table``: the object neither floats nor starts inside the table."""
    X = np.array(X_WO, dtype=np.float64).reshape(4, 4)
    vertices = np.asarray(mesh.vertices, dtype=np.float64)
    X[2, 3] = z_table - float(np.min(vertices @ X[2, :3]))
    return X


def lowest_point_z(mesh: trimesh.Trimesh, X_WO) -> float:
    """Height (m) of the lowest point of ``mesh`` (frame O) posed at ``X_WO`` (4, 4)."""
    X = np.asarray(X_WO, dtype=np.float64).reshape(4, 4)
    return float(np.min(np.asarray(mesh.vertices) @ X[2, :3]) + X[2, 3])


def _convex_polygon(points: np.ndarray) -> np.ndarray:
    """The 2-D convex hull (counter-clockwise vertices) of ``points``; for collinear or
    coincident points, the two extreme points (a segment) or the point."""
    points = np.unique(np.round(points, 12), axis=0)
    if len(points) >= 3:
        try:
            return points[ConvexHull(points).vertices]
        except (QhullError, ValueError):
            pass
    if len(points) == 1:
        return points
    centred = points - points.mean(axis=0)
    direction = np.linalg.svd(centred, full_matrices=False)[2][0]
    s = centred @ direction
    return points[[int(np.argmin(s)), int(np.argmax(s))]]


def _polygon_centroid(polygon: np.ndarray) -> np.ndarray:
    """Area centroid of a convex polygon; the midpoint of a segment; the point itself."""
    if len(polygon) < 3:
        return polygon.mean(axis=0)
    x, y = polygon[:, 0], polygon[:, 1]
    xn, yn = np.roll(x, -1), np.roll(y, -1)
    cross = x * yn - xn * y
    area = 0.5 * cross.sum()
    if abs(area) < 1e-14:
        return polygon.mean(axis=0)
    return np.array([((x + xn) * cross).sum(), ((y + yn) * cross).sum()]) / (6.0 * area)


def _tilt_margin(polygon: np.ndarray, p: np.ndarray, height: float) -> float:
    """atan(signed distance of ``p`` inside ``polygon`` / ``height``) in degrees; a segment or
    point support gives minus the distance from it (0 when ``p`` is on it)."""
    if len(polygon) >= 3:
        x, y = polygon[:, 0], polygon[:, 1]
        area = 0.5 * (x * np.roll(y, -1) - np.roll(x, -1) * y).sum()
    else:
        area = 0.0
    if abs(area) > 1e-14:
        edges = np.roll(polygon, -1, axis=0) - polygon
        normals = np.column_stack([edges[:, 1], -edges[:, 0]]) * np.sign(area)  # outward
        normals /= np.linalg.norm(normals, axis=1, keepdims=True)
        d = -float(np.max(np.einsum("ij,ij->i", p - polygon, normals)))
    elif len(polygon) == 2:
        a, b = polygon
        t = np.clip(np.dot(p - a, b - a) / max(np.dot(b - a, b - a), 1e-300), 0.0, 1.0)
        d = -float(np.linalg.norm(p - (a + t * (b - a))))
    else:
        d = -float(np.linalg.norm(p - polygon[0]))
    return float(np.degrees(np.arctan2(d, max(height, 1e-12))))
