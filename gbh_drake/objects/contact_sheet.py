"""A contact sheet of the object set, rendered offscreen with Drake's RenderEngineVtk.

Each object is rendered alone on a grey floor, seen from the front-right and above, with its
ground-truth hangable parts drawn in: a red ball at each centre and a red rod along each axis
(a blue ball and rod for open hooks). Tiles are laid out with matplotlib (Agg, no display).

    python -m gbh_drake.objects.contact_sheet docs/objects_contact_sheet.png
"""

from __future__ import annotations

import sys
import tempfile
from pathlib import Path

import numpy as np

from gbh_drake.objects.catalog import list_objects, make_object
from gbh_drake.objects.export import obj_bytes
from gbh_drake.objects.spec import ObjectSpec

#: Direction from the object toward the camera (frame O), before normalising.
VIEW_DIRECTION = (0.9, -1.3, 1.0)
FOV_Y = np.radians(35.0)
TITLE = "gbh_drake object set (red: closed loops, blue: open hooks; rod = hole axis)"


def _look_at(eye: np.ndarray, target: np.ndarray):
    """Drake camera pose X_WC: +z_C toward the target, +y_C down on the image."""
    from pydrake.math import RigidTransform, RotationMatrix

    z = target - eye
    z /= np.linalg.norm(z)
    x = np.cross(z, [0.0, 0.0, 1.0])
    x /= np.linalg.norm(x)
    y = np.cross(z, x)
    return RigidTransform(RotationMatrix(np.column_stack([x, y, z])), eye)


def render_object(spec: ObjectSpec, width: int = 400, height: int = 320) -> np.ndarray:
    """An RGB image ``(height, width, 3)`` uint8 of one object with its hangable parts."""
    from pydrake.geometry import (
        Box,
        ClippingRange,
        ColorRenderCamera,
        Cylinder,
        GeometryInstance,
        MakeRenderEngineVtk,
        Mesh,
        PerceptionProperties,
        RenderCameraCore,
        RenderEngineVtkParams,
        RenderLabel,
        Rgba,
        SceneGraph,
        Sphere,
    )
    from pydrake.math import RigidTransform, RotationMatrix
    from pydrake.systems.sensors import CameraInfo

    scene_graph = SceneGraph()
    params = RenderEngineVtkParams()
    params.default_clear_color = np.array([1.0, 1.0, 1.0])
    scene_graph.AddRenderer("vtk", MakeRenderEngineVtk(params))
    source = scene_graph.RegisterSource("contact_sheet")

    def add(shape, X_WG, rgba, name):
        gid = scene_graph.RegisterAnchoredGeometry(
            source, GeometryInstance(X_WG, shape, name)
        )
        props = PerceptionProperties()
        props.AddProperty("phong", "diffuse", Rgba(*rgba))
        props.AddProperty("label", "id", RenderLabel(len(name)))
        scene_graph.AssignRole(source, gid, props)

    lo, hi = spec.mesh.bounds
    centre = 0.5 * (lo + hi)
    radius = 0.5 * float(np.linalg.norm(hi - lo))
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / f"{spec.name}.obj"
        path.write_bytes(obj_bytes(spec.mesh))
        add(Mesh(str(path)), RigidTransform(), spec.rgba, spec.name)
        floor = 4.0 * radius
        add(Box(floor, floor, 0.002), RigidTransform([centre[0], centre[1], -0.001]),
            (0.95, 0.95, 0.93, 1.0), "floor")
        for k, part in enumerate(spec.hangable_parts):
            colour = (0.9, 0.05, 0.05, 1.0) if part.kind == "closed" else (0.1, 0.2, 0.95, 1.0)
            add(Sphere(0.004), RigidTransform(part.center_O), colour, f"c{k}")
            R = RotationMatrix.MakeFromOneVector(part.axis_O, 2)
            add(Cylinder(0.0015, 0.08), RigidTransform(R, part.center_O), colour, f"a{k}")
        context = scene_graph.CreateDefaultContext()
        query = scene_graph.get_query_output_port().Eval(context)
        direction = np.asarray(VIEW_DIRECTION) / np.linalg.norm(VIEW_DIRECTION)
        distance = 1.15 * radius / np.tan(0.5 * FOV_Y)
        X_WC = _look_at(centre + distance * direction, centre)
        core = RenderCameraCore(
            "vtk", CameraInfo(width, height, FOV_Y), ClippingRange(0.01, 10.0), RigidTransform()
        )
        image = query.RenderColorImage(
            ColorRenderCamera(core, False), scene_graph.world_frame_id(), X_WC
        )
    return np.asarray(image.data)[:, :, :3].copy()


def contact_sheet(out_png, names: list[str] | None = None, columns: int = 6, *,
                  specs: list[ObjectSpec] | None = None, title: str = TITLE,
                  dpi: int = 90) -> Path:
    """Render every object of the set (or ``names``, or the given ``specs``, each in its frame
    O) into one labelled PNG; returns its path."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    if specs is None:
        specs = [make_object(name) for name in (names or list_objects())]
    rows = int(np.ceil(len(specs) / columns))
    fig, axes = plt.subplots(rows, columns, figsize=(3.2 * columns, 2.9 * rows))
    for ax in np.ravel(axes):
        ax.axis("off")
    for ax, spec in zip(np.ravel(axes), specs, strict=False):
        ax.imshow(render_object(spec))
        lo, hi = spec.mesh.bounds
        mass = spec.density * _volume_for_label(spec)
        size = " x ".join(f"{100 * e:.1f}" for e in hi - lo)
        label = f"{spec.name}{' (control)' if spec.is_control else ''}\n{size} cm, {mass:.2f} kg"
        ax.set_title(label, fontsize=9)
    fig.suptitle(title)
    fig.tight_layout()
    out = Path(out_png)
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out, dpi=dpi)
    plt.close(fig)
    return out


def _volume_for_label(spec: ObjectSpec) -> float:
    from gbh_drake.objects.mass import mass_properties_detailed

    return mass_properties_detailed(spec.mesh, 1.0).mass


def main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    out = argv[0] if argv else "docs/objects_contact_sheet.png"
    print(contact_sheet(out))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
