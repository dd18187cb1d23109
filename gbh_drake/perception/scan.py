"""A whole scan: find the object, aim the views at it, render, segment, fuse, cut and cap.

``scan_object`` works on a SceneGraph ``QueryObject``:

1. **First look** (``first_look``): two small, wide depth views from the sides of the nominal
   target T find the table plane (``table.fit_table_plane``) and the object's cluster
   (``segment.segment_points``: the cluster nearest T that rests on the table and is not the
   robot). If the object reaches the edge of those views, a second look is aimed at it from
   farther away.
2. **Aimed views**: the ``num_views`` views look at the centre of the object's bounding sphere
   from the distance at which the sphere fits the field of view (``viewpoints.fit_view_distance``).
3. **Segmentation**: the views' points near the object are segmented again (the clusters that
   touch what the first look saw are the object's, even when a view does not see where it rests
   on the table); only the object's pixels and the table's around it are fused (TSDF),
   everything else (robot, other objects) is dropped.
4. **Cut and cap**: the mesh is cut just above the table and its bottom capped, except where
   the cameras saw the table through the object (``cap.cap_bottom``).

``scan_depth_images`` does steps 3-4 from depth images already in hand (e.g. from a real camera).
Neither needs a running simulation. Problems that do not stop the scan (the object reaches an
image border or the workspace bound, no table plane found, ...) are listed in
``ScanResult.warnings``; an empty scan says why in ``message``.
"""

from __future__ import annotations

import dataclasses
import time
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
from pydrake.geometry import QueryObject
from pydrake.math import RigidTransform

from gbh_drake.core.free_space import FreeSpace
from gbh_drake.core.lazy import lazy_module
from gbh_drake.perception.camera import CameraIntrinsics, make_depth_camera, render_depth_images
from gbh_drake.perception.cap import CapReport, cap_bottom, cut_at_height
from gbh_drake.perception.cleanup import keep_large_components
from gbh_drake.perception.config import ScanConfig
from gbh_drake.perception.crop import CropBox
from gbh_drake.perception.depth import valid_depth
from gbh_drake.perception.fusion import integrate, masked_depths, view_points
from gbh_drake.perception.noise import sensor_depth
from gbh_drake.perception.segment import (
    ROI_MARGIN,
    ROI_SCALE,
    Segmentation,
    bounding_sphere,
    box_faces_reached,
    segment_points,
)
from gbh_drake.perception.self_filter import robot_masks, without_pixels
from gbh_drake.perception.table import TablePlane, fit_table_plane
from gbh_drake.perception.view_choice import chosen_config
from gbh_drake.perception.viewpoints import (
    camera_poses,
    first_look_poses,
    fit_view_distance,
    half_fov,
)

trimesh = lazy_module("trimesh")

#: Views fit the table (when no first look did) to every TABLE_FIT_STRIDE-th row and column's
#: points: 1.8 mm apart at 0.5 m in 640 x 480 images, several per the fit's 5 mm cells, a
#: quarter of the points (10 views: about 3 million points otherwise).
TABLE_FIT_STRIDE = 2


@dataclass
class ScanResult:
    """The scanned object in W. When ``empty``, ``mesh_W`` has no faces and ``message`` says
    why (nothing is raised)."""

    mesh_W: trimesh.Trimesh
    """The fused, segmented, cleaned mesh (m, in W), cut ``crop_z_min`` above the table and
    capped there except over holes the cameras saw the table through."""
    p_WQ: np.ndarray
    """Measured points (n, 3) of the object (m, in W), from all views."""
    X_WCs: list[RigidTransform] = field(default_factory=list)
    """Pose of each camera C in W."""
    intrinsics: CameraIntrinsics | None = None
    crop: CropBox | None = None
    """The workspace box (W): nothing outside it was scanned."""
    timing: dict[str, float] = field(default_factory=dict)
    """Wall-clock seconds of the stages, which add up to the whole scan: ``first_look`` (render
    and segment), ``view_choice`` (with ``view_choice`` ``holes`` or ``material``), ``render`` (the views),
    ``segment`` (noise, points, table and clusters), ``fuse`` (TSDF, cut, clean-up), ``cap``."""
    empty: bool = False
    message: str = ""
    warnings: list[str] = field(default_factory=list)
    """What may be wrong with a non-empty scan (e.g. the object reaches an image border or the
    workspace bound: part of it may be missing). Empty when all is well."""
    table: TablePlane | None = None
    """The table plane found (or assumed): ``table.as_ground()`` gives GbhParams' ground."""
    aim_W: np.ndarray | None = None
    """(3,) m: the point the views looked at (the object's centre when aimed, else T)."""
    view_distance: float = 0.0
    """Camera-to-``aim_W`` distance (m) of the views."""
    object_radius: float = 0.0
    """Radius (m) of the object's bounding sphere from the first look (0 if not aimed)."""
    first_look_X_WCs: list[RigidTransform] = field(default_factory=list)
    """Poses of the first look's cameras (not fused)."""
    cap: CapReport = field(default_factory=CapReport)
    """What capping the bottom did."""
    free_space: FreeSpace | None = None
    """What the cameras saw free: the fused views' depth images as measured (noise included,
    with the intrinsics and poses; :func:`free_space_margin`) and, after a first look, its two
    side views' (``first_look_free_space``, each view at its own margin). The GbH core treats
    the rest as possibly occupied (``GbhParams.unknown_is_occupied``). None for an empty scan."""
    taken_at: float = float("nan")
    """Simulated time (s) at which the ``Scanner`` took the scan; nan for a scan taken outside a
    simulation and for the Scanner's "not scanned yet" placeholder."""
    region: CropBox | None = None
    """The region the object was looked for in (the workspace box, around the first look's
    sphere when there was one): the scan says nothing beyond it."""
    first_look_free_space: FreeSpace | None = None
    """What the first look's two wide side views saw free (low resolution, not fused; its
    views are also in ``free_space``). None without a first look."""
    request: int = 0
    """Which scan request this answers: 0 for the Scanner's first scan, n for the scan taken on
    its ``scan_request`` input's n-th request (a re-scan after the object was set down anew)."""
    reframes: int = 0
    """How many times the views were re-framed because the object reached the edge of the
    region framed by the first look (see ``ScanConfig.reframe_tries``)."""
    target_W: np.ndarray | None = None
    """(3,) m: the scan target T the object was looked for around (the workspace box's
    centre, the segmentation's reference before anything was found)."""
    robot_masks: list[np.ndarray] | None = None
    """(h, w) bool per view of ``X_WCs``: the pixels that saw the robot itself (the self
    filter's, :mod:`~gbh_drake.perception.self_filter`; no measurement of the object, still in
    ``free_space``); None: none filtered. ``first_look_robot_masks``: the first look's."""
    first_look_robot_masks: list[np.ndarray] | None = None

    def __deepcopy__(self, memo) -> ScanResult:
        """The mesh, the arrays and the free space are shared, not copied: a scan is never
        modified once taken, and Drake copies abstract state at every unrestricted update
        (the Scanner's stillness watch), where a deep copy of the mesh cost ~2 ms each time.
        The lists and dicts are copied, so a copy's warnings can be extended on their own."""
        return dataclasses.replace(self, X_WCs=list(self.X_WCs), timing=dict(self.timing),
                                   warnings=list(self.warnings),
                                   first_look_X_WCs=list(self.first_look_X_WCs))

    @staticmethod
    def empty_result(message: str) -> ScanResult:
        """An empty result that says why there is no scan."""
        return ScanResult(trimesh.Trimesh(), np.zeros((0, 3)), empty=True, message=message)

    def o3d_mesh(self):
        """``mesh_W`` as an ``open3d.geometry.TriangleMesh`` (with vertex normals)."""
        from gbh_drake.core.o3d import open3d
        o3d = open3d()  # lazy: see gbh_drake.core.o3d

        mesh = o3d.geometry.TriangleMesh(o3d.utility.Vector3dVector(self.mesh_W.vertices),
                                         o3d.utility.Vector3iVector(self.mesh_W.faces))
        return mesh.compute_vertex_normals()


@dataclass
class FirstLook:
    """What the first look found: the table and the object's whereabouts."""

    X_WCs: list[RigidTransform]
    table: TablePlane
    p_W_object: np.ndarray
    """(n, 3) the object's points seen (empty if none)."""
    reference_W: np.ndarray | None = None
    """(3,) a point on the object (the one nearest T), to find it again."""
    centre_W: np.ndarray | None = None
    radius: float = 0.0
    warnings: list[str] = field(default_factory=list)
    message: str = ""
    """Why nothing was found ("" if the object was)."""
    free_space: FreeSpace | None = None
    """What the look's views (of its last round) saw free; None before they found the object."""
    robot_masks: list[np.ndarray] | None = None
    """(h, w) bool per view of its last round: the robot's own pixels (None: none filtered)."""

    @property
    def found(self) -> bool:
        return len(self.p_W_object) > 0


def scan_object(query_object: QueryObject, config: ScanConfig, p_WT, *,
                noise_seed: int = 0, robot_labels: frozenset[int] = frozenset()) -> ScanResult:
    """Scans the object near the target p_WT (m, in W) with ``config``'s views.

    ``query_object`` comes from the SceneGraph's ``query`` output port; its renderer
    ``config.renderer_name`` must exist. ``noise_seed`` seeds the depth noise (with
    ``config.noise``): same seed, same images, same mesh. With ``config.aim_views`` a first look
    finds the object and the views are aimed at it; the table, the robot and everything else
    are segmented away. ``robot_labels``: the render labels of the robot's own geometry
    (:func:`~gbh_drake.perception.self_filter.robot_labels`): its pixels are no measurement of
    the object (a self filter; empty: none)."""
    config.validate()
    p_WT = np.asarray(p_WT, dtype=float).reshape(3)
    start = time.perf_counter()
    look = first_look(query_object, config, p_WT, noise_seed=noise_seed,
                      robot_labels=robot_labels) if config.aim_views else None
    look_s = time.perf_counter() - start
    timing: dict[str, float] = {"first_look": look_s, "render": 0.0}
    config, choice = chosen_config(look, config)  # one view, chosen (view_choice: holes or material)
    if choice is not None:
        timing["view_choice"] = choice.seconds
    reframes = 0
    while True:
        result, aim, distance = _aimed_scan(query_object, config, p_WT, look, noise_seed, timing,
                                            robot_labels)
        if not (look is not None and look.found and _reaches_frame(result)):
            break
        if reframes >= config.reframe_tries:
            if reframes:
                result.warnings = [w + f" (still after {reframes} re-framings)"
                                   if w.startswith(FRAME_EDGE_WARNING) else w
                                   for w in result.warnings]
            break
        # The views saw more of the object than the first look framed: frame all of it seen so
        # far and look again.
        look = _reframed(look, result.p_WQ, config)
        reframes += 1
    result.aim_W, result.view_distance = np.asarray(aim, dtype=float), float(distance)
    result.reframes = reframes
    if look is not None:
        add_first_look(result, look)
    result.timing = timing
    return result


def add_first_look(result: ScanResult, look: FirstLook) -> None:
    """Records the first look in ``result`` (in place): its camera poses, the object's radius,
    its free space, also added to the scan's (each view at its own margin)."""
    result.first_look_X_WCs = look.X_WCs
    result.object_radius = look.radius
    result.first_look_free_space = look.free_space
    result.first_look_robot_masks = look.robot_masks
    if result.free_space is not None and look.free_space is not None:
        result.free_space = result.free_space.with_views(look.free_space)


#: The start of the warning that the object reaches the edge of the region framed by the first
#: look (``scan_object`` re-frames it, up to ``ScanConfig.reframe_tries`` times).
FRAME_EDGE_WARNING = "the object reaches the edge of the region framed by the first look"


def _aimed_scan(query_object: QueryObject, config: ScanConfig, p_WT: np.ndarray,
                look: FirstLook | None, noise_seed: int, timing: dict[str, float],
                robot_labels: frozenset[int] = frozenset()):
    """The views aimed at what ``look`` found (or at T), rendered and fused: (result, aim,
    distance); adds the stages' wall seconds to ``timing``."""
    aim, distance, warnings = p_WT, config.distance, []
    if look is not None and look.found:
        distance, limited = fit_view_distance(look.radius, config)
        aim = look.centre_W
        if limited:
            warnings.append(
                f"the object's bounding sphere (radius {look.radius:.3f} m) needs views from "
                f"{config.fov_margin * look.radius / np.sin(half_fov(config)):.2f} m to fit the "
                f"field of view; they are at distance_max = {config.distance_max:.2f} m")
    X_WCs = camera_poses(config, aim, distance)
    start = time.perf_counter()
    camera = make_depth_camera(config)
    depths = render_depth_images(query_object, camera, X_WCs)
    masks = robot_masks(query_object, camera, X_WCs, robot_labels) if robot_labels else None
    timing["render"] += time.perf_counter() - start
    result = scan_depth_images(depths, CameraIntrinsics.from_config(config), X_WCs, config, p_WT,
                               first_look=look, noise_seed=noise_seed, view_distance=distance,
                               robot_masks=masks)
    result.warnings = warnings + result.warnings
    for stage, seconds in result.timing.items():
        timing[stage] = timing.get(stage, 0.0) + seconds
    return result, aim, distance


def _reaches_frame(result: ScanResult) -> bool:
    """Whether the object the views segmented reaches the edge of the region framed by the
    first look (and not only the workspace bound)."""
    return not result.empty and any(w.startswith(FRAME_EDGE_WARNING) for w in result.warnings)


def _reframed(look: FirstLook, p_W_seen: np.ndarray, config: ScanConfig) -> FirstLook:
    """``look`` framing all of the object seen: its points and the views' ``p_W_seen`` (n, 3)
    (one per ``cluster_cell``, in a deterministic order), and their bounding sphere."""
    cells = np.floor(np.asarray(p_W_seen, dtype=float) / config.cluster_cell).astype(np.int64)
    _, first = np.unique(cells, axis=0, return_index=True)
    points = np.concatenate([look.p_W_object, np.asarray(p_W_seen)[np.sort(first)]]).astype(
        look.p_W_object.dtype)
    centre, radius = bounding_sphere(points, look.table)
    return dataclasses.replace(look, p_W_object=points, centre_W=centre,
                               radius=max(radius, look.radius), warnings=list(look.warnings))


def first_look(query_object: QueryObject, config: ScanConfig, p_WT, *,
               noise_seed: int = 0, robot_labels: frozenset[int] = frozenset()) -> FirstLook:
    """Finds the table and the object from two small wide views from the sides of p_WT (see
    ``viewpoints.first_look_poses``); looks again, aimed and farther, if the object reaches the
    edge of those views. Renders, then :func:`look_at_images` does the rest; ``robot_labels``:
    the robot's pixels are not the object's (see :func:`scan_object`)."""
    p_WT = np.asarray(p_WT, dtype=float).reshape(3)
    small = first_look_config(config)
    camera, intrinsics = make_depth_camera(small), CameraIntrinsics.from_config(small)
    rng = np.random.default_rng([int(noise_seed), 1])
    target, distance, reference = p_WT, config.first_look_distance, None
    look = None
    for _ in range(2):
        X_WCs = first_look_poses(config, target, distance)
        depths = render_depth_images(query_object, camera, X_WCs)
        if config.noise or config.depth_unit:
            depths = [sensor_depth(d, intrinsics, small, rng) for d in depths]
        masks = robot_masks(query_object, camera, X_WCs, robot_labels) if robot_labels else None
        look, at_border = look_at_images(depths, intrinsics, X_WCs, config, p_WT, look,
                                         reference=reference, distance=distance,
                                         robot_masks=masks)
        if not at_border:
            break
        # The object goes beyond the first look's images: look again, at it, from farther.
        target, reference = look.centre_W, look.reference_W
        distance = max(distance, 1.25 * config.fov_margin * look.radius / np.sin(
            half_fov(config)))
        distance = min(distance, config.depth_max - 2.0 * look.radius)
    return look


def first_look_config(config: ScanConfig) -> ScanConfig:
    """The first look's camera: ``config``'s with images ``first_look_scale`` times smaller
    (the same field of view)."""
    scale = config.first_look_scale
    return dataclasses.replace(config, width=max(config.width // scale, 8),
                               height=max(config.height // scale, 6))


def look_at_images(depths: Sequence[np.ndarray], intrinsics: CameraIntrinsics,
                   X_WCs: Sequence[RigidTransform], config: ScanConfig, p_WT,
                   look: FirstLook | None = None, *, reference=None, distance: float,
                   table: TablePlane | None = None, sensor_error: float | None = None,
                   robot_masks: Sequence[np.ndarray] | None = None
                   ) -> tuple[FirstLook, bool]:
    """One round of the first look on depth images in hand (h, w) float32 (m; 0 or inf: no
    measurement) taken from X_WC: (the look, whether the object reaches the images' border).

    The first round (``look`` None) fits the table to the images' points (or takes ``table``)
    and bounds the workspace around the target p_WT (m, in W); a later round keeps the
    previous round's table and keeps the previous round's findings when it finds nothing.
    The object is the cluster nearest ``reference`` (default p_WT), on a grid coarse enough
    for small images (two pixels' footprint at ``first_look_distance``). The views' free space
    (:func:`make_free_space`) has the margin for views at ``distance`` (m), or that of
    ``sensor_error`` (m) when given. ``robot_masks`` (one (h, w) bool per image): the robot's
    own pixels, no measurement of the table or the object, still of free space (see
    :func:`scan_depth_images`)."""
    p_WT = np.asarray(p_WT, dtype=float).reshape(3)
    seen = without_pixels(depths, robot_masks)  # the robot's own pixels: not the object
    if look is None:
        warning = ""
        if table is None:
            points = view_points(seen, intrinsics, X_WCs, CropBox.workspace(p_WT, config))
            table, warning = fit_table_plane(points.p_WQ, config)
        look = FirstLook(list(X_WCs), table, np.zeros((0, 3)),
                         warnings=[warning] if warning else [])
    box = CropBox.workspace(p_WT, config, _table_height_at(look.table, p_WT))
    # Clusters on a grid coarse enough for the small images' sampling: two pixels' footprint at
    # the look's distance (surfaces seen at up to 60 deg stay connected).
    footprint = 1.0 / intrinsics.fy  # (m per pixel at 1 m)
    coarse = dataclasses.replace(
        config, cluster_cell=max(config.cluster_cell, 2.0 * footprint * config.first_look_distance),
        min_cluster_points=max(5, config.min_cluster_points // config.first_look_scale ** 2),
        min_cell_points=1)
    points = view_points(seen, intrinsics, X_WCs, box)
    segmentation = segment_points(points.p_WQ, look.table, coarse, p_WT, box,
                                  reference=reference)
    if not segmentation.found:
        if not look.found:
            look.message = _nothing_found(segmentation.dropped, config, p_WT, box)
        return look, False
    p_W_object = points.p_WQ[segmentation.object_mask]
    look.X_WCs, look.p_W_object = list(X_WCs), p_W_object
    look.robot_masks = None if robot_masks is None else list(robot_masks)
    look.free_space = make_free_space(depths, intrinsics, X_WCs, config, distance,
                                      sensor_error=sensor_error)
    look.reference_W = p_W_object[np.argmin(np.linalg.norm(p_W_object - p_WT, axis=1))]
    look.centre_W, look.radius = bounding_sphere(p_W_object, look.table)
    return look, len(points.at_border(intrinsics, segmentation.object_mask)) > 0


def free_space_margin(config: ScanConfig, depth: float) -> float:
    """Margin (m) by which a point must be nearer than a pixel's measured depth to count as
    seen free (``FreeSpace.observed_free``), for views at about ``depth`` (m).

    One TSDF voxel (``voxel_size``): the fused surface, hence the object's samples, lies up to
    about a voxel from the measured depth (trilinear SDF, marching cubes), so without it the
    scan's own surface points would be "seen free" by the view that measured them. With
    ``config.noise``, plus three standard deviations of the axial noise at ``depth`` and one
    disparity step (a measured depth can lie that far behind the true surface). Noise-free at
    2.5 mm voxels: 2.5 mm; with noise at 0.6 m: about 7 mm."""
    return float(config.voxel_size + depth_error(config, depth))


def depth_error(config: ScanConfig, depth: float) -> float:
    """How far (m) a measured depth at about ``depth`` (m) may lie from the surface it hit:
    with ``config.noise``, three standard deviations of the axial noise and one disparity
    step; 0 without noise."""
    if not config.noise:
        return 0.0
    z = max(float(depth), config.depth_min)
    return float(3.0 * (config.noise_sigma + config.noise_sigma_quadratic * (z - 0.4) ** 2)
                 + config.noise_depth_step * z * z)


def make_free_space(depths: Sequence[np.ndarray], intrinsics: CameraIntrinsics,
                    X_WCs: Sequence[RigidTransform], config: ScanConfig, depth: float, *,
                    far_is_free: bool = True, sensor_error: float | None = None) -> FreeSpace:
    """The views' observed-free space (``core.free_space``) at :func:`free_space_margin`.
    ``far_is_free``: an ``inf`` pixel means nothing was hit up to ``config.depth_max`` (Drake's
    renderer); False for a sensor whose "no return" may hide a surface. ``sensor_error`` (m):
    how far a measured depth may lie from the surface it hit, when known (images in hand),
    instead of the noise model's :func:`depth_error` at ``depth``; the margin is then
    ``voxel_size`` plus it."""
    error = depth_error(config, depth) if sensor_error is None else float(sensor_error)
    return FreeSpace.from_depth_images(
        depths, intrinsics.fx, intrinsics.fy, intrinsics.cx, intrinsics.cy,
        [X_WC.inverse().GetAsMatrix4() for X_WC in X_WCs], float(config.voxel_size + error),
        config.depth_max if far_is_free else None, error)


def scan_depth_images(depths: Sequence[np.ndarray], intrinsics: CameraIntrinsics,
                      X_WCs: Sequence[RigidTransform], config: ScanConfig, p_WT, *,
                      first_look: FirstLook | None = None, noise_seed: int = 0,
                      view_distance: float | None = None, far_is_free: bool = True,
                      table: TablePlane | None = None, reference=None,
                      sensor_error: float | None = None,
                      pixel_masks: Sequence[np.ndarray] | None = None,
                      robot_masks: Sequence[np.ndarray] | None = None) -> ScanResult:
    """Fuses depth images (h, w) float32 (m; 0 or inf: no measurement) taken from X_WC into the
    mesh of the object near target p_WT (m, in W); makes them what the sensor delivers first
    (``noise.sensor_depth``: noise when ``config.noise``, seeded by ``noise_seed``, and whole
    ``depth_unit`` steps). The simulated scan renders its views and calls this; images
    from a real camera come here the same way (``gbh_drake.scan_grasps``).

    The table plane is fitted to the images' points (or ``table`` is taken as given) and the
    object is the cluster nearest ``reference`` (default p_WT; see ``segment.segment_points``),
    unless ``first_look`` (from :func:`first_look` or :func:`look_at_images`) already found
    them. ``pixel_masks`` (one (h, w) bool per image): only their pixels may be the object's.
    The images (noisy) are kept as ``free_space`` (:func:`make_free_space`, its margin for
    views at ``view_distance``, default ``config.distance``, or from ``sensor_error``;
    ``far_is_free``: an inf pixel saw nothing up to ``config.depth_max``, true of Drake's
    renderer). ``robot_masks`` (one (h, w) bool per image): the pixels that see the robot itself
    (:mod:`~gbh_drake.perception.self_filter`): no measurement of the object (the table fit,
    its points, segmentation and fusion), still measurements for free space."""
    start = time.perf_counter()
    p_WT = np.asarray(p_WT, dtype=float).reshape(3)
    timing: dict[str, float] = {}
    if config.noise or config.depth_unit:
        rng = np.random.default_rng(int(noise_seed))
        depths = [sensor_depth(d, intrinsics, config, rng) for d in depths]
    seen = without_pixels(depths, robot_masks)  # the robot's own pixels: not the object
    warnings: list[str] = list(first_look.warnings) if first_look is not None else []
    if first_look is not None:
        table = first_look.table
    elif table is None:
        # Every other pixel's point: still several per 5 mm cell the fit thins them to.
        points = view_points(seen, intrinsics, X_WCs, CropBox.workspace(p_WT, config),
                             stride=TABLE_FIT_STRIDE)
        table, warning = fit_table_plane(points.p_WQ, config)
        warnings += [warning] if warning else []
    box = CropBox.workspace(p_WT, config, _table_height_at(table, p_WT))
    region = box
    if first_look is not None and first_look.found:
        region = object_region(box, first_look.centre_W, first_look.radius)
    result = ScanResult(trimesh.Trimesh(), np.zeros((0, 3)), list(X_WCs), intrinsics, box,
                        table=table, aim_W=p_WT, view_distance=config.distance, region=region,
                        target_W=p_WT,
                        robot_masks=None if robot_masks is None else list(robot_masks))
    points = view_points(seen, intrinsics, X_WCs, region)
    looked = first_look is not None and first_look.found
    reference = first_look.reference_W if looked else reference
    segmentation = _segment(points, table, config, p_WT, box, reference,
                            first_look.p_W_object if looked else None, pixel_masks)
    result.p_WQ = points.p_WQ[segmentation.object_mask].astype(np.float64)
    timing["segment"] = time.perf_counter() - start

    message = _empty_reason(depths, points, segmentation, first_look, config, p_WT, box)
    blocked = _blocked_views(depths, X_WCs, config) if message else ""
    if blocked:
        message = message.removesuffix(IN_VIEW_QUESTION) + blocked
    if not message:
        t = time.perf_counter()
        low = np.flatnonzero(segmentation.low_mask)
        near = np.zeros(len(points.p_WQ), dtype=bool)
        near[low[_near_footprint(points.p_WQ[low], result.p_WQ, table, config.table_margin)]] = True
        keep = segmentation.object_mask | near
        mesh = integrate(masked_depths(seen, points, keep), intrinsics, X_WCs, config)
        mesh = cut_at_height(mesh, table, config.crop_z_min)
        mesh = keep_large_components(mesh, config.min_component_fraction)
        timing["fuse"] = time.perf_counter() - t
        t = time.perf_counter()
        if config.cap_bottom and len(mesh.faces):
            mesh, result.cap = cap_bottom(mesh, table, config, points.p_WQ[near])
        timing["cap"] = time.perf_counter() - t
        result.mesh_W = mesh
        distance = config.distance if view_distance is None else view_distance
        result.free_space = make_free_space(depths, intrinsics, X_WCs, config, distance,
                                            far_is_free=far_is_free, sensor_error=sensor_error)
        if len(mesh.faces) == 0:
            message = (f"empty scan: {len(result.p_WQ)} points of the object but fusion gave "
                       f"no surface (voxel {config.voxel_size} m)")
        warnings += _edge_warnings(points, segmentation, intrinsics, box, region, config)
    result.message, result.empty = message, bool(message)
    result.warnings = warnings
    result.timing = timing
    return result


def object_region(box: CropBox, centre_W: np.ndarray, radius: float) -> CropBox:
    """The region the views are read in around an object's bounding sphere (``centre_W``, m,
    ``radius``, m): a cube of half side ``ROI_SCALE`` x radius + ``ROI_MARGIN`` (room for what
    the first look may have missed, warned of if the object reaches its edge) within the
    workspace ``box``, down to the box's floor; the table beyond it is not read at all."""
    half = ROI_SCALE * radius + ROI_MARGIN
    c = np.asarray(centre_W, dtype=float)
    region = box.intersect(CropBox(tuple(c - half), tuple(c + half)))
    return CropBox((*region.lower_W[:2], box.lower_W[2]), region.upper_W)


def _segment(points, table: TablePlane, config: ScanConfig, p_WT: np.ndarray, box: CropBox,
             reference, known_W: np.ndarray | None,
             pixel_masks: Sequence[np.ndarray] | None) -> Segmentation:
    """``segment.segment_points`` on the views' ``points`` (``fusion.ViewPoints``); with
    ``pixel_masks``, the points above the table outside them are not the object's (nor
    clustered)."""
    if pixel_masks is None:
        return segment_points(points.p_WQ, table, config, p_WT, box, reference=reference,
                              known_W=known_W)
    in_mask = np.zeros(len(points.p_WQ), dtype=bool)
    for i, mask in enumerate(pixel_masks):
        mine = points.view == i
        in_mask[mine] = np.asarray(mask, dtype=bool)[points.v[mine], points.u[mine]]
    considered = np.flatnonzero(in_mask | (table.heights(points.p_WQ) < config.crop_z_min))
    part = segment_points(points.p_WQ[considered], table, config, p_WT, box,
                          reference=reference, known_W=known_W)
    whole = Segmentation(np.zeros(len(points.p_WQ), dtype=bool),
                         np.zeros(len(points.p_WQ), dtype=bool), table.heights(points.p_WQ),
                         part.dropped, part.touches)
    whole.object_mask[considered] = part.object_mask
    whole.low_mask[considered] = part.low_mask
    return whole


def _near_footprint(p_WQ: np.ndarray, p_W_object: np.ndarray, table: TablePlane,
                    margin: float) -> np.ndarray:
    """Mask (n,) of the points p_WQ (n, 3) within ``margin`` (m), along the table, of the box
    around the object's points p_W_object (m, 3) in the table's frame."""
    e = table.basis()[:, :2].T.astype(np.float32)
    footprint = p_W_object @ e.T
    lower, upper = footprint.min(axis=0) - margin, footprint.max(axis=0) + margin
    inside = np.ones(len(p_WQ), dtype=bool)
    for k in range(2):
        along = p_WQ[:, 0] * e[k, 0] + p_WQ[:, 1] * e[k, 1] + p_WQ[:, 2] * e[k, 2]
        inside &= (along >= lower[k]) & (along <= upper[k])
    return inside


def _table_height_at(table: TablePlane, p_WT: np.ndarray) -> float:
    """z (m) of the table plane under the point p_WT."""
    return float(table.point_W(p_WT)[2])


def _edge_warnings(points, segmentation, intrinsics: CameraIntrinsics, box: CropBox,
                   region: CropBox, config: ScanConfig) -> list[str]:
    """Warnings that the object reaches the edge of what the cameras see."""
    warnings = []
    views = points.at_border(intrinsics, segmentation.object_mask)
    if len(views):
        warnings.append(f"the object reaches the image border in {len(views)} of the views "
                        f"({views.tolist()}): part of it may be out of view and missing")
    if segmentation.touches:
        warnings.append(f"the object reaches the workspace bound ({', '.join(segmentation.touches)}"
                        f" of {_box_text(box)}): part of it may be outside and missing")
    if region is not box:
        inner = [face for face in box_faces_reached(points.p_WQ[segmentation.object_mask],
                                                    region, config.cluster_cell)
                 if face not in segmentation.touches]
        if inner:
            warnings.append(f"{FRAME_EDGE_WARNING} "
                            f"({', '.join(inner)} of {_box_text(region)}): it may be larger than "
                            "the first look saw")
    return warnings


def _box_text(box: CropBox) -> str:
    return f"{np.round(box.lower_W, 3).tolist()}-{np.round(box.upper_W, 3).tolist()} m (W)"


def _nothing_found(dropped: dict[str, int], config: ScanConfig, p_WT, box: CropBox) -> str:
    seen = ", ".join(f"{n} {reason}" for reason, n in dropped.items() if n)
    return (f"empty scan: nothing stands on the table within {config.object_search_radius} m of "
            f"the scan target {np.round(p_WT, 3).tolist()} in the workspace box {_box_text(box)}"
            + (f" (clusters dropped: {seen})" if seen else "") + IN_VIEW_QUESTION)


#: A view is blocked at the camera when at least this fraction of its pixels is nearer than
#: ``depth_min`` (Drake's depth images hold 0 there).
BLOCKED_FRACTION = 0.5
IN_VIEW_QUESTION = "; is the object at the scan target and in view of the cameras?"


def _blocked_views(depths, X_WCs, config: ScanConfig) -> str:
    """For an empty scan: why, when views are blocked at the camera (most of the image nearer
    than ``depth_min``: the camera is inside or against something, e.g. the robot's arm at its
    home pose); "" when no view is."""
    near = [float(np.mean(d == 0.0)) for d in depths]
    blocked = [(i, f) for i, f in enumerate(near) if f >= BLOCKED_FRACTION]
    if not blocked:
        return ""
    views = ", ".join(f"view {i} (camera at p_WC {np.round(X_WCs[i].translation(), 3).tolist()}"
                      f" m: {100 * f:.0f} % of its pixels)" for i, f in blocked)
    return (f"; blocked at the lens: {views} nearer than depth_min = {config.depth_min} m, "
            "something is in front of the camera (the robot at its home pose?); a larger object "
            "puts the views farther from it, up to distance_max")


def _empty_reason(depths, points, segmentation, first_look: FirstLook | None,
                  config: ScanConfig, p_WT, box: CropBox) -> str:
    """Why the scan is empty, or "" when it has the object's points."""
    n = len(depths)
    if not any(valid_depth(d).any() for d in depths):
        return (f"empty scan: none of the {n} depth images has a valid pixel (depth range "
                f"{config.depth_min}-{config.depth_max} m)")
    if len(points.p_WQ) == 0:
        return (f"empty scan: no depth pixel of the {n} views falls inside the workspace box "
                f"{_box_text(box)}" + IN_VIEW_QUESTION)
    if segmentation.found:
        return ""
    if first_look is not None and first_look.message:
        return first_look.message
    return _nothing_found(segmentation.dropped, config, p_WT, box)
