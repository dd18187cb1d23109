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
