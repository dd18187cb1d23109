"""Object sets as data: a YAML manifest lists the objects of a set.

Each entry is a mesh file (a path relative to the manifest, or ``pypi://DISTRIBUTION/PATH``, a
file inside a PyPI distribution: the installed one when its version matches, else the copy
``gbh objects fetch`` put in the cache) with its scale, real mass (or density), whether it is a
control, its natural rest and its ground-truth hangable parts; or a built-in object of the
generated set (``builtin: mug_classic``). The built-in set is itself a manifest
(``scenarios/object_sets/own.yaml``)::

    name: my_set
    objects:
      - name: my_mug
        mesh: meshes/mug.stl          # relative to this file
        scale: 0.001                  # file units -> m
        mass: 0.32                    # kg (or density: kg/m^3)
        rest: {as_given: true, reason: "upright on its base"}
        tags: [cup]
        hangable_parts:               # file frame, m (after scale)
          - {name: handle, center: [0.06, 0, 0.05], axis: [0, 1, 0], kind: closed,
             clear_diameter: 0.02}
      - {builtin: teapot}

:func:`load_object_set` reads and checks a manifest with the loader of scenario files
(:mod:`gbh_drake.yamlfiles.layers`): a problem raises :class:`ObjectSetError` naming the
manifest, the entry, the field and its line (a field left out: the line of what holds it).
:func:`set_object` resolves one entry into a :class:`SetObject` (the mesh file found);
:meth:`ObjectSet.rest_mesh` reads its mesh into its natural rest and refuses one that is not a
mesh or whose size cannot be simulated, as a scenario's ``object.mesh`` is refused; the natural
rest and the ground truth in frame O of the placed mesh are made by
:func:`gbh_drake.modeling.object_asset.load_object_asset`. :func:`object_digest` says which
version of an entry a trial ran (its facts and its mesh file's bytes).
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import re
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import yaml

from gbh_drake.core.ranges import FieldError, check_fields, format_path
from gbh_drake.objects.manifest import (
    ObjectSetManifest,
    SetEntry,
    SetPart,
    SetRest,
)
from gbh_drake.yamlfiles.layers import LayerError, file_layer, load_layers
from gbh_drake.yamlfiles.yaml_text import line_of

#: The scheme of a mesh inside a PyPI distribution: ``pypi://DISTRIBUTION/PATH``.
PYPI = "pypi://"
#: What an object's name may hold (it names files and rows).
NAME = re.compile(r"^[a-z0-9_]+$")


class ObjectSetError(LayerError):
    """A manifest is invalid: ``<manifest>: objects[i] (<name>).<field> (line N): <problem>``."""


class MissingMesh(FileNotFoundError):
    """An entry's mesh file is not there; ``field``: the entry's field that says where to look
    (``mesh``, or ``source.version`` for a distribution installed at another version)."""

    def __init__(self, field_name: str, problem: str):
        super().__init__(problem)
        self.field = field_name


@dataclass
class SetObject:
    """One object of a set, resolved: ``name``; ``builtin`` (the generated object's name, or
    "") or ``mesh_path`` (the file found); ``entry``: the manifest's entry; ``set_name`` and
    ``manifest`` (the file)."""

    name: str
    entry: SetEntry
    set_name: str
    manifest: Path
    builtin: str = ""
    mesh_path: Path | None = None
    index: int = 0
    """The entry's index in the manifest (``objects[index]``)."""

    @property
    def is_control(self) -> bool:
        if self.builtin:
            from gbh_drake.objects import make_object

            return bool(make_object(self.builtin).is_control)
        return bool(self.entry.control)

    @property
    def tags(self) -> tuple[str, ...]:
        return tuple(self.entry.tags)


@dataclass
class ObjectSet:
    """A loaded manifest: its ``name``, ``description``, the file (``path``, resolved; ``given``:
    as it was given, for messages), its entries in order and its node tree (``root``: the lines
    of later errors)."""

    name: str
    description: str
    path: Path
    entries: list[SetEntry] = field(default_factory=list)
    given: str = ""
    root: yaml.Node | None = field(default=None, repr=False, compare=False)

    @property
    def names(self) -> list[str]:
        return [entry_name(e) for e in self.entries]

    def entry(self, name: str) -> SetEntry:
        for e in self.entries:
            if entry_name(e) == name:
                return e
        raise KeyError(f"{self.path}: no object {name!r} (the set has: {', '.join(self.names)})")

    def object(self, name: str) -> SetObject:
        """The entry ``name`` resolved (its mesh file found; :class:`ObjectSetError` when it
        cannot be)."""
        return set_object(self, self.names.index(name) if name in self.names else
                          self.names.index(self.entry(name).name))

    def error(self, index: int, field_name: str, problem: str) -> ObjectSetError:
        """``problem`` of entry ``index``'s field ``field_name`` (``mesh``, ``source.version``),
        naming the manifest, the entry and the line (:func:`written_line`)."""
        path = ("objects", index, *_parse_field(field_name))
        where = _with_entry(format_path(path), self.entries)
        return ObjectSetError(self.given or str(self.path), where, written_line(self.root, path),
                              problem)

    def rest_mesh(self, name: str):
        """The mesh (trimesh, m) of the mesh entry ``name``: its file at its ``scale``, turned
        into its natural rest (as given without one). Raises :class:`ObjectSetError` when the
        file is not found (``mesh``), cannot be imported (``mesh``) or makes an object that
        cannot be simulated (``scale``: the refusal of a scenario's ``object.mesh``,
        :func:`~gbh_drake.objects.plausibility.size_refusal`)."""
        from gbh_drake.objects.mesh_io import MeshImportError, load_mesh_file
        from gbh_drake.objects.plausibility import size_refusal

        obj = self.object(name)
        try:
            mesh = load_mesh_file(obj.mesh_path, scale=obj.entry.scale)
        except MeshImportError as e:
            raise self.error(obj.index, "mesh", str(e)) from None
        low, high = mesh.bounds  # the file's frame, m (after scale): where parts are given
        mesh.apply_transform(rest_transform(obj.entry))
        refusal = size_refusal(mesh, obj.entry.scale)
        if refusal:  # refused before anything is simulated (a mm file read as m: 100 m)
            raise self.error(obj.index, "scale", f"{obj.mesh_path}: {refusal}")
        for j, part in enumerate(obj.entry.hangable_parts):
            refusal = part_outside(part, low, high)
            if refusal:
                raise self.error(obj.index, f"hangable_parts[{j}].center",
                                 f"{obj.mesh_path}: {refusal}")
        return mesh

    def mass(self, name: str, mesh=None) -> float:
        """kg: the mesh entry ``name``'s mass: its ``mass``, else its ``density`` times the
        volume of its mesh (``mesh``: its :meth:`rest_mesh`, given to spare reading it again),
        as the station computes it (:func:`~gbh_drake.objects.mass.mass_properties_for`)."""
        entry = self.entry(name)
        if entry.mass > 0:
            return float(entry.mass)
        from gbh_drake.objects.mass import mass_properties_for

        mesh = self.rest_mesh(name) if mesh is None else mesh
        return float(mass_properties_for(mesh, density=entry.density).mass)

    def check_payload(self, name: str, mass: float) -> None:
        """Raises :class:`ObjectSetError` on the mesh entry ``name``'s ``mass`` (or
        ``density``) when an object of ``mass`` kg is beyond the arm's payload
        (:func:`~gbh_drake.objects.plausibility.payload_refusal`): refused by ``gbh run``,
        ``gbh experiment`` (before any trial) and ``gbh objects list`` alike."""
        from gbh_drake.objects.plausibility import payload_refusal

        refusal = payload_refusal(mass)
        if refusal:
            obj = self.object(name)
            raise self.error(obj.index, "mass" if obj.entry.mass > 0 else "density",
                             f"{obj.mesh_path}: {refusal}")


def entry_name(entry: SetEntry) -> str:
    """An entry's name: its ``name``, or the built-in object's it names."""
    return entry.name or entry.builtin


def load_object_set(path: str | Path) -> ObjectSet:
    """Reads and checks the manifest at ``path`` (see the module docstring); raises
    :class:`ObjectSetError` naming the manifest, the entry, the field and its line."""
    path = Path(path)
    origin, text = file_layer(path, "object set", ObjectSetError)
    try:
        manifest, trees = load_layers(ObjectSetManifest, [(origin, text)], ObjectSetManifest(),
                                      what="object set", error=ObjectSetError)
    except ObjectSetError as e:  # an unknown or mistyped field: its entry named as every other
        field_text = _with_entry(e.field, _written_entries(text))
        if field_text == e.field:
            raise
        raise ObjectSetError(e.origin, field_text, e.line, e.problem, e.column) from None
    root = trees.roots[0][1]
    try:
        _check(manifest)
    except FieldError as e:
        error = trees.locate(e, origin, ObjectSetError)
        line = error.line
        if error.field == format_path(e.path) and line_of(root, e.path) is None:
            line = written_line(root, e.path)  # left out: the line of what holds it
        raise ObjectSetError(error.origin, _with_entry(error.field, manifest.objects), line,
                             error.problem) from None
    return ObjectSet(manifest.name or path.stem, manifest.description, path.resolve(),
                     list(manifest.objects), origin, root)


def written_line(root: yaml.Node | None, path: tuple) -> int | None:
    """The line of field ``path`` in the manifest's tree ``root``, or, left out, of the nearest
    field holding it that is written (an entry's ``mass`` left out: the entry's line)."""
    for end in range(len(path), 0, -1):
        line = line_of(root, path[:end])
        if line is not None:
            return line
    return None


def _parse_field(text: str) -> tuple:
    """``rest.reason`` -> ``("rest", "reason")``; ``parts[0].center`` -> ``("parts", 0,
    "center")``."""
    return tuple(int(p) if p.isdigit() else p for p in re.findall(r"[^.\[\]]+", text))


def _written_entries(text: str) -> list[SetEntry]:
    """The entries' names (``name`` or ``builtin``) as written in a manifest's ``text`` that did
    not load (an unknown field), for its message; [] when they cannot be read."""
    try:
        objects = (yaml.safe_load(text) or {}).get("objects") or []
    except (yaml.YAMLError, AttributeError):
        return []
    if not isinstance(objects, list):
        return []
    return [SetEntry(**{k: str(v) for k, v in o.items() if k in ("name", "builtin")})
            if isinstance(o, dict) else SetEntry() for o in objects]


def _with_entry(field_text: str, entries: list[SetEntry]) -> str:
    """``objects[2].mass`` -> ``objects[2] (my_mug).mass``: the entry's name in a message."""
    found = re.match(r"^objects\[(\d+)\]", field_text)
    if not found or int(found.group(1)) >= len(entries):
        return field_text
    name = entry_name(entries[int(found.group(1))])
    return f"{found.group(0)} ({name}){field_text[found.end():]}" if name else field_text


def _check(manifest: ObjectSetManifest) -> None:
    """Every entry's fields and the rules between them; names unique; built-in names known."""
    if not manifest.objects:
        raise FieldError(("objects",), "list at least one object")
    check_fields(manifest)
    seen: dict[str, int] = {}
    for i, entry in enumerate(manifest.objects):
        at = ("objects", i)
        check_fields(entry, at)
        if entry.rest is not None:
            check_fields(entry.rest, at + ("rest",))
        if entry.source is not None:
            check_fields(entry.source, at + ("source",))
        for j, part in enumerate(entry.hangable_parts):
            try:
                check_fields(part, at + ("hangable_parts", j))
            except FieldError as e:
                raise _with_scale_hint(e, entry) from None
        if entry.builtin:
            from gbh_drake.objects import list_objects

            if entry.builtin not in list_objects():
                raise FieldError(at + ("builtin",), f"unknown built-in object {entry.builtin!r} "
                                                    f"(known: {', '.join(list_objects())})")
        name = entry_name(entry)
        if name in seen:
            raise FieldError(at + ("name",), f"{name!r} is the name of objects[{seen[name]}] "
                                             "too; give each object its own name")
        seen[name] = i


def _with_scale_hint(error: FieldError, entry: SetEntry) -> FieldError:
    """``error`` of a part's length out of range, with what most often causes it: the part in
    the file's units (millimetres) where ``scale`` is 1 (parts are in metres after ``scale``)."""
    length = "clear_diameter" in error.path or "center" in error.path
    if entry.scale != 1.0 or not length:
        return error
    return FieldError(error.path, f"{error.problem}: parts are in metres, after the entry's "
                                  "scale; a mesh in millimetres needs scale: 0.001 and its "
                                  "parts in metres", error.other)


def set_object(object_set: ObjectSet, index: int) -> SetObject:
    """Entry ``index`` of ``object_set`` with its mesh file found (:func:`mesh_file`)."""
    entry = object_set.entries[index]
    name = entry_name(entry)
    if entry.builtin:
        return SetObject(name, entry, object_set.name, object_set.path, builtin=entry.builtin,
                         index=index)
    try:
        path = mesh_file(entry, object_set.path.parent, manifest=object_set.given)
    except MissingMesh as e:
        raise object_set.error(index, e.field, str(e)) from None
    return SetObject(name, entry, object_set.name, object_set.path, mesh_path=path, index=index)


def mesh_file(entry: SetEntry, directory: Path, *, manifest: str | Path = "") -> Path:
    """The file of ``entry.mesh``: relative to ``directory`` (the manifest's), or inside a PyPI
    distribution (``pypi://DIST/PATH``: the installed distribution when its version is the
    entry's ``source.version``, else the cache :mod:`gbh_drake.objects.fetch` fills).
    :class:`MissingMesh` says what is missing and how to get it (``manifest``: the file the
    fetch hint names)."""
    if not entry.mesh.startswith(PYPI):
        path = Path(entry.mesh).expanduser()
        path = path if path.is_absolute() else Path(directory) / path
        if not path.is_file():
            from gbh_drake.objects.fetch import did_you_mean

            hint = did_you_mean(path.name, path.parent, ()) if path.parent.is_dir() else \
                f" (no folder {path.parent})"
            raise MissingMesh("mesh", f"no mesh file {path}{hint}")
        return path
    from gbh_drake.objects.fetch import Source, cache_path, installed_file

    source = entry.source
    source = Source(source.package, source.version, source.archive, source.license)
    try:
        installed = installed_file(entry.mesh, source)
        cached = cache_path(entry.mesh, source)
    except ValueError as e:  # an unsafe path (``..``)
        raise MissingMesh("mesh", str(e)) from None
    if installed.path is not None:
        return installed.path
    if installed.matches:  # the installed files are the archive's: a wrong path
        raise MissingMesh("mesh", f"no such file in {source.package} {source.version} "
                                  f"({installed.root}): {installed.inner}{installed.hint}")
    if cached.is_file():
        return cached
    fetch = f"run `gbh objects fetch --set {manifest}`" if manifest else "run `gbh objects fetch`"
    if installed.version:
        raise MissingMesh("source.version", f"installed {installed.version}, the entry asks "
                                            f"{source.version}, which is not in the cache "
                                            f"either ({cached}): give version: "
                                            f"'{installed.version}', or {fetch}")
    raise MissingMesh("mesh", f"{entry.mesh}: not in the cache ({cached}); {fetch}")


#: The facts of a mesh entry that change the object a trial simulates or what its row records
#: (the mesh file's bytes besides): a row made before one of them changed is of another object.
#: Words (``mass_note``, ``description``, ``rest.reason``, the licence) and ``tags`` (which
#: group the report, not the trial) are not among them.
OBJECT_FACTS = ("scale", "mass", "density", "control", "rest", "hangable_parts")


def object_digest(obj: SetObject) -> str:
    """sha256 of a mesh entry's :data:`OBJECT_FACTS` (its rest as the rotation it makes) and of
    its mesh file's bytes; "" for a built-in object (its code is the commit's)."""
    if obj.builtin:
        return ""
    facts = {name: getattr(obj.entry, name) for name in OBJECT_FACTS}
    rest = natural_rest_of(obj.entry)
    facts["rest"] = None if rest is None else [float(a) for a in rest.rpy_deg]
    facts["hangable_parts"] = [dataclasses.asdict(p) for p in obj.entry.hangable_parts]
    digest = hashlib.sha256(json.dumps(facts, sort_keys=True).encode())
    with open(obj.mesh_path, "rb") as f:
        for block in iter(lambda: f.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


def part_outside(part: SetPart, low, high) -> str:
    """Why the ground-truth ``part``'s centre cannot be on the mesh whose bounds in the file's
    frame (m, after ``scale``) are ``low``, ``high``: farther outside them than its clear
    diameter (a hole's or a hook's rod passes through the object's material), e.g. a centre in
    centimetres; "" when it is not."""
    center = np.asarray(part.center, float)
    outside = float(np.linalg.norm(np.maximum(0.0, np.maximum(low - center, center - high))))
    if outside <= max(float(part.clear_diameter), 0.005):
        return ""
    def m(v: float) -> str:
        return f"{round(float(v), 3) + 0.0:.3f}"  # (+ 0.0: never -0.000)

    bounds = ", ".join(f"{a} {m(lo)} to {m(hi)}" for a, lo, hi in zip("xyz", low, high, strict=True))
    return (f"({', '.join(f'{c:g}' for c in center)}) lies {100.0 * outside:.1f} cm outside the "
            f"mesh ({bounds} m): give the centre in metres in the file's frame, after scale")


def parts_in_file_frame(entry: SetEntry):
    """The entry's ground-truth hangable parts (:class:`~gbh_drake.objects.spec.HangablePart`)
    in the mesh file's frame, metres (after ``scale``)."""
    from gbh_drake.objects.spec import HangablePart

    return [HangablePart(p.name or f"part_{i}", np.asarray(p.center, float),
                         np.asarray(p.axis, float), p.kind, float(p.clear_diameter))
            for i, p in enumerate(entry.hangable_parts)]


def rest_transform(entry: SetEntry) -> np.ndarray:
    """X_RF (4, 4): the rotation of the mesh file's frame F into the entry's natural rest R
    (the identity without one)."""
    X_RF = np.eye(4)
    rest = natural_rest_of(entry)
    if rest is not None:
        X_RF[:3, :3] = rest.R
    return X_RF


def natural_rest_of(entry: SetEntry):
    """The entry's declared natural rest (:class:`~gbh_drake.objects.spec.NaturalRest`: the
    rotation of the file's frame into it), or None."""
    from gbh_drake.objects.spec import NaturalRest

    rest: SetRest | None = entry.rest
    if rest is None:
        return None
    angles = (0.0, 0.0, 0.0) if rest.as_given else tuple(float(a) for a in rest.rpy_deg)
    return NaturalRest(angles, rest.reason)


__all__ = ["OBJECT_FACTS", "PYPI", "MissingMesh", "ObjectSet", "ObjectSetError", "SetEntry",
           "SetObject", "SetPart", "entry_name", "load_object_set", "mesh_file",
           "natural_rest_of", "object_digest", "parts_in_file_frame", "rest_transform",
           "set_object", "written_line"]
