"""``gbh grasps INPUT``: ranked hook grasps for a scan you have, in the robot's base frame B.

The argument parser (:func:`add_subcommand`) and the command (:func:`run_command`); the work is
:func:`gbh_drake.scan_grasps.api.grasps`'s.
"""

from __future__ import annotations

import argparse
from pathlib import Path

DESCRIPTION = """\
Ranked hook grasps (GbH) for one object on a table, in the robot's base frame B (Franka's
panda_link0): the gripper frame G and the flange panda_link8 at the pre-grasp, the grasp, closed
and lifted, the jaw's opening, the score and its terms (docs/grasps.md; the document's fields:
docs/grasps_schema.md).

INPUT is a mesh (.obj .ply .stl .glb .gltf .off: the object alone), a point cloud (.ply
without faces, .pcd, .npy (n, 3)) or a folder of depth images with its views.yaml (intrinsics,
each camera's pose in B, depth scale; gbh run --save-views writes one). Depth images go through
the simulated scan's table fit, segmentation, TSDF fusion, cap and free space; a mesh or a cloud
has no free space (the through-hole exit proof does not run: the output says so)."""

EPILOG = """\
examples:
  gbh grasps output/default/views                 # the views gbh run --save-views wrote
  gbh grasps mug.obj --table-z 0.0 --html mug.html
  gbh grasps mug_mm.stl --scale 0.001             # a mesh in millimetres
  gbh grasps cloud.npy --frame 0.4,0,0.5,180,0,90 --out cloud_grasps.json
Exit 0 with grasps or with a reason there are none (in the output's "none"); 2 for an input
that cannot be used or an output that cannot be written (one line naming the file and the
field or option; nothing is written)."""


def add_subcommand(sub) -> None:
    """Adds ``gbh grasps`` to the ``gbh`` parser's subcommands."""
    p = sub.add_parser("grasps", help="ranked grasps for a mesh, point cloud or depth images "
                                      "you have, in the robot's base frame",
                       description=DESCRIPTION, epilog=EPILOG,
                       formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("input", help="a mesh, a point cloud, or a folder of depth images (or its "
                                 "views.yaml)")
    p.add_argument("--scale", type=float, metavar="S", default=1.0,
                   help="the file's units in metres, for a mesh or a point cloud (0.001: "
                        "millimetres, 0.01: centimetres, 0.0254: inches), applied before "
                        "--frame; default 1")
    table = p.add_mutually_exclusive_group()
    table.add_argument("--table-z", type=float, metavar="Z",
                       help="the table top is the horizontal plane z = Z (m, in B); default: the "
                            "views file's, else fitted to the data, else under the object")
    table.add_argument("--table-plane", metavar="A,B,C,D",
                       help="the table is the plane A x + B y + C z + D = 0 (in B)")
    p.add_argument("--frame", metavar="POSE",
                   help="the input's own frame I as its pose in B, when the input is not in B: "
                        "x,y,z,roll,pitch,yaw (m, deg; R = Rz Ry Rx) or 16 numbers (X_BI by "
                        "rows); e.g. a cloud in the camera's frame with the camera's pose")
    p.add_argument("--target", metavar="X,Y,Z",
                   help="where the object is (m, in B); default: where the views look, or the "
                        "cloud's middle above the table")
    p.add_argument("--out", metavar="FILE",
                   help="write the grasps here (default grasps.json, or grasps.yaml with "
                        "--yaml; '-' for stdout)")
    p.add_argument("--yaml", action="store_true", help="write YAML instead of JSON")
    p.add_argument("--html", metavar="FILE",
                   help="also write a static Meshcat page of the scan, its hanging "
                        "structures, the ranked grasps and the closest refused ones")
    p.add_argument("--top", type=int, metavar="K",
                   help="how many grasps (default GbhParams.top_k: 40; distinct)")
    p.add_argument("--preset", choices=["paper"],
                   help="'paper': the paper's rules alone (no turned approaches, unseen space "
                        "free, no de-duplication)")
    p.add_argument("--seed", type=int, metavar="N",
                   help="the surface sampler's seed (default: the views file's, else 0)")


def _numbers(text: str, n: int, flag: str):
    import numpy as np

    values = [float(v) for v in text.replace(",", " ").split()]
    if len(values) != n or not np.isfinite(values).all():
        raise ValueError(f"{flag}: {n} finite numbers, got {text!r}")
    return np.array(values)


def run_command(args, parser) -> int:
    """Runs ``gbh grasps`` with parsed ``args`` (``parser.error`` for a bad flag). The output
    files are checked before the work and written together at the end, whole or not at
    all."""
    import numpy as np

    from gbh_drake.scan_grasps.api import grasps_as
    from gbh_drake.scan_grasps.document import document, to_json, to_yaml
    from gbh_drake.scan_grasps.poses import parse_pose

    out = args.out or ("grasps.yaml" if args.yaml else "grasps.json")
    files = {flag: Path(path) for flag, path in (("--out", out), ("--html", args.html))
             if path and path != "-"}
    try:
        if not (np.isfinite(args.scale) and args.scale > 0):
            raise ValueError(f"--scale: the file's units in metres, a positive finite number; "
                             f"got {args.scale}")
        frame = parse_pose(args.frame) if args.frame else None
        plane = _numbers(args.table_plane, 4, "--table-plane") if args.table_plane else None
        target = _numbers(args.target, 3, "--target") if args.target else None
        if args.top is not None and not 1 <= args.top <= 100:
            raise ValueError(f"--top: 1 to 100, got {args.top}")
        if args.table_z is not None and not np.isfinite(args.table_z):
            raise ValueError(f"--table-z: a finite height, got {args.table_z}")
        for flag, path in files.items():
            check_writable(path, flag)
        if len(files) == 2 and files["--html"].resolve() == files["--out"].resolve():
            raise ValueError(f"--html {args.html}: the same file as --out")
        result = grasps_as(True, args.input, scale=args.scale, table_z=args.table_z,
                           table_plane=plane, frame=frame, target=target, preset=args.preset,
                           seed=args.seed, top=args.top)
    except ValueError as e:
        from gbh_drake.scan_grasps.errors import GraspsInputError

        if isinstance(e, GraspsInputError):
            raise
        parser.error(str(e))
    doc = document(result)
    text = to_yaml(doc) if args.yaml else to_json(doc)
    contents = {"--out": text}
    if args.html:
        from gbh_drake.scan_grasps.page import grasps_page

        contents["--html"] = grasps_page(result)
    write_together([(path, contents[flag]) for flag, path in files.items()])
    if out == "-":
        print(text, end="")
    else:
        print(summary_text(result))
        for path in files.values():
            print(f"wrote {path}")
    return 0


def check_writable(path: Path, option: str) -> None:
    """Raises ``OutputError`` (naming ``path`` and ``option``) when ``path`` cannot be
    written: a folder, in a folder that does not exist or is not writable."""
    import os

    from gbh_drake.outputs import OutputError, reason, special_file

    if "\0" in str(path):
        raise OutputError(repr(str(path)), f"{option}: holds a NUL character")
    folder = path.parent
    try:
        if special_file(path):  # /dev/null: written into, its folder not used
            return
        if path.is_dir():
            problem = "is a folder"
        elif not folder.is_dir():
            problem = (f"its folder {folder} is not a folder" if folder.exists() else
                       f"its folder {folder} does not exist")
        elif not os.access(folder, os.W_OK | os.X_OK):
            problem = f"its folder {folder} is not writable"
        else:
            return
    except OSError as e:  # a name too long, a folder that cannot be looked into
        problem = f"cannot be used ({reason(e)})"
    raise OutputError(path, f"{option}: {problem}")


def write_together(files: list[tuple[Path, str]]) -> None:
    """Writes each (path, text) of ``files`` whole, or none of them: all to temporary files
    first, then renamed into place (``outputs.write_file``); a device or a pipe
    (``/dev/null``) is written into at the end (``outputs.special_file``); raises
    ``OutputError``."""
    import os

    from gbh_drake.outputs import OutputError, reason, remove, special_file, write_file, write_into

    staged: list[tuple[Path | None, Path, str]] = []
    try:
        for path, data in files:
            staged.append((None if special_file(path) else write_file(path, data), path, data))
        for tmp, path, data in staged:
            if tmp is None:
                write_into(path, data)
                continue
            try:
                os.replace(tmp, path)
            except OSError as e:
                raise OutputError(path, f"could not write it ({reason(e)})") from None
    finally:
        for tmp, _, _ in staged:
            if tmp is not None:
                remove(tmp)


def summary_text(result) -> str:
    """What ``gbh grasps`` found, in a few lines."""
    from gbh_drake.core.words import counted
    from gbh_drake.scan_grasps.table import plane_text

    lines = [f"input {result.input_path} ({result.input_kind.replace('_', ' ')}; free space: "
             f"{'yes' if result.free_space else 'no'}); table {plane_text(result.table)} "
             f"({result.table_source})"]
    lines += [f"  note: {n}" for n in result.notes]
    lines += [f"  warning: {w}" for w in result.warnings]
    lines.append(f"grasps: {counted(len(result.structures), 'hanging structure')}, "
                 f"{counted(result.n_candidates, 'candidate')}, {len(result.grasps)} ranked "
                 "(poses in B, Franka's panda_link0)")
    for g in result.grasps:
        p, y = g.X_B_link8[:3, 3], g.X_BG[:3, 1]
        lines.append(f"  #{g.rank} {g.kind:8s} score {g.score:.3f}  flange at "
                     f"({p[0]:.3f}, {p[1]:.3f}, {p[2]:.3f}) m, approach "
                     f"{g.terms['alpha_deg']:.0f} deg from straight down, closing along "
                     f"({y[0]:.2f}, {y[1]:.2f}, {y[2]:.2f}), lift {g.waypoints.lift_height:.2f} m")
    if result.none is not None:
        lines.append(f"  none: {result.none.outcome}: {result.none.message}")
    lines.append(f"  time {result.timings.get('total', 0.0):.2f} s")
    return "\n".join(lines)

