"""The API pages' griffe extension (tools/griffe_docs.py): Sphinx roles read as code, and a
config field's default shows as its value, not as the call that declares its range."""

import ast
import importlib.util

from gbh_drake import REPO_ROOT

spec = importlib.util.spec_from_file_location("griffe_docs", REPO_ROOT / "tools" / "griffe_docs.py")
griffe_docs = importlib.util.module_from_spec(spec)
spec.loader.exec_module(griffe_docs)


def _default(source: str) -> str | None:
    return griffe_docs.field_default(ast.parse(source, mode="eval").body)


def test_roles_become_code_spans():
    text = ":class:`~gbh_drake.station.Station` and :func:`plan_grasps`, :mod:`.schema`"
    assert griffe_docs.plain_roles(text) == "`Station` and `plan_grasps`, `.schema`"
    assert griffe_docs.plain_roles("no role: `x`") == "no role: `x`"


def test_field_defaults_are_their_values():
    assert _default('ranged(0.01, NonNeg(0.1, "m"))') == "0.01"
    assert _default("ranged(lambda: [0.45, 0.62], Items(2))") == "[0.45, 0.62]"
    assert _default("field(default_factory=ObjectConfig)") == "ObjectConfig()"
    assert _default("field(default_factory=lambda: [1, 2])") == "[1, 2]"
    assert _default("field(default=3)") == "3"
    assert _default("make_thing(1)") is None
    assert _default("0.5") is None
