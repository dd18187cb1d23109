"""An object set's manifest as data: the schema :mod:`gbh_drake.objects.sets` loads.

Plain dataclasses with each field's unit, default and range beside it
(:func:`gbh_drake.core.ranges.ranged`), loaded with Drake's ``yaml_load_typed`` (no ``from
__future__ import annotations`` here: the loader needs real types).
"""

from dataclasses import dataclass, field

from gbh_drake.core.ranges import (
    FieldError,
    Items,
    NonNeg,
    OneOf,
    Pos,
    Range,
    ranged,
    sibling,
)

#: What an object's name in a set may hold (it names files, rows and Drake model instances).
SET_NAME = r"^[a-z0-9_]+$"
#: Kinds of hangable part: a closed loop (a through hole) or an open hook.
PART_KINDS = ("closed", "open")


@dataclass
class SetSource:
    """Where a mesh of a PyPI distribution comes from, and its licence (an object set entry's
    ``source``)."""

    package: str = ""
    """The PyPI distribution (e.g. ``pybullet``)."""
    version: str = ""
    """Its exact version: the file is read from that version only."""
    archive: str = ranged("wheel", OneOf(("wheel", "sdist")))
    """Whether the path is inside the distribution's wheel or its source archive."""
    license: str = ""
    """The mesh's licence (an SPDX identifier where there is one)."""
    license_note: str = ""
    """Where the mesh's own licence or attribution differs from the package's."""
    url: str = ""
    """Where the distribution or the mesh is described."""

    def check_relations(self, at: tuple = ()) -> None:
        for name in ("package", "version", "license"):
            if not getattr(self, name).strip():
                raise FieldError(at + (name,), "give it (the mesh's source is recorded: "
                                               "package, version and licence)")


@dataclass
class SetRest:
    """An object's natural rest: how a person sets it down (the ``natural`` protocol)."""

    rpy_deg: list[float] = ranged(lambda: [0.0, 0.0, 0.0],
                                  Items(3, Range(-360.0, 360.0, unit="deg"),
                                        what="angles roll, pitch, yaw (deg)"))
    """Roll, pitch, yaw (deg; R = Rz(yaw) Ry(pitch) Rx(roll)) turning the mesh file's frame into
    the rest (before the trial's random yaw)."""
    as_given: bool = False
    """The mesh file's frame, its z up, is the rest (rpy 0, 0, 0)."""
    reason: str = ""
    """One line: why a person sets it down so."""

    def check_relations(self, at: tuple = ()) -> None:
        if not self.reason.strip() or "\n" in self.reason:
            raise FieldError(at + ("reason",), "give a one-line reason (how a person sets it "
                                               "down)")
        if self.as_given and any(a != 0.0 for a in self.rpy_deg):
            raise FieldError(at + ("rpy_deg",), f"{sibling(at, 'as_given')} is true: the file's "
                                                "frame is the rest; give one of them")


@dataclass
class SetPart:
    """A ground-truth hangable part, in the mesh file's frame (m, after ``scale``)."""

    name: str = ""
    center: list[float] = ranged(list, Items(3, Range(-10.0, 10.0, unit="m"),
                                             what="coordinates x, y, z (m)"))
    """The hole's centre (where a rod through it passes)."""
    axis: list[float] = ranged(list, Items(3, what="components of the hole's axis"))
    """The hole's axis (any length but 0; sign arbitrary)."""
    kind: str = ranged("closed", OneOf(PART_KINDS))
    """``closed`` (a through hole) or ``open`` (a hook)."""
    clear_diameter: float = ranged(0.0, Pos(1.0, "m"))
    """The diameter of the largest rod that passes along the axis through the centre."""

    def check_relations(self, at: tuple = ()) -> None:
        if not any(a != 0.0 for a in self.axis):
            raise FieldError(at + ("axis",), "must not be zero")


@dataclass
class SetEntry:
    """One object of a set: a mesh file with its facts, or a built-in object (``builtin``)."""

    name: str = ""
    """The object's name (letters a-z, digits, underscores; unique in the set); a built-in
    entry has its own."""
    builtin: str = ""
    """A built-in object of the generated set (``gbh objects list``) instead of a mesh."""
    mesh: str = ""
    """The mesh file: a path relative to the manifest, or ``pypi://DISTRIBUTION/PATH``."""
    source: SetSource | None = None
    """Where the mesh comes from and its licence (required for ``pypi://`` meshes)."""
    scale: float = ranged(1.0, Pos(1000.0, note="file units to metres, e.g. 0.001 for mm"))
    """File units to metres."""
    mass: float = ranged(0.0, NonNeg(100.0, "kg", "the real object's mass"))
    """kg: the real object's mass (or give ``density``)."""
    mass_note: str = ""
    """Where the mass comes from (a dataset, a product, an estimate)."""
    density: float = ranged(0.0, NonNeg(25000.0, "kg/m^3"))
    """kg/m^3 of the mesh's volume, when no ``mass`` is given."""
    control: bool = False
    """A control: nothing to hang it by (no hangable parts)."""
    rest: SetRest | None = None
    """The natural rest (the ``natural`` protocol refuses an object without one)."""
    tags: list[str] = field(default_factory=list)
    """Free words the report groups by: ``cup`` (cups, mugs, pitchers), ``flat`` (lies flat)."""
    hangable_parts: list[SetPart] = field(default_factory=list)
    """Ground truth for the report's columns (part found, hooked it); may be empty (unknown)."""
    description: str = ""
    """What the object is, in a few words."""

    def check_relations(self, at: tuple = ()) -> None:
        import re

        if self.builtin:
            given = [f for f in ("name", "mesh", "mass", "density", "rest", "hangable_parts",
                                 "source") if getattr(self, f) not in ("", 0.0, None, [])]
            given += ["scale"] if self.scale != 1.0 else []
            given += ["control"] if self.control else []
            if given:
                raise FieldError(at + (given[-1],), f"{sibling(at, 'builtin')} names a built-in "
                                 "object, which brings its own mesh, mass, rest and parts; give "
                                 "only tags and description beside it")
            return
        if not self.name:
            raise FieldError(at + ("name",), "give the object a name (or builtin: a built-in "
                                             "object's)")
        if not re.match(SET_NAME, self.name):
            raise FieldError(at + ("name",), f"letters a-z, digits and underscores only, got "
                                             f"{self.name!r}")
        if not self.mesh:
            raise FieldError(at + ("mesh",), "give the mesh file (a path relative to the "
                                             "manifest, or pypi://DISTRIBUTION/PATH)")
        if self.mesh.startswith("pypi://"):
            dist, _, inner = self.mesh[len("pypi://"):].partition("/")
            if not dist or not inner:
                raise FieldError(at + ("mesh",), f"pypi://DISTRIBUTION/PATH, got {self.mesh!r}")
            if self.source is None:
                raise FieldError(at + ("source",), "a pypi:// mesh needs its source (package, "
                                                   "version, licence)")
            if self.source.package != dist:
                raise FieldError(at + ("source", "package"), f"must be {dist!r}, the mesh's "
                                                             "distribution")
        if self.mass > 0 and self.density > 0:
            raise FieldError(at + ("mass",), f"give {sibling(at, 'mass')} or "
                                             f"{sibling(at, 'density')}, not both")
        if self.mass == 0 and self.density == 0:
            raise FieldError(at + ("mass",), "give the real object's mass (kg), or a density")
        if self.control and self.hangable_parts:
            raise FieldError(at + ("hangable_parts",), "a control has nothing to hang it by: "
                                                       "remove the parts or control: true")
        for i, tag in enumerate(self.tags):
            if not re.match(SET_NAME, tag):
                raise FieldError(at + ("tags", i), f"letters a-z, digits and underscores, got "
                                                   f"{tag!r}")


@dataclass
class ObjectSetManifest:
    """An object set's manifest file (:mod:`gbh_drake.objects.sets`)."""

    name: str = ""
    """The set's name (default: the file's stem)."""
    description: str = ""
    objects: list[SetEntry] = field(default_factory=list)
    """The objects, in order."""
