"""Layered YAML files: one loader for scenario files and experiment files.

A file is loaded, then each override (``--set`` text) on top of it, every layer with Drake's
``yaml_load_typed`` over the result of the ones before (typos fail loudly). Each layer's text is
first read and composed by :mod:`gbh_drake.yamlfiles.yaml_text` (UTF-8 only, no key given twice,
no string where a list is expected), and its node tree is kept, so that an error found later,
by a field's range or a rule between fields, names the layer (the file, or ``<file>
(overrides)``) and the line where the field was written last (:meth:`Layers.locate`).

An override is YAML text (a ``str``, or ``bytes`` decoded as a file is: UTF-8, a byte-order
mark dropped, UTF-16 and invalid bytes named). A relative path an override writes (a field whose
rule is :class:`~gbh_drake.core.ranges.FilePath`: ``output_dir``, ``object.mesh``, an
experiment's ``base``) is the current folder's and is made absolute as it is loaded; a relative
path written in the file stays the file folder's.

Errors read ``<origin>: <field> (line N): <problem>`` (:func:`error_text`), and are
:class:`LayerError` s: :class:`~gbh_drake.scenario.loader.ScenarioError` for a scenario,
:class:`~gbh_drake.experiment.config.ExperimentError` for an experiment.
"""

import copy
import dataclasses
import functools
import types
import typing
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import TypeVar

import yaml
from pydrake.common.yaml import yaml_load_typed

from gbh_drake.core.ranges import FieldError, FilePath, format_path, rule_of, shown
from gbh_drake.yamlfiles.yaml_text import (
    YamlFieldError,
    YamlTextError,
    check_document,
    compose,
    decode,
    line_of,
    locate_load_error,
    node_at,
    read_text,
)

T = TypeVar("T")


def error_text(origin: str, field: str, line: int | None, problem: str,
               column: int | None = None) -> str:
    """``<origin>: <field> (line N): <problem>``, or ``<origin>: line N, column C: <problem>``
    for the file as a whole (the line only where it is known)."""
    if field:
        where = f"{field}{f' (line {line})' if line else ''}: "
    else:
        where = f"line {line}{f', column {column}' if column else ''}: " if line else ""
    return f"{origin}: {where}{problem}"


class LayerError(ValueError):
    """A layered file is invalid (see :func:`error_text` for the message). ``origin``: the
    file, or ``<file> (overrides)``; ``field``: the field's path (``""`` for the file as a
    whole); ``line``: 1-based or None; ``problem``: what is wrong and what was expected."""

    def __init__(self, origin: str, field: str, line: int | None, problem: str,
                 column: int | None = None):
        super().__init__(error_text(origin, field, line, problem, column))
        self.origin = origin
        self.field = field
        self.line = line
        self.column = column
        self.problem = problem

    def __reduce__(self):  # picklable (e.g. from a worker process) with its parts
        return type(self), (self.origin, self.field, self.line, self.problem, self.column)


@dataclass
class Layers:
    """The node trees of the layers loaded, in order: (origin, root; None for an empty one)."""

    roots: list[tuple[str, yaml.Node | None]] = field(default_factory=list)

    def wrote(self, path: tuple) -> tuple[str | None, int | None]:
        """(origin, line) of the last layer that wrote ``path``, or the list holding it (a later
        layer's list replaces an earlier one's whole: ``q_home`` for ``q_home[3]``); (None,
        None) when no layer did (a default)."""
        for origin, root in reversed(self.roots):
            for end in range(len(path), 0, -1):
                if end == len(path) or isinstance(path[end], int):
                    line = line_of(root, path[:end])
                    if line is not None:
                        return origin, line
        return None, None

    def node(self, path: tuple) -> yaml.Node | None:
        """The node of ``path`` in the last layer that wrote it (None: none did)."""
        for _, root in reversed(self.roots):
            node = node_at(root, path)
            if node is not None:
                return node
        return None

    def locate(self, error: FieldError, origin: str, kind: type[LayerError]) -> LayerError:
        """``error`` as a ``kind``, naming the layer and line where its field was written last
        (``origin`` and no line when no layer wrote it: a default judged by a rule). For a bound
        between two fields (``error.other``), the one written last is named: a field left at
        its default is not where the user sees the problem."""
        said = (error, error.other) if getattr(error, "other", None) is not None else (error,)
        for i in range(len(self.roots) - 1, -1, -1):
            for e in said:
                written, line = Layers(self.roots[i:i + 1]).wrote(tuple(e.path))
                if written is not None:
                    return kind(written, format_path(tuple(e.path)), line, e.problem)
        return kind(origin, format_path(tuple(error.path)), None, error.problem)


def written(root: yaml.Node | None, path: tuple, *, nonempty: bool = False) -> bool:
    """Whether the layer ``root`` writes ``path`` (not as null; with ``nonempty``, not as an
    empty string)."""
    node = node_at(root, path)
    if node is None or node.tag == "tag:yaml.org,2002:null":
        return False
    return not (nonempty and isinstance(node, yaml.ScalarNode) and node.value == "")


def file_layer(path, what: str, error: type[LayerError]) -> tuple[str, str]:
    """(origin, text) of the file at ``path`` as a layer (``what`` names the kind of file);
    ``error`` names the file when it cannot be read as UTF-8 YAML text."""
    origin = str(path)
    try:
        return origin, read_text(Path(path), what)
    except YamlTextError as e:
        raise error(origin, "", e.line, e.problem, e.column) from None


def load_layers(schema: type[T], layers: list[tuple[str, str]], start: T, *,
                what: str, error: type[LayerError], overrides_from: int = 1,
                prepare: Callable[[yaml.Node], yaml.Node] | None = None,
                reload: Callable[[T, T, str], T] | None = None) -> tuple[T, Layers]:
    """``start`` updated by each (origin, YAML text) layer in turn, and the layers' trees.

    ``what`` names the kind of file in messages (``scenario``, ``experiment``); ``error``: the
    :class:`LayerError` raised; ``overrides_from``: the index of the first override (the
    layers from it on make their relative paths the current folder's: :func:`absolute_paths`);
    ``prepare(root)``: the tree ``yaml_load_typed`` reads, when a layer's text needs reshaping
    first (an experiment's ``overrides`` mappings become text); ``reload(loaded, defaults,
    text)``: a second look at a loaded layer (a scenario's GbH preset changes the defaults the
    layer's own fields go over)."""
    result, trees = copy.deepcopy(start), Layers()
    for i, (origin, text) in enumerate(layers):
        result, root = _load_layer(schema, text, origin, result, what, error, prepare, reload)
        trees.roots.append((origin, root))
        if i >= overrides_from:
            absolute_paths(result, root, path_fields(schema))
    return result, trees


def _load_layer(schema, text: str, origin: str, defaults, what: str, error, prepare, reload):
    try:
        if "\0" in text:
            decode(text.encode("utf-8", "surrogatepass"))  # names the NUL's line and column
        root = compose(text, what)
    except YamlTextError as e:
        raise error(origin, "", e.line, e.problem, e.column) from None
    if root is None:  # empty, whitespace or comments only, or only "---": nothing changes
        return copy.deepcopy(defaults), None
    try:
        check_document(root, schema, what)
    except YamlFieldError as e:
        raise error(origin, format_path(e.path), e.line, e.problem) from None
    loaded = prepare(root) if prepare is not None else root
    data = text if loaded is root else yaml.serialize(loaded)
    try:
        result = yaml_load_typed(schema=schema, data=data, defaults=defaults)
        if reload is not None:
            result = reload(result, defaults, data)
    except Exception as e:  # noqa: BLE001  (Drake raises RuntimeError, ValueError, TypeError...)
        found = locate_load_error(loaded, schema, e, what)
        raise error(origin, format_path(found.path), found.line, found.problem) from None
    return result, root


def override_layers(origin: str, overrides, error: type[LayerError] = LayerError
                    ) -> list[tuple[str, str]]:
    """(origin, text) of each non-blank override (a ``str``, ``bytes`` decoded as a file is, or
    a list of them), labelled ``<origin> (overrides)`` (``(overrides i of n)`` when there are
    several) for messages; ``error`` for what is not YAML text."""
    several = isinstance(overrides, list | tuple)
    items = list(overrides) if several else [overrides]
    for i, item in enumerate(items):
        if not isinstance(item, str | bytes):
            where = f"overrides[{i}]" if several else "overrides"
            raise error(f"{origin} ({where})", "", None, "expected YAML text (a str, or bytes in "
                        "UTF-8) or a list of them, got " + shown(item))
    texts = [t for t in items if t.strip()]
    layers = []
    for i, text in enumerate(texts):
        label = f"{origin} ({'overrides' if len(texts) == 1 else f'overrides {i + 1} of {len(texts)}'})"
        if isinstance(text, bytes):
            try:
                text = decode(text)
            except YamlTextError as e:
                raise error(label, "", e.line, e.problem, e.column) from None
        layers.append((label, text))
    return layers


@functools.cache
def path_fields(schema) -> tuple[tuple, ...]:
    """The paths of ``schema``'s fields (its dataclass sections' too) whose rule is
    :class:`~gbh_drake.core.ranges.FilePath`."""
    found = []

    def walk(cls, at: tuple) -> None:
        hints = typing.get_type_hints(cls)
        for f in dataclasses.fields(cls):
            if isinstance(rule_of(f), FilePath):
                found.append(at + (f.name,))
            kind = hints.get(f.name)
            options = typing.get_args(kind) if typing.get_origin(kind) in (typing.Union,
                                                                            types.UnionType) \
                else (kind,)
            for option in options:
                if dataclasses.is_dataclass(option):
                    walk(option, at + (f.name,))

    walk(schema, ())
    return tuple(found)


def absolute_paths(config, root: yaml.Node | None, paths) -> None:
    """Each field of ``paths`` (tuples of names) that the YAML document ``root`` writes, when it
    is a relative path, made absolute against the current folder (a path given in an override,
    e.g. ``--set "output_dir: out"``, is where the user is, not where the file is)."""
    for path in paths:
        if not written(root, path, nonempty=True):
            continue
        *parents, name = path
        holder = config
        for part in parents:
            holder = getattr(holder, part, None)
        value = getattr(holder, name, None)
        if isinstance(value, str) and "\0" not in value:
            p = Path(value).expanduser()
            if not p.is_absolute():
                setattr(holder, name, str(Path.cwd() / p))
