"""The start state must allow a meaningful trial: the object on the table top (not below it),
inside the scan's workspace and search radius around ``scan_target``, within the arm's reach;
for a pick, the place position on the table and within reach."""

import numpy as np
from pydrake.common import schema as drake_schema

from gbh_drake.core.ranges import FieldError, Path_
from gbh_drake.modeling.directives import ModelInfo

#: The arm reaches about 0.855 m from its shoulder axis; farther than this (horizontally, from
#: its base) is out of reach by far, nearer is inside its base.
REACH_MAX = 0.95
REACH_MIN = 0.15


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
