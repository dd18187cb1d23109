"""The scan configuration: where the depth camera looks from, its image, the fusion, the
segmentation of the object from the scene and the capping of its bottom.

Frames: W is the world (z up, table top at z = 0 by default); T is the scan target, the nominal
spot of W where the object is expected. A first look from T finds the object; the views are then
aimed at the object's centre (see ``gbh_drake.perception.scan``). Loadable with Drake's
``yaml_load_typed``.
"""

# (No ``from __future__ import annotations`` here: yaml_load_typed needs the field types as
# types, not strings.)
from dataclasses import dataclass

from gbh_drake.core.ranges import (
    FieldError,
    Int,
    Items,
    NonNeg,
    OneOf,
    Pos,
    Range,
    Relation,
    checker,
    ranged,
)

#: Viewpoint layouts: ``ring`` (all views at ``elevation_deg``) or ``spiral`` (views spread over
#: the band of the hemisphere from ``elevation_deg`` to ``elevation_max_deg``).
LAYOUTS = ("spiral", "ring")
#: How a one-view scan's view is chosen: ``fixed`` (from ``azimuth_deg``, ``elevation_deg``),
#: ``holes`` (the candidate view that sees through the first look's candidate holes best) or
#: ``material`` (the candidate view that sees most of the material round them;
#: ``perception.view_choice``).
VIEW_CHOICES = ("fixed", "holes", "material")
#: Pixels a scan may render and fuse in all (views x width x height).
MAX_SCAN_PIXELS = 40_000_000
#: A camera distance's bounds: what the camera measures.
_BETWEEN_DEPTHS = (Relation(">", "depth_min", "the camera would measure nothing there"),
                   Relation("<", "depth_max", "the camera would measure nothing there"))


@dataclass
class ScanConfig:
    """How the object is scanned (the paper: a Primesense camera, 10 views or 1 view, TSDF)."""

    # --- Viewpoints (around the object's centre, or around T when ``aim_views`` is off) ---
    num_views: int = ranged(10, Int(1, 100))
    """Number of depth views (1: a single view from ``azimuth_deg``)."""
    layout: str = ranged("spiral", OneOf(LAYOUTS))
    """``spiral`` or ``ring`` (see ``LAYOUTS``); a ring at one elevation misses the inside of
    deep cups."""
    distance: float = ranged(0.5, Pos(5.0, "m"), relations=_BETWEEN_DEPTHS)
    """Camera-to-centre distance (m) of the views, and the least one when they are aimed: views
    move farther (up to ``distance_max``) only when the object needs it to fit the field of
    view. Primesense works from about 0.35 m."""
    distance_max: float = ranged(1.0, Pos(5.0, "m"),
                                 relations=(Relation(">=", "distance", "aimed views back off "
                                                     "from distance up to this"),
                                            *_BETWEEN_DEPTHS))
    """Farthest camera-to-centre distance (m) of aimed views; a larger object is scanned from
    here and gets a warning if it reaches the image border."""
    aim_views: bool = True
    """Aim the views at the object: a first look from T finds the object's cluster, then the
    views look at the centre of its bounding sphere from a distance at which the sphere fits the
    field of view (with ``fov_margin``). False: the views look at T from ``distance``."""
    fov_margin: float = ranged(1.15, Range(1.0, 10.0))
    """The object's bounding sphere, enlarged by this factor, must fit the narrower half field
    of view of aimed views."""
    first_look_distance: float = ranged(0.8, Pos(5.0, "m"), relations=_BETWEEN_DEPTHS)
    """Camera-to-T distance (m) of the first look (wide: it must see the whole object)."""
    first_look_elevation_deg: float = ranged(
        60.0, Range(0.0, 90.0, lo_open=True, hi_open=True, unit="deg"))
    """Elevation (deg) of the first look's two views, which look from the sides (azimuth
    ``azimuth_deg`` +-90: away from the robot's side)."""
    first_look_scale: int = ranged(4, Int(1, 64))
    """The first look's images are ``width`` / scale x ``height`` / scale pixels (same field of
    view); it is only for finding and framing the object."""
    reframe_tries: int = ranged(3, Int(0, 10))
    """How many times the views are re-framed when the object they segment reaches the edge of
    the region the first look framed (the first look saw only part of it): the region is grown
    to the sphere around all the object seen so far, the views re-aimed and backed off to fit it,
    and the scan taken again. 0: never (the warning stays)."""

    view_choice: str = ranged("fixed", OneOf(VIEW_CHOICES))
    """With one view (``num_views: 1``): ``fixed``, the view from ``azimuth_deg`` and
    ``elevation_deg`` (the paper's one view); ``holes``, the candidate view that sees the
    first look's candidate holes best (``perception.view_choice``: a next-best-view score over
    the fixed view and a spiral of ``view_candidates`` views, each aimed and backed off as the
    fixed one: through the hole, ``core.view_choice.hole_view_scores``); ``material``, the
    candidate that sees most of the material round them, as the first look's model has it
    (``core.view_choice.material_view_scores``). Ignored with more than one view."""
    view_candidates: int = ranged(10, Int(1, 100))
    """With ``view_choice`` ``holes`` or ``material``: how many candidate views besides the
    fixed one (a spiral over the band ``elevation_deg``-``elevation_max_deg``, the layout of
    as many views: for 10, the ten-view scan's)."""

    # --- When to scan (the Scanner with a scan time and the object's state connected) ---
    still_speed: float = ranged(0.003, Pos(1.0, "m/s"))
    """The object is still when the speed of its origin is below this (m/s) and its angular
    speed below ``still_angular_speed_deg``. An object at rest on the table creeps at about
    1e-5 m/s and 0.02 deg/s in the plant (SAP's regularised friction); a bottle rolling or
    rocking moves at 10-150 mm/s and 10-200 deg/s: 3 mm/s is far above the one, far below the
    other, and drifts under 1 cm in the few seconds before the hook arrives."""
    still_angular_speed_deg: float = ranged(3.0, Pos(360.0, "deg/s"))
    """Angular speed (deg/s) under which the object is still (3 deg/s: a 3 cm radius rolling at
    1.6 mm/s)."""
    still_dwell: float = ranged(0.2, NonNeg(10.0, "s"))
    """How long (s) the object must stay still before it is scanned: longer than an object
    rocking on its rim spends near a turning point, and 2-3 time constants sqrt(l / g) of an
    object of 5-20 cm starting to tip (0.07-0.14 s), so one that is falling over shows it."""
    still_max_wait: float = ranged(3.0, NonNeg(60.0, "s"))
    """The scan is taken at the latest this long (s) after the scan time even if the object is
    still moving (with a warning)."""
    still_period: float = ranged(0.01, Pos(1.0, "s"))
    """How often (s) the Scanner watches the object's speed."""
    elevation_deg: float = ranged(
        40.0, Range(0.0, 89.0, unit="deg",
                    note="90 would look straight down, where the view's up is undefined"))
    """Elevation of the views above the horizontal plane through T (deg); the lowest for spiral."""
    elevation_max_deg: float = ranged(70.0, Range(0.0, 89.0, unit="deg"),
                                      relations=(Relation(">=", "elevation_deg", "a spiral's "
                                                          "views rise from elevation_deg to this"),))
    """Highest elevation of a ``spiral`` layout (deg); unused by ``ring``."""
    azimuth_deg: float = ranged(180.0, Range(-360.0, 360.0, unit="deg"))
    """Azimuth of the first view about +z_W, from +x_W (deg); 180 puts it on the robot's side
    for an object in front of the robot (+x_W)."""

    # --- Camera (pinhole, depth in metres) ---
    width: int = ranged(640, Int(16, 4096, "each view renders and fuses width x height pixels"))
    """Image width (pixels)."""
    height: int = ranged(480, Int(16, 4096, "each view renders and fuses width x height pixels"))
    """Image height (pixels)."""
    fov_y_deg: float = ranged(45.0, Range(1.0, 170.0, unit="deg"))
    """Vertical field of view (deg); Primesense: about 45."""
    depth_min: float = ranged(0.2, Pos(10.0, "m"))
    """Nearest measured depth (m); closer pixels are invalid."""
    depth_max: float = ranged(1.5, Pos(10.0, "m"), relations=(
        Relation(">", "depth_min", "no depth would be measured"),))
    """Farthest measured depth (m); farther pixels are invalid."""

    # --- TSDF fusion ---
    voxel_size: float = ranged(
        0.0025, Range(0.001, 0.05, unit="m", note="smaller voxels take minutes and gigabytes of TSDF"))
    """TSDF voxel edge (m)."""
    sdf_trunc: float = ranged(0.01, Pos(0.2, "m"), relations=(
        Relation(">=", "voxel_size", "the TSDF needs a band of two voxels", factor=2.0),))
    """TSDF truncation distance (m), a few voxels."""

    # --- Workspace and segmentation (the object is segmented, not cropped by a fixed box) ---
    crop_half_size_xy: float = ranged(0.6, Pos(2.0, "m"))
    """Half side (m) of the workspace box around T in x and y: nothing outside it is scanned. A
    generous bound, not the object's box: the object is segmented inside it. (Before the
    segmentation this was a tight +-0.15 m crop box.)"""
    crop_z_max: float = ranged(0.6, Pos(2.0, "m"), relations=(
        Relation(">", "crop_z_min", "the workspace would be empty"),))
    """Top of the workspace box: height above the table (m)."""
    crop_z_min: float = ranged(0.004, Pos(0.5, "m"))
    """Height above the table (m) below which points and mesh parts go with the table; the mesh
    is cut there and its bottom capped (see ``cap_bottom``)."""
    min_component_fraction: float = ranged(0.05, NonNeg(1.0))
    """Connected mesh parts with fewer triangles than this fraction of the largest are dropped."""
    table_height: float = ranged(0.0, Range(-1.0, 1.0, unit="m"))
    """Expected height (m, z in W) of the horizontal table top. The plane is fitted to the depth
    data (RANSAC); a fit within ``table_tolerance`` of this is snapped to it, a fit elsewhere is
    used as found, and with no plane in the data this one is assumed (with a warning)."""
    table_margin: float = ranged(0.04, NonNeg(1.0, "m"))
    """The table is fused (its rays carve free space around the object, then it is cut away)
    only within this horizontal distance (m) of the object's footprint box."""
    table_tolerance: float = ranged(0.002, Pos(0.05, "m"), relations=(
        Relation("<", "crop_z_min", "points counted as the table must lie below the cut"),))
    """How far (m) a point may be from the table plane and count as the table (RANSAC inlier
    distance), and how close a fitted plane must be to ``table_height`` to be snapped to it."""
    cluster_cell: float = ranged(
        0.005, Range(0.001, 0.1, unit="m", note="smaller cells make millions of cells"))
    """Edge (m) of the grid cells whose face-, edge- and corner-neighbours form the connected
    clusters of points above the table: gaps of 2 cells or more always separate clusters."""
    object_search_radius: float = ranged(0.3, Pos(2.0, "m"))
    """The object is the cluster nearest T among those that come within this horizontal
    distance (m) of T, rest on the table and keep clear of the robot's base."""
    support_gap: float = ranged(0.02, NonNeg(0.5, "m"))
    """A cluster rests on the table if its lowest point is at most this high (m); the robot's
    hand above the object does not."""
    robot_base_xy: list[float] = ranged(lambda: [0.0, 0.0], Items(2, what="coordinates (x, y in m)"))
    """Where (m, x and y in W) the robot stands; clusters within ``robot_clearance`` of it are the
    robot's (it may be partly in view)."""
    robot_clearance: float = ranged(0.2, NonNeg(2.0, "m"))
    """Horizontal distance (m) from ``robot_base_xy`` within which a cluster is the robot."""
    min_cluster_points: int = ranged(50, Int(1, 10_000_000))
    """Clusters with fewer points are noise."""
    min_cell_points: int = ranged(3, Int(1, 1_000_000))
    """Grid cells with fewer points are empty when clustering (depth noise rising above the
    table leaves isolated points; an object's surface fills its cells). The first look, with
    its small images, takes every point."""

    # --- Capping the bottom (the table hides it) ---
    cap_bottom: bool = True
    """Close the scanned mesh where it was cut at the table, except where the cameras saw the
    table through it (a real hole, e.g. a key ring lying flat)."""
    cap_height: float = ranged(0.02, NonNeg(0.5, "m"))
    """Open boundaries of the mesh up to this height (m) above the cut count as its bottom (the
    cameras never see under an object's rounded or bevelled foot): they are capped too, with a
    skirt down to the cut."""
    cap_gap: float = ranged(0.006, NonNeg(0.1, "m"))
    """Gaps narrower than 2 x this (m) in the cut's outline are bridged before deciding what it
    encloses."""
    hole_evidence_fraction: float = ranged(0.3, Range(0.0, 1.0, lo_open=True))
    """An enclosed region of the cut stays open when at least this fraction of its core (farther
    than ``cap_gap`` from its outline) was seen at table height: the cameras saw the table
    through the object."""

    # --- Depth noise (Kinect/Primesense-like; off by default) ---
    noise: bool = False
    """Whether to corrupt the depth images (see ``gbh_drake.perception.noise``)."""
    noise_sigma: float = ranged(0.0012, NonNeg(0.1, "m"))
    """Axial noise standard deviation at 0.4 m depth (m)."""
    noise_sigma_quadratic: float = ranged(0.0019, NonNeg(1.0, "1/m"))
    """Growth of the axial standard deviation with depth: sigma + k (z - 0.4)^2 (1/m)."""
    noise_depth_step: float = ranged(0.00285, NonNeg(0.1, "1/m"))
    """Disparity quantisation: depth steps of noise_depth_step * z^2 (1/m); 0 turns it off."""
    noise_grazing_deg: float = ranged(70.0, Range(0.0, 90.0, lo_open=True, unit="deg"))
    """Pixels seen at more than this angle from the surface normal start dropping out (deg);
    all are dropped at 90."""
    depth_unit: float = ranged(0.0, Range(0.0, 0.01, unit="m", note="0: the renderer's floats"))
    """The sensor's depth unit (m): it delivers each depth in whole units, as a 16-bit depth
    image holds them (Primesense and RealSense: 0.001, millimetres; 0.0001 keeps tenths), after
    the noise. 0 (default): the renderer's float depths. With it, the views ``gbh run
    --save-views`` writes as 16-bit PNG are the very depths the scan fused."""

    # --- Renderer ---
    renderer_name: str = "default"
    """SceneGraph render engine used for the depth images."""

    validate = checker(ValueError)

    def check_relations(self, at: tuple = ()) -> None:
        """The rules between fields no :class:`Relation` states (``at``: where this config is,
        for the messages)."""
        pixels = self.num_views * self.width * self.height
        if pixels > MAX_SCAN_PIXELS:
            raise FieldError(at + ("num_views",), f"{self.num_views} views of {self.width} x "
                             f"{self.height} pixels are {pixels / 1e6:.0f} million pixels; at most "
                             f"{MAX_SCAN_PIXELS / 1e6:.0f} million (about 0.25 s and 100 MB each to "
                             "render and fuse): fewer views or smaller images")
        if self.first_look_scale > min(self.width, self.height) // 8:
            raise FieldError(at + ("first_look_scale",), "leaves first-look images smaller than "
                             f"8 pixels (width {self.width}, height {self.height})")
        if self.depth_unit and self.depth_max / self.depth_unit > 65534:
            raise FieldError(at + ("depth_unit",), f"{self.depth_unit:g} m: depth_max "
                             f"{self.depth_max:g} m is more than 65534 units, more than a 16-bit "
                             "image holds")
