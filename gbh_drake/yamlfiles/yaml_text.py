"""Scenario YAML text: what Drake's ``yaml_load_typed`` does not check, and where a field is.

The scenario is loaded by Drake's ``yaml_load_typed`` alone. This module only adds:

* :func:`read_text`: the file's bytes as text, refusing what is not a small UTF-8 text file
  (a folder, a FIFO, UTF-16, binary data, invalid UTF-8) with the line and column of a bad byte;
* :func:`compose`: PyYAML's node tree (it keeps line numbers), with syntax errors at their line;
* :func:`check_document`: what ``yaml_load_typed`` silently accepts although it is wrong: a key
  given twice (the last one would win), a string or a number where a list is expected (a string
  would be split into characters), aliases that expand into a huge document;
* :func:`locate_load_error`: when ``yaml_load_typed`` has refused a document, which field (path
  and line) it refused, found by loading each field on its own with ``yaml_load_typed``;
* :func:`line_of`: the line of a field, to point at a value that loaded but is out of range;
* :func:`compose_own` and :func:`serialize`: the node tree of YAML this program dumped itself,
  and a node tree's text, through libyaml (PyYAML's C loader and emitter, where PyYAML was
  built with it): the same trees and the same text as the pure-Python ones, ten times faster
  (an experiment's task list composes and serializes one scenario per method, object and
  protocol: ``bench/bench_import.py``). A user's file still goes through :func:`compose`,
  whose syntax errors are PyYAML's own words.

Paths are tuples of keys and list indices, printed as ``object.pose.translation`` or
``robot.q_home[3]`` (:func:`format_path`).
"""

from __future__ import annotations

import dataclasses
import difflib
import math
import re
import types
import typing
from pathlib import Path

import numpy as np
import yaml
from pydrake.common import pretty_class_name
from pydrake.common.yaml import yaml_load_typed

from gbh_drake.core.ranges import format_path

#: PyYAML's libyaml loader and emitter, or its pure-Python ones where it was built without
#: libyaml (:func:`compose_own`, :func:`serialize`).
_OWN_LOADER = getattr(yaml, "CSafeLoader", yaml.SafeLoader)
_DUMPER = getattr(yaml, "CSafeDumper", yaml.SafeDumper)
#: Largest scenario file read (bytes): a scenario is a few kilobytes.
MAX_FILE_BYTES = 1_000_000
#: Largest number of YAML values a document may expand to (aliases included).
MAX_VALUES = 100_000
#: Deepest nesting of YAML collections accepted (the schema is about 6 deep).
MAX_DEPTH = 40

_MAP_TAG = "tag:yaml.org,2002:map"
_STR_TAG = "tag:yaml.org,2002:str"
_NULL_TAG = "tag:yaml.org,2002:null"
_TYPE_NAMES = {bool: "true or false", int: "an integer", float: "a number", str: "a string"}

Path_ = tuple[str | int, ...]


class YamlTextError(ValueError):
    """The text is not a YAML document we can read: ``line`` and ``column`` are 1-based or None."""

    def __init__(self, message: str, line: int | None = None, column: int | None = None):
        where = ""
        if line is not None:
            where = f"line {line}" + (f", column {column}" if column is not None else "") + ": "
        super().__init__(where + message)
        self.problem = message
        self.line = line
        self.column = column

    def __reduce__(self):  # picklable with its parts
        return type(self), (self.problem, self.line, self.column)


class YamlFieldError(ValueError):
    """A field does not fit the schema: ``path`` names it, ``line`` is 1-based or None."""

    def __init__(self, path: Path_, line: int | None, message: str):
        where = format_path(path) or "<document>"
        super().__init__(f"{where}{f' (line {line})' if line else ''}: {message}")
        self.path = tuple(path)
        self.line = line
        self.problem = message

    def __reduce__(self):  # picklable with its parts
        return type(self), (self.path, self.line, self.problem)


# ---- reading the file ------------------------------------------------------------------------


def read_text(path: Path, what: str = "scenario") -> str:
    """The text of scenario file ``path`` (``what``: the kind of file, for messages). Raises
    :class:`YamlTextError` (without the file name) for a missing or unreadable file, a folder or
    other non-regular file, a file over :data:`MAX_FILE_BYTES`, UTF-16/32, NUL bytes or invalid
    UTF-8 (with line and column)."""
    try:
        info = path.stat()
    except FileNotFoundError:
        raise YamlTextError(f"{what} file not found") from None
    except (OSError, ValueError) as e:  # a loop of links, a name with a NUL byte...
        raise YamlTextError(f"cannot read the {what} file ({_os_reason(e)})") from None
    if path.is_dir():
        raise YamlTextError(f"is a folder, not a {what} file")
    if not path.is_file():
        raise YamlTextError("is not a regular file (a device, socket or pipe?)")
    if info.st_size > MAX_FILE_BYTES:
        raise YamlTextError(f"is {info.st_size} bytes; a {what} file has at most "
                            f"{MAX_FILE_BYTES} bytes")
    try:
        data = path.read_bytes()
    except OSError as e:
        raise YamlTextError(f"cannot read the {what} file ({_os_reason(e)})") from None
    return decode(data)


def _os_reason(e: BaseException) -> str:
    return e.strerror if isinstance(e, OSError) and e.strerror else str(e)


def decode(data: bytes) -> str:
    """``data`` as text: UTF-8 (a byte-order mark is dropped); raises :class:`YamlTextError`."""
    for bom, name in ((b"\xff\xfe\x00\x00", "UTF-32"), (b"\x00\x00\xfe\xff", "UTF-32"),
                      (b"\xff\xfe", "UTF-16"), (b"\xfe\xff", "UTF-16")):
        if data.startswith(bom):
            raise YamlTextError(f"is {name} text; save it as UTF-8")
    if len(data) >= 2 and b"\x00" in data[:200] and (data[0] == 0 or data[1] == 0):
        raise YamlTextError("looks like UTF-16 text (NUL bytes between characters); save it "
                            "as UTF-8")
    if data.startswith(b"\xef\xbb\xbf"):
        data = data[3:]
    if b"\x00" in data:
        line, column = _line_column(data, data.index(b"\x00"))
        raise YamlTextError("holds a NUL byte: not a text file", line, column)
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as e:
        line, column = _line_column(data, e.start)
        raise YamlTextError(f"is not UTF-8 text (byte 0x{data[e.start]:02x}); save it as UTF-8",
                            line, column) from None


def _line_column(data: bytes, offset: int) -> tuple[int, int]:
    line = data.count(b"\n", 0, offset) + 1
    return line, offset - (data.rfind(b"\n", 0, offset) + 1) + 1


# ---- the node tree --------------------------------------------------------------------------


def compose_own(text: str) -> yaml.Node | None:
    """The node tree of YAML text this program wrote itself (``yaml_dump_typed``'s), through
    libyaml: no user's syntax error to word (a user's text goes through :func:`compose`)."""
    return yaml.compose(text, Loader=_OWN_LOADER)


def serialize(node: yaml.Node, width: int | None = None) -> str:
    """The YAML text of the node tree ``node`` (lines up to ``width`` characters where PyYAML
    may break them; its default 80 when None), through libyaml: the text PyYAML's own emitter
    writes."""
    return yaml.serialize(node, Dumper=_DUMPER, width=width)


def compose(text: str, what: str = "scenario") -> yaml.Node | None:
    """The YAML node tree of ``text`` (None for an empty, comment-only or whitespace-only text,
    and for a document that is only ``---`` or ``null``: nothing, as an empty file).
    Raises :class:`YamlTextError` on bad syntax (with its line), several documents or nesting
    deeper than :data:`MAX_DEPTH`."""
    if _too_deep(text):
        raise YamlTextError(f"nested deeper than {MAX_DEPTH} levels: not a {what}")
    try:
        root = yaml.compose(text, Loader=yaml.SafeLoader)
    except yaml.MarkedYAMLError as e:
        mark = e.problem_mark or e.context_mark
        problem = " ".join(str(p) for p in (e.context, e.problem) if p)
        raise YamlTextError(f"not valid YAML: {problem}", mark.line + 1 if mark else None,
                            mark.column + 1 if mark else None) from None
    except yaml.YAMLError as e:
        raise YamlTextError(f"not valid YAML: {e}") from None
    except RecursionError:
        raise YamlTextError(f"nested deeper than {MAX_DEPTH} levels: not a {what}") from None
    if isinstance(root, yaml.ScalarNode) and root.tag == _NULL_TAG:
        return None  # "---" alone, "~" or "null": no document, the defaults
    return root


def _too_deep(text: str) -> bool:
    """A cheap upper bound of the nesting of flow collections (``[[[[...``), which PyYAML's
    recursive composer would otherwise take to its recursion limit."""
    depth = deepest = 0
    for ch in text:
        if ch in "[{":
            depth += 1
            deepest = max(deepest, depth)
            if deepest > MAX_DEPTH:
                return True
        elif ch in "]}":
            depth = max(0, depth - 1)
    return False


def line_of_node(node: yaml.Node | None) -> int | None:
    return node.start_mark.line + 1 if node is not None and node.start_mark else None


def describe(node: yaml.Node) -> str:
    if isinstance(node, yaml.MappingNode):
        return "a mapping"
    if isinstance(node, yaml.SequenceNode):
        return "a list"
    if node.tag == _NULL_TAG:
        return "nothing (null)"
    return repr(node.value)


def _tag_name(node: yaml.Node) -> str | None:
    """``Rpy`` for a node tagged ``!Rpy``; None for plain nodes."""
    return node.tag[1:] if node.tag.startswith("!") and not node.tag.startswith("!!") else None


def check_document(root: yaml.Node, schema, what: str = "scenario") -> None:
    """Refuses (:class:`YamlFieldError`) what Drake's loader would accept silently: duplicate
    keys, a scalar where the schema has a list or vector (a string would be split into its
    characters), more than :data:`MAX_VALUES` values once aliases are expanded."""
    _check_size(root, what)
    _check_depth(root, what)
    _check_duplicates(root, ())
    _check_shapes(root, schema, (), root_level=True)


def _check_size(root: yaml.Node, what: str = "scenario") -> None:
    sizes: dict[int, int] = {}

    def size(node) -> int:  # memoised on node identity: an alias is the same node object
        key = id(node)
        if key not in sizes:
            sizes[key] = 0  # a recursive alias counts once
            if isinstance(node, yaml.SequenceNode):
                total = 1 + sum(size(n) for n in node.value)
            elif isinstance(node, yaml.MappingNode):
                total = 1 + sum(size(k) + size(v) for k, v in node.value)
            else:
                total = 1
            sizes[key] = min(total, MAX_VALUES + 1)
        return sizes[key]

    if size(root) > MAX_VALUES:
        raise YamlFieldError((), None, f"expands to more than {MAX_VALUES} values (YAML "
                                       f"aliases?): not a {what}")


def _check_depth(root: yaml.Node, what: str = "scenario") -> None:
    stack, seen = [(root, 1)], set()
    while stack:
        node, depth = stack.pop()
        if depth > MAX_DEPTH:
            raise YamlFieldError((), line_of_node(node), f"nested deeper than {MAX_DEPTH} "
                                                         f"levels: not a {what}")
        if id(node) in seen:
            continue
        seen.add(id(node))
        if isinstance(node, yaml.SequenceNode):
            stack.extend((n, depth + 1) for n in node.value)
        elif isinstance(node, yaml.MappingNode):
            stack.extend((v, depth + 1) for _, v in node.value)


def _check_duplicates(node: yaml.Node, path: Path_, seen_nodes: set | None = None) -> None:
    seen_nodes = set() if seen_nodes is None else seen_nodes
    if id(node) in seen_nodes:  # an alias: checked where its anchor is
        return
    seen_nodes.add(id(node))
    if isinstance(node, yaml.MappingNode):
        first: dict[str, int | None] = {}
        for key, value in node.value:
            if not isinstance(key, yaml.ScalarNode):
                continue  # Drake refuses non-string keys as unknown fields
            if key.value == "<<" and key.tag == "tag:yaml.org,2002:merge":
                continue
            if key.value in first:
                raise YamlFieldError(path + (key.value,), line_of_node(key),
                                     f"given twice (first at line {first[key.value]}); "
                                     "remove one")
            first[key.value] = line_of_node(key)
            _check_duplicates(value, path + (key.value,), seen_nodes)
    elif isinstance(node, yaml.SequenceNode):
        for i, item in enumerate(node.value):
            _check_duplicates(item, path + (i,), seen_nodes)


def struct_fields(schema) -> dict[str, typing.Any] | None:
    """Field name -> type of a dataclass or a Drake struct (``__fields__``); None otherwise."""
    if not isinstance(schema, type):
        return None
    if dataclasses.is_dataclass(schema):
        return {f.name: f.type for f in dataclasses.fields(schema)}
    fields = getattr(schema, "__fields__", None)
    if fields is not None and not isinstance(fields, dict):  # (pydantic-style dicts are not ours)
        return {f.name: f.type for f in fields}
    return None


def optional_of(schema):
    """``T`` for ``Optional[T]``, else None."""
    if typing.get_origin(schema) in (typing.Union, types.UnionType):
        args = typing.get_args(schema)
        if len(args) == 2 and args[1] is type(None):
            return args[0]
    return None


def union_options(schema) -> tuple | None:
    if typing.get_origin(schema) in (typing.Union, types.UnionType) and optional_of(schema) is None:
        return typing.get_args(schema)
    return None


def _variant_name(option) -> str:
    name = pretty_class_name(option)
    return name.split("[", 1)[0]


def _variant_for(node: yaml.Node, options: tuple):
    """The union member that a tagged mapping selects (or the first one, untagged)."""
    tag = _tag_name(node)
    if tag is None:
        return options[0]
    for option in options:
        if _variant_name(option) == tag:
            return option
    return None


def _check_shapes(node: yaml.Node, schema, path: Path_, root_level: bool = False) -> None:
    if node.tag == _NULL_TAG:
        return
    inner = optional_of(schema)
    if inner is not None:
        schema = inner
    fields = struct_fields(schema)
    origin = typing.get_origin(schema)
    if fields is not None:
        if not isinstance(node, yaml.MappingNode):
            return  # the loader refuses it
        for key, value in node.value:
            if not isinstance(key, yaml.ScalarNode) or key.value not in fields:
                continue
            if root_level and key.value.startswith("_"):
                continue
            _check_shapes(value, fields[key.value], path + (key.value,))
    elif origin in (list, typing.List) or schema is np.ndarray:  # noqa: UP006
        if isinstance(node, yaml.ScalarNode):
            what = "a list" if origin else "a list of numbers"
            raise YamlFieldError(path, line_of_node(node),
                                 f"expected {what}, got {describe(node)}")
        if isinstance(node, yaml.SequenceNode) and origin:
            (item,) = typing.get_args(schema)
            for i, sub in enumerate(node.value):
                _check_shapes(sub, item, path + (i,))
    elif origin in (dict, typing.Dict) and isinstance(node, yaml.MappingNode):  # noqa: UP006
        for key, value in node.value:
            if isinstance(key, yaml.ScalarNode):
                _check_shapes(value, typing.get_args(schema)[1], path + (key.value,))
    elif union_options(schema) and isinstance(node, yaml.MappingNode):
        option = _variant_for(node, union_options(schema))
        if option is not None:
            _check_shapes(_untagged(node), option, path)


def _untagged(node: yaml.MappingNode) -> yaml.MappingNode:
    return yaml.MappingNode(_MAP_TAG, node.value, node.start_mark, node.end_mark,
                            node.flow_style)


# ---- locating what yaml_load_typed refused -----------------------------------------------------


def loads_alone(node: yaml.Node, schema) -> Exception | None:
    """Loads ``node`` as a value of ``schema`` with ``yaml_load_typed`` (through a one-field
    holder); returns the exception it raised, or None."""
    holder = _holder(schema)
    document = yaml.MappingNode(_MAP_TAG, [(yaml.ScalarNode(_STR_TAG, "value"), node)])
    try:
        yaml_load_typed(schema=holder, data=yaml.serialize(document, Dumper=yaml.SafeDumper))
    except Exception as e:  # noqa: BLE001  (Drake raises RuntimeError/ValueError/TypeError/...)
        return e
    return None


def _holder(schema):
    if schema in _TYPE_NAMES:
        factory = schema
    elif schema is np.ndarray:
        def factory():
            return np.zeros(0)
    elif optional_of(schema) is not None or union_options(schema):
        def factory():
            return None
    elif typing.get_origin(schema) is not None:
        factory = typing.get_origin(schema)
    else:
        factory = schema
    return dataclasses.make_dataclass(
        "_Holder", [("value", schema, dataclasses.field(default_factory=factory))])


def locate_load_error(root: yaml.Node, schema, error: BaseException,
                      what: str = "scenario") -> YamlFieldError:
    """The field of ``root`` that ``yaml_load_typed`` refused (``error`` is what it raised)."""
    if not isinstance(root, yaml.MappingNode):
        article = "an" if what[:1] in "aeiou" else "a"
        return YamlFieldError((), line_of_node(root), f"{article} {what} is a mapping of fields "
                              f"(field: value), got {describe(root)}")
    found = _locate(root, schema, (), root_level=True)
    return found or YamlFieldError((), None, _clean(error))


def _locate(node: yaml.Node, schema, path: Path_, root_level: bool = False):
    if not root_level:
        error = loads_alone(node, schema)
        if error is None:
            return None
    else:
        error = None
    line = line_of_node(node)
    inner = optional_of(schema)
    if inner is not None:
        if node.tag == _NULL_TAG:
            return None
        schema = inner
    fields = struct_fields(schema)
    origin = typing.get_origin(schema)
    if fields is not None:
        if not isinstance(node, yaml.MappingNode):
            return YamlFieldError(path, line, f"expected a mapping of {_kind(schema)} fields "
                                              f"({', '.join(fields)}), got {describe(node)}")
        if _tag_name(node) is not None:
            return YamlFieldError(path, line, f"unexpected tag !{_tag_name(node)}")
        for key, value in node.value:
            if not isinstance(key, yaml.ScalarNode) or key.tag not in (_STR_TAG, ):
                if isinstance(key, yaml.ScalarNode) and key.tag == "tag:yaml.org,2002:merge":
                    continue
                shown = key.value if isinstance(key, yaml.ScalarNode) else describe(key)
                return YamlFieldError(path + (str(shown),), line_of_node(key),
                                      f"not a field name ({describe(key)}); "
                                      f"known: {', '.join(fields)}")
            name = key.value
            if root_level and name.startswith("_"):
                continue  # Drake drops the document's private keys (anchors, templates)
            if name not in fields:
                return YamlFieldError(path + (name,), line_of_node(key),
                                      _unknown_field(name, list(fields)))
            found = _locate(value, fields[name], path + (name,))
            if found:
                return found
        if error is None:
            return None
        for key, value in node.value:  # a field that fails only inside its struct
            alone = yaml.MappingNode(_MAP_TAG, [(key, value)])
            if loads_alone(alone, schema) is not None:
                return YamlFieldError(path + (key.value,), line_of_node(key), _clean(
                    loads_alone(alone, schema)))
        return YamlFieldError(path, line, _clean(error))
    if origin in (list, typing.List):  # noqa: UP006
        if not isinstance(node, yaml.SequenceNode):
            return YamlFieldError(path, line, f"expected a list, got {describe(node)}")
        (item,) = typing.get_args(schema)
        for i, sub in enumerate(node.value):
            found = _locate(sub, item, path + (i,))
            if found:
                return found
        return YamlFieldError(path, line, _clean(error))
    if origin in (dict, typing.Dict):  # noqa: UP006
        if not isinstance(node, yaml.MappingNode):
            return YamlFieldError(path, line, f"expected a mapping, got {describe(node)}")
        for key, value in node.value:
            found = _locate(value, typing.get_args(schema)[1], path + (str(key.value),))
            if found:
                return found
        return YamlFieldError(path, line, _clean(error))
    options = union_options(schema)
    if options:
        names = ", ".join(f"!{_variant_name(o)}" for o in options
                          if not _variant_name(o).startswith("_") and o is not np.ndarray)
        if np.ndarray in options:
            names = "a list of numbers, " + names
        if isinstance(node, yaml.MappingNode):
            option = _variant_for(node, options)
            if option is None:
                return YamlFieldError(path, line, f"unknown tag !{_tag_name(node)} (allowed: "
                                                  f"{names})")
            found = _locate(_untagged(node), option, path)
            return found or YamlFieldError(path, line, _clean(error))
        if isinstance(node, yaml.SequenceNode) and np.ndarray in options:
            return _locate(node, np.ndarray, path) or YamlFieldError(path, line, _clean(error))
        return YamlFieldError(path, line, f"expected a value or one of {names}, got "
                                          f"{describe(node)}")
    if schema in _TYPE_NAMES:
        return YamlFieldError(path, line, _primitive_message(node, schema))
    if schema is np.ndarray:
        return YamlFieldError(path, line, f"expected a list of numbers, got {describe(node)}")
    return YamlFieldError(path, line, _clean(error))


def _kind(schema) -> str:
    return getattr(schema, "__name__", str(schema)).split("𝓣")[0]


def _unknown_field(name: str, known: list[str]) -> str:
    close = difflib.get_close_matches(name, known, n=1)
    hint = f"did you mean {close[0]!r}? " if close else ""
    return f"unknown field ({hint}known: {', '.join(known)})"


def _primitive_message(node: yaml.Node, schema) -> str:
    expected = _TYPE_NAMES[schema]
    if not isinstance(node, yaml.ScalarNode):
        return f"expected {expected}, got {describe(node)}"
    if schema is str:
        return f"expected {expected}, got {describe(node)} (quote it: \"{node.value}\")"
    if schema is int and _is_number(node.value):
        return f"expected {expected} (whole number, digits only), got {node.value!r}"
    if schema is bool:
        return f"expected {expected}, got {node.value!r}"
    return f"expected {expected}, got {describe(node)}"


def _is_number(text: str) -> bool:
    try:
        return math.isfinite(float(text))
    except ValueError:
        return False


def _clean(error: BaseException | None) -> str:
    """Drake's message on one line; a pybind11 argument error said as the size it wanted."""
    if error is None:
        return "not accepted"
    text = " ".join(str(error).split())
    size = re.search(r"incompatible function arguments.*?numpy\.float64\[(\d+), 1\]", text)
    if size:
        return f"needs {size.group(1)} numbers"
    return text or type(error).__name__


# ---- where a field is ---------------------------------------------------------------------------


def node_at(root: yaml.Node | None, path: Path_, *, key: bool = False) -> yaml.Node | None:
    """The node of ``path`` in ``root`` (tags of variants are looked through), or None; with
    ``key``, the key node of the last part when it is a mapping key."""
    node, key_node = root, None
    for part in path:
        key_node = None
        if isinstance(node, yaml.MappingNode) and isinstance(part, str):
            matches = [(k, v) for k, v in node.value
                       if isinstance(k, yaml.ScalarNode) and k.value == part]
            if not matches:
                return None
            key_node, node = matches[-1]
        elif isinstance(node, yaml.SequenceNode) and isinstance(part, int):
            if part >= len(node.value):
                return None
            node = node.value[part]
        else:
            return None
    return key_node if key and key_node is not None else node


def line_of(root: yaml.Node | None, path: Path_) -> int | None:
    """The line where field ``path`` is written in ``root`` (its key's line; a list item's
    own line), None when it is not written there."""
    if root is None or not path:
        return None
    return line_of_node(node_at(root, path, key=True))
