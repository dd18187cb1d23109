"""The scan configuration: where the depth camera looks from, its image, the fusion, the
segmentation of the object from the scene and the capping of its bottom.

Frames: W is the world (z up, table top at z = 0 by default); T is the scan target, the nominal
spot of W where the object is expected. A first look from T finds the object; the views are then
aimed at the object's centre (see ``gbh_drake.perception.scan``). Loadable with Drake's
``yaml_load_typed``.
"""

# (No ``from __future__ import annotations`` here: yaml_load_typed needs the field types as
# types, not strings.)
from dataclasses import dataclass, field

#: Viewpoint layouts: ``ring`` (all views at ``elevation_deg``) or ``spiral`` (views spread over
#: the band of the hemisphere from ``elevation_deg`` to ``elevation_max_deg``).
LAYOUTS = ("ring", "spiral")


@dataclass
class ScanConfig:
    """How the object is scanned (the paper: a Primesense camera, 10 views or 1 view, TSDF)."""

    # --- Viewpoints (around the object's centre, or around T when ``aim_views`` is off) ---
    num_views: int = 10
    """Number of depth views (1: a single view from ``azimuth_deg``)."""
    layout: str = "spiral"
    """``spiral`` or ``ring`` (see ``LAYOUTS``); a ring at one elevation misses the inside of
    deep cups."""
    distance: float = 0.5
    """Camera-to-centre distance (m) of the views, and the least one when they are aimed: views
    move farther (up to ``distance_max``) only when the object needs it to fit the field of
    view. Primesense works from about 0.35 m."""
    distance_max: float = 1.0
    """Farthest camera-to-centre distance (m) of aimed views; a larger object is scanned from
    here and gets a warning if it reaches the image border."""
    aim_views: bool = True
    """Aim the views at the object: a first look from T finds the object's cluster, then the
    views look at the centre of its bounding sphere from a distance at which the sphere fits the
    field of view (with ``fov_margin``). False: the views look at T from ``distance``."""
    fov_margin: float = 1.15
    """The object's bounding sphere, enlarged by this factor, must fit the narrower half field
    of view of aimed views."""
    first_look_distance: float = 0.8
    """Camera-to-T distance (m) of the first look (wide: it must see the whole object)."""
    first_look_elevation_deg: float = 60.0
    """Elevation (deg) of the first look's two views, which look from the sides (azimuth
    ``azimuth_deg`` +-90: away from the robot's side)."""
    first_look_scale: int = 4
    """The first look's images are ``width`` / scale x ``height`` / scale pixels (same field of
    view); it is only for finding and framing the object."""
    elevation_deg: float = 40.0
    """Elevation of the views above the horizontal plane through T (deg); the lowest for spiral."""
    elevation_max_deg: float = 70.0
    """Highest elevation of a ``spiral`` layout (deg); unused by ``ring``."""
    azimuth_deg: float = 180.0
    """Azimuth of the first view about +z_W, from +x_W (deg); 180 puts it on the robot's side
    for an object in front of the robot (+x_W)."""

    # --- Camera (pinhole, depth in metres) ---
    width: int = 640
    """Image width (pixels)."""
    height: int = 480
    """Image height (pixels)."""
    fov_y_deg: float = 45.0
    """Vertical field of view (deg); Primesense: about 45."""
    depth_min: float = 0.2
    """Nearest measured depth (m); closer pixels are invalid."""
    depth_max: float = 1.5
    """Farthest measured depth (m); farther pixels are invalid."""

    # --- TSDF fusion ---
    voxel_size: float = 0.0025
    """TSDF voxel edge (m)."""
    sdf_trunc: float = 0.01
    """TSDF truncation distance (m), a few voxels."""

    # --- Workspace and segmentation (the object is segmented, not cropped by a fixed box) ---
    crop_half_size_xy: float = 0.6
    """Half side (m) of the workspace box around T in x and y: nothing outside it is scanned. A
    generous bound, not the object's box: the object is segmented inside it. (Before the
    segmentation this was a tight +-0.15 m crop box.)"""
    crop_z_max: float = 0.6
    """Top of the workspace box: height above the table (m)."""
    crop_z_min: float = 0.004
    """Height above the table (m) below which points and mesh parts go with the table; the mesh
    is cut there and its bottom capped (see ``cap_bottom``)."""
    min_component_fraction: float = 0.05
    """Connected mesh parts with fewer triangles than this fraction of the largest are dropped."""
    table_height: float = 0.0
    """Expected height (m, z in W) of the horizontal table top. The plane is fitted to the depth
    data (RANSAC); a fit within ``table_tolerance`` of this is snapped to it, a fit elsewhere is
    used as found, and with no plane in the data this one is assumed (with a warning)."""
    table_margin: float = 0.04
    """The table is fused (its rays carve free space around the object, then it is cut away)
    only within this horizontal distance (m) of the object's footprint box."""
    table_tolerance: float = 0.002
    """How far (m) a point may be from the table plane and count as the table (RANSAC inlier
    distance), and how close a fitted plane must be to ``table_height`` to be snapped to it."""
    cluster_cell: float = 0.005
    """Edge (m) of the grid cells whose face-, edge- and corner-neighbours form the connected
    clusters of points above the table: gaps of 2 cells or more always separate clusters."""
    object_search_radius: float = 0.3
    """The object is the cluster nearest T among those that come within this horizontal
    distance (m) of T, rest on the table and keep clear of the robot's base."""
    support_gap: float = 0.02
    """A cluster rests on the table if its lowest point is at most this high (m); the robot's
    hand above the object does not."""
    robot_base_xy: list[float] = field(default_factory=lambda: [0.0, 0.0])
    """Where (m, x and y in W) the robot stands; clusters within ``robot_clearance`` of it are the
    robot's (it may be partly in view)."""
    robot_clearance: float = 0.2
    """Horizontal distance (m) from ``robot_base_xy`` within which a cluster is the robot."""
    min_cluster_points: int = 50
    """Clusters with fewer points are noise."""
    min_cell_points: int = 3
    """Grid cells with fewer points are empty when clustering (depth noise rising above the
    table leaves isolated points; an object's surface fills its cells). The first look, with
    its small images, takes every point."""

    # --- Capping the bottom (the table hides it) ---
    cap_bottom: bool = True
    """Close the scanned mesh where it was cut at the table, except where the cameras saw the
    table through it (a real hole, e.g. a key ring lying flat)."""
    cap_height: float = 0.02
    """Open boundaries of the mesh up to this height (m) above the cut count as its bottom (the
    cameras never see under an object's rounded or bevelled foot): they are capped too, with a
    skirt down to the cut."""
    cap_gap: float = 0.006
    """Gaps narrower than 2 x this (m) in the cut's outline are bridged before deciding what it
    encloses."""
    hole_evidence_fraction: float = 0.3
    """An enclosed region of the cut stays open when at least this fraction of its core (farther
    than ``cap_gap`` from its outline) was seen at table height: the cameras saw the table
    through the object."""

    # --- Depth noise (Kinect/Primesense-like; off by default) ---
    noise: bool = False
    """Whether to corrupt the depth images (see ``gbh_drake.perception.noise``)."""
    noise_sigma: float = 0.0012
    """Axial noise standard deviation at 0.4 m depth (m)."""
    noise_sigma_quadratic: float = 0.0019
    """Growth of the axial standard deviation with depth: sigma + k (z - 0.4)^2 (1/m)."""
    noise_depth_step: float = 0.00285
    """Disparity quantisation: depth steps of noise_depth_step * z^2 (1/m); 0 turns it off."""
    noise_grazing_deg: float = 70.0
    """Pixels seen at more than this angle from the surface normal start dropping out (deg);
    all are dropped at 90."""

    # --- Renderer ---
    renderer_name: str = "default"
    """SceneGraph render engine used for the depth images."""

    def validate(self) -> None:
        """Raises ``ValueError`` naming the first invalid field."""
        checks = [
            ("num_views", self.num_views >= 1, "must be >= 1"),
            ("layout", self.layout in LAYOUTS, f"must be one of {LAYOUTS}"),
            ("distance", self.distance > 0, "must be positive"),
            ("distance_max", self.distance_max >= self.distance, "must be >= distance"),
            ("fov_margin", self.fov_margin >= 1.0, "must be >= 1"),
            ("first_look_distance", self.first_look_distance > 0, "must be positive"),
            ("first_look_elevation_deg", 0 < self.first_look_elevation_deg < 90,
             "must be in (0, 90)"),
            ("first_look_scale", self.first_look_scale >= 1, "must be >= 1"),
            ("width", self.width > 0 and self.height > 0, "image size must be positive"),
            ("fov_y_deg", 0 < self.fov_y_deg < 180, "must be in (0, 180)"),
            ("depth_min", 0 < self.depth_min < self.depth_max, "need 0 < depth_min < depth_max"),
            ("voxel_size", self.voxel_size > 0, "must be positive"),
            ("sdf_trunc", self.sdf_trunc >= 2 * self.voxel_size, "must be >= 2 voxel_size"),
            ("crop_z_max", self.crop_z_max > self.crop_z_min, "must exceed crop_z_min"),
            ("crop_z_min", self.crop_z_min > 0, "must be positive"),
            ("crop_half_size_xy", self.crop_half_size_xy > 0, "must be positive"),
            ("table_margin", self.table_margin >= 0, "must be >= 0"),
            ("table_tolerance", 0 < self.table_tolerance < self.crop_z_min,
             "must be in (0, crop_z_min)"),
            ("cluster_cell", self.cluster_cell > 0, "must be positive"),
            ("object_search_radius", self.object_search_radius > 0, "must be positive"),
            ("support_gap", self.support_gap >= 0, "must be >= 0"),
            ("robot_base_xy", len(self.robot_base_xy) == 2, "needs 2 coordinates (x, y)"),
            ("robot_clearance", self.robot_clearance >= 0, "must be >= 0"),
            ("min_cluster_points", self.min_cluster_points >= 1, "must be >= 1"),
            ("min_cell_points", self.min_cell_points >= 1, "must be >= 1"),
            ("cap_height", self.cap_height >= 0, "must be >= 0"),
            ("cap_gap", self.cap_gap >= 0, "must be >= 0"),
            ("hole_evidence_fraction", 0 < self.hole_evidence_fraction <= 1,
             "must be in (0, 1]"),
            ("min_component_fraction", 0 <= self.min_component_fraction <= 1,
             "must be in [0, 1]"),
            ("noise_grazing_deg", 0 < self.noise_grazing_deg <= 90, "must be in (0, 90]"),
        ]
        for name, ok, message in checks:
            if not ok:
                raise ValueError(f"ScanConfig.{name}: {message}")
