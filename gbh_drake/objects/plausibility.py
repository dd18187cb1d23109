"""Is an imported mesh a plausible hand-held object? Warnings with a hint at the fix.

Pure numpy/trimesh. Each warning of :func:`plausibility_warnings` is one line,
``"<source>: <what is wrong> (<figures>): <hint>"``, where the hint names the scenario field that
fixes it (``scale``, ``mass``, ``density``; see :data:`FIELD_SCALE` etc.). The rules:

* **Size**: the largest extent must be within [:data:`MIN_EXTENT`, :data:`MAX_EXTENT`]
  (1 cm - 1 m). Outside it, the hint proposes the unit that brings the extent nearest to a typical
  :data:`TYPICAL_EXTENT` (15 cm) within the range: millimetres (x 0.001), centimetres (x 0.01) or
  inches (x 0.0254) when too big, x 10 / 100 / 1000 when too small; the proposed ``scale`` is the
  total one (it includes the scale already applied).
* **Mass**: within [:data:`MIN_MASS`, :data:`MAX_MASS`] (5 g - 5 kg); hint: give ``mass``
  directly or another ``density``.
* **Solid-filled**: only when the mass comes from a density (and the size is plausible). The
  mesh is a filled solid when its volume is at least :data:`SOLID_MIN_FILL` (50 %) of its
  convex hull's and its mean thickness 2 V / A (volume over half the area: a wall's thickness
  for a thin shell, a third of the side for a cube) is at least :data:`SOLID_MIN_THICKNESS`
  (1 cm). Then density x volume weighs a solid block; if the real object is hollow (a scanned
  mug whose inside was closed, a box, a bottle) its mass is far lower. The warning gives the
  mass of a hollow object of the same outer surface with :data:`ASSUMED_WALL` (4 mm) walls
  (area x wall x density), and the hint is to give ``mass`` directly. Calibrated on the object
  set: its modelled-wall objects have 2 V / A of 2-5 mm (headphones 14 mm at 22 % fill,
  pybullet's mug 9 mm at 43 %, the tape roll 9 mm at 50 %); its solid objects (ball, bottle,
  box, can, spray bottle) and a solid-filled classic mug have 23-35 mm at 78-100 % fill. Objects
  that really are solid (a full bottle) warn too when given by density: the warning says "if
  the real object is hollow".
"""

from __future__ import annotations

import numpy as np
import trimesh

MIN_EXTENT = 0.01
"""m: a hand-held object's largest extent is at least this."""
MAX_EXTENT = 1.0
"""m: ... and at most this."""
TYPICAL_EXTENT = 0.15
"""m: the unit hint picks the scale whose result is nearest (in log) to this."""
MIN_MASS = 0.005
"""kg: plausible mass range of a hand-held object, lower end (5 g)."""
MAX_MASS = 5.0
"""kg: ... upper end (5 kg)."""
SOLID_MIN_FILL = 0.5
"""volume / convex-hull volume at or above which a mesh may be solid-filled."""
SOLID_MIN_THICKNESS = 0.01
"""m: mean thickness 2 V / A at or above which a mesh is solid-filled (with the fill)."""
ASSUMED_WALL = 0.004
"""m: wall thickness of the hollow object the solid-filled warning compares with."""

REFUSE_MAX_EXTENT = 1.2
"""m: a scenario refuses an object larger than this: the scanner's workspace box (1.2 m wide,
``ScanConfig.workspace``) could not hold it, nor the arm lift it (a mesh in millimetres read as
metres is a 100 m object)."""
REFUSE_MIN_EXTENT = 0.005
"""m: ... or smaller than this: two TSDF voxels (2.5 mm), below what the scan can resolve and
thinner than the gripper's 8 mm rods."""

PAYLOAD = 3.0
"""kg: the Franka Panda's payload. A heavier object is refused (the arm may not carry it; it
would fail every trial), by ``gbh run``, ``gbh experiment`` and ``gbh objects list`` alike."""

#: Scenario fields named in hints.
FIELD_SCALE, FIELD_MASS, FIELD_DENSITY = "scale", "mass", "density"

#: (name, factor) of units a too-big mesh may be in.
UNITS_TOO_BIG = (("millimetres", 0.001), ("centimetres", 0.01), ("inches", 0.0254))
#: Factors that may fix a too-small mesh.
FACTORS_TOO_SMALL = (10.0, 100.0, 1000.0)


def extent_warnings(mesh: trimesh.Trimesh, scale: float = 1.0) -> list[str]:
    """Warnings (without the source's name) when the largest extent of ``mesh`` (m, after the
    ``scale`` already applied) is outside [MIN_EXTENT, MAX_EXTENT], with the ``scale`` hint."""
    extent = float(np.max(mesh.extents)) if len(mesh.vertices) else 0.0
    if MIN_EXTENT <= extent <= MAX_EXTENT or extent <= 0.0 or not np.isfinite(extent):
        return []
    what = (f"largest extent {_length(extent)} is implausible for a hand-held object "
            f"({_length(MIN_EXTENT)} - {_length(MAX_EXTENT)})")
    hint = scale_hint(extent, scale)
    return [f"{what}: {hint}"]


def size_refusal(mesh: trimesh.Trimesh, scale: float = 1.0, *,
                 field: str = FIELD_SCALE) -> str | None:
    """Why an object of ``mesh`` (m, after ``scale``) cannot be simulated at all, with the
    hint naming ``field`` (:func:`scale_hint`), or None: its largest extent is outside
    [REFUSE_MIN_EXTENT, REFUSE_MAX_EXTENT] (the warnings' range is narrower:
    :func:`extent_warnings`)."""
    extent = float(np.max(mesh.extents)) if len(mesh.vertices) else 0.0
    if not np.isfinite(extent) or REFUSE_MIN_EXTENT <= extent <= REFUSE_MAX_EXTENT:
        return None
    what = ("larger than the workspace" if extent > REFUSE_MAX_EXTENT else
            "smaller than the scan and the gripper can sense")
    bound = REFUSE_MAX_EXTENT if extent > REFUSE_MAX_EXTENT else REFUSE_MIN_EXTENT
    sign = ">" if extent > REFUSE_MAX_EXTENT else "<"
    return (f"largest extent {_length(extent)} is {what} ({sign} {_length(bound)}): "
            f"{scale_hint(extent, scale, field=field)}")


def payload_refusal(mass: float) -> str | None:
    """Why an object of ``mass`` (kg) cannot be picked (heavier than :data:`PAYLOAD`), or
    None."""
    if mass <= PAYLOAD:
        return None
    return f"weighs {mass:.3g} kg, above the Franka's payload ({PAYLOAD:g} kg)"


def scale_hint(extent: float, scale: float = 1.0, *, field: str = FIELD_SCALE,
               within: tuple[float, float] = (MIN_EXTENT, MAX_EXTENT)) -> str:
    """The hint for a mesh of largest ``extent`` (m) read at ``scale``: which total scale
    brings it ``within`` the plausible range (m; default a hand-held object's), e.g.
    ``"looks like centimetres: give scale: 0.01"``. ``field`` names the setting as its caller
    writes it: a scenario's field (``scale``: ``scale: 0.01``), a command's option (``--scale``:
    ``--scale 0.01``) or a Python argument (``scale=``: ``scale=0.01``)."""
    low, high = within
    if extent > high:
        options = [(name, f) for name, f in UNITS_TOO_BIG]
    else:
        options = [(f"{f:g}x too small", f) for f in FACTORS_TOO_SMALL]
    fitting = [(abs(np.log(extent * f / TYPICAL_EXTENT)), name, f) for name, f in options
               if low <= extent * f <= high]
    if not fitting:
        return f"check the file's unit and give {field.removesuffix('=')} (now {scale:g})"
    _, name, factor = min(fitting)
    looks = f"looks like {name}" if extent > high else f"looks {name}"
    give = f"{field} " if field.startswith("--") else field if field.endswith("=") else \
        f"{field}: "
    return f"{looks}: give {give}{scale * factor:g} (then {_length(extent * factor)})"


def plausibility_warnings(
    mesh: trimesh.Trimesh,
    mass: float,
    source: str,
    *,
    density: float | None = None,
    scale: float = 1.0,
) -> list[str]:
    """Warnings, each ``"<source>: ..."`` with a hint, for an object of ``mesh`` (m) and ``mass``
    (kg) that is implausible as a hand-held object (see the module docstring for the rules).

    ``density`` (kg/m^3) is the one that gave ``mass``, or None when the mass was given
    directly (then no solid-filled warning); ``scale`` the scale already applied to the file
    (for the hint's total scale). Empty list: nothing to say.
    """
    out = [f"{source}: {w}" for w in extent_warnings(mesh, scale)]
    if not (np.isfinite(mass) and MIN_MASS <= mass <= MAX_MASS):
        side = "light" if mass < MIN_MASS else "heavy"
        figures = f"{_mass(mass)}"
        if density is not None:
            figures += f" = density {density:g} kg/m^3 x volume {mass / density * 1e6:.4g} cm^3"
        fix = (f"give {FIELD_MASS} (kg) directly" if density is not None
               else f"check {FIELD_MASS}")
        if extent_warnings(mesh, scale):
            fix = f"fix {FIELD_SCALE} first, then " + fix
        elif density is not None:
            fix += f" or another {FIELD_DENSITY}"
        out.append(f"{source}: mass {figures} is implausibly {side} for a hand-held object "
                   f"({_mass(MIN_MASS)} - {_mass(MAX_MASS)}): {fix}")
    if density is not None and not extent_warnings(mesh, scale):
        filled = solid_fill(mesh, mass / density)
        if filled is not None:
            fill, thickness = filled
            shell = density * mesh.area * ASSUMED_WALL
            shell_note = (f"a hollow object of this shape with {ASSUMED_WALL * 1e3:g} mm walls "
                          f"would weigh ~{_mass(shell)}")
            out.append(
                f"{source}: the mesh is solid-filled (volume {fill:.0%} of its convex hull, mean "
                f"thickness 2V/A {thickness * 1e3:.0f} mm), so density {density:g} kg/m^3 gives "
                f"the mass of a solid block, {_mass(mass)}; {shell_note}: if the real object is "
                f"hollow (a mug, a box, a bottle), give {FIELD_MASS} (kg) directly")
    return out


def solid_fill(mesh: trimesh.Trimesh, volume: float | None = None) -> tuple[float, float] | None:
    """``(volume / hull volume, mean thickness 2 V / A (m))`` when ``mesh`` looks solid-filled
    (both at or above SOLID_MIN_FILL and SOLID_MIN_THICKNESS), else None. ``volume`` (m^3)
    defaults to the mesh's own (use the voxel fill's for a mesh that is not watertight)."""
    if volume is None:
        volume = float(mesh.volume)
    area = float(mesh.area)
    try:
        hull_volume = float(mesh.convex_hull.volume)
    except Exception:  # noqa: BLE001  (qhull on flat input)
        return None
    if not (volume > 0 and area > 0 and hull_volume > 0):
        return None
    fill, thickness = volume / hull_volume, 2.0 * volume / area
    if fill >= SOLID_MIN_FILL and thickness >= SOLID_MIN_THICKNESS:
        return min(fill, 1.0), thickness
    return None


def _length(metres: float) -> str:
    if metres >= 1.0:
        return f"{metres:.3g} m"
    if metres >= 0.01:
        return f"{metres * 100:.3g} cm"
    return f"{metres * 1000:.3g} mm"


def _mass(kg: float) -> str:
    return f"{kg:.3g} kg" if kg >= 1.0 else f"{kg * 1000:.3g} g"
