"""Modules imported when first used, not when this package is imported.

trimesh (with scipy and networkx) takes ~0.6 s to import, more than pydrake's systems; a user who
imports ``gbh_drake.systems`` to build a diagram should not wait for it before anything runs.
The modules that use them hold a :class:`LazyModule` instead, which imports the real module on
its first attribute access (``trimesh.Trimesh``, ``spatial.cKDTree``...).
"""

from __future__ import annotations

import importlib


class LazyModule:
    """Stands for the module ``name`` and imports it on first attribute access (then every
    access is a lookup in ``sys.modules`` and on the module)."""

    def __init__(self, name: str):
        self.__dict__["_name"] = name

    def __getattr__(self, attribute: str):
        return getattr(importlib.import_module(self.__dict__["_name"]), attribute)

    def __repr__(self) -> str:
        return f"<lazy module {self.__dict__['_name']!r}>"


def lazy_module(name: str) -> LazyModule:
    """The module ``name``, imported on first use (see :class:`LazyModule`)."""
    return LazyModule(name)
