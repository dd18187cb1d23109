"""What ``gbh grasps INPUT`` reads: a mesh, a point cloud or a folder of depth images, turned
into the object in the robot's base frame B as the GbH core takes it (a ``ScanResult``).

* **Depth images** (a folder with ``views.yaml``, :mod:`~gbh_drake.scan_grasps.views`) go
  through the simulated scan's own functions (``perception.scan``: the first look's
  :func:`~gbh_drake.perception.scan.look_at_images`, then
  :func:`~gbh_drake.perception.scan.scan_depth_images`: table fit, segmentation, TSDF fusion,
  cut and cap, free space): the Scanner renders its views and calls them, this reads them.
  With ``mesh:`` in the file the views give only the free space and the table.
* **A mesh** (.obj .ply .stl .glb .gltf .off) is the object alone (crop it first), repaired
  by the object set's importer; the table is given or lies under its lowest point. No free
  space: the exit proof does not run (a note says so).
* **A point cloud** (.ply without faces, .pcd, .npy (n, 3) or (n, 6)) is fused
  (:mod:`~gbh_drake.scan_grasps.cloud`): table fitted (or given), object segmented as in a
  scan, TSDF-fused from virtual views; no free space either.

Every problem raises :class:`~gbh_drake.scan_grasps.errors.GraspsInputError` naming the file
and the field.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from gbh_drake.scan_grasps.errors import GraspsInputError, setting
from gbh_drake.scan_grasps.table import plane_text, table_plane, under

#: Suffixes read as meshes, and as point clouds (a .ply is a cloud when it has no faces).
MESH_SUFFIXES = (".obj", ".ply", ".stl", ".glb", ".gltf", ".off")
CLOUD_SUFFIXES = (".ply", ".pcd", ".npy")
#: A point cloud whose largest extent (m, after ``scale``) exceeds this is not in metres (the
#: object itself is held to ``gbh run``'s sizes: ``objects.plausibility.size_refusal``).
MAX_INPUT_EXTENT = 20.0
#: m: a point this far below a given table is under it (more than a scan's noise or a
#: rounded base).
BELOW_TABLE = 0.005
#: A given table above more than this share of the object's points is refused (it cuts
#: the object, or lies elsewhere); above at least :data:`BELOW_TABLE_WARNING` of them, warned of.
BELOW_TABLE_REFUSAL = 0.5
BELOW_TABLE_WARNING = 0.01


#: The note when there is no free space (a mesh, a point cloud).
NO_FREE_SPACE = ("no free space: the input says where the surface is, not what the camera saw "
                 "free, so the through-hole exit proof did not run (unknown_is_occupied "
                 "without free space); a hole is taken from the mesh alone, as in the paper, "
                 "and a single view's unseen back may pass for one")


@dataclass
class ScanInput:
    """The object as read, in B (the GbH core's W is B here)."""

    kind: str
    """``mesh``, ``point_cloud`` or ``depth_images``."""
    path: str
    scan: object
    """A :class:`~gbh_drake.perception.scan.ScanResult` in B: the object's mesh, its points,
    the table, the free space (None for a mesh or a cloud), warnings; ``empty`` and
    ``message`` when nothing was found."""
    table_source: str
    """``given``, ``fitted``, ``verified`` (fitted where ``scan.table_height`` expected it),
    ``assumed`` (none found: the config's) or ``lowest point`` (under the object)."""
    notes: list[str] = field(default_factory=list)
    """What the input lacks and what that means (no free space, how a cloud was fused)."""
    gbh: dict = field(default_factory=dict)
    """GbhParams fields the views file gives."""
    seed: int | None = None
    """The views file's seed for the GbH core's sampler."""


@dataclass(frozen=True)
class InputOptions:
    """How to read an input. Poses are 4x4 matrices, lengths metres."""

    X_BI: np.ndarray | None = None
    """Pose of the input's frame I in B (None: the input is in B)."""
    table: tuple[np.ndarray, float] | None = None
    """The table plane (normal (3,), height) in B: normal . p = height (None: the file's, or
    fitted)."""
    target: np.ndarray | None = None
    """(3,) where in B to look for the object (None: the file's, or the input's own middle)."""
    scale: float = 1.0
    """The file's units in metres (a mesh's or a point cloud's; applied before ``X_BI``)."""
    table_option: str = "table"
    """What gave ``table``, as a refusal of it names it (``table_z``, ``--table-plane``)."""
    cli: bool = False
    """The caller is ``gbh grasps``: problems name its flags (``--scale``), else the arguments
    of ``gbh_drake.grasps`` (``scale``; :func:`~.errors.setting`)."""


def load_input(path, options: InputOptions = InputOptions()) -> ScanInput:
    """Reads ``path`` (a mesh, a point cloud, a folder of depth images or its views.yaml)."""
    path = Path(path)
    if path.is_dir() or path.suffix.lower() in (".yaml", ".yml"):
        if options.scale != 1.0:
            raise GraspsInputError(path, setting("scale", options.cli), "scales a mesh or a "
                                   "point cloud; depth "
                                   "images are scaled by depth_scale in views.yaml")
        return _depth_images(path, options)
    if not path.exists():
        raise GraspsInputError(path, "", "file not found")
    suffix = path.suffix.lower()
    if suffix not in MESH_SUFFIXES + CLOUD_SUFFIXES:
        raise GraspsInputError(path, "", f"unsupported input {suffix!r}: a mesh "
                               f"({' '.join(MESH_SUFFIXES)}), a point cloud "
                               f"({' '.join(CLOUD_SUFFIXES)}) or a folder of depth images "
                               "with views.yaml")
    from gbh_drake.scan_grasps.cloud import read_cloud

    if suffix in (".pcd", ".npy") or (suffix == ".ply" and not _ply_has_faces(path)):
        points = read_cloud(path) * options.scale
        check_units(path, points, "points", options.scale, cli=options.cli)
        return _point_cloud(path, _transformed(points, options.X_BI), options)
    return _mesh(path, options)


def _ply_has_faces(path: Path) -> bool:
    """Whether a PLY file's header declares faces (a mesh) rather than vertices alone."""
    with open(path, "rb") as f:
        header = f.read(4096).split(b"end_header")[0]
    return any(line.startswith(b"element face") and not line.endswith(b" 0")
               for line in header.splitlines())


def _transformed(points: np.ndarray, X_BI: np.ndarray | None) -> np.ndarray:
    if X_BI is None:
        return points
    return points @ X_BI[:3, :3].T + X_BI[:3, 3]


def check_units(path: Path, points: np.ndarray, what: str, scale: float = 1.0, *,
                cli: bool) -> None:
    """Refuses a point cloud whose coordinates (``points`` (n, 3), m after ``scale``) are not
    metres: a largest extent over :data:`MAX_INPUT_EXTENT`, with the scale that brings it
    under (``objects.plausibility.scale_hint``), named as ``cli`` says (:func:`~.errors.setting`)."""
    from gbh_drake.objects.plausibility import MIN_EXTENT, scale_hint

    extent = points.max(axis=0) - points.min(axis=0)
    if float(extent.max()) > MAX_INPUT_EXTENT:
        units = "its units" if scale == 1.0 else f"its units x {scale:g}"
        hint = scale_hint(float(extent.max()), scale, field=setting("scale", cli, given=True),
                          within=(MIN_EXTENT, MAX_INPUT_EXTENT))
        raise GraspsInputError(path, what, f"spans {' x '.join(f'{e:.4g}' for e in extent)} "
                                           f"({units}): not metres; {hint}")


def check_object_size(path: Path, mesh, what: str, scale: float = 1.0, *,
                      cli: bool) -> None:
    """Refuses an object (``mesh``, m after ``scale``, in B) ``gbh run`` refuses: smaller than
    the scan and the gripper sense or larger than the workspace
    (``objects.plausibility.size_refusal``), with the scale that fixes it, named as ``cli``
    says (:func:`~.errors.setting`)."""
    from gbh_drake.objects.plausibility import size_refusal

    refusal = size_refusal(mesh, scale, field=setting("scale", cli, given=True))
    if refusal:
        raise GraspsInputError(path, what, refusal)


def check_table_under(path: Path, option: str, table, points: np.ndarray, what: str, *,
                      cli: bool) -> list[str]:
    """Refuses a given ``table`` that lies above most of the object's ``points`` (n, 3, m, in
    B; more than :data:`BELOW_TABLE_REFUSAL` of them over :data:`BELOW_TABLE` under it): a
    table in another frame or at the wrong height, which GbH would take the object for lying
    under. Returns the warning when it cuts off fewer (at least
    :data:`BELOW_TABLE_WARNING`), else none. ``option`` names what gave the table, ``what``
    the points; ``cli``: how the frame's setting is named (:func:`~.errors.setting`)."""
    if not len(points):
        return []
    heights = table.heights(points)
    below = heights < -BELOW_TABLE
    share = float(np.mean(below))
    if share < BELOW_TABLE_WARNING:
        return []
    z = points[:, 2]
    where = (f"the table {plane_text(table)} lies above {100 * share:.0f} % of {what} (z "
             f"{z.min():.3f} to {z.max():.3f} m in B; down to {-heights.min() * 1e3:.0f} mm "
             "below it)")
    if share > BELOW_TABLE_REFUSAL:
        raise GraspsInputError(path, option, f"{where}: a table under the object lies at its "
                                             f"lowest point or below (z = {z.min():.4f} m); or "
                                             "give the input's pose in B with "
                                             f"{setting('frame', cli, given=True)}")
    return [f"{where}: GbH takes that part for under the table; is {option} where the object "
            "stands?"]


def _mesh(path: Path, options: InputOptions) -> ScanInput:
    """A mesh file: the object alone."""
    from gbh_drake.objects.mesh_io import MeshImportError, load_mesh_file
    from gbh_drake.perception.scan import ScanResult

    objects_log = logging.getLogger("gbh_drake.objects")  # its warnings go in the result
    level = objects_log.level
    objects_log.setLevel(logging.ERROR)
    try:
        mesh = load_mesh_file(path, scale=options.scale)
    except MeshImportError as e:
        raise GraspsInputError(path, "", str(e).removeprefix(f"{path}: ")) from None
    finally:
        objects_log.setLevel(level)
    if options.X_BI is not None:
        mesh.apply_transform(options.X_BI)
    check_object_size(path, mesh, "vertices", options.scale, cli=options.cli)
    vertices = np.asarray(mesh.vertices, dtype=float)
    table = table_plane(options.table) if options.table is not None else under(vertices)
    warnings = [w for w in mesh.metadata.get("gbh_warnings", []) if "extent" not in w]
    if options.table is not None:
        warnings += check_table_under(path, options.table_option, table, vertices,
                                      "the mesh's vertices", cli=options.cli)
    scan = ScanResult(mesh, vertices, table=table, warnings=warnings)
    notes = [NO_FREE_SPACE]
    if table.source == "lowest point":
        given = [setting(name, options.cli, given=True) for name in ("table_z", "table_plane")]
        notes.append(f"the table: horizontal, under the mesh's lowest point (z = "
                     f"{table.height:.4f} m in B); give {given[0]} or {given[1]} if it is "
                     "elsewhere")
    return ScanInput("mesh", str(path), scan, table.source, notes)


def _point_cloud(path: Path, points: np.ndarray, options: InputOptions) -> ScanInput:
    from gbh_drake.perception.config import ScanConfig
    from gbh_drake.scan_grasps.cloud import find_object, fuse_object

    config = ScanConfig()
    table = table_plane(options.table) if options.table is not None else None
    found = find_object(points, config, table=table, target=options.target, cli=options.cli)
    warnings = [] if table is None else check_table_under(
        path, options.table_option, table, found.column,
        "the object's points (with the cloud's under it)" if found.object_points is not None
        else "the cloud's points", cli=options.cli)
    fused = fuse_object(found, config)
    fused.scan.warnings += warnings
    if not fused.scan.empty:
        check_object_size(path, fused.scan.mesh_W, "points", options.scale, cli=options.cli)
    return ScanInput("point_cloud", str(path), fused.scan, fused.table_source,
                     [NO_FREE_SPACE] + ([fused.note] if fused.note else []))


def _depth_images(path: Path, options: InputOptions) -> ScanInput:
    from gbh_drake.scan_grasps.depth_input import scan_views
    from gbh_drake.scan_grasps.views import read_views

    views = read_views(path)
    scan, source, notes = scan_views(views, options)
    return ScanInput("depth_images", str(views.path), scan, source, notes, dict(views.gbh),
                     views.seed)
