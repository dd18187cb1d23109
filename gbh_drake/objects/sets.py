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
manifest, the entry, the field and its line. :func:`set_object` resolves one entry into a
:class:`SetObject` (the mesh file found, the natural rest and the ground truth in frame O of the
placed mesh are made by :func:`gbh_drake.modeling.object_asset.load_object_asset`).
"""

from __future__ import annotations

import importlib.metadata
import re
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from gbh_drake.core.ranges import FieldError, check_fields
from gbh_drake.objects.manifest import (
    ObjectSetManifest,
    SetEntry,
    SetPart,
    SetRest,
)
from gbh_drake.yamlfiles.layers import LayerError, file_layer, load_layers

#: The scheme of a mesh inside a PyPI distribution: ``pypi://DISTRIBUTION/PATH``.
PYPI = "pypi://"
#: What an object's name may hold (it names files and rows).
NAME = re.compile(r"^[a-z0-9_]+$")


class ObjectSetError(LayerError):
    """A manifest is invalid: ``<manifest>: objects[i] (<name>).<field> (line N): <problem>``."""


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
    """A loaded manifest: its ``name``, ``description``, the file, and its entries in order."""

    name: str
    description: str
    path: Path
    entries: list[SetEntry] = field(default_factory=list)

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


def entry_name(entry: SetEntry) -> str:
    """An entry's name: its ``name``, or the built-in object's it names."""
    return entry.name or entry.builtin


def load_object_set(path: str | Path) -> ObjectSet:
    """Reads and checks the manifest at ``path`` (see the module docstring); raises
    :class:`ObjectSetError` naming the manifest, the entry, the field and its line."""
    path = Path(path)
    origin, text = file_layer(path, "object set", ObjectSetError)
    manifest, trees = load_layers(ObjectSetManifest, [(origin, text)], ObjectSetManifest(),
                                  what="object set", error=ObjectSetError)
    try:
        _check(manifest)
    except FieldError as e:
        error = trees.locate(e, origin, ObjectSetError)
        raise ObjectSetError(error.origin, _with_entry(error.field, manifest), error.line,
                             error.problem) from None
    return ObjectSet(manifest.name or path.stem, manifest.description, path.resolve(),
                     list(manifest.objects))


def _with_entry(field_text: str, manifest: ObjectSetManifest) -> str:
    """``objects[2].mass`` -> ``objects[2] (my_mug).mass``: the entry's name in a message."""
    found = re.match(r"^objects\[(\d+)\]", field_text)
    if not found or int(found.group(1)) >= len(manifest.objects):
        return field_text
    name = entry_name(manifest.objects[int(found.group(1))])
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
            check_fields(part, at + ("hangable_parts", j))
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


def set_object(object_set: ObjectSet, index: int) -> SetObject:
    """Entry ``index`` of ``object_set`` with its mesh file found (:func:`mesh_file`)."""
    entry = object_set.entries[index]
    name = entry_name(entry)
    if entry.builtin:
        return SetObject(name, entry, object_set.name, object_set.path, builtin=entry.builtin)
    try:
        path = mesh_file(entry, object_set.path.parent)
    except FileNotFoundError as e:
        raise ObjectSetError(str(object_set.path), f"objects[{index}] ({name}).mesh", None,
                             str(e)) from None
    return SetObject(name, entry, object_set.name, object_set.path, mesh_path=path)


def mesh_file(entry: SetEntry, directory: Path) -> Path:
    """The file of ``entry.mesh``: relative to ``directory`` (the manifest's), or inside a PyPI
    distribution (``pypi://DIST/PATH``: the installed distribution when its version is the
    entry's ``source.version``, else the cache :mod:`gbh_drake.objects.fetch` fills).
    ``FileNotFoundError`` says what is missing and how to get it."""
    if not entry.mesh.startswith(PYPI):
        path = Path(entry.mesh).expanduser()
        path = path if path.is_absolute() else Path(directory) / path
        if not path.is_file():
            raise FileNotFoundError(f"no mesh file {path}")
        return path
    dist, _, inner = entry.mesh[len(PYPI):].partition("/")
    version = entry.source.version if entry.source is not None else ""
    try:
        installed = importlib.metadata.distribution(dist)
        if installed.version == version:
            path = Path(str(installed.locate_file(inner)))
            if path.is_file():
                return path
    except importlib.metadata.PackageNotFoundError:
        pass
    from gbh_drake.objects.fetch import resolve

    source = entry.source
    return resolve(entry.mesh, {"package": source.package, "version": source.version,
                                "archive": source.archive, "license": source.license})


def parts_in_file_frame(entry: SetEntry):
    """The entry's ground-truth hangable parts (:class:`~gbh_drake.objects.spec.HangablePart`)
    in the mesh file's frame, metres (after ``scale``)."""
    from gbh_drake.objects.spec import HangablePart

    return [HangablePart(p.name or f"part_{i}", np.asarray(p.center, float),
                         np.asarray(p.axis, float), p.kind, float(p.clear_diameter))
            for i, p in enumerate(entry.hangable_parts)]


def natural_rest_of(entry: SetEntry):
    """The entry's declared natural rest (:class:`~gbh_drake.objects.spec.NaturalRest`: the
    rotation of the file's frame into it), or None."""
    from gbh_drake.objects.spec import NaturalRest

    rest: SetRest | None = entry.rest
    if rest is None:
        return None
    angles = (0.0, 0.0, 0.0) if rest.as_given else tuple(float(a) for a in rest.rpy_deg)
    return NaturalRest(angles, rest.reason)


__all__ = ["PYPI", "ObjectSet", "ObjectSetError", "SetEntry", "SetObject", "SetPart",
           "entry_name", "load_object_set", "mesh_file", "natural_rest_of",
           "parts_in_file_frame", "set_object"]
