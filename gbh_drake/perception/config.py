"""The scan configuration: where the depth camera looks from, its image, the fusion and the crop.

Frames: W is the world (z up, table top at z = 0); T is the scan target, a point of W near the
object's centre that every camera looks at. Loadable with Drake's ``yaml_load_typed``.
"""

# (No ``from __future__ import annotations`` here: yaml_load_typed needs the field types as
# types, not strings.)
from dataclasses import dataclass

#: Viewpoint layouts: ``ring`` (all views at ``elevation_deg``) or ``spiral`` (views spread over
#: the band of the hemisphere from ``elevation_deg`` to ``elevation_max_deg``).
LAYOUTS = ("ring", "spiral")


@dataclass
class ScanConfig:
    """How the object is scanned (the paper: a Primesense camera, 10 views or 1 view, TSDF)."""

    # --- Viewpoints (around the target T) ---
    num_views: int = 10
    """Number of depth views (1: a single view from ``azimuth_deg``)."""
    layout: str = "spiral"
    """``spiral`` or ``ring`` (see ``LAYOUTS``); a ring at one elevation misses the inside of
    deep cups."""
    distance: float = 0.5
    """Camera-to-target distance (m); Primesense works from about 0.35 m."""
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

    # --- Workspace crop, in W: a box around T, above the table ---
    crop_half_size_xy: float = 0.15
    """Half the side of the crop box in x and y, centred on T (m)."""
    crop_z_min: float = 0.004
    """Mesh parts below this height are removed with the table (m)."""
    crop_z_max: float = 0.3
    """Top of the crop box (m); keep it below the robot's hand."""
    min_component_fraction: float = 0.05
    """Connected mesh parts with fewer triangles than this fraction of the largest are dropped."""

    # --- Depth noise (Kinect/Primesense-like; off by default) ---
    noise: bool = False
    """Whether to corrupt the depth images (see ``gbh_drake.perception.noise``)."""
    noise_seed: int = 0
    """Seed of the noise: the same seed gives the same images, hence the same mesh."""
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
            ("width", self.width > 0 and self.height > 0, "image size must be positive"),
            ("fov_y_deg", 0 < self.fov_y_deg < 180, "must be in (0, 180)"),
            ("depth_min", 0 < self.depth_min < self.depth_max, "need 0 < depth_min < depth_max"),
            ("voxel_size", self.voxel_size > 0, "must be positive"),
            ("sdf_trunc", self.sdf_trunc >= 2 * self.voxel_size, "must be >= 2 voxel_size"),
            ("crop_z_max", self.crop_z_max > self.crop_z_min, "must exceed crop_z_min"),
            ("crop_half_size_xy", self.crop_half_size_xy > 0, "must be positive"),
            ("min_component_fraction", 0 <= self.min_component_fraction <= 1,
             "must be in [0, 1]"),
            ("noise_grazing_deg", 0 < self.noise_grazing_deg <= 90, "must be in (0, 90]"),
        ]
        for name, ok, message in checks:
            if not ok:
                raise ValueError(f"ScanConfig.{name}: {message}")
