"""The object of a scenario as configuration: which object, how it starts (ground floor).

:class:`ObjectConfig` (the scenario's ``object``) and :class:`RandomRestingPose` (its
``random_pose``), with each field's unit, default and range beside it
(:func:`gbh_drake.core.ranges.ranged`). No ``from __future__ import annotations`` here: Drake's
``yaml_load_typed`` needs real types. Imports nothing of the pipeline.
"""

from dataclasses import dataclass, field

from pydrake.common.schema import Transform

from gbh_drake.core.ranges import (
    FieldError,
    FilePath,
    Items,
    NonNeg,
    OneOf,
    Pos,
    Range,
    ranged,
    sibling,
)

#: How a random start pose rests (``RandomRestingPose.rest``; the experiment's ``protocols``):
#:
#: * ``stable``: one of the object's stable resting orientations, drawn by its probability (the
#:   harder protocol: a mug may lie on its handle, a hanger flat side up or down);
#: * ``natural``: the rest a person would set the object down in (mugs, kettles, baskets upright;
#:   a hanger, scissors, a key ring lying flat; a tote standing), declared once per object of the
#:   set with a one-line reason (``gbh_drake/objects/catalog.py``); the paper's objects were set
#:   down by a person.
RESTS = ("stable", "natural")


@dataclass
class RandomRestingPose:
    """A random start pose: a resting orientation (``rest``: a stable one drawn by its
    probability, or the object's natural rest), a uniform yaw and a uniform position on the
    table, from the scenario's seed."""

    x: list[float] = ranged(lambda: [0.45, 0.62], Items(2, what="values [min, max] (m)"))
    """Range [min, max] (m) of the object's x in W (its footprint's centre)."""
    y: list[float] = ranged(lambda: [-0.18, 0.18], Items(2, what="values [min, max] (m)"))
    """Range [min, max] (m) of the object's y in W."""
    yaw_deg: list[float] = ranged(
        lambda: [-180.0, 180.0], Items(2, Range(-360.0, 360.0, unit="deg"), what="values [min, max] (deg)"))
    """Range [min, max] (deg) of the yaw about +z_W."""
    stable: bool = True
    """With ``rest: stable``: draw among the object's stable resting orientations (trimesh);
    False: as modelled."""
    rest: str = ranged("stable", OneOf(RESTS, note="natural: the rest declared for each object "
                                                   "of the set; not for a mesh file"))
    """``stable`` (a stable resting orientation by its probability, or as modelled when
    ``stable`` is False) or ``natural`` (the rest a person would set the object down in, declared
    per object of the set); see :data:`RESTS`."""

    def check_relations(self, at: tuple = ()) -> None:
        for name in ("x", "y", "yaw_deg"):
            lo_hi = getattr(self, name)
            if lo_hi[0] > lo_hi[1]:
                raise FieldError(at + (name,), f"needs [min, max] with min <= max, got {list(lo_hi)}")
        if self.rest == "natural" and not self.stable:
            raise FieldError(at + ("stable",), f"{sibling(at, 'rest')}: natural takes the "
                                               "object's natural rest; stable: false (as "
                                               "modelled) says otherwise: give one of them")


@dataclass
class ObjectConfig:
    """The object to pick."""

    name: str = "mug_classic"
    """A named object: of the built-in set (``gbh objects list``), or of the object set
    ``set``; ignored when ``mesh`` is set."""
    set: str = ranged("", FilePath("object set manifest"))
    """An object set's manifest (a path relative to the scenario file, given in an override:
    to the current folder;
    :mod:`gbh_drake.objects.sets`): ``name`` is one of its objects, with its mesh, mass,
    natural rest and ground truth."""
    mesh: str = ranged("", FilePath("mesh file"))
    """Path to any mesh file (obj/stl/ply/glb/gltf/off), relative to the scenario file (given
    in an override: to the current folder); ``scale`` turns its units into metres. It is placed
    resting on the table whatever its origin."""
    scale: float = ranged(1.0, Pos(1000.0, note="e.g. 0.001 for a file in millimetres"))
    """Uniform scale applied to ``mesh`` (e.g. 0.001 for a file in millimetres)."""
    orientation: str = ranged("keep", OneOf(("keep", "nearest_stable", "most_probable")))
    """How a ``mesh`` file stands on the table: ``keep`` (the file's z is up), ``nearest_stable``
    (its stable resting pose nearest to that) or ``most_probable`` (its likeliest resting
    pose)."""
    density: float = ranged(
        0.0, NonNeg(25000.0, "kg/m^3", "0: the object's own; osmium, the densest metal, is 22600"))
    """kg/m^3 for mass and inertia; 0: the named object's own density (600 for a mesh)."""
    mass: float = ranged(0.0, NonNeg(100.0, "kg", "0: from the density; the Franka carries at most 3 kg"))
    """kg; when positive, the object's mass (inertia scaled to it) instead of ``density``."""
    pose: Transform = field(default_factory=lambda: Transform(translation=[0.55, 0.0, 0.0]))
    """X_WO, the object's pose on the table (its lowest point at z = 0 when the translation's z
    is 0). Takes Drake's distributions (``!UniformVector``, ``!Rpy {deg: !UniformVector ...}``),
    sampled from the scenario's seed. Ignored when ``random_pose`` is given."""
    random_pose: RandomRestingPose | None = None
    """When given: a stable resting pose, yaw and position drawn from the seed."""
    drop_height: float = ranged(0.002, NonNeg(0.5, "m"))
    """Extra height (m) above the resting pose at the start, so the object settles onto the
    table."""

    def check_relations(self, at: tuple = ()) -> None:
        if self.set:
            if self.mesh:
                raise FieldError(at + ("mesh",), f"give {sibling(at, 'set')} (and its object's "
                                                 "name) or a mesh file, not both")
            given = [f for f, default in (("scale", 1.0), ("density", 0.0), ("mass", 0.0),
                                          ("orientation", "keep")) if getattr(self, f) != default]
            if given:
                raise FieldError(at + (given[0],), f"the object set ({sibling(at, 'set')}) gives "
                                                   "each object's scale, mass and rest: remove it")
        if self.density > 0 and self.mass > 0:
            raise FieldError(at + ("mass",), f"give {sibling(at, 'mass')} or {sibling(at, 'density')}, "
                                             "not both (mass wins otherwise)")
