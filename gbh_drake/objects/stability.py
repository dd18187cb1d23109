"""Stable resting poses of a rigid object on a table, and random resting poses drawn from them.

Pure numpy/trimesh/scipy. Frames: O the object's frame (its mesh's coordinates), W the world
(z up, table top at z = 0).

:func:`stable_poses` finds the orientations in which the object rests on a plane and the
probability of each when the object is dropped in a uniformly random orientation (quasi-static
toppling on the convex hull; trimesh's :func:`trimesh.poses.compute_stable_poses`, after Goldberg
et al., "Part pose statistics"). Robustness around trimesh's function:

* It works on the convex hull, so any mesh (not watertight, several bodies) is fine; the centre of
  mass is the uniform-density one from :mod:`gbh_drake.objects.mass` (exact or voxel fill) unless
  given. A centre of mass outside the hull (which would make trimesh loop forever) is replaced by
  the hull's centroid, with a note.
* Time is capped: a hull of more than ``max_hull_faces`` (:data:`MAX_HULL_FACES`) triangles, and
  any mesh of more than :data:`EXACT_HULL_MAX_VERTICES` vertices, is replaced by the hull of its
  support points in ``max_hull_faces / 2 + 2`` directions (a Fibonacci sphere; the points are
  mesh vertices, so the simplified hull lies inside the true one, within ~0.5 % of the radius of
  a sphere). Measured here (2 shared cores, loaded): 0.01-0.3 s per object of the set with the
  centre of mass given (box 0.007 s, mugs 0.1 s, teapot 0.3 s, the finely tessellated ball
  0.65 s: every facet of a sphere is a stable pose); a 200k-triangle sphere 1.6 s (its support
  points 0.1 s, trimesh's analysis of the 800-face hull the rest).
* Results are cached per mesh (vertices, faces, centre of mass and options; :data:`CACHE_SIZE`
  entries) and trimesh's use of numpy's global random state is undone.
* Poses whose support normals are within :data:`MERGE_DEG` are merged (probabilities added).
  Each pose gets a tilt margin: the angle it can be tipped about the nearest edge of its support
  polygon before it topples, atan(d / h) with d the distance of the centre of mass's projection
  from that edge and h its height. Poses below ``min_tilt_deg`` (default
  :data:`MIN_TILT_DEG`) are dropped (resting on an edge or a needle point; a tessellated
  cylinder's side facets pass) and the probabilities renormalised. A degenerate mesh (flat,
  fewer than four points in general position) gets one pose, O's own orientation, with a note.

:func:`sample_resting_pose` draws a resting pose: a stable orientation (by probability), a
uniform yaw about the vertical through the centre of mass and a uniform position of the centre of
mass, with the lowest point of the mesh at z = 0.
"""

from __future__ import annotations

import hashlib
import time
from collections import OrderedDict
from dataclasses import dataclass, field

import numpy as np
import trimesh
from scipy.spatial import ConvexHull, QhullError

MAX_HULL_FACES = 800
"""Hulls with more triangles are simplified (support points) before the toppling analysis."""
EXACT_HULL_MAX_VERTICES = 50_000
"""Meshes with more vertices go straight to the support points (qhull on millions of points on a
hull, e.g. a finely tessellated sphere, takes seconds)."""
MERGE_DEG = 0.5
"""Stable poses whose support normals are closer than this (deg) are one pose."""
MIN_TILT_DEG = 1.0
"""Default minimum tilt margin (deg) of a returned pose."""
NATURAL_DEG = 1.0
"""A pose whose support normal is within this (deg) of -z_O is O's own (natural) orientation."""
CACHE_SIZE = 32
ORIENTATIONS = ("stable", "natural", "most_probable")


@dataclass(frozen=True, eq=False)
class StablePose:
    """One resting orientation.

    ``R`` (3, 3): the rotation that takes O to the resting orientation (applied to O's
    coordinates, it turns ``normal_O`` to -z; the shortest such rotation, so O's own upright
    pose has R = I); a yaw about z may follow. ``normal_O`` (3,): outward unit normal, in O, of the
    convex hull's face the object rests on. ``probability``: chance of this pose after a random
    drop, renormalised over the returned poses; ``raw_probability`` trimesh's figure.
    ``tilt_margin_deg``: how far (deg) it can be tipped before it topples (see the module
    docstring); ``com_height`` (m) the centre of mass's height when resting; ``natural``: the
    pose is O's own orientation (normal within NATURAL_DEG of -z_O).
    """

    R: np.ndarray
    normal_O: np.ndarray
    probability: float
    raw_probability: float
    tilt_margin_deg: float
    com_height: float
    natural: bool


@dataclass(frozen=True, eq=False)
class StablePoses:
    """The stable poses of a mesh, most probable first (ties broken by the normal, so the order
    is deterministic), and how they were computed: ``com_O`` (3,) the centre of mass used,
    ``hull_faces`` the triangles of the hull analysed, ``simplified`` whether that hull was
    reduced to support points, ``seconds`` the compute time, ``notes`` anything unusual."""

    poses: tuple[StablePose, ...]
    com_O: np.ndarray
    hull_faces: int
    simplified: bool
    seconds: float
    notes: tuple[str, ...] = field(default=())

    def probabilities(self) -> np.ndarray:
        """(n,) probabilities (sum 1) in the order of ``poses``."""
        return np.array([p.probability for p in self.poses])

    def natural(self) -> StablePose | None:
        """O's own orientation if it is one of the stable poses, else None."""
        return next((p for p in self.poses if p.natural), None)

    def nearest(self, down_O=(0.0, 0.0, -1.0)) -> StablePose:
        """The stable pose whose support normal is closest to ``down_O`` (default -z_O: the
        pose nearest to O's own orientation)."""
        down = np.asarray(down_O, dtype=np.float64)
        return max(self.poses, key=lambda p: float(p.normal_O @ down))


_CACHE: OrderedDict[bytes, StablePoses] = OrderedDict()


def stable_poses(
    mesh: trimesh.Trimesh,
    com=None,
    *,
    min_tilt_deg: float = MIN_TILT_DEG,
    min_probability: float = 0.0,
    max_hull_faces: int = MAX_HULL_FACES,
    cache: bool = True,
) -> StablePoses:
    """Stable resting orientations of ``mesh`` (m, frame O) with their probabilities.

    ``com`` (3,): centre of mass in O (default: uniform density, from
    :func:`gbh_drake.objects.mass.mass_properties_detailed`). Poses with a tilt margin below
    ``min_tilt_deg`` or a raw probability below ``min_probability`` are left out (if that leaves
    none, the pose with the largest margin stays). See the module docstring.
    """
    vertices = np.asarray(mesh.vertices, dtype=np.float64)
    faces = np.asarray(mesh.faces)
    if com is None:
        from gbh_drake.objects.mass import mass_properties_detailed

        com = mass_properties_detailed(mesh, 1.0).com
    com = np.asarray(com, dtype=np.float64).reshape(3)
    key = _key(vertices, faces, com, (min_tilt_deg, min_probability, max_hull_faces))
    if cache and key in _CACHE:
        _CACHE.move_to_end(key)
        return _CACHE[key]
    result = _compute(vertices, com, min_tilt_deg, min_probability, max_hull_faces)
    if cache:
        _CACHE[key] = result
        while len(_CACHE) > CACHE_SIZE:
            _CACHE.popitem(last=False)
    return result


def sample_resting_pose(
    mesh: trimesh.Trimesh,
    rng: np.random.Generator,
    x_range=(0.0, 0.0),
    y_range=(0.0, 0.0),
    yaw_range=(-np.pi, np.pi),
    *,
    com=None,
    orientation: str = "stable",
    poses: StablePoses | None = None,
    R_rest=None,
) -> tuple[np.ndarray, dict]:
    """A random resting pose ``X_WO`` (4, 4) of ``mesh`` (frame O) on the table z = 0, and info.

    Draws, in this order and always all four (so that the position for a seed does not depend on
    ``orientation``): the stable pose (one uniform number against the cumulative
    probabilities), the yaw (rad, uniform in ``yaw_range``), x and y (m, uniform in ``x_range``,
    ``y_range``). ``X_WO`` rotates O by the stable pose's ``R``, then by the yaw about z, puts the
    centre of mass at (x, y) and the lowest point of the mesh at z = 0. Same generator state, same
    pose. Seed it with ``np.random.default_rng(seed)`` (numpy hashes the seed through a
    SeedSequence, so consecutive small seeds give unrelated draws). Drake's
    ``RandomGenerator(seed)`` (std::mt19937) is no worse statistically: the old sampler's seeds
    1-3 all landing near y = +5-6 cm was chance (see
    ``tests/objects/test_stability.py::test_drake_generator_was_not_the_cause_of_the_clustering``).

    ``orientation``: ``"stable"`` draws among :func:`stable_poses` by probability;
    ``"natural"`` keeps O's own orientation (R = I; right for the object set, whose frame O is
    its natural resting pose), or ``R_rest`` (3, 3) when given (an object's declared natural
    rest, :class:`~gbh_drake.objects.spec.NaturalRest`); ``"most_probable"`` always takes the
    most probable pose.
    ``com`` (3,) is the centre of mass in O (default: uniform density); ``poses`` precomputed
    :func:`stable_poses`.

    ``info``: ``pose_index`` (into ``poses.poses``, or -1 for ``"natural"`` when O's orientation
    is not among them), ``stable`` (False in that case: it will topple when released),
    ``probability``, ``natural``, ``normal_O``, ``tilt_margin_deg``, ``yaw``
    (rad), ``xy`` (m), ``com_W`` (3,), ``reach_xy`` (m: the largest horizontal distance of a
    vertex from the centre of mass, to keep the object inside a region) and ``num_poses``.
    """
    if orientation not in ORIENTATIONS:
        raise ValueError(f"orientation must be one of {ORIENTATIONS}, got {orientation!r}")
    ranges = [_check_range(name, r) for name, r in
              (("x_range", x_range), ("y_range", y_range), ("yaw_range", yaw_range))]
    if poses is None:
        poses = stable_poses(mesh, com)
    com = poses.com_O if com is None else np.asarray(com, dtype=np.float64).reshape(3)
    u = rng.random()
    yaw, x, y = (rng.uniform(lo, hi) for lo, hi in (ranges[2], ranges[0], ranges[1]))
    probs = poses.probabilities()
    if orientation == "stable":
        index = int(min(np.searchsorted(np.cumsum(probs), u * probs.sum(), side="right"),
                        len(probs) - 1))
    elif orientation == "most_probable":
        index = 0
    elif R_rest is None:
        natural = poses.natural()
        index = -1 if natural is None else poses.poses.index(natural)
    else:  # the stable pose that R_rest turns onto the table, if it is one
        R_rest = np.asarray(R_rest, dtype=np.float64).reshape(3, 3)
        down = R_rest.T @ np.array([0.0, 0.0, -1.0])
        near = poses.nearest(down)
        index = poses.poses.index(near) if near.normal_O @ down > np.cos(
            np.radians(NATURAL_DEG)) else -1
    pose = poses.poses[index] if index >= 0 else None
    if orientation == "natural":
        R_rest = np.eye(3) if R_rest is None else R_rest
    else:
        R_rest = pose.R
    R = _rot_z(yaw) @ R_rest
    vertices = np.asarray(mesh.vertices, dtype=np.float64)
    com_rot = R @ com
    z_low = float(np.min(vertices @ R[2]))
    X_WO = np.eye(4)
    X_WO[:3, :3] = R
    X_WO[:3, 3] = (x - com_rot[0], y - com_rot[1], -z_low)
    rel = vertices @ R[:2].T - com_rot[:2]
    info = {
        "pose_index": index,
        "probability": pose.probability if pose is not None else 0.0,
        "natural": bool(pose.natural) if pose is not None else True,
        "stable": pose is not None,
        "normal_O": pose.normal_O if pose is not None else np.array([0.0, 0.0, -1.0]),
        "tilt_margin_deg": pose.tilt_margin_deg if pose is not None else float("nan"),
        "yaw": float(yaw),
        "xy": np.array([x, y]),
        "com_W": X_WO[:3, :3] @ com + X_WO[:3, 3],
        "reach_xy": float(np.sqrt(np.max(np.einsum("ij,ij->i", rel, rel)))),
        "num_poses": len(poses.poses),
    }
    return X_WO, info


def rotation_to_down(normal) -> np.ndarray:
    """The shortest rotation (3, 3) taking the unit vector ``normal`` to -z (a half turn about x
    when ``normal`` is +z)."""
    n = np.asarray(normal, dtype=np.float64)
    n = n / np.linalg.norm(n)
    down = np.array([0.0, 0.0, -1.0])
    c = float(n @ down)
    if c < -1.0 + 1e-12:
        return np.diag([1.0, -1.0, -1.0])
    v = np.cross(n, down)
    vx = np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])
    return np.eye(3) + vx + vx @ vx / (1.0 + c)


# ---- internals -----------------------------------------------------------------------------------
def _compute(vertices, com, min_tilt_deg, min_probability, max_hull_faces) -> StablePoses:
    start = time.perf_counter()
    notes: list[str] = []
    hull, simplified = _hull(vertices, max_hull_faces)
    if hull is None:
        notes.append("degenerate (flat) mesh: one pose, O's own orientation")
        pose = StablePose(np.eye(3), np.array([0.0, 0.0, -1.0]), 1.0, 1.0, 0.0,
                          float(com[2] - vertices[:, 2].min()), True)
        return StablePoses((pose,), com, 0, False, time.perf_counter() - start, tuple(notes))
    if not _inside(hull, com):
        notes.append("centre of mass outside the convex hull: the hull's centroid is used")
        com = np.asarray(hull.center_mass, dtype=np.float64)
    # trimesh draws from numpy's global generator (to no effect with sigma = 0): restore it.
    state = np.random.get_state()  # noqa: NPY002
    try:
        transforms, raw = trimesh.poses.compute_stable_poses(hull, center_mass=com, sigma=0.0,
                                                             n_samples=1)
    finally:
        np.random.set_state(state)  # noqa: NPY002
    normals = [-np.asarray(tf[2, :3]) for tf in transforms]
    merged = _merge(normals, [float(p) for p in raw])
    hull_vertices = np.asarray(hull.vertices)
    scale = float(np.max(np.ptp(hull_vertices, axis=0)))
    poses = []
    for normal, prob in merged:
        R = rotation_to_down(normal)
        margin, height = _tilt_margin(hull_vertices @ R.T, R @ com, 1e-4 * scale)
        natural = bool(normal[2] < -np.cos(np.radians(NATURAL_DEG)))
        poses.append(StablePose(R, normal, prob, prob, margin, height, natural))
    kept = [p for p in poses if p.tilt_margin_deg >= min_tilt_deg
            and p.raw_probability >= min_probability]
    if not kept:
        best = max(poses, key=lambda p: p.tilt_margin_deg)
        notes.append(f"no pose with a tilt margin of {min_tilt_deg:g} deg or more: kept the "
                     f"steadiest ({best.tilt_margin_deg:.2f} deg)")
        kept = [best]
    total = sum(p.raw_probability for p in kept)
    kept = [StablePose(p.R, p.normal_O, p.raw_probability / total if total > 0 else 1.0 / len(kept),
                       p.raw_probability, p.tilt_margin_deg, p.com_height, p.natural)
            for p in kept]
    kept.sort(key=lambda p: (-round(p.probability, 9), *np.round(p.normal_O, 6)))
    for p in kept:
        for a in (p.R, p.normal_O):
            a.setflags(write=False)
    com = com.copy()
    com.setflags(write=False)
    return StablePoses(tuple(kept), com, len(hull.faces), simplified,
                       time.perf_counter() - start, tuple(notes))


def _hull(vertices: np.ndarray, max_faces: int) -> tuple[trimesh.Trimesh | None, bool]:
    """The convex hull to analyse (simplified to support points when large), or None if flat."""
    points, simplified = vertices, False
    if len(points) > EXACT_HULL_MAX_VERTICES:
        points, simplified = _support_points(points, max_faces // 2 + 2), True
    hull = _qhull(points)
    if hull is not None and len(hull.faces) > max_faces:
        hull, simplified = _qhull(_support_points(np.asarray(hull.vertices),
                                                  max_faces // 2 + 2)), True
    return hull, simplified


def _qhull(points: np.ndarray) -> trimesh.Trimesh | None:
    """The convex hull as an outward-wound trimesh, or None for flat or too few points."""
    if len(points) < 4:
        return None
    try:
        qh = ConvexHull(points, qhull_options="Qt")
    except (QhullError, ValueError):
        return None
    if qh.volume <= 1e-15 * max(1.0, float(np.max(np.ptp(points, axis=0))) ** 3):
        return None
    faces = np.array(qh.simplices, dtype=np.int64)
    tri = points[faces]
    normals = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    flip = np.einsum("ij,ij->i", normals, qh.equations[:, :3]) < 0  # qhull's are outward
    faces[flip] = faces[flip][:, ::-1]
    hull = trimesh.Trimesh(points[qh.vertices], _reindex(faces, qh.vertices), process=True)
    if not (hull.is_watertight and hull.volume > 0):
        return None
    return hull


def _reindex(simplices: np.ndarray, used: np.ndarray) -> np.ndarray:
    remap = np.full(int(used.max()) + 1, -1, dtype=np.int64)
    remap[used] = np.arange(len(used))
    return remap[simplices]


def _support_points(points: np.ndarray, n_directions: int) -> np.ndarray:
    """The points extreme in ``n_directions`` Fibonacci-sphere directions (unique, sorted)."""
    i = np.arange(n_directions) + 0.5
    z = 1.0 - 2.0 * i / n_directions
    r = np.sqrt(1.0 - z * z)
    phi = np.pi * (3.0 - np.sqrt(5.0)) * i
    # float32: 3x faster here, and a support point off by 1e-7 of the size does not matter.
    directions = np.column_stack([r * np.cos(phi), r * np.sin(phi), z]).astype(np.float32)
    centred = (points - points.mean(axis=0)).astype(np.float32)
    best = np.full(n_directions, -np.inf)
    index = np.zeros(n_directions, dtype=np.int64)
    chunk = 50_000
    for s in range(0, len(points), chunk):
        d = directions @ centred[s:s + chunk].T  # (directions, points): argmax along rows
        arg = np.argmax(d, axis=1)
        val = np.take_along_axis(d, arg[:, None], axis=1)[:, 0]
        better = val > best
        best[better], index[better] = val[better], arg[better] + s
    return points[np.unique(index)]


def _inside(hull: trimesh.Trimesh, point: np.ndarray) -> bool:
    """``point`` strictly inside the (convex, outward) hull."""
    gap = np.einsum("ij,ij->i", point - hull.triangles_center, hull.face_normals)
    return bool(np.all(gap < -1e-9 * max(1.0, float(np.max(hull.extents)))))


def _merge(normals, probs) -> list[tuple[np.ndarray, float]]:
    """Poses with normals within MERGE_DEG as one (the most probable one's normal), greedily in
    the order of decreasing probability."""
    if not len(normals):
        return []
    probs = np.asarray(probs, dtype=np.float64)
    order = np.argsort(-probs, kind="stable")
    n = np.asarray(normals, dtype=np.float64)[order]
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    p = probs[order]
    close = n @ n.T >= np.cos(np.radians(MERGE_DEG))
    leader = np.full(len(n), -1)
    for i in range(len(n)):
        if leader[i] < 0:
            leader[close[i] & (leader < 0)] = i
    heads = np.flatnonzero(leader == np.arange(len(n)))
    return [(n[h], float(p[leader == h].sum())) for h in heads]


def _tilt_margin(points_rest: np.ndarray, com_rest: np.ndarray, tol: float) -> tuple[float, float]:
    """``(tilt margin deg, com height m)`` of a pose: points (hull vertices) and CoM already
    rotated into it (normal -> -z); the support polygon is the points within ``tol`` of the
    lowest."""
    z_low = float(points_rest[:, 2].min())
    height = float(com_rest[2] - z_low)
    contact = points_rest[points_rest[:, 2] <= z_low + tol, :2]
    d = _inside_distance(contact, com_rest[:2])
    return float(np.degrees(np.arctan2(d, max(height, 1e-12)))), height


def _inside_distance(polygon_points: np.ndarray, p: np.ndarray) -> float:
    """Signed distance of ``p`` from the boundary of the convex hull of 2-D points (positive
    inside; 0 for a hull of no area)."""
    if len(polygon_points) < 3:
        return 0.0
    try:
        qh = ConvexHull(polygon_points)
    except (QhullError, ValueError):
        return 0.0
    # qhull's equations: n . x + offset <= 0 inside, n unit.
    return float(-np.max(qh.equations[:, :2] @ p + qh.equations[:, 2]))


def _rot_z(yaw: float) -> np.ndarray:
    c, s = np.cos(yaw), np.sin(yaw)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def _check_range(name: str, value) -> tuple[float, float]:
    try:
        lo, hi = (float(v) for v in value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be (min, max), got {value!r}") from None
    if not (np.isfinite(lo) and np.isfinite(hi) and lo <= hi):
        raise ValueError(f"{name} must be finite with min <= max, got {value!r}")
    return lo, hi


def _key(vertices, faces, com, options) -> bytes:
    h = hashlib.blake2b(digest_size=20)
    for a in (vertices, faces, com, np.asarray(options, dtype=np.float64)):
        a = np.ascontiguousarray(a)
        h.update(str((a.dtype, a.shape)).encode())
        h.update(a.tobytes())
    return h.digest()
