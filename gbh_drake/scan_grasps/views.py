"""A folder of depth images and the YAML that says how they were taken (``views.yaml``).

Read by ``gbh grasps FOLDER`` (or ``gbh grasps FOLDER/views.yaml``); written by ``gbh run
--save-views`` and by :func:`write_views`. Every pose is in the robot's base frame B, every
length in metres; the format is documented in ``docs/grasps.md`` (section "Depth images")::

    version: 1
    intrinsics: {width: 640, height: 480, fx: 579.4, fy: 579.4, cx: 319.5, cy: 239.5}
    depth_scale: 0.001          # m per unit of a 16-bit PNG (RealSense: 0.001)
    depth_range: [0.2, 1.5]     # m: what the sensor measures; other pixels are not measurements
    depth_error: 0.004          # m: how far a depth may lie from the surface (the noise bound)
    views:
    - {depth: depth_000.png, X_BC: [[...], [...], [...], [0, 0, 0, 1]], mask: mask_000.png}

Optional: ``no_hit_value`` (a raw value meaning "nothing within range": the ray is free up to
``depth_range[1]``), ``first_look`` (views that find the table and the object and add free
space but are not fused, with their own ``intrinsics`` and ``depth_error``), ``target`` and
``object_point`` (where to look for the object, B), ``table`` (the plane ``{normal, height}``),
``mesh`` (the object's fused mesh: the views then give only the free space and the table),
``scan`` (``ScanConfig`` fields: voxel size, segmentation), ``gbh`` (``GbhParams`` fields) and
``seed``. Intrinsics are OpenCV's and ROS ``CameraInfo``'s K: pixel (u, v)'s centre at (u, v).

Everything is checked when read; a problem raises
:class:`~gbh_drake.scan_grasps.errors.GraspsInputError` naming the file and the field.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from gbh_drake.perception.camera import CameraIntrinsics
from gbh_drake.scan_grasps.errors import GraspsInputError
from gbh_drake.scan_grasps.poses import quaternion_matrix

#: The name ``gbh grasps FOLDER`` looks for.
VIEWS_FILE = "views.yaml"
#: The version of the format this module reads and writes.
VIEWS_VERSION = 1
#: The keys of the file and of a ``first_look`` block.
TOP_KEYS = ("version", "intrinsics", "depth_scale", "depth_range", "depth_error", "no_hit_value",
            "views", "first_look", "target", "object_point", "table", "mesh", "scan", "gbh", "seed")
GROUP_KEYS = ("intrinsics", "depth_error", "views")
VIEW_KEYS = ("depth", "X_BC", "mask")
#: A rotation's columns may be this far from orthonormal (a pose printed with 6 digits).
ROTATION_TOLERANCE = 1e-5
#: The depth scale ``write_views`` uses (m per unit: 0.1 mm steps up to 6.55 m).
WRITE_DEPTH_SCALE = 1e-4
#: The raw value ``write_views`` gives a ray that hit nothing within range.
WRITE_NO_HIT = 65535


@dataclass
class ViewSet:
    """Depth images from one camera model, each with its pose in B."""

    intrinsics: CameraIntrinsics
    """The pinhole, in Drake's convention (pixel (u, v) covers [u, u + 1): OpenCV's cx + 0.5)."""
    depths: list[np.ndarray]
    """(height, width) float32, m along +z_C: 0 no measurement, inf nothing hit within range."""
    X_BCs: list[np.ndarray]
    """(4, 4) pose of each camera C in B (+z_C the optical axis, +x_C right, +y_C down)."""
    masks: list[np.ndarray] | None
    """(height, width) bool per image: only these pixels may be the object's; None: any."""
    depth_error: float
    """m: how far a measured depth may lie from the surface it hit."""
    files: list[str]


@dataclass
class ViewsFile:
    """A ``views.yaml`` as read (see the module docstring)."""

    path: Path
    views: ViewSet
    depth_range: tuple[float, float]
    first_look: ViewSet | None = None
    target: np.ndarray | None = None
    object_point: np.ndarray | None = None
    table: tuple[np.ndarray, float] | None = None
    """(normal (3,), height): the plane normal . p = height in B, normal up."""
    mesh: Path | None = None
    scan: dict = field(default_factory=dict)
    gbh: dict = field(default_factory=dict)
    seed: int | None = None


def read_views(path) -> ViewsFile:
    """Reads and checks a views file (or the ``views.yaml`` of a folder) and its images."""
    import yaml

    path = Path(path)
    if path.is_dir():
        path = path / VIEWS_FILE
    if not path.is_file():
        raise GraspsInputError(path, "", "file not found")
    try:
        data = yaml.safe_load(path.read_text())
    except (yaml.YAMLError, UnicodeDecodeError) as e:
        raise GraspsInputError(path, "", f"not YAML ({' '.join(str(e).split())})") from None
    reader = _Reader(path)
    data = reader.mapping(data, "", TOP_KEYS, required=("intrinsics", "views"))
    version = data.get("version", VIEWS_VERSION)
    if version != VIEWS_VERSION:
        raise GraspsInputError(path, "version", f"this gbh_drake reads version {VIEWS_VERSION}, "
                                                f"got {version!r}")
    scale = reader.number(data.get("depth_scale", 0.001), "depth_scale", positive=True)
    lo, hi = reader.vector(data.get("depth_range", [0.1, 10.0]), "depth_range", 2)
    if not 0 <= lo < hi:
        raise GraspsInputError(path, "depth_range", f"must be [min, max] m with 0 <= min < max, "
                                                    f"got [{lo:g}, {hi:g}]")
    no_hit = data.get("no_hit_value")
    if no_hit is not None:
        no_hit = int(reader.number(no_hit, "no_hit_value", positive=True))
    decode = _Decoder(scale, (lo, hi), no_hit)
    views = reader.group(data, "", decode)
    first_look = reader.group(data["first_look"], "first_look", decode) \
        if data.get("first_look") is not None else None
    table = None
    if data.get("table") is not None:
        plane = reader.mapping(data["table"], "table", ("normal", "height"),
                               required=("normal", "height"))
        normal = reader.vector(plane["normal"], "table.normal", 3)
        if not np.linalg.norm(normal) > 0:
            raise GraspsInputError(path, "table.normal", "must not be zero")
        normal = normal / np.linalg.norm(normal)
        height = reader.number(plane["height"], "table.height")
        if normal[2] < 0:  # the table's normal points up
            normal, height = -normal, -height
        table = (normal, height)
    mesh = None
    if data.get("mesh") is not None:
        mesh = (path.parent / str(data["mesh"])).resolve()
        if not mesh.is_file():
            raise GraspsInputError(path, "mesh", f"file not found: {mesh}")
    for name in ("scan", "gbh"):
        if data.get(name) is not None:
            reader.mapping(data[name], name, None)
    seed = data.get("seed")
    if seed is not None and (isinstance(seed, bool) or not isinstance(seed, int) or seed < 0):
        raise GraspsInputError(path, "seed", f"must be an integer >= 0, got {seed!r}")
    return ViewsFile(path, views, (lo, hi), first_look,
                     reader.point(data.get("target"), "target"),
                     reader.point(data.get("object_point"), "object_point"), table, mesh,
                     dict(data.get("scan") or {}), dict(data.get("gbh") or {}), seed)


@dataclass
class _Decoder:
    """Raw depth images to metres."""

    scale: float
    depth_range: tuple[float, float]
    no_hit: int | None

    def __call__(self, raw: np.ndarray) -> np.ndarray:
        """(h, w) float32 m: 0 (and NaN, negative) no measurement, inf nothing hit within range
        (``no_hit``, or a float image's +inf, as ROS's REP 117 has it); every other pixel is a
        measurement as it is (the scan reads them within ``depth_range``, as its own)."""
        if np.issubdtype(raw.dtype, np.integer):
            depth = raw.astype(np.float64) * self.scale
            far = raw == self.no_hit if self.no_hit is not None else np.zeros(raw.shape, bool)
        else:
            depth = raw.astype(np.float64)
            far = np.isposinf(depth)
        with np.errstate(invalid="ignore"):
            valid = np.isfinite(depth) & (depth > 0)
        out = np.where(valid, depth, 0.0).astype(np.float32)
        out[far] = np.inf
        return out

    def in_range(self, depth: np.ndarray) -> bool:
        """Whether a decoded image holds a pixel within ``depth_range``."""
        lo, hi = self.depth_range
        return bool(((depth >= lo) & (depth <= hi)).any())


class _Reader:
    """Checks the parts of a views file, naming the file and the field."""

    def __init__(self, path: Path):
        self.path = path

    def fail(self, where: str, problem: str) -> GraspsInputError:
        return GraspsInputError(self.path, where, problem)

    def mapping(self, data, where: str, keys: Sequence[str] | None,
                required: Sequence[str] = ()) -> dict:
        if not isinstance(data, dict):
            raise self.fail(where or "<file>", f"must be a mapping, got {type(data).__name__}")
        if keys is not None:
            unknown = [k for k in data if k not in keys]
            if unknown:
                raise self.fail(_join(where, str(unknown[0])),
                                f"unknown key (known: {', '.join(keys)})")
        for k in required:
            if k not in data or data[k] is None:
                raise self.fail(_join(where, k), "missing")
        return data

    def number(self, value, where: str, positive: bool = False) -> float:
        if isinstance(value, bool) or not isinstance(value, int | float):
            raise self.fail(where, f"must be a number, got {value!r}")
        if not math.isfinite(value):
            raise self.fail(where, f"must be a finite number, got {value}")
        if positive and not value > 0:
            raise self.fail(where, f"must be > 0, got {value}")
        return float(value)

    def vector(self, value, where: str, n: int) -> np.ndarray:
        if not isinstance(value, list | tuple) or len(value) != n:
            raise self.fail(where, f"must be a list of {n} numbers, got {value!r}")
        return np.array([self.number(v, f"{where}[{i}]") for i, v in enumerate(value)])

    def point(self, value, where: str) -> np.ndarray | None:
        return None if value is None else self.vector(value, where, 3)

    def pose(self, value, where: str) -> np.ndarray:
        """A pose X_BC: a 4x4 matrix (rows), or {translation, quaternion_wxyz |
        quaternion_xyzw (ROS's order)}."""
        if isinstance(value, dict):
            value = self.mapping(value, where, ("translation", "quaternion_wxyz",
                                                "quaternion_xyzw"), required=("translation",))
            keys = [k for k in ("quaternion_wxyz", "quaternion_xyzw") if k in value]
            if len(keys) != 1:
                raise self.fail(where, "give the rotation as one of quaternion_wxyz or "
                                       "quaternion_xyzw (ROS's order)")
            q = self.vector(value[keys[0]], f"{where}.{keys[0]}", 4)
            if keys[0] == "quaternion_xyzw":
                q = np.roll(q, 1)
            if abs(np.linalg.norm(q) - 1.0) > 1e-3:
                raise self.fail(f"{where}.{keys[0]}", f"is not a unit quaternion (norm "
                                                      f"{np.linalg.norm(q):.4g})")
            X = np.eye(4)
            X[:3, :3] = quaternion_matrix(q / np.linalg.norm(q))
            X[:3, 3] = self.vector(value["translation"], f"{where}.translation", 3)
            return X
        if not (isinstance(value, list | tuple) and len(value) == 4
                and all(isinstance(r, list | tuple) and len(r) == 4 for r in value)):
            raise self.fail(where, "must be a 4x4 matrix (4 rows of 4 numbers) or "
                                   "{translation, quaternion_wxyz}")
        X = np.array([[self.number(v, f"{where}[{i}][{j}]") for j, v in enumerate(row)]
                      for i, row in enumerate(value)])
        if not np.allclose(X[3], [0, 0, 0, 1]):
            raise self.fail(f"{where}[3]", f"the last row must be [0, 0, 0, 1], got "
                                           f"{X[3].tolist()}")
        R = X[:3, :3]
        error = float(np.abs(R.T @ R - np.eye(3)).max())
        if error > ROTATION_TOLERANCE or np.linalg.det(R) < 0:
            raise self.fail(where, f"is not a pose: its 3x3 part is not a rotation (R^T R "
                                   f"differs from I by {error:.2g}, det {np.linalg.det(R):.3g})")
        return X

    def intrinsics(self, value, where: str) -> tuple[int, int, float, float, float, float]:
        where = _join(where, "intrinsics")
        k = self.mapping(value, where, ("width", "height", "fx", "fy", "cx", "cy"),
                         required=("width", "height", "fx", "fy", "cx", "cy"))
        size = []
        for name in ("width", "height"):
            v = k[name]
            if isinstance(v, bool) or not isinstance(v, int) or v < 1:
                raise self.fail(f"{where}.{name}", f"must be a whole number of pixels, got {v!r}")
            size.append(v)
        fx, fy = (self.number(k[n], f"{where}.{n}", positive=True) for n in ("fx", "fy"))
        cx, cy = (self.number(k[n], f"{where}.{n}") for n in ("cx", "cy"))
        for name, c, n in (("cx", cx, size[0]), ("cy", cy, size[1])):
            if not -0.5 <= c <= n - 0.5:
                raise self.fail(f"{where}.{name}", f"{c:g} px lies outside the image (0 to "
                                                   f"{n - 1} px): the intrinsics do not fit it")
        return size[0], size[1], fx, fy, cx + 0.5, cy + 0.5  # Drake's pixel convention

    def group(self, data, where: str, decode: _Decoder) -> ViewSet:
        """The intrinsics, depth error and views of the file or of its ``first_look``."""
        data = self.mapping(data, where, TOP_KEYS if not where else GROUP_KEYS,
                            required=("intrinsics", "views"))
        width, height, fx, fy, cx, cy = self.intrinsics(data["intrinsics"], where)
        error = self.number(data.get("depth_error", 0.0), _join(where, "depth_error"))
        if error < 0:
            raise self.fail(_join(where, "depth_error"), f"must be >= 0, got {error:g}")
        items = data["views"]
        if not isinstance(items, list) or not items:
            raise self.fail(_join(where, "views"), "must be a list of at least one view")
        depths, poses, masks, files = [], [], [], []
        for i, item in enumerate(items):
            at = f"{_join(where, 'views')}[{i}]"
            item = self.mapping(item, at, VIEW_KEYS, required=("depth", "X_BC"))
            file = self.path.parent / str(item["depth"])
            raw = read_image(file, f"{at}.depth")
            if raw.shape != (height, width):
                raise GraspsInputError(file, f"{at}.depth", f"{raw.shape[1]}x{raw.shape[0]} "
                                       f"pixels; the intrinsics say {width}x{height}")
            depth = decode(raw)
            if not decode.in_range(depth):
                raise GraspsInputError(file, f"{at}.depth", _no_depth(raw, decode))
            depths.append(depth)
            poses.append(self.pose(item["X_BC"], f"{at}.X_BC"))
            files.append(str(file))
            if item.get("mask") is not None:
                mask_file = self.path.parent / str(item["mask"])
                mask = read_image(mask_file, f"{at}.mask")
                if mask.shape[:2] != (height, width):
                    raise GraspsInputError(mask_file, f"{at}.mask", f"{mask.shape[1]}x"
                                           f"{mask.shape[0]} pixels; the depth image is "
                                           f"{width}x{height}")
                masks.append(mask.reshape(height, width, -1).any(axis=2))
            else:
                masks.append(None)
        if any(m is not None for m in masks) and any(m is None for m in masks):
            missing = next(i for i, m in enumerate(masks) if m is None)
            raise self.fail(f"{_join(where, 'views')}[{missing}].mask",
                            "missing: give a mask for every view or for none")
        return ViewSet(CameraIntrinsics(width, height, fx, fy, cx, cy), depths, poses,
                       masks if masks[0] is not None else None, error, files)


def _join(where: str, key: str) -> str:
    return f"{where}.{key}" if where else key


def _no_depth(raw: np.ndarray, decode: _Decoder) -> str:
    """Why an image holds no depth within range, with the values it does hold."""
    values = raw[np.isfinite(raw) & (raw > 0)] if not np.issubdtype(raw.dtype, np.integer) \
        else raw[(raw > 0) & (raw != (decode.no_hit if decode.no_hit is not None else -1))]
    lo, hi = decode.depth_range
    if len(values) == 0:
        what = "all NaN" if not np.issubdtype(raw.dtype, np.integer) and np.isnan(raw).all() \
            else "no measurement in it (all 0 or no return)"
        return f"no valid depth pixel: {what}"
    scale = decode.scale if np.issubdtype(raw.dtype, np.integer) else 1.0
    return (f"no pixel within depth_range [{lo:g}, {hi:g}] m: its values are "
            f"{float(values.min()) * scale:.4g}-{float(values.max()) * scale:.4g} m after "
            f"depth_scale {scale:g} (is depth_scale right? RealSense: 0.001)")


def read_image(path: Path, where: str) -> np.ndarray:
    """A depth image or mask: a PNG (16-bit for depth; any for a mask) or a .npy array (2-D)."""
    path = Path(path)
    if not path.is_file():
        raise GraspsInputError(path, where, "file not found")
    try:
        if path.suffix.lower() == ".npy":
            array = np.load(path, allow_pickle=False)
        elif path.suffix.lower() == ".png":
            from PIL import Image

            with Image.open(path) as image:
                array = np.asarray(image)
        else:
            raise GraspsInputError(path, where, f"unsupported format {path.suffix!r} (a 16-bit "
                                                ".png or a .npy array)")
    except GraspsInputError:
        raise
    except Exception as e:  # noqa: BLE001  (PIL and numpy raise many types on bad bytes)
        raise GraspsInputError(path, where, f"cannot be read ({type(e).__name__}: "
                                            f"{' '.join(str(e).split())})") from None
    if array.ndim not in (2, 3) or array.size == 0:
        raise GraspsInputError(path, where, f"not an image (shape {array.shape})")
    if where.endswith(".depth"):
        if array.ndim != 2:
            raise GraspsInputError(path, where, f"a depth image has one channel, this one "
                                                f"{array.shape[2]}")
        if array.dtype == np.uint8:
            raise GraspsInputError(path, where, "8-bit: depth needs a 16-bit PNG (or a float "
                                                ".npy in metres)")
    return array


# ---- writing ------------------------------------------------------------------------------------


def encode_depth(depth: np.ndarray, scale: float = WRITE_DEPTH_SCALE,
                 no_hit: int = WRITE_NO_HIT, depth_max: float | None = None) -> np.ndarray:
    """(h, w) uint16 raw values of ``depth`` (m): NaN, 0 and out of range -> 0; ``depth_max``
    (a ray the renderer found free up to it) and inf -> ``no_hit``."""
    d = np.asarray(depth, dtype=np.float64)
    far = np.isposinf(d)
    if depth_max is not None:
        far |= d == np.float32(depth_max)
    with np.errstate(invalid="ignore"):
        raw = np.where(np.isfinite(d) & (d > 0), np.round(d / scale), 0.0)
    if raw.max(initial=0.0) >= no_hit:
        raise ValueError(f"depths up to {d[np.isfinite(d)].max():.3f} m do not fit 16 bits at "
                         f"{scale} m per unit")
    raw[far] = no_hit
    return raw.astype(np.uint16)


def write_png(path: Path, raw: np.ndarray) -> None:
    """A 16-bit PNG (or an 8-bit one for a bool mask)."""
    from PIL import Image

    array = raw.astype(np.uint8) * 255 if raw.dtype == bool else raw
    Image.fromarray(array).save(path, format="PNG")


def group_entry(views: ViewSet, names: Sequence[str], mask_names: Sequence[str] | None = None
                ) -> dict:
    """The YAML of a :class:`ViewSet` whose images are (to be) written as ``names``."""
    k = views.intrinsics
    return {"intrinsics": {"width": k.width, "height": k.height, "fx": k.fx, "fy": k.fy,
                           "cx": k.cx - 0.5, "cy": k.cy - 0.5},
            "depth_error": float(views.depth_error),
            "views": [{"depth": name, "X_BC": np.asarray(X, dtype=float).tolist(),
                       **({"mask": mask_names[i]} if mask_names else {})}
                      for i, (name, X) in enumerate(zip(names, views.X_BCs, strict=True))]}
