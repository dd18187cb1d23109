"""A griffe extension for the documentation site's API pages (mkdocs.yml, mkdocstrings).

gbh_drake's docstrings are written for Sphinx and plain reading; two things read badly when
mkdocstrings renders them as Markdown, and this fixes them while griffe reads the sources
(statically: nothing is imported):

* Sphinx roles (``:class:`~gbh_drake.station.Station```, ``:func:`plan_grasps```) become code
  spans (```Station```, ```plan_grasps```);
* a config field's default written with its range, ``ranged(0.01, NonNeg(0.1, "m"))`` or
  ``ranged(lambda: [0.45, 0.62], ...)``, shows as its default, ``0.01`` or ``[0.45, 0.62]``, and
  ``field(default_factory=ObjectConfig)`` as ``ObjectConfig()`` (the range itself is in the
  docstring and in the field reference's generated table).
"""

from __future__ import annotations

import ast
import re

import griffe

#: A Sphinx cross-reference role: ``:kind:`target``` or ``:kind:`~a.b.target```.
_ROLE = re.compile(r":(?:py:)?(?:class|func|meth|mod|data|attr|exc|obj|const):`(~?)([^`]+)`")


def _role(match: re.Match) -> str:
    target = match.group(2)
    return f"`{target.rsplit('.', 1)[-1] if match.group(1) else target}`"


def plain_roles(text: str) -> str:
    """``text`` with Sphinx roles as Markdown code spans."""
    return _ROLE.sub(_role, text)


def field_default(node: ast.AST) -> str | None:
    """The default a field's value expression gives (``ranged(...)``, ``field(...)``), or None
    for any other expression."""
    if not (isinstance(node, ast.Call) and isinstance(node.func, ast.Name)):
        return None
    if node.func.id == "ranged" and node.args:
        default = node.args[0]
        return ast.unparse(default.body if isinstance(default, ast.Lambda) else default)
    if node.func.id == "field":
        for keyword in node.keywords:
            if keyword.arg == "default":
                return ast.unparse(keyword.value)
            if keyword.arg == "default_factory":
                factory = keyword.value
                if isinstance(factory, ast.Lambda):
                    return ast.unparse(factory.body)
                return f"{ast.unparse(factory)}()"
    return None


class DocsReadable(griffe.Extension):
    """See the module docstring."""

    def on_instance(self, *, node, obj, agent, **kwargs) -> None:
        if obj.docstring is not None:
            obj.docstring.value = plain_roles(obj.docstring.value)

    def on_attribute_instance(self, *, node, attr, agent, **kwargs) -> None:
        value = getattr(node, "value", None)
        default = field_default(value) if isinstance(value, ast.AST) else None
        if default is not None:
            attr.value = default
