"""Field-by-field checks of a YAML document against a dataclass schema, for clear errors.

Drake's ``yaml_load_typed`` rejects bad input, but its messages do not always say which field
(``invalid literal for int()``) nor where in the file. :func:`check_yaml_against_schema` walks the
document's node tree (PyYAML's composer keeps line numbers) beside the schema and reports the
first problem as ``<field.path> (line N): <what is wrong>``. Fields whose type is a Drake struct
(``CameraConfig``, ``Transform``, ...) are handed to ``yaml_load_typed`` on their own, so their
errors are also attributed to the right field.
"""

from __future__ import annotations

import dataclasses
import types
import typing

import yaml
from pydrake.common.yaml import yaml_load_typed

_SCALAR_TAGS = {
    bool: {"tag:yaml.org,2002:bool"},
    int: {"tag:yaml.org,2002:int"},
    float: {"tag:yaml.org,2002:float", "tag:yaml.org,2002:int"},
    str: {"tag:yaml.org,2002:str"},
}
_TYPE_NAMES = {bool: "a boolean", int: "an integer", float: "a number", str: "a string"}


class _AnyTagLoader(yaml.SafeLoader):
    """Composes documents with Drake's tags (``!Rpy``, ``!UniformVector``) without failing."""


class YamlFieldError(ValueError):
    """A YAML document does not fit the schema: ``path`` names the field, ``line`` is 1-based."""

    def __init__(self, path: str, line: int | None, message: str):
        where = f"{path or '<document>'}" + (f" (line {line})" if line else "")
        super().__init__(f"{where}: {message}")
        self.path = path
        self.line = line


def _line(node) -> int | None:
    return node.start_mark.line + 1 if node is not None and node.start_mark else None


def _describe(node) -> str:
    if isinstance(node, yaml.MappingNode):
        return "a mapping"
    if isinstance(node, yaml.SequenceNode):
        return "a list"
    return f"{node.value!r}"


def compose(text: str):
    """The YAML node tree of ``text`` (raises ``yaml.YAMLError`` with a line on bad syntax)."""
    return yaml.compose(text, Loader=_AnyTagLoader)


def check_yaml_against_schema(text: str, schema: type) -> None:
    """Raises :class:`YamlFieldError` on the first field of ``text`` that does not fit ``schema``."""
    try:
        root = compose(text)
    except yaml.YAMLError as e:
        mark = getattr(e, "problem_mark", None)
        raise YamlFieldError("", mark.line + 1 if mark else None, f"not valid YAML: {e}") from e
    if root is None:
        return
    _check(root, schema, "", text)


def _check(node, schema, path: str, text: str) -> None:
    origin = typing.get_origin(schema)
    args = typing.get_args(schema)
    is_null = isinstance(node, yaml.ScalarNode) and node.tag == "tag:yaml.org,2002:null"
    if origin in (typing.Union, types.UnionType):
        if is_null and type(None) in args:
            return
        options = [a for a in args if a is not type(None)]
        errors = []
        for option in options:
            try:
                _check(node, option, path, text)
                return
            except YamlFieldError as e:
                errors.append(str(e))
        raise YamlFieldError(path, _line(node), " / ".join(errors))
    if dataclasses.is_dataclass(schema):
        _check_dataclass(node, schema, path, text)
    elif origin is list:
        if not isinstance(node, yaml.SequenceNode):
            raise YamlFieldError(path, _line(node), f"expected a list, got {_describe(node)}")
        for i, item in enumerate(node.value):
            _check(item, args[0], f"{path}[{i}]", text)
    elif origin is dict:
        if not isinstance(node, yaml.MappingNode):
            raise YamlFieldError(path, _line(node), f"expected a mapping, got {_describe(node)}")
        for key, value in node.value:
            _check(value, args[1], f"{path}.{key.value}" if path else key.value, text)
    elif schema in _SCALAR_TAGS:
        if not isinstance(node, yaml.ScalarNode) or node.tag not in _SCALAR_TAGS[schema]:
            raise YamlFieldError(
                path, _line(node), f"expected {_TYPE_NAMES[schema]}, got {_describe(node)}"
            )
    else:
        _check_drake_struct(node, schema, path, text)


def _check_dataclass(node, schema, path: str, text: str) -> None:
    if not isinstance(node, yaml.MappingNode):
        raise YamlFieldError(path, _line(node), f"expected a mapping, got {_describe(node)}")
    hints = typing.get_type_hints(schema)
    known = [f.name for f in dataclasses.fields(schema)]
    seen = set()
    for key, value in node.value:
        sub = f"{path}.{key.value}" if path else key.value
        if key.value in seen:
            raise YamlFieldError(sub, _line(key), "given twice")
        seen.add(key.value)
        if key.value not in hints:
            raise YamlFieldError(sub, _line(key), f"unknown field (known: {', '.join(known)})")
        _check(value, hints[key.value], sub, text)


def _check_drake_struct(node, schema, path: str, text: str) -> None:
    """Loads one Drake-typed field on its own so that its error names the field."""
    snippet = text[node.start_mark.index : node.end_mark.index]
    if isinstance(node, yaml.MappingNode) and node.flow_style is False:
        # Re-indent a block mapping so it parses on its own.
        lines = text[: node.end_mark.index].splitlines()[node.start_mark.line :]
        indent = node.start_mark.column
        snippet = "\n".join(line[indent:] for line in lines)
    doc = "value: " + snippet if not isinstance(node, yaml.MappingNode) else snippet
    try:
        if isinstance(node, yaml.MappingNode):
            yaml_load_typed(schema=schema, data=doc)
        else:
            holder = dataclasses.make_dataclass("_Holder", [("value", schema)])
            yaml_load_typed(schema=holder, data=doc)
    except Exception as e:  # Drake raises RuntimeError/ValueError/TypeError
        raise YamlFieldError(path, _line(node), f"{type(e).__name__}: {e}") from e
