"""Layered YAML files: one loader for scenario files and experiment files.

A file is loaded, then each override (``--set`` text) on top of it, every layer with Drake's
``yaml_load_typed`` over the result of the ones before (typos fail loudly). Each layer's text is
first read and composed by :mod:`gbh_drake.yamlfiles.yaml_text` (UTF-8 only, no key given twice,
no string where a list is expected), and its node tree is kept, so that an error found later,
by a field's range or a rule between fields, names the layer (the file, or ``<file>
(overrides)``) and the line where the field was written last (:meth:`Layers.locate`).

Errors read ``<origin>: <field> (line N): <problem>`` (:func:`error_text`), and are
:class:`LayerError` s: :class:`~gbh_drake.scenario.loader.ScenarioError` for a scenario,
:class:`~gbh_drake.experiment.config.ExperimentError` for an experiment.
"""

import copy
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import TypeVar

import yaml
from pydrake.common.yaml import yaml_load_typed

from gbh_drake.core.ranges import FieldError, format_path
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
        (``origin`` and no line when no layer wrote it: a default judged by a rule)."""
        path = tuple(error.path)
        written, line = self.wrote(path)
        return kind(written or origin, format_path(path), line, error.problem)


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
                what: str, error: type[LayerError],
                prepare: Callable[[yaml.Node], yaml.Node] | None = None,
                reload: Callable[[T, T, str], T] | None = None) -> tuple[T, Layers]:
    """``start`` updated by each (origin, YAML text) layer in turn, and the layers' trees.

    ``what`` names the kind of file in messages (``scenario``, ``experiment``); ``error``: the
    :class:`LayerError` raised; ``prepare(root)``: the tree ``yaml_load_typed`` reads, when a
    layer's text needs reshaping first (an experiment's ``overrides`` mappings become text);
    ``reload(loaded, defaults, text)``: a second look at a loaded layer (a scenario's GbH
    preset changes the defaults the layer's own fields go over)."""
    result, trees = copy.deepcopy(start), Layers()
    for origin, text in layers:
        result, root = _load_layer(schema, text, origin, result, what, error, prepare, reload)
        trees.roots.append((origin, root))
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


def override_layers(origin: str, overrides: str | list[str] | tuple[str, ...]
                    ) -> list[tuple[str, str]]:
    """(origin, text) of each non-blank override, labelled ``<origin> (overrides)`` (``(overrides
    i of n)`` when there are several) for messages."""
    texts = [overrides] if isinstance(overrides, str) else list(overrides)
    texts = [t for t in texts if t.strip()]
    return [(f"{origin} ({'overrides' if len(texts) == 1 else f'overrides {i + 1} of {len(texts)}'})",
             t) for i, t in enumerate(texts)]
