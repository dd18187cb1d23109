"""Every field of a loaded :class:`~gbh_drake.scenario.Scenario` checked before anything is built.

:func:`check_scenario` raises :class:`FieldError` (the field's path and what was expected) on
the first field that cannot give a meaningful run:

1. every number anywhere (our dataclasses and Drake's config structs, poses and their
   distributions included) is finite;
2. each field is in its range (:data:`RULES`: positive where it must be, bounded where a larger
   value would take minutes, gigabytes or hang: views, image sizes, sample counts, periods,
   times), lists have their length, names are among the allowed ones (ours and those Drake
   accepts, e.g. ``plant_config.contact_model``, ``simulator_config.integration_scheme``);
3. what Drake would refuse deep inside the build (some with an assertion that kills the
   process) is checked here with the field named: camera rates, clipping and depth ranges,
   intrinsics, renderer classes, distributions (``!UniformVector`` min <= max, Gaussian
   stddev > 0), model directives (parsed by Drake, offline only), ``robot.q_home`` within the
   arm's joint limits (read from the directives' arm model);
4. fields the run does not use are refused rather than ignored (a pose's ``base_frame``, the
   visualizer's ``lcm_bus``, a nonzero ``simulator_config.start_time``...);
5. the start state must allow a meaningful trial: the object on the table top, not below it,
   within the scan's search radius of ``scan_target``, within the arm's reach, and the place
   position on the table and within reach.

The config dataclasses themselves (``GbhParams``, ``ScanConfig``, ``AntipodalParams``...) are
only read here; their own ``check``/``validate`` methods run last, as a safety net.
"""

from __future__ import annotations

import dataclasses
import math
import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from pydrake.common import schema as drake_schema
from pydrake.multibody.parsing import ModelDirective
from pydrake.systems.analysis import GetIntegrationSchemes

from gbh_drake.yaml_check import format_path, struct_fields

Path_ = tuple


class FieldError(ValueError):
    """A field that cannot work: ``path`` (tuple of names and indices) and ``problem``."""

    def __init__(self, path: Path_, problem: str):
        super().__init__(f"{format_path(path) or '<scenario>'}: {problem}")
        self.path = tuple(path)
        self.problem = problem

    def __reduce__(self):  # picklable with its parts
        return type(self), (self.path, self.problem)


# ---- rules ----------------------------------------------------------------------------------


@dataclass(frozen=True)
class Range:
    """A closed or open interval of numbers (either bound may be None) with a unit."""

    lo: float | None = None
    hi: float | None = None
    lo_open: bool = False
    hi_open: bool = False
    unit: str = ""
    note: str = ""
    integer: bool = False

    def contains(self, v) -> bool:
        if self.lo is not None and (v <= self.lo if self.lo_open else v < self.lo):
            return False
        return not (self.hi is not None and (v >= self.hi if self.hi_open else v > self.hi))

    def text(self) -> str:
        unit = f" {self.unit}" if self.unit else ""
        lo, hi = _num(self.lo), _num(self.hi)
        if self.lo is not None and self.hi is not None:
            return (f"{'an integer ' if self.integer else ''}in {'(' if self.lo_open else '['}"
                    f"{lo}, {hi}{')' if self.hi_open else ']'}{unit}")
        if self.lo is not None:
            if self.lo == 0:
                return ("> 0" if self.lo_open else ">= 0") + unit
            return f"{'>' if self.lo_open else '>='} {lo}{unit}"
        if self.hi is not None:
            return f"{'<' if self.hi_open else '<='} {hi}{unit}"
        return "finite"

    def check(self, path: Path_, value) -> None:
        if isinstance(value, bool) or not isinstance(value, int | float | np.number):
            raise FieldError(path, f"expected a number, got {value!r}")
        if self.integer and not float(value).is_integer():
            raise FieldError(path, f"expected an integer, got {value!r}")
        if not self.contains(value):
            note = f" ({self.note})" if self.note else ""
            unit = f" {self.unit}" if self.unit else ""
            raise FieldError(path, f"must be {self.text()}, got {_num(value)}{unit}{note}")


def _num(v) -> str:
    if v is None:
        return ""
    if isinstance(v, int | np.integer) and not isinstance(v, bool):
        return str(int(v))
    if math.isfinite(v) and float(v).is_integer() and abs(v) < 1e12:
        return str(int(v))
    return f"{float(v):g}"


def Int(lo=None, hi=None, note: str = "") -> Range:  # noqa: N802  (a rule constructor)
    return Range(lo, hi, integer=True, note=note)


def Pos(hi=None, unit="", note="", hi_open=False) -> Range:  # noqa: N802
    return Range(0.0, hi, lo_open=True, hi_open=hi_open, unit=unit, note=note)


def NonNeg(hi=None, unit="", note="") -> Range:  # noqa: N802
    return Range(0.0, hi, unit=unit, note=note)


@dataclass(frozen=True)
class OneOf:
    values: tuple
    note: str = ""

    def check(self, path: Path_, value) -> None:
        if value not in self.values:
            shown = ", ".join(repr(v) if v == "" else str(v) for v in self.values)
            note = f" ({self.note})" if self.note else ""
            raise FieldError(path, f"must be one of {shown}; got {value!r}{note}")


@dataclass(frozen=True)
class Items:
    """A list of ``length`` numbers (any length when None), each within ``each``."""

    length: int | None
    each: Range = Range()
    what: str = "values"

    def check(self, path: Path_, value) -> None:
        if self.length is not None and len(value) != self.length:
            raise FieldError(path, f"needs {self.length} {self.what}, got {len(value)}")
        for i, v in enumerate(value):
            self.each.check(path + (i,), v)


@dataclass(frozen=True)
class Fixed:
    """A field that must keep one value (the run derives or ignores it)."""

    value: object
    why: str

    def check(self, path: Path_, value) -> None:
        if value != self.value:
            raise FieldError(path, f"must be {self.value!r} ({self.why}); got {value!r}")


#: The station's gravity is -z_W and its table is horizontal.
_UP = "the station's table is horizontal (gravity along -z): give [0, 0, 1]"
_SEED = "one seed for the whole run: set the scenario's top-level seed, which seeds every stage"
_TIME = "s"

#: Ranges and allowed values of the scalar fields, by section of the scenario. Fields not listed
#: are still checked for finiteness; a field listed but absent (renamed) is skipped (a test
#: keeps this table in step with the dataclasses).
RULES: dict[tuple, dict[str, object]] = {
    (): {
        "seed": Int(0, 2**64 - 1, "seeds are unsigned 64-bit integers"),
        "task": OneOf(("pick", "settle")),
        "grasp_method": OneOf(("gbh", "antipodal", "gbh_fallback")),
        "settle_time": NonNeg(60.0, _TIME),
        "max_time": Pos(600.0, _TIME, "a pick takes about 10-20 simulated seconds"),
        "replay_fps": Pos(120.0, "frames/s"),
        "scan_target": Items(3, what="coordinates (x, y, z in m)"),
    },
    ("object",): {
        "scale": Pos(1000.0, note="e.g. 0.001 for a file in millimetres"),
        "orientation": OneOf(("keep", "nearest_stable", "most_probable")),
        "density": NonNeg(25000.0, "kg/m^3", "0: the object's own; osmium, the densest metal, "
                                             "is 22600"),
        "mass": NonNeg(100.0, "kg", "0: from the density; the Franka carries at most 3 kg"),
        "drop_height": NonNeg(0.5, "m"),
    },
    ("object", "random_pose"): {
        "x": Items(2, what="values [min, max] (m)"),
        "y": Items(2, what="values [min, max] (m)"),
        "yaw_deg": Items(2, Range(-360.0, 360.0, unit="deg"), what="values [min, max] (deg)"),
    },
    ("robot",): {
        "q_home": Items(7, what="joint positions (rad, panda_joint1..7)"),
        "arm_kp": Items(7, Pos(1e6, "N m/rad"), what="gains (panda_joint1..7)"),
        "arm_kd": Items(7, Pos(1e5, "N m s/rad"), what="gains (panda_joint1..7)"),
    },
    ("robot", "hand"): {
        "force": Pos(1000.0, "N"),
        "max_force": Pos(1000.0, "N"),
        "speed": Pos(1.0, "m/s"),
        "kp": Pos(1e7, "N/m"),
        "kd": Pos(1e5, "N s/m"),
    },
    ("plant_config",): {
        "time_step": Range(1e-5, 0.01, unit="s", note="gbh_drake needs a discrete plant; "
                                                        "smaller steps make a trial take hours"),
        "penetration_allowance": Pos(1.0, "m"),
        "stiction_tolerance": Pos(1.0, "m/s"),
        "contact_model": OneOf(("hydroelastic_with_fallback", "point"),
                               "'hydroelastic' alone fails: the arm's meshes have no "
                               "hydroelastic representation"),
        "discrete_contact_approximation": OneOf(("", "sap", "similar", "lagged"),
                                                "the fingers' coupler constraint needs a "
                                                "SAP-family solver; 'tamsi' cannot"),
        "sap_near_rigid_threshold": NonNeg(1000.0),
        "contact_surface_representation": OneOf(("polygon", "triangle")),
    },
    ("simulator_config",): {
        "integration_scheme": OneOf(tuple(GetIntegrationSchemes())),
        "max_step_size": Pos(10.0, "s"),
        "accuracy": Pos(1.0),
        "start_time": Fixed(0.0, "the trial's phases count from t = 0"),
        "target_realtime_rate": NonNeg(1000.0, note="0: as fast as possible"),
    },
    ("visualization",): {
        "lcm_bus": Fixed("default", "gbh_drake publishes on an in-memory bus only"),
        "publish_period": Range(1e-3, 10.0, unit="s"),
        "initial_proximity_alpha": NonNeg(1.0),
        "enable_meshcat_creation": Fixed(True, "a run always records its Meshcat replay"),
    },
    ("scan",): {
        "num_views": Int(1, 100),
        "layout": OneOf(("spiral", "ring")),
        "distance": Pos(5.0, "m"),
        "distance_max": Pos(5.0, "m"),
        "fov_margin": Range(1.0, 10.0),
        "first_look_distance": Pos(5.0, "m"),
        "first_look_scale": Int(1, 64),
        "first_look_elevation_deg": Range(0.0, 90.0, lo_open=True, hi_open=True, unit="deg"),
        "elevation_deg": Range(0.0, 89.0, unit="deg", note="90 would look straight down, "
                                                             "where the view's up is undefined"),
        "elevation_max_deg": Range(0.0, 89.0, unit="deg"),
        "azimuth_deg": Range(-360.0, 360.0, unit="deg"),
        "width": Int(16, 4096, "each view renders and fuses width x height pixels"),
        "height": Int(16, 4096, "each view renders and fuses width x height pixels"),
        "fov_y_deg": Range(1.0, 170.0, unit="deg"),
        "depth_min": Pos(10.0, "m"),
        "depth_max": Pos(10.0, "m"),
        "voxel_size": Range(0.001, 0.05, unit="m", note="smaller voxels take minutes and "
                                                          "gigabytes of TSDF"),
        "sdf_trunc": Pos(0.2, "m"),
        "crop_half_size_xy": Pos(2.0, "m"),
        "crop_z_max": Pos(2.0, "m"),
        "crop_z_min": Pos(0.5, "m"),
        "min_component_fraction": NonNeg(1.0),
        "table_height": Range(-1.0, 1.0, unit="m"),
        "table_margin": NonNeg(1.0, "m"),
        "table_tolerance": Pos(0.05, "m"),
        "cluster_cell": Range(0.001, 0.1, unit="m", note="smaller cells make millions of "
                                                           "cells"),
        "object_search_radius": Pos(2.0, "m"),
        "support_gap": NonNeg(0.5, "m"),
        "robot_base_xy": Items(2, what="coordinates (x, y in m)"),
        "robot_clearance": NonNeg(2.0, "m"),
        "min_cluster_points": Int(1, 10_000_000),
        "min_cell_points": Int(1, 1_000_000),
        "cap_height": NonNeg(0.5, "m"),
        "cap_gap": NonNeg(0.1, "m"),
        "hole_evidence_fraction": Range(0.0, 1.0, lo_open=True),
        "noise_sigma": NonNeg(0.1, "m"),
        "noise_sigma_quadratic": NonNeg(1.0, "1/m"),
        "noise_depth_step": NonNeg(0.1, "1/m"),
        "noise_grazing_deg": Range(0.0, 90.0, lo_open=True, unit="deg"),
    },
    ("gbh",): {
        "n_points": Int(100, 50_000, "sampling and ray casting grow with it"),
        "oversampling": Int(1, 20),
        "contact_angle_deg": Range(0.0, 90.0, lo_open=True, hi_open=True, unit="deg"),
        "cluster_radius": Pos(100.0),
        "min_cluster_size": Int(1, 50_000),
        "max_contacts_per_cluster": Int(1, 1000),
        "n_segment_samples": Int(2, 1000),
        "max_hanging_distance": Pos(1.0, "m"),
        "min_clearance": NonNeg(0.1, "m"),
        "dedup_radius_factor": NonNeg(100.0),
        "n_plane_normals": Int(2, 10_000),
        "n_rays_per_plane": Int(3, 720),
        "refine_cone_deg": Range(0.0, 90.0, hi_open=True, unit="deg"),
        "n_refine_normals": Int(1, 5000),
        "ground_normal": Items(3, what="components"),
        "p_theta": Range(0.0, 1.0, lo_open=True),
        "d1": NonNeg(0.1, "m"),
        "d2": Range(-0.05, 0.05, unit="m"),
        "cage_clearance": NonNeg(0.05, "m"),
        "slice_half_width": Pos(0.05, "m"),
        "ground_height": Range(-1.0, 1.0, unit="m"),
        "ground_clearance": Range(-1.0, 0.1, unit="m", note="negative: no ground check"),
        "p_c": Int(1, 50_000),
        "p_sweep": Int(1, 50_000),
        "sweep_margin_spacings": NonNeg(10.0),
        "collision_margin": NonNeg(0.05, "m"),
        "gamma_alpha": Pos(100.0, "rad^2"),
        "gamma_beta": Pos(100.0, "rad^2"),
        "top_k": Int(1, 100),
        "min_miss_resultant": Range(0.0, 1.0),
    },
    ("antipodal",): {
        "n_points": Int(100, 50_000),
        "n_samples": Int(1, 10_000),
        "n_rolls": Int(1, 360),
        "max_roll_deg": Range(0.0, 90.0, unit="deg"),
        "contact_depth": NonNeg(0.08, "m"),
        "min_contact_depth": NonNeg(0.08, "m"),
        "opening_margin": NonNeg(0.04, "m"),
        "min_width": NonNeg(0.08, "m"),
        "friction_coefficient": Pos(10.0),
        "contact_tolerance": NonNeg(0.01, "m"),
        "approach_distance": NonNeg(0.5, "m"),
        "p_c": Int(1, 50_000),
        "collision_margin": NonNeg(0.05, "m"),
        "ground_normal": Items(3, what="components"),
        "ground_height": Range(-1.0, 1.0, unit="m"),
        "ground_clearance": Range(-1.0, 0.1, unit="m"),
        "weight_direction": Range(-1e3, 1e3),
        "weight_antipodal": Range(-1e3, 1e3),
        "weight_com": Range(-1e3, 1e3, unit="1/m"),
        "top_k": Int(1, 100),
    },
    ("pick",): {
        "approach_distance": Pos(0.5, "m"),
        "max_approach_distance": Pos(0.5, "m"),
        "lift_clearance": NonNeg(0.5, "m"),
        "min_lift": Pos(1.0, "m"),
        "max_lift": Pos(1.0, "m"),
        "place_position": Items(2, what="coordinates (x, y in m)"),
        "place_depth": NonNeg(0.2, "m"),
        "unloaded_fraction": Range(0.0, 1.0, lo_open=True, hi_open=True),
        "unload_depth": NonNeg(0.05, "m"),
        "cage_test_force": NonNeg(1000.0, "N"),
        "cage_test_time": NonNeg(30.0, _TIME),
        "hold_time": NonNeg(30.0, _TIME),
        "release_depth": NonNeg(0.05, "m"),
        "release_shift": NonNeg(0.05, "m"),
        "retreat_distance": NonNeg(0.5, "m"),
        "planner_iterations": Int(1, 100_000),
        "max_grasps": Int(1, 100),
    },
    ("monitor",): {
        "lifted_height": Pos(1.0, "m"),
        "closed_tolerance": Pos(0.02, "m"),
        "period": Range(1e-3, 1.0, unit="s"),
    },
}

#: The arm reaches about 0.855 m from its shoulder axis; farther than this (horizontally, from
#: its base) is out of reach by far, nearer is inside its base.
REACH_MAX = 0.95
REACH_MIN = 0.15
#: Renderer classes a camera may use: VTK works headless and offline (GL needs a display,
#: glTF-client a render server over the network).
RENDERER_CLASSES = ("", "RenderEngineVtk")
#: The station's model names and the hand's actuated joints (gbh_drake.station's; not imported
#: from there: the configuration imports nothing of the pipeline; a test keeps them equal).
ARM, GRIPPER, TABLE = "panda", "hook_gripper", "table"
HAND_ACTUATORS = ("straight_finger_joint", "l_finger_joint", "bar_joint")
#: Segment samples per cluster GbH may test (max_contacts_per_cluster x n_segment_samples).
MAX_SEGMENT_SAMPLES = 50_000
#: Pixels a scan may render and fuse in all (views x width x height).
MAX_SCAN_PIXELS = 40_000_000
#: Camera limits.
MAX_CAMERA_PIXELS_SIDE = 4096
MAX_CAMERA_FPS = 240.0
MAX_CAMERAS = 8


# ---- the walk ---------------------------------------------------------------------------------


def check_scenario(scenario) -> None:
    """Raises :class:`FieldError` on the first field of ``scenario`` that cannot work (see the
    module docstring). Imports the object set and parses the directives (cached)."""
    check_finite(scenario)
    check_rules(scenario)
    check_relations(scenario)
    check_poses(scenario)
    check_object(scenario)
    info = check_models(scenario)
    check_cameras(scenario, info)
    check_start_state(scenario, info)
    check_own_methods(scenario)


def _get(obj, path: Path_):
    for part in path:
        obj = getattr(obj, part, None) if isinstance(part, str) else obj[part]
        if obj is None:
            return None
    return obj


def iter_numbers(value, path: Path_ = ()):
    """(path, number) for every number in ``value``: dataclasses, Drake structs (with YAML
    paths: a ``schema.Rotation``'s ``value`` is skipped as YAML does), lists, dicts, arrays."""
    if isinstance(value, bool) or value is None or isinstance(value, str | Path):
        return
    if isinstance(value, int | float | np.number):
        yield path, value
    elif isinstance(value, np.ndarray):
        for i, v in enumerate(np.ravel(value)):
            yield path + (i,), v
    elif isinstance(value, list | tuple):
        for i, v in enumerate(value):
            yield from iter_numbers(v, path + (i,))
    elif isinstance(value, dict):
        for k, v in value.items():
            yield from iter_numbers(v, path + (str(k),))
    elif isinstance(value, drake_schema.Rotation):
        yield from iter_numbers(value.value, path)
    else:
        fields = struct_fields(type(value))
        if fields is None:
            return
        for name in fields:
            yield from iter_numbers(getattr(value, name, None), path + (name,))


def check_finite(scenario) -> None:
    for path, v in iter_numbers(scenario):
        try:
            finite = math.isfinite(v)
        except OverflowError:  # an int too large for a float
            finite = False
        if not finite:
            raise FieldError(path, f"must be a finite number, got {v}")


def check_rules(scenario) -> None:
    for section, rules in RULES.items():
        obj = _get(scenario, section)
        if obj is None:
            continue
        for name, rule in rules.items():
            if hasattr(obj, name):
                rule.check(section + (name,), getattr(obj, name))


def check_relations(scenario) -> None:
    """Fields that depend on each other."""
    s = scenario
    if s.task == "pick" and s.max_time <= s.settle_time:
        raise FieldError(("max_time",), f"must exceed settle_time ({s.settle_time:g} s): the "
                                        "pick starts when settling ends")
    hand = s.robot.hand
    if hand.force > hand.max_force:
        raise FieldError(("robot", "hand", "force"), f"must be <= robot.hand.max_force "
                                                     f"({hand.max_force:g} N), got {hand.force:g}")
    pick = s.pick
    if pick.max_approach_distance < pick.approach_distance:
        raise FieldError(("pick", "max_approach_distance"),
                         f"must be >= pick.approach_distance ({pick.approach_distance:g} m)")
    if pick.min_lift > pick.max_lift:
        raise FieldError(("pick", "min_lift"), f"must be <= pick.max_lift ({pick.max_lift:g} m)")
    if pick.cage_test_force > hand.max_force:
        raise FieldError(("pick", "cage_test_force"),
                         f"must be <= robot.hand.max_force ({hand.max_force:g} N)")
    for section in ("gbh", "antipodal"):
        params = getattr(s, section)
        n = np.asarray(params.ground_normal, float)
        if n.shape == (3,) and not (np.linalg.norm(n) > 0 and np.allclose(n / np.linalg.norm(n),
                                                                          [0, 0, 1])):
            raise FieldError((section, "ground_normal"), f"{_UP}; got {list(n)}")
        n_points = getattr(params, "n_points", None)
        for name in ("p_c", "p_sweep"):
            value = getattr(params, name, None)
            if value is not None and n_points is not None and value > n_points:
                raise FieldError((section, name), f"must be <= {section}.n_points ({n_points})")
    g = s.gbh
    work = g.max_contacts_per_cluster * g.n_segment_samples
    if work > MAX_SEGMENT_SAMPLES:
        raise FieldError(("gbh", "n_segment_samples"), f"gbh.max_contacts_per_cluster x "
                         f"n_segment_samples = {work}; at most {MAX_SEGMENT_SAMPLES} per cluster "
                         "(1000 x 1000 took two minutes on a mug)")
    a = s.antipodal
    if a.min_contact_depth > a.contact_depth:
        raise FieldError(("antipodal", "min_contact_depth"),
                         f"must be <= antipodal.contact_depth ({a.contact_depth:g} m)")
    scan = s.scan
    for lo, hi in (("distance", "distance_max"), ("depth_min", "depth_max"),
                   ("elevation_deg", "elevation_max_deg"), ("crop_z_min", "crop_z_max")):
        if hasattr(scan, lo) and hasattr(scan, hi) and getattr(scan, lo) > getattr(scan, hi):
            raise FieldError(("scan", hi), f"must be >= scan.{lo} ({getattr(scan, lo):g}), got "
                                           f"{getattr(scan, hi):g}")
    for name in ("distance", "distance_max", "first_look_distance"):
        if hasattr(scan, name) and not scan.depth_min < getattr(scan, name) < scan.depth_max:
            raise FieldError(("scan", name), f"must lie between scan.depth_min and "
                                             f"scan.depth_max ({scan.depth_min:g}-"
                                             f"{scan.depth_max:g} m), got {getattr(scan, name):g} "
                                             "m: the camera would measure nothing there")
    pixels = scan.num_views * scan.width * scan.height
    if pixels > MAX_SCAN_PIXELS:
        raise FieldError(("scan", "num_views"), f"{scan.num_views} views of {scan.width} x "
                         f"{scan.height} pixels are {pixels / 1e6:.0f} million pixels; at most "
                         f"{MAX_SCAN_PIXELS / 1e6:.0f} million (about 0.25 s and 100 MB each to "
                         "render and fuse): fewer views or smaller images")
    if hasattr(scan, "first_look_scale") and scan.first_look_scale > min(scan.width,
                                                                         scan.height) // 8:
        raise FieldError(("scan", "first_look_scale"), "leaves first-look images smaller than "
                         f"8 pixels (width {scan.width}, height {scan.height})")
    rp = s.object.random_pose
    if rp is not None:
        for name in ("x", "y", "yaw_deg"):
            lo_hi = getattr(rp, name)
            if len(lo_hi) == 2 and lo_hi[0] > lo_hi[1]:
                raise FieldError(("object", "random_pose", name),
                                 f"needs [min, max] with min <= max, got {list(lo_hi)}")
    if s.object.density > 0 and s.object.mass > 0:
        raise FieldError(("object", "mass"), "give object.mass or object.density, not both "
                                             "(mass wins otherwise)")
    for name in ("output_dir", "source_path"):
        if "\0" in getattr(s, name):
            raise FieldError((name,), "holds a NUL character")
    if s.output_dir:
        out = s.resolve(s.output_dir)
        if out.exists() and not out.is_dir():
            raise FieldError(("output_dir",), f"{out} is a file, not a folder")


# ---- poses and distributions -------------------------------------------------------------------


def check_poses(scenario) -> None:
    pose = scenario.object.pose
    if pose.base_frame not in (None, "", "world"):
        raise FieldError(("object", "pose", "base_frame"),
                         f"the object's pose is X_WO, in the world frame; base_frame "
                         f"{pose.base_frame!r} is not supported (remove it)")
    if scenario.object.random_pose is None:
        check_transform(("object", "pose"), pose)
    for i, camera in enumerate(scenario.cameras):
        for name in ("X_PB", "X_BC", "X_BD"):
            check_transform(("cameras", i, name), getattr(camera, name), fixed=True)
        if camera.X_BC.base_frame or camera.X_BD.base_frame:
            which = "X_BC" if camera.X_BC.base_frame else "X_BD"
            raise FieldError(("cameras", i, which, "base_frame"),
                             "Drake uses base_frame only in X_PB (the camera body's parent)")


def check_transform(path: Path_, transform, *, fixed: bool = False) -> None:
    """A ``schema.Transform``: 3-vectors, valid distributions (and deterministic if ``fixed``)."""
    _check_vector(path + ("translation",), transform.translation, 3)
    rotation = transform.rotation.value
    rpath = path + ("rotation",)
    if isinstance(rotation, drake_schema.Rotation.Rpy):
        _check_vector(rpath + ("deg",), rotation.deg, 3)
    elif isinstance(rotation, drake_schema.Rotation.AngleAxis):
        _check_scalar_distribution(rpath + ("angle_deg",), rotation.angle_deg)
        _check_vector(rpath + ("axis",), rotation.axis, 3)
        axis = rotation.axis
        if isinstance(axis, np.ndarray) and axis.shape == (3,) and not np.linalg.norm(axis) > 0:
            raise FieldError(rpath + ("axis",), "must not be zero")
    if fixed and not transform.IsDeterministic():
        raise FieldError(path, "must be a fixed pose (Drake does not sample it)")
    try:  # what Drake still refuses (a safety net: the checks above should have caught it)
        import copy

        from pydrake.common import RandomGenerator

        unframed = copy.deepcopy(transform)
        unframed.base_frame = None  # (Sample refuses any base frame; it is checked elsewhere)
        unframed.Sample(RandomGenerator(0))
    except Exception as e:  # noqa: BLE001
        raise FieldError(path, " ".join(str(e).split())) from None


def _check_vector(path: Path_, vector, size: int) -> None:
    s = drake_schema
    if isinstance(vector, np.ndarray):
        if vector.shape != (size,):
            raise FieldError(path, f"needs {size} numbers, got {_shape_text(vector)}")
        return
    name = type(vector).__name__
    if name.startswith("_InvalidVariantSelection"):
        kind = name.removeprefix("_InvalidVariantSelection")
        raise FieldError(path, f"a vector needs !{kind}Vector, not the scalar !{kind}")
    if isinstance(vector, s.DeterministicVectorX | s.DeterministicVector[size]):
        _sized(path + ("value",), vector.value, size)
    elif isinstance(vector, s.UniformVectorX | s.UniformVector[size]):
        lo = _sized(path + ("min",), vector.min, size)
        hi = _sized(path + ("max",), vector.max, size)
        bad = [i for i in range(size) if lo[i] > hi[i]]
        if bad:
            raise FieldError(path, f"!UniformVector needs min <= max in every component; "
                                   f"component {bad[0]}: min {lo[bad[0]]:g} > max {hi[bad[0]]:g}")
    elif isinstance(vector, s.GaussianVectorX | s.GaussianVector[size]):
        _sized(path + ("mean",), vector.mean, size)
        std = np.atleast_1d(np.asarray(vector.stddev, float))
        if std.size not in (1, size):
            raise FieldError(path + ("stddev",), f"needs 1 or {size} numbers, got {std.size}")
        if np.any(std <= 0):
            raise FieldError(path + ("stddev",), "must be positive, got "
                                                 f"[{', '.join(f'{v:g}' for v in std)}]")


def _sized(path: Path_, value, size: int) -> np.ndarray:
    array = np.asarray(value, float)
    if array.shape != (size,):
        raise FieldError(path, f"needs {size} numbers, got {_shape_text(array)}")
    return array


def _shape_text(array: np.ndarray) -> str:
    return "one number" if array.ndim == 0 else f"{array.size} numbers"


def _check_scalar_distribution(path: Path_, value) -> None:
    s = drake_schema
    if isinstance(value, s.Uniform) and value.min > value.max:
        raise FieldError(path, f"!Uniform needs min <= max, got min {value.min:g} > max "
                               f"{value.max:g}")
    if isinstance(value, s.Gaussian) and not value.stddev > 0:
        raise FieldError(path + ("stddev",), f"must be positive, got {value.stddev:g}")
    if isinstance(value, s.UniformDiscrete) and not value.values:
        raise FieldError(path + ("values",), "needs at least one value")


def _xy_box(scenario) -> tuple[np.ndarray, np.ndarray] | None:
    """The range (lo, hi) of the object's start x, y, z (m) before it is put on the table, or
    None when its pose is not a box (a Gaussian: the mean is used)."""
    obj = scenario.object
    s = drake_schema
    if obj.random_pose is not None:
        rp = obj.random_pose
        return np.array([rp.x[0], rp.y[0], 0.0]), np.array([rp.x[1], rp.y[1], 0.0])
    t = obj.pose.translation
    if isinstance(t, np.ndarray):
        return t, t
    if isinstance(t, s.DeterministicVectorX | s.DeterministicVector[3]):
        v = np.asarray(t.value, float)
        return v, v
    if isinstance(t, s.UniformVectorX | s.UniformVector[3]):
        return np.asarray(t.min, float), np.asarray(t.max, float)
    if isinstance(t, s.GaussianVectorX | s.GaussianVector[3]):
        m = np.asarray(t.mean, float)
        return m, m
    return None


# ---- the object ---------------------------------------------------------------------------------


def check_object(scenario) -> None:
    obj = scenario.object
    if obj.mesh:
        if "\0" in obj.mesh:
            raise FieldError(("object", "mesh"), "holds a NUL character")
        path = scenario.resolve(obj.mesh)
        if not path.is_file():
            what = "is a folder" if path.is_dir() else "file not found"
            raise FieldError(("object", "mesh"), f"{what}: {path}")
        from gbh_drake.objects import MeshImportError, load_mesh_object

        try:
            load_mesh_object(path, scale=obj.scale, density=obj.density or None,
                             mass=obj.mass or None, orientation=obj.orientation)
        except MeshImportError as e:
            raise FieldError(("object", "mesh"), str(e)) from None
        return
    if obj.orientation != "keep":
        raise FieldError(("object", "orientation"), "applies to mesh files (object.mesh); the "
                                                    "named objects stand as designed")
    if not obj.name:
        raise FieldError(("object",), "give a named object (object.name) or a mesh file "
                                      "(object.mesh)")
    from gbh_drake.objects import list_objects  # the object set (its generators) on demand

    known = list_objects()
    if obj.name not in known:
        import difflib

        close = difflib.get_close_matches(obj.name, known, n=1)
        hint = f"did you mean {close[0]!r}? " if close else ""
        raise FieldError(("object", "name"), f"unknown object {obj.name!r} ({hint}known: "
                                             f"{', '.join(known)}; or give object.mesh)")
    size = _named_extent(obj.name) * obj.scale
    if not NAMED_SIZE[0] <= size <= NAMED_SIZE[1]:
        raise FieldError(("object", "scale"), f"makes {obj.name} {size * 1000:.3g} mm across; "
                                              f"objects of {NAMED_SIZE[0] * 100:g} cm to "
                                              f"{NAMED_SIZE[1]:g} m can be simulated")


#: Largest extent (m) a scaled named object may have.
NAMED_SIZE = (0.01, 2.0)
_EXTENTS: dict[str, float] = {}


def _named_extent(name: str) -> float:
    """Largest extent (m) of the object set's ``name`` at scale 1 (cached per process)."""
    if name not in _EXTENTS:
        from gbh_drake.objects import make_object

        bounds = make_object(name).mesh.bounds
        _EXTENTS[name] = float(np.max(bounds[1] - bounds[0]))
    return _EXTENTS[name]


def object_model_name(scenario) -> str:
    from gbh_drake.modeling.object_sdf import model_name

    return model_name(Path(scenario.object.mesh).stem if scenario.object.mesh
                      else scenario.object.name)


# ---- the models (directives), parsed once per distinct directives ----------------------------------


@dataclass(frozen=True)
class ModelInfo:
    """What the scenario's directives give the station (read from a plant Drake parsed)."""

    model_names: tuple[str, ...]
    arm_limits: tuple[tuple[str, float, float], ...]
    """(joint, lower, upper) of panda_joint1..7 (rad)."""
    frames: frozenset[str]
    """Frame names a camera may be mounted on (scoped ``model::frame``, unique plain names)."""
    table_top: tuple[float, float, float, float, float] | None
    """(x_min, x_max, y_min, y_max, z_top) of the table's top box in W, None if not a box."""
    arm_base_xy: tuple[float, float]


_MODEL_CACHE: dict[str, ModelInfo | FieldError] = {}
_URI = re.compile(r"\b(package|file|model|https?)://([^\s'\"},\]]+)")
#: Drake's package that is downloaded on first use (never here: runs are offline).
REMOTE_PACKAGES = ("drake_models",)


def check_models(scenario) -> ModelInfo:
    """Parses the directives (offline) and checks what the station needs of them."""
    from pydrake.common.yaml import yaml_dump_typed

    key = yaml_dump_typed(_Directives(list(scenario.directives)))
    if key not in _MODEL_CACHE:
        try:
            _MODEL_CACHE[key] = _model_info(scenario.directives)
        except FieldError as e:
            _MODEL_CACHE[key] = e
    result = _MODEL_CACHE[key]
    if isinstance(result, FieldError):
        raise FieldError(result.path, result.problem)
    name = object_model_name(scenario)
    if name in result.model_names:
        raise FieldError(("directives",), f"a model is named {name!r} like the object: rename "
                                          "one of them")
    q = scenario.robot.q_home
    for i, (joint, lo, hi) in enumerate(result.arm_limits):
        if not lo <= q[i] <= hi:
            raise FieldError(("robot", "q_home", i), f"{q[i]:g} rad is outside {joint}'s limits "
                                                     f"[{lo:.4f}, {hi:.4f}] rad")
    return result


#: A holder to dump the directives as text: the cache key of :func:`check_models` (made with
#: make_dataclass: this module's annotations are strings, Drake's dumper needs types).
_Directives = dataclasses.make_dataclass("_Directives", [("directives", list[ModelDirective])])


def _model_info(directives) -> ModelInfo:
    from pydrake.geometry import Box, SceneGraph
    from pydrake.multibody.parsing import ModelDirectives, ProcessModelDirectives
    from pydrake.multibody.plant import MultibodyPlant
    from pydrake.multibody.tree import FrameIndex

    from gbh_drake.modeling.package_map import make_parser

    names = [d.add_model.name for d in directives if d.add_model is not None]
    for required in (ARM, GRIPPER, TABLE):
        if required not in names:
            raise FieldError(("directives",), f"must add a model named {required!r} (the "
                                              "station needs it); the default directives are in "
                                              "gbh_drake/scenario.py")
    plant = MultibodyPlant(0.0)
    scene_graph = SceneGraph()
    plant.RegisterAsSourceForSceneGraph(scene_graph)
    parser = make_parser(plant)
    known_packages = [p for p in parser.package_map().GetPackageNames()
                      if p not in REMOTE_PACKAGES]
    for i, d in enumerate(directives):
        for kind in ("add_model", "add_directives"):
            item = getattr(d, kind)
            if item is not None:
                _check_uri(("directives", i, kind, "file"), item.file, parser.package_map(),
                           known_packages, depth=0)
        if d.add_model is not None and d.add_model.name in (ARM, GRIPPER) \
                and d.add_model.default_joint_positions:
            raise FieldError(("directives", i, "add_model", "default_joint_positions"),
                             "the station sets the robot's joints (robot.q_home, "
                             "robot.gripper_open); remove it")
    try:
        ProcessModelDirectives(ModelDirectives(directives=list(directives)), plant, parser)
        plant.Finalize()
    except Exception as e:  # noqa: BLE001  (Drake's parser raises RuntimeError)
        raise FieldError(("directives",), " ".join(str(e).split())) from None
    arm = plant.GetModelInstanceByName(ARM)
    gripper = plant.GetModelInstanceByName(GRIPPER)
    limits = []
    for i in range(1, 8):
        joint_name = f"panda_joint{i}"
        if not plant.HasJointNamed(joint_name, arm):
            raise FieldError(("directives",), f"model {ARM!r} has no joint {joint_name!r} (the "
                                              "station drives panda_joint1..7)")
        joint = plant.GetJointByName(joint_name, arm)
        limits.append((joint_name, float(joint.position_lower_limits()[0]),
                       float(joint.position_upper_limits()[0])))
    for joint_name in HAND_ACTUATORS:
        if not plant.HasJointActuatorNamed(joint_name, gripper):
            raise FieldError(("directives",), f"model {GRIPPER!r} has no actuated joint "
                                              f"{joint_name!r} (use the hook_gripper model)")
    frames: set[str] = set()
    plain: dict[str, int] = {}
    for i in range(plant.num_frames()):
        frame = plant.get_frame(FrameIndex(i))
        frames.add(frame.scoped_name().get_full())
        plain[frame.name()] = plain.get(frame.name(), 0) + 1
    frames |= {n for n, count in plain.items() if count == 1}
    context = plant.CreateDefaultContext()
    base = plant.EvalBodyPoseInWorld(context, plant.GetBodyByName("panda_link0", arm)) \
        if plant.HasBodyNamed("panda_link0", arm) else None
    table_top = None
    table = plant.GetModelInstanceByName(TABLE)
    if plant.HasBodyNamed("table_top", table):
        body = plant.GetBodyByName("table_top", table)
        inspector = scene_graph.model_inspector()
        X_WB = plant.EvalBodyPoseInWorld(context, body)
        for gid in plant.GetCollisionGeometriesForBody(body):
            shape = inspector.GetShape(gid)
            if isinstance(shape, Box):
                X_WG = X_WB @ inspector.GetPoseInFrame(gid)
                half = np.array([shape.width(), shape.depth(), shape.height()]) / 2
                corners = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1)
                                    for sz in (-1, 1)]) * half
                p = np.array([X_WG.multiply(c) for c in corners])
                table_top = (p[:, 0].min(), p[:, 0].max(), p[:, 1].min(), p[:, 1].max(),
                             p[:, 2].max())
                break
    return ModelInfo(tuple(plant.GetModelInstanceName(plant.GetModelInstanceByName(n))
                           for n in names), tuple(limits), frozenset(frames),
                     tuple(float(v) for v in table_top) if table_top else None,
                     tuple(base.translation()[:2]) if base is not None else (0.0, 0.0))


def _check_uri(path: Path_, uri: str, package_map, known: list[str], depth: int,
               stack: tuple[Path, ...] = ()) -> None:
    """A model file's URI: package:// of a local package or file:// (Drake's parser refuses
    plain paths when directives come from text, and would download drake_models). Nested
    directive files are followed: their URIs too, no loop (Drake would recurse until it
    crashes), at most 8 deep."""
    match = _URI.match(uri.strip())
    if not match:
        raise FieldError(path, f"{uri!r} is not a package:// or file:// URI (e.g. "
                               "package://gbh_drake/table.sdf or file:///abs/path/model.sdf)")
    scheme, rest = match.groups()
    if scheme in ("http", "https"):
        raise FieldError(path, f"{uri!r}: runs are offline; give a local file")
    if scheme == "package":
        package = rest.split("/", 1)[0]
        if package in REMOTE_PACKAGES:
            raise FieldError(path, f"{uri!r}: package {package!r} is downloaded by Drake on "
                                   "first use and runs are offline; use a local file")
        if package not in known:
            raise FieldError(path, f"{uri!r}: unknown package {package!r} (known: "
                                   f"{', '.join(sorted(known))})")
        local = Path(package_map.GetPath(package)) / rest.split("/", 1)[-1]
    elif scheme == "file":
        local = Path(rest if rest.startswith("/") else "/" + rest)
    else:
        return
    if not local.is_file():
        raise FieldError(path, f"{uri!r}: file not found: {local}")
    if local.suffix not in (".yaml", ".yml", ".dmd"):
        return
    local = local.resolve()
    if local in stack:
        raise FieldError(path, f"directive files include each other in a loop through {local} "
                               "(Drake would recurse until it crashes)")
    if depth >= 8:
        raise FieldError(path, f"directive files nested more than 8 deep (at {local})")
    text = local.read_text(errors="replace")
    for nested in _URI.finditer(text):
        _check_uri(path, nested.group(0), package_map, known, depth + 1, stack + (local,))


# ---- cameras -------------------------------------------------------------------------------


def check_cameras(scenario, info: ModelInfo) -> None:
    cameras = scenario.cameras
    if len(cameras) > MAX_CAMERAS:
        raise FieldError(("cameras",), f"at most {MAX_CAMERAS} cameras, got {len(cameras)}")
    renderers = {"default"}
    seen: set[str] = set()
    for i, c in enumerate(cameras):
        p = ("cameras", i)
        if not c.name:
            raise FieldError(p + ("name",), "must not be empty")
        if c.name in seen:
            raise FieldError(p + ("name",), f"{c.name!r} is used by two cameras")
        seen.add(c.name)
        for side in ("width", "height"):
            Int(1, MAX_CAMERA_PIXELS_SIDE).check(p + (side,), getattr(c, side))
        Range(0.0, MAX_CAMERA_FPS, lo_open=True, unit="frames/s").check(p + ("fps",), c.fps)
        NonNeg(unit="s").check(p + ("capture_offset",), c.capture_offset)
        Range(0.0, 1.0 / c.fps, hi_open=True, unit="s",
              note="less than one frame period, 1/fps").check(p + ("output_delay",),
                                                               c.output_delay)
        if not 0 < c.clipping_near < c.clipping_far:
            raise FieldError(p + ("clipping_near",), "needs 0 < clipping_near < clipping_far, "
                                                     f"got {c.clipping_near:g}, "
                                                     f"{c.clipping_far:g}")
        if not c.clipping_near <= c.z_near < c.z_far <= c.clipping_far:
            raise FieldError(p + ("z_near",), "needs clipping_near <= z_near < z_far <= "
                                              f"clipping_far, got {c.z_near:g}, {c.z_far:g} "
                                              f"(clipping {c.clipping_near:g}, "
                                              f"{c.clipping_far:g})")
        for name in ("center_x", "center_y"):
            value, size = getattr(c, name), c.width if name == "center_x" else c.height
            if value is not None and not 0 < value < size:
                raise FieldError(p + (name,), f"must lie in (0, {size}) pixels, got {value:g}")
        focal = c.focal
        for axis in ("x", "y"):
            value = getattr(focal, axis)
            if value is None:
                continue
            if type(focal).__name__ == "FovDegrees":
                Range(0.0, 180.0, lo_open=True, hi_open=True, unit="deg").check(
                    p + ("focal", axis), value)
            else:
                Pos(unit="pixels").check(p + ("focal", axis), value)
        params = None if isinstance(c.renderer_class, str) else c.renderer_class
        renderer_class = c.renderer_class if params is None else \
            type(params).__name__.removesuffix("Params")
        if renderer_class not in RENDERER_CLASSES:
            raise FieldError(p + ("renderer_class",),
                             f"must be '' or 'RenderEngineVtk' (got {renderer_class!r}: GL "
                             "needs a display, glTF-client a render server over the network)")
        if params is not None:
            backend = getattr(params, "backend", "")
            if backend not in ("", "EGL"):
                raise FieldError(p + ("renderer_class", "backend"),
                                 f"must be '' or 'EGL' (got {backend!r}: GLX needs an X display)")
            if c.renderer_name == "default":
                raise FieldError(p + ("renderer_class",), "the renderer 'default' is the "
                                 "station's own VTK renderer: give no renderer parameters for "
                                 "it, or use another renderer_name")
        if not c.renderer_name:
            raise FieldError(p + ("renderer_name",), "must not be empty")
        renderers.add(c.renderer_name)
        if c.lcm_bus != "default":
            raise FieldError(p + ("lcm_bus",), "must be 'default': gbh_drake publishes images "
                                               "on an in-memory bus only")
        base = c.X_PB.base_frame
        if base and base not in info.frames:
            some = ", ".join(sorted(f for f in info.frames if "::" in f and "__" not in f
                                    and "joint" not in f and "World" not in f)[:6])
            raise FieldError(p + ("X_PB", "base_frame"), f"no frame named {base!r} (e.g. world, "
                                                         f"{some}, ...)")
        try:  # Drake's own checks of the intrinsics and ranges, with its message
            c.MakeCameras()
        except Exception as e:  # noqa: BLE001
            raise FieldError(p, " ".join(str(e).split())) from None
    renderer = getattr(scenario.scan, "renderer_name", "default")
    if renderer not in renderers:
        raise FieldError(("scan", "renderer_name"), f"no renderer named {renderer!r} (the "
                                                    f"station has: {', '.join(sorted(renderers))})")


# ---- the start state -------------------------------------------------------------------------


def check_start_state(scenario, info: ModelInfo) -> None:
    """The object on the table, found by the scan, within reach; the place position too."""
    box = _xy_box(scenario)
    where = ("object", "random_pose") if scenario.object.random_pose is not None else \
        ("object", "pose", "translation")
    target = np.asarray(scenario.scan_target, float)
    base = np.asarray(info.arm_base_xy)
    _on_table(("scan_target",), "scan_target", target[:2], info)
    if info.table_top is not None and not -0.05 <= target[2] - info.table_top[4] <= 0.5:
        raise FieldError(("scan_target",), f"z = {target[2]:g} m is {target[2] - info.table_top[4]:.2f} "
                                           "m from the table top; the scan looks for the object "
                                           "on the table: give a point 0-0.5 m above it")
    if box is not None:
        lo, hi = box
        if scenario.object.random_pose is None and lo[2] < 0:
            raise FieldError(where, f"z = {lo[2]:g} m is below the table top (z = 0): the object "
                                    "would start inside the table")
        corners = [np.array([x, y]) for x in (lo[0], hi[0]) for y in (lo[1], hi[1])]
        for corner in corners:
            _on_table(where, "the object", corner, info)
            half = getattr(scenario.scan, "crop_half_size_xy", None)
            if half is not None and np.max(np.abs(corner - target[:2])) > half:
                raise FieldError(where, f"the object at ({corner[0]:g}, {corner[1]:g}) m is "
                                        f"outside the scan's workspace, scan_target +- "
                                        f"scan.crop_half_size_xy ({half:g} m): the cameras "
                                        "would not see it; move scan_target or the object")
            radius = getattr(scenario.scan, "object_search_radius", None)
            if radius is not None:
                d = float(np.linalg.norm(corner - target[:2]))
                if d > radius:
                    raise FieldError(where, f"the object at ({corner[0]:g}, {corner[1]:g}) m is "
                                            f"{d:.2f} m from scan_target, beyond the scan's "
                                            f"search radius ({radius:g} m): the cameras would "
                                            "not find it; move scan_target or the object")
            _in_reach(where, "the object", corner, base)
    place = np.asarray(scenario.pick.place_position, float)
    if scenario.task == "pick":
        _on_table(("pick", "place_position"), "the place position", place, info)
        _in_reach(("pick", "place_position"), "the place position", place, base)


def _on_table(path: Path_, what: str, xy: np.ndarray, info: ModelInfo) -> None:
    if info.table_top is None:
        return
    x0, x1, y0, y1, _ = info.table_top
    if not (x0 <= xy[0] <= x1 and y0 <= xy[1] <= y1):
        raise FieldError(path, f"{what} at ({xy[0]:g}, {xy[1]:g}) m is off the table top "
                               f"(x in [{x0:.2f}, {x1:.2f}], y in [{y0:.2f}, {y1:.2f}] m)")


def _in_reach(path: Path_, what: str, xy: np.ndarray, base: np.ndarray) -> None:
    d = float(np.linalg.norm(xy - base))
    if d > REACH_MAX:
        raise FieldError(path, f"{what} at ({xy[0]:g}, {xy[1]:g}) m is {d:.2f} m from the arm's "
                               f"base: out of the Franka's reach (about 0.85 m) by far")
    if d < REACH_MIN:
        raise FieldError(path, f"{what} at ({xy[0]:g}, {xy[1]:g}) m is {d:.2f} m from the arm's "
                               f"base: inside the robot's footprint")


# ---- the configs' own checks --------------------------------------------------------------------


#: "ScanConfig.width: image size must be positive", "GbhParams.p_c = 0 is out of range".
_OWN_MESSAGE = re.compile(r"^\w+\.(\w+)(?::\s*| = )(.*)$")


def check_own_methods(scenario) -> None:
    """``ScanConfig.validate``, ``GbhParams.check``, ``AntipodalParams.check``: whatever they
    refuse that the rules above let through, with the field named."""
    for section, method in (("scan", "validate"), ("gbh", "check"), ("antipodal", "check")):
        try:
            getattr(getattr(scenario, section), method)()
        except ValueError as e:
            text = str(e)
            match = _OWN_MESSAGE.match(text)
            if match:
                problem = match.group(2)
                if " = " in text.split(":")[0]:  # "= 0 is out of range"
                    problem = f"{problem.split(' is ')[-1]} (got {problem.split(' is ')[0]})"
                raise FieldError((section, match.group(1)), problem) from None
            raise FieldError((section,), text) from None


def rules_markdown() -> str:
    """The table of :data:`RULES` as Markdown (docs/errors.md includes it; a test keeps the two
    equal)."""
    rows = ["| field | must be |", "|---|---|"]
    for section, rules in RULES.items():
        for name, rule in rules.items():
            path = format_path(section + (name,))
            if isinstance(rule, Range):
                text = rule.text() + (f" ({rule.note})" if rule.note else "")
            elif isinstance(rule, OneOf):
                text = "one of " + ", ".join(f"`{v}`" if v else "`''`" for v in rule.values)
                text += f" ({rule.note})" if rule.note else ""
            elif isinstance(rule, Fixed):
                text = f"`{rule.value!r}` ({rule.why})"
            else:
                each = "" if rule.each == Range() else f", each {rule.each.text()}"
                text = (f"{rule.length} {rule.what}" if rule.length else rule.what) + each
            rows.append(f"| `{path}` | {text} |")
    return "\n".join(rows) + "\n"
