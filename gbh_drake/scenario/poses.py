"""Poses and distributions of a scenario (Drake's ``schema.Transform``), checked field by field.

3-vectors, ``!UniformVector`` min <= max in every component, Gaussian stddev > 0, ``!Uniform``
min <= max, a nonzero ``!AngleAxis`` axis, no scalar tag for a vector, camera poses fixed, the
object's pose in the world frame; then Drake's own ``Sample`` as a safety net.
"""

import copy

import numpy as np
from pydrake.common import RandomGenerator
from pydrake.common import schema as drake_schema

from gbh_drake.core.ranges import FieldError, Path_


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
