"""The named objects of the set: parametric builders in metres, frame O (see ``spec``).

Each builder takes keyword parameters with realistic defaults and returns a :class:`Design`
(a manifold solid, the designed holes, genus, target mass, colour). :func:`make_object` turns a
design into an :class:`ObjectSpec`: it converts the solid to a mesh, puts the lowest point on
z = 0, sets the density so that the solid's volume has the target mass (walls are modelled a few
millimetres thick and closed containers as solids, so a material density would give wrong
masses), and measures each hole (:func:`gbh_drake.objects.holes.fit_hole`) to fill in its
ground truth: the centre is moved across the axis to the middle of the largest clear disc, and
the clear diameter is that disc's diameter.

Hole axes: loops in the x-z plane have axis +y, flat loops axis +z.

Each object is registered with its natural rest (:class:`~gbh_drake.objects.spec.NaturalRest`,
the ``natural`` protocol of the experiment): the rest a person would set it down in, with a
one-line reason. Every object of the set is modelled in that rest (frame O upright as a person
sets it down), so every rest here is :func:`as_modelled`; the tests check that each is one of the
object's stable resting poses.
"""

from __future__ import annotations

import inspect
import math
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
from manifold3d import CrossSection, Manifold

from gbh_drake.core.arguments import argument_problem, require
from gbh_drake.core.ranges import is_number
from gbh_drake.objects import primitives as P
from gbh_drake.objects.handles import XZ, LoopPlane, arch_handle, handle_loop, side_handle
from gbh_drake.objects.holes import fit_hole
from gbh_drake.objects.spec import HangablePart, NaturalRest, ObjectSpec

Y_AXIS = (0.0, 1.0, 0.0)
Z_AXIS = (0.0, 0.0, 1.0)


@dataclass
class HoleDesign:
    """A designed hole: first-guess ``center`` (3,), ``axis`` (3,), ``kind``, and how far (m)
    :func:`fit_hole` may move the centre across the axis (0 for open hooks: keep the centre)."""

    name: str
    center: np.ndarray
    axis: tuple[float, float, float]
    kind: str = "closed"
    search_radius: float = 0.01


@dataclass
class Design:
    """What a builder returns; ``mass`` is the target mass (kg)."""

    solid: Manifold
    genus: int
    mass: float
    rgba: tuple[float, float, float, float]
    description: str
    holes: list[HoleDesign] = field(default_factory=list)
    is_control: bool = False
    center_xy: bool = False
    """Shift x/y so that the bounding box is centred (flat objects without a body axis)."""


_BUILDERS: dict[str, Callable[..., Design]] = {}
_EXTERNAL: dict[str, Callable[[], ObjectSpec]] = {}
_RESTS: dict[str, NaturalRest] = {}


def as_modelled(reason: str) -> NaturalRest:
    """The natural rest of an object modelled in it: frame O as it is (rpy 0, 0, 0)."""
    return NaturalRest((0.0, 0.0, 0.0), reason)


def register(name: str, *, rest: NaturalRest | None = None):
    """Decorator adding a builder to the set under ``name``, with its natural rest (None: the
    object has none, and the ``natural`` protocol refuses it)."""

    def wrap(fn: Callable[..., Design]) -> Callable[..., Design]:
        _BUILDERS[name] = fn
        _set_rest(name, rest)
        return fn

    return wrap


def register_external(name: str, loader: Callable[[], ObjectSpec], *,
                      rest: NaturalRest | None = None) -> None:
    """Add a non-procedural object (a loader returning a finished ObjectSpec), with its natural
    rest as :func:`register`."""
    _EXTERNAL[name] = loader
    _set_rest(name, rest)


def _set_rest(name: str, rest: NaturalRest | None) -> None:
    if rest is None:
        _RESTS.pop(name, None)
    else:
        _RESTS[name] = rest


def natural_rest(name: str) -> NaturalRest | None:
    """The declared natural rest of the object ``name`` (without building it), or None."""
    if name not in _BUILDERS and name not in _EXTERNAL:
        raise KeyError(f"unknown object {name!r}; known: {', '.join(list_objects())}")
    return _RESTS.get(name)


def list_objects() -> list[str]:
    """Names of all objects, controls included, sorted."""
    return sorted([*_BUILDERS, *_EXTERNAL])


def make_object(name: str, **params) -> ObjectSpec:
    """Build the object ``name`` (parameters override the builder's defaults: numbers, or a
    list of numbers for a box's ``size``; lengths in m and masses in kg are positive, angles
    ``*_deg`` any finite number). Deterministic. Raises KeyError for an unknown name, TypeError
    for a name or parameter of the wrong type or a parameter the object does not have,
    ValueError for a length or mass that is not positive or parameters that give no solid (a
    wall as thick as the radius)."""
    require("make_object", "name", name, str, "an object's name (gbh objects list)")
    for key, value in params.items():
        values = value if isinstance(value, list | tuple) else [value]
        if not values or not all(is_number(v) and math.isfinite(v) for v in values):
            raise TypeError(argument_problem("make_object", key, "a finite number (or a list "
                                             "of them)", value))
        if not key.endswith("_deg") and not all(v > 0 for v in values):
            raise ValueError(argument_problem("make_object", key, "positive (a length in m or "
                                              "a mass in kg)", value))
    if name in _EXTERNAL:
        if params:
            raise TypeError(f"object {name!r} takes no parameters")
        spec = _EXTERNAL[name]()
        if spec.natural_rest is None:
            spec.natural_rest = _RESTS.get(name)
        return spec
    if name not in _BUILDERS:
        raise KeyError(f"unknown object {name!r}; known: {', '.join(list_objects())}")
    accepted = inspect.signature(_BUILDERS[name]).parameters
    for key in params:
        if key not in accepted:
            raise TypeError(f"make_object(): object {name!r} has no parameter {key!r}; its "
                            f"parameters: {', '.join(accepted)}")
    try:
        return finish(name, _BUILDERS[name](**params))
    except ValueError as e:  # manifold3d: an invalid construction
        given = ", ".join(f"{k}={v!r}" for k, v in params.items())
        raise ValueError(f"make_object(): {name!r} with {given or 'its defaults'} gives no "
                         f"solid ({e}): a wall as thick as the radius, a hole larger than its "
                         "part?") from None


def finish(name: str, design: Design) -> ObjectSpec:
    """Mesh, placement, density and measured ground truth of a design."""
    mesh = P.to_trimesh(design.solid)
    lo, hi = mesh.bounds
    shift = np.array([0.0, 0.0, -lo[2]])
    if design.center_xy:
        shift[:2] = -0.5 * (lo[:2] + hi[:2])
    mesh.apply_translation(shift)
    parts = []
    for hole in design.holes:
        center, clear = fit_hole(mesh, hole.center + shift, hole.axis, hole.search_radius)
        parts.append(HangablePart(hole.name, center, hole.axis, hole.kind, clear))
    density = round(design.mass / mesh.volume, 1)
    return ObjectSpec(
        name=name,
        mesh=mesh,
        density=density,
        hangable_parts=parts,
        is_control=design.is_control,
        rgba=design.rgba,
        description=design.description,
        genus=design.genus,
        natural_rest=_RESTS.get(name),
    )


# ---- shared pieces -------------------------------------------------------------------------------
def _radius_at(outer: np.ndarray, z: float) -> float:
    """Outer radius (m) of a revolution profile ``(r, z)`` at height ``z``."""
    side = outer[1:]
    return float(np.interp(z, side[:, 1], side[:, 0]))


def _mug(
    outer,
    wall: float,
    z_top: float,
    z_bottom: float,
    reach: float,
    section: np.ndarray,
    fillet: float,
    rise: float = 0.0,
) -> tuple[Manifold, HoleDesign]:
    """A vessel of revolution with one side handle on +x (hole axis +y)."""
    outer = np.asarray(outer, dtype=np.float64)
    shell, cavity = P.vessel(outer, wall)
    handle, guess = side_handle(
        XZ,
        (_radius_at(outer, z_top), z_top),
        (_radius_at(outer, z_bottom), z_bottom),
        reach,
        section,
        fillet,
        rise=rise,
        inset=wall,
    )
    return P.subtract(P.union(shell, handle), cavity), HoleDesign("handle", guess, Y_AXIS)


def _ring(center_uv, outer_half, inner_half) -> tuple[CrossSection, CrossSection]:
    """An elliptic ring in 2-D: ``(outer disc, inner disc)`` with half axes ``(a, b)``."""

    def disc(half):
        return CrossSection.circle(1.0, 48).scale(tuple(half)).translate(tuple(center_uv))

    return disc(outer_half), disc(inner_half)


# ---- cups and mugs -------------------------------------------------------------------------------
@register("mug_classic",
          rest=as_modelled("upright on its base, as a mug is set down on a table or shelf"))
def mug_classic(radius=0.041, height=0.095, wall=0.0045, reach=0.045, mass=0.33) -> Design:
    """Straight ceramic mug (8.2 cm x 9.5 cm) with a round-section C handle."""
    outer = [(0, 0), (radius - 0.003, 0), (radius, 0.003), (radius, height)]
    solid, hole = _mug(outer, wall, 0.8 * height, 0.25 * height, reach,
                       P.circle_section(0.0055), fillet=0.02)
    return Design(solid, 1, mass, (0.92, 0.92, 0.88, 1.0),
                  "classic straight ceramic mug, C handle of round section", [hole])


@register("mug_large",
          rest=as_modelled("upright on its base, as a mug is set down on a table or shelf"))
def mug_large(radius=0.048, height=0.105, wall=0.005, reach=0.05, mass=0.45) -> Design:
    """Large latte mug (9.6 cm x 10.5 cm), tall D handle with a flat oval section."""
    outer = [(0, 0), (radius - 0.004, 0), (radius - 0.001, 0.004), (radius, height)]
    solid, hole = _mug(outer, wall, 0.85 * height, 0.2 * height, reach,
                       P.ellipse_section(0.005, 0.008), fillet=0.012)
    return Design(solid, 1, mass, (0.2, 0.45, 0.75, 1.0),
                  "large latte mug, tall D handle with flat oval section", [hole])


@register("teacup",
          rest=as_modelled("upright on its base, as a cup is set down on a table or saucer"))
def teacup(r_base=0.028, r_rim=0.043, height=0.065, wall=0.0035, mass=0.2) -> Design:
    """Tapered teacup with an ear-shaped handle that rises outward."""
    outer = [(0, 0), (r_base - 0.003, 0), (r_base, 0.005), (r_rim, height)]
    solid, hole = _mug(outer, wall, 0.9 * height, 0.22 * height, 0.036,
                       P.circle_section(0.0045), fillet=0.016, rise=0.008)
    return Design(solid, 1, mass, (0.85, 0.75, 0.55, 1.0),
                  "tapered teacup, ear handle rising outward", [hole])


@register("mug_square_handle",
          rest=as_modelled("upright on its base, as a mug is set down on a table or shelf"))
def mug_square_handle(radius=0.0425, height=0.1, wall=0.005, mass=0.38) -> Design:
    """Straight mug with an angular handle of square section."""
    outer = [(0, 0), (radius, 0), (radius, height)]
    solid, hole = _mug(outer, wall, 0.82 * height, 0.3 * height, 0.043,
                       P.rounded_rect_section(0.005, 0.005, 0.0015), fillet=0.006)
    return Design(solid, 1, mass, (0.25, 0.25, 0.27, 1.0),
                  "straight mug, angular handle of square section", [hole])


# ---- containers with top handles or bails --------------------------------------------------------
@register("bucket",
          rest=as_modelled("upright on its base, bail up, as a bucket is set down (it holds things)"))
def bucket(r_base=0.09, r_rim=0.11, height=0.18, bail_height=0.27, mass=0.45) -> Design:
    """Plastic bucket with a rim bead, two ears and a 5 mm steel wire bail (hole axis +y)."""
    outer = np.array([(0, 0), (r_base, 0), (r_rim, height)])
    shell, cavity = P.vessel(outer, 0.003)
    bead = P.revolve(P.polygon(P.arc((r_rim, height), 0.004, 0, 2 * np.pi, 16)))
    z_ear = height - 0.02
    x_ear = _radius_at(outer, z_ear)
    ears = [P.box((0.02, 0.02, 0.03), (s * (x_ear + 0.006), 0, z_ear)) for s in (-1, 1)]
    bail = arch_handle(XZ, x_ear + 0.012, z_ear - 0.005, bail_height,
                       P.circle_section(0.0025, 12), fillet=0.09)
    solid = P.subtract(P.union(shell, bead, *ears, bail), cavity)
    guess = np.array([0.0, 0.0, 0.5 * (height + bail_height)])
    return Design(solid, 1, mass, (0.9, 0.55, 0.1, 1.0),
                  "plastic bucket with a wire bail handle",
                  [HoleDesign("bail", guess, Y_AXIS, search_radius=0.02)])


@register("basket",
          rest=as_modelled("upright on its base, handle up, as a basket is set down (it holds things)"))
def basket(r_base=0.085, r_rim=0.1, height=0.11, handle_top=0.2, mass=0.35) -> Design:
    """Round basket with a wide flat arched handle strapped along the outside of the wall."""
    outer = np.array([(0, 0), (r_base, 0), (r_rim, height)])
    shell, cavity = P.vessel(outer, 0.004)
    x_foot = _radius_at(outer, 0.07) + 0.002
    handle = arch_handle(XZ, x_foot, 0.07, handle_top,
                         P.rounded_rect_section(0.004, 0.01, 0.002), fillet=0.08,
                         top_half_span=x_foot + 0.004)
    solid = P.subtract(P.union(shell, handle), cavity)
    guess = np.array([0.0, 0.0, 0.5 * (height + handle_top)])
    return Design(solid, 1, mass, (0.72, 0.55, 0.33, 1.0),
                  "round basket with a flat bail handle",
                  [HoleDesign("handle", guess, Y_AXIS, search_radius=0.02)])


@register("tote_bag",
          rest=as_modelled("standing on its bottom, handles up, as a bag is set down by its handles"))
def tote_bag(width=0.28, depth=0.09, height=0.24, handle_top=0.35, mass=0.3) -> Design:
    """Tote bag as a rigid open box (3 mm walls) with two rigid arched handles (axis +y)."""
    wall = 0.003
    body = P.box((width, depth, height), (0, 0, 0.5 * height))
    cavity = P.box((width - 2 * wall, depth - 2 * wall, 1.0), (0, 0, wall + 0.5))
    handles = [
        arch_handle(LoopPlane(origin=(0.0, s * 0.5 * (depth - wall), 0.0)), 0.06,
                    height - 0.025, handle_top, P.circle_section(0.006), fillet=0.05)
        for s in (-1, 1)
    ]
    solid = P.subtract(P.union(body, *handles), cavity)
    z = 0.5 * (height + handle_top)
    holes = [HoleDesign(f"handle_{tag}", np.array([0.0, s * 0.5 * (depth - wall), z]), Y_AXIS,
                        search_radius=0.02) for tag, s in (("front", -1), ("back", 1))]
    return Design(solid, 2, mass, (0.55, 0.7, 0.45, 1.0),
                  "tote bag with two rigid handles", holes)


@register("kettle",
          rest=as_modelled("upright on its base, handle on top, as a kettle stands on a stove"))
def kettle(mass=0.7) -> Design:
    """Stovetop kettle (open top, lid removed) with an arched top handle and a straight spout."""
    outer = np.array([(0, 0), (0.085, 0), (0.09, 0.01), (0.09, 0.08), (0.06, 0.125),
                      (0.045, 0.135), (0.045, 0.145)])
    shell, cavity = P.vessel(outer, 0.003)
    handle = arch_handle(XZ, 0.066, 0.112, 0.225, P.ellipse_section(0.007, 0.01),
                         fillet=0.04, top_half_span=0.05)
    spout = P.cone_between((0.07, 0, 0.04), (0.16, 0, 0.125), 0.016, 0.007)
    solid = P.subtract(P.union(shell, handle, spout), cavity)
    return Design(solid, 1, mass, (0.75, 0.75, 0.78, 1.0),
                  "stovetop kettle with an arched top handle",
                  [HoleDesign("handle", np.array([0.0, 0.0, 0.185]), Y_AXIS, search_radius=0.02)])


@register("teapot", rest=as_modelled("upright on its base, as a teapot is set down to pour from"))
def teapot(mass=0.55) -> Design:
    """Round ceramic teapot (open top) with a side handle on -x and a spout on +x."""
    outer = np.array([(0, 0), (0.05, 0), (0.06, 0.01), (0.07, 0.045), (0.065, 0.08),
                      (0.045, 0.1), (0.04, 0.103), (0.04, 0.11)])
    shell, cavity = P.vessel(outer, 0.004)
    plane = LoopPlane(u=(-1.0, 0.0, 0.0), v=(0.0, 0.0, 1.0))
    handle, guess = side_handle(plane, (_radius_at(outer, 0.085), 0.085),
                                (_radius_at(outer, 0.025), 0.025), 0.05,
                                P.ellipse_section(0.006, 0.009), fillet=0.02, inset=0.004)
    spout = P.cone_between((0.055, 0, 0.035), (0.125, 0, 0.105), 0.014, 0.006)
    solid = P.subtract(P.union(shell, handle, spout), cavity)
    return Design(solid, 1, mass, (0.6, 0.2, 0.2, 1.0),
                  "round teapot with a side handle and spout",
                  [HoleDesign("handle", guess, Y_AXIS)])


@register("watering_can",
          rest=as_modelled("upright on its base, as a watering can is set down (it holds water)"))
def watering_can(mass=0.35) -> Design:
    """Plastic watering can: cylinder with a filling neck, rear D handle, long spout and rose."""
    outer = np.array([(0, 0), (0.07, 0), (0.075, 0.005), (0.075, 0.17), (0.05, 0.195),
                      (0.04, 0.2), (0.04, 0.205)])
    shell, cavity = P.vessel(outer, 0.0025)
    handle = handle_loop(XZ, [(-0.058, 0.19), (-0.135, 0.215), (-0.14, 0.09), (-0.072, 0.07)],
                         P.circle_section(0.007), fillet=0.03)
    spout = P.cone_between((0.06, 0, 0.03), (0.2, 0, 0.2), 0.013, 0.008)
    rose = P.cone_between((0.195, 0, 0.194), (0.215, 0, 0.218), 0.009, 0.022)
    solid = P.subtract(P.union(shell, handle, spout, rose), cavity)
    return Design(solid, 1, mass, (0.15, 0.6, 0.35, 1.0),
                  "plastic watering can with a rear handle",
                  [HoleDesign("handle", np.array([-0.105, 0.0, 0.14]), Y_AXIS, search_radius=0.02)])


@register("pot", rest=as_modelled("upright on its base, as a pot stands on a stove"))
def pot(radius=0.09, height=0.11, mass=0.7) -> Design:
    """Cooking pot with two horizontal U side handles (hole axes +z)."""
    outer = np.array([(0, 0), (radius - 0.005, 0), (radius, 0.005), (radius, height)])
    shell, cavity = P.vessel(outer, 0.003)
    z = height - 0.02
    handles, holes = [], []
    for tag, s in (("right", 1.0), ("left", -1.0)):
        plane = LoopPlane(origin=(0.0, 0.0, z), u=(s, 0.0, 0.0), v=(0.0, s, 0.0))
        handles.append(handle_loop(plane, [(radius - 0.012, -0.035), (radius + 0.04, -0.035),
                                           (radius + 0.04, 0.035), (radius - 0.012, 0.035)],
                                   P.ellipse_section(0.005, 0.006), fillet=0.012))
        holes.append(HoleDesign(f"handle_{tag}", np.array([s * (radius + 0.018), 0.0, z]),
                                Z_AXIS))
    solid = P.subtract(P.union(shell, *handles), cavity)
    return Design(solid, 2, mass, (0.55, 0.55, 0.6, 1.0),
                  "cooking pot with two side handles", holes)


@register("frying_pan",
          rest=as_modelled("on its base, handle out to the side, as a pan stands on a stove"))
def frying_pan(tilt_deg=12.0, handle_length=0.17, hole_radius=0.0155, mass=0.75) -> Design:
    """Frying pan whose handle rises at ``tilt_deg`` and ends in a large hang hole."""
    outer = np.array([(0, 0), (0.075, 0), (0.1, 0.045)])
    shell, cavity = P.vessel(outer, 0.004)
    bar = CrossSection.square((handle_length, 0.026)).translate((0.0, -0.013))
    end = CrossSection.circle(hole_radius + 0.009, 48).translate((handle_length, 0.0))
    hole = CrossSection.circle(hole_radius, 48).translate((handle_length, 0.0))
    t = np.radians(tilt_deg)
    rot = np.array([[np.cos(t), 0, -np.sin(t)], [0, 1, 0], [np.sin(t), 0, np.cos(t)]])
    origin = np.array([0.08, 0.0, 0.035])
    plate = P.extrude(bar + end - hole, 0.008).translate((0, 0, -0.004))
    handle = plate.transform(np.column_stack([rot, origin]))
    solid = P.subtract(P.union(shell, handle), cavity)
    center = origin + rot @ np.array([handle_length, 0.0, 0.0])
    return Design(solid, 1, mass, (0.15, 0.15, 0.15, 1.0),
                  "frying pan with a tilted handle ending in a hang hole",
                  [HoleDesign("hang_hole", center, tuple(rot[:, 2]), search_radius=0.003)])


# ---- flat and small objects ----------------------------------------------------------------------
@register("tape_roll",
          rest=as_modelled("lying flat on one side, as a roll of tape is put down on a desk"))
def tape_roll(core_radius=0.038, outer_radius=0.054, width=0.019, mass=0.13) -> Design:
    """Roll of 19 mm masking tape on a 76 mm core, lying flat (hole axis +z)."""
    solid = P.revolve(np.array([(core_radius, 0), (outer_radius, 0), (outer_radius, width),
                                (core_radius, width)]))
    return Design(solid, 1, mass, (0.93, 0.87, 0.6, 1.0), "roll of masking tape lying flat",
                  [HoleDesign("core", np.array([0.0, 0.0, 0.5 * width]), Z_AXIS)])


@register("key_ring", rest=as_modelled("lying flat, as keys are dropped on a table"))
def key_ring(ring_radius=0.021, wire=0.0025, mass=0.045) -> Design:
    """A split ring (torus) with two flat keys, lying flat (hole axis +z)."""
    ring = P.revolve(P.polygon(P.arc((ring_radius, wire), wire, 0, 2 * np.pi, 16)), 48)
    keys = []
    for angle, length in ((-20.0, 0.05), (-100.0, 0.042)):
        head = CrossSection.circle(0.012, 32)
        blade = CrossSection.square((length, 0.008)).translate((0.008, -0.004))
        teeth = [CrossSection.square((0.003, 0.003)).translate((0.02 + 0.006 * k, -0.0045))
                 for k in range(int((length - 0.02) / 0.006))]
        shape = head + blade
        for tooth in teeth:
            shape = shape - tooth
        r = ring_radius + wire + 0.012 - 0.004
        shape = shape.translate((r, 0.0)).rotate(angle)
        keys.append(P.extrude(shape, 0.0022))
    solid = P.union(ring, *keys)
    return Design(solid, 1, mass, (0.8, 0.7, 0.3, 1.0), "key ring with two keys lying flat",
                  [HoleDesign("ring", np.array([0.0, 0.0, wire]), Z_AXIS)], center_xy=True)


@register("scissors", rest=as_modelled("lying flat, closed, as scissors are put down on a desk"))
def scissors(thickness=0.006, mass=0.09) -> Design:
    """Closed scissors lying flat: two blades and two finger loops (hole axes +z)."""

    def capsule(p0, r0, p1, r1):
        return CrossSection.batch_hull([CrossSection.circle(r0, 24).translate(p0),
                                        CrossSection.circle(r1, 24).translate(p1)])

    thumb = _ring((-0.05, 0.02), (0.0185, 0.0185), (0.0135, 0.0135))
    finger = _ring((-0.055, -0.024), (0.031, 0.0205), (0.025, 0.0145))
    outline = (capsule((0, 0), 0.008, (0.1, 0.004), 0.0015)
               + capsule((0, 0), 0.008, (0.1, -0.004), 0.0015)
               + capsule((0, 0), 0.006, (-0.034, 0.014), 0.005)
               + capsule((0, 0), 0.006, (-0.032, -0.02), 0.005)
               + thumb[0] + finger[0]) - thumb[1] - finger[1]
    solid = P.extrude(outline, thickness)
    z = 0.5 * thickness
    holes = [HoleDesign("thumb_loop", np.array([-0.05, 0.02, z]), Z_AXIS, search_radius=0.004),
             HoleDesign("finger_loop", np.array([-0.055, -0.024, z]), Z_AXIS,
                        search_radius=0.004)]
    return Design(solid, 2, mass, (0.85, 0.15, 0.15, 1.0),
                  "scissors lying flat, two finger loops", holes, center_xy=True)


@register("clothes_hanger",
          rest=as_modelled("lying flat, as a hanger is put down on a table or a bed"))
def clothes_hanger(width=0.4, drop=0.11, hook_radius=0.02, wire=0.0035, mass=0.06) -> Design:
    """Plastic clothes hanger lying flat: closed triangle plus an open J hook (axes +z)."""
    plane = LoopPlane(origin=(0.0, 0.0, wire), u=(1.0, 0.0, 0.0), v=(0.0, 1.0, 0.0))
    w = 0.5 * width
    tri = P.rounded_polyline(np.array([(0, -drop), (w, -drop), (0, 0), (-w, -drop),
                                       (0, -drop)]), 0.015)
    triangle = P.sweep(plane.to_3d(tri), P.circle_section(wire), Z_AXIS, closed=True)
    neck = np.array([(0.0, -0.008), (0.0, 0.03)])
    hook_path = np.vstack([neck, P.arc((-hook_radius, 0.03), hook_radius, 0.0,
                                       np.radians(240.0), 30)[1:]])
    hook = P.sweep(plane.to_3d(P.resample(hook_path)), P.circle_section(wire), Z_AXIS)
    solid = P.union(triangle, hook)
    side = np.hypot(w, drop)
    r_in = w * drop / (w + side)
    holes = [HoleDesign("hook", np.array([-hook_radius, 0.03, wire]), Z_AXIS, kind="open",
                        search_radius=0.0),
             HoleDesign("triangle", np.array([0.0, -drop + r_in, wire]), Z_AXIS,
                        search_radius=0.02)]
    return Design(solid, 1, mass, (0.3, 0.3, 0.85, 1.0),
                  "plastic clothes hanger lying flat, open hook and closed triangle", holes)


@register("spray_bottle",
          rest=as_modelled("standing on its base, as a spray bottle is put down (upright: it holds liquid)"))
def spray_bottle(mass=0.35) -> Design:
    """Half-full spray bottle (solid) whose trigger and guard close a loop (hole axis +y)."""
    body = P.revolve(np.array([(0, 0), (0.038, 0), (0.04, 0.004), (0.04, 0.14), (0.036, 0.155),
                               (0.016, 0.172), (0.014, 0.175), (0.014, 0.2), (0, 0.2)]))
    head = P.box((0.08, 0.032, 0.037), (0.015, 0.0, 0.2165))
    nozzle = P.cylinder_between((0.05, 0, 0.222), (0.068, 0, 0.222), 0.007)
    guard = handle_loop(XZ, [(0.042, 0.21), (0.058, 0.16), (0.05, 0.132), (0.028, 0.128)],
                        P.rounded_rect_section(0.004, 0.007, 0.002), fillet=0.01)
    solid = P.union(body, head, nozzle, guard)
    return Design(solid, 1, mass, (0.95, 0.95, 0.95, 1.0),
                  "spray bottle with a closed trigger guard",
                  [HoleDesign("trigger_guard", np.array([0.032, 0.0, 0.178]), Y_AXIS)])


@register("headphones",
          rest=as_modelled("standing on their ear cups, headband up, as headphones are put down on a desk"))
def headphones(half_width=0.085, band_radius=0.085, mass=0.25) -> Design:
    """Over-ear headphones standing on their ear cups; the headband is an open hook (axis +y).

    The hook's centre is put 0.4 band radii above the arc's centre, so that the band is within a
    finger length (8 cm) of it."""
    cup_xs = P.rounded_rect_xs(0.065, 0.08, 0.012).translate((0.0, 0.04))
    to_yz = np.array([[0.0, 0.0, 1.0, 0.0], [1.0, 0.0, 0.0, 0.0], [0.0, 1.0, 0.0, 0.0]])
    cups = [P.extrude(cup_xs, 0.035).transform(to_yz).translate((s * half_width - 0.0175, 0, 0))
            for s in (-1, 1)]
    z_c = 0.12
    path = np.vstack([[(-half_width, 0.06)],
                      P.arc((0.0, z_c), band_radius, np.pi, 0.0, 48),
                      [(half_width, 0.06)]])
    band = P.sweep(XZ.to_3d(P.resample(path)), P.rounded_rect_section(0.005, 0.012, 0.003),
                   Y_AXIS)
    solid = P.union(*cups, band)
    return Design(solid, 0, mass, (0.1, 0.1, 0.12, 1.0),
                  "over-ear headphones standing on their cups, headband as an open hook",
                  [HoleDesign("headband", np.array([0.0, 0.0, z_c + 0.4 * band_radius]), Y_AXIS,
                              kind="open", search_radius=0.0)])


# ---- controls: nothing to hang by ----------------------------------------------------------------
@register("box",
          rest=as_modelled("standing on its 7 x 12 cm end, as a box of tea or cereal stands on a shelf"))
def box(size=(0.07, 0.12, 0.16), mass=0.3) -> Design:
    """Cardboard box (control)."""
    return Design(P.box(size, (0, 0, 0.5 * size[2])), 0, mass, (0.8, 0.65, 0.45, 1.0),
                  "closed cardboard box (control)", is_control=True)


@register("ball", rest=as_modelled("on its flat spot, where the ball comes to rest"))
def ball(radius=0.035, flat=0.0015, mass=0.1) -> Design:
    """Ball with a tiny flat spot so that it stays put (control)."""
    sphere = P.revolve(np.vstack([P.arc((0, 0), radius, -0.5 * np.pi, 0.5 * np.pi, 25)]), 48)
    solid = sphere ^ P.box((1.0, 1.0, 1.0), (0, 0, 0.5 - radius + flat))
    return Design(solid, 0, mass, (0.85, 0.9, 0.2, 1.0), "ball (control)", is_control=True)


@register("bottle", rest=as_modelled("upright on its base, as a capped bottle is put down"))
def bottle(mass=0.55) -> Design:
    """Capped 0.5 l bottle, as a solid (control)."""
    profile = np.array([(0, 0), (0.033, 0), (0.035, 0.004), (0.035, 0.16), (0.03, 0.185),
                        (0.013, 0.205), (0.013, 0.215), (0.015, 0.215), (0.015, 0.235),
                        (0, 0.235)])
    return Design(P.revolve(profile), 0, mass, (0.4, 0.7, 0.9, 1.0), "capped bottle (control)",
                  is_control=True)


@register("can", rest=as_modelled("upright on its base, as a drink can is put down"))
def can(mass=0.37) -> Design:
    """Full 33 cl drink can, as a solid (control)."""
    profile = np.array([(0, 0), (0.026, 0), (0.033, 0.008), (0.033, 0.11), (0.028, 0.12),
                        (0.027, 0.122), (0, 0.122)])
    return Design(P.revolve(profile), 0, mass, (0.8, 0.1, 0.2, 1.0), "drink can (control)",
                  is_control=True)
