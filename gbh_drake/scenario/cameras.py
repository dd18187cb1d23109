"""The scenario's extra cameras (Drake's ``CameraConfig``), checked here because Drake would
stop deep inside the build, some with an assertion that kills the process."""

from gbh_drake.core.ranges import FieldError, Int, NonNeg, Pos, Range
from gbh_drake.modeling.directives import ModelInfo

#: Renderer classes a camera may use: VTK works headless and offline (GL needs a display,
#: glTF-client a render server over the network).
RENDERER_CLASSES = ("", "RenderEngineVtk")
#: Camera limits.
MAX_CAMERA_PIXELS_SIDE = 4096
MAX_CAMERA_FPS = 240.0
MAX_CAMERAS = 8


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
