"""Open3D, imported without the parts this package never uses until someone asks for them.

``import open3d`` runs ``open3d.ml`` (which imports scikit-learn and the Open3D-ML dataset
readers) and ``open3d.visualization`` (which imports Dash and Plotly): 1.5 s of its 2.2-3 s on
our machines, for code the pipeline never calls. :func:`open3d` imports Open3D with those two
subpackages *deferred*: each is a placeholder module whose first attribute access imports the
real subpackage and answers from it, so ``open3d.ml.datasets`` or
``open3d.visualization.draw_geometries`` still work in the same process, only later.

When Open3D is already imported (by the user's code, say), it is returned as it is.
"""

from __future__ import annotations

import importlib
import importlib.util
import sys
import types
from pathlib import Path

#: The subpackages deferred (they are imported by ``open3d/__init__.py`` itself).
DEFERRED = ("ml", "visualization")


class _Deferred(types.ModuleType):
    """Stands in ``sys.modules`` for a subpackage until one of its attributes is read; then
    imports the real one (in its place in ``sys.modules`` and on the parent package) and
    answers from it."""

    def __getattr__(self, name: str):
        real = self.__dict__.get("_real")
        if real is None:
            parent, _, child = self.__name__.rpartition(".")
            if sys.modules.get(self.__name__) is self:
                del sys.modules[self.__name__]
            real = importlib.import_module(self.__name__)
            setattr(sys.modules[parent], child, real)
            self.__dict__["_real"] = real
        return getattr(real, name)


def _defer(package: Path, name: str) -> None:
    full = f"open3d.{name}"
    if full in sys.modules or not (package / name / "__init__.py").is_file():
        return
    module = _Deferred(full)
    module.__path__ = [str(package / name)]
    module.__spec__ = importlib.util.spec_from_file_location(
        full, package / name / "__init__.py", submodule_search_locations=module.__path__)
    module.__file__ = str(package / name / "__init__.py")
    sys.modules[full] = module


def open3d() -> types.ModuleType:
    """The ``open3d`` module, imported with :data:`DEFERRED` deferred if it was not yet."""
    if "open3d" not in sys.modules:
        spec = importlib.util.find_spec("open3d")  # (finds the package; does not import it)
        if spec is not None and spec.submodule_search_locations:
            package = Path(next(iter(spec.submodule_search_locations)))
            for name in DEFERRED:
                _defer(package, name)
    module = importlib.import_module("open3d")
    for name in DEFERRED:
        placeholder = sys.modules.get(f"open3d.{name}")
        if placeholder is not None and name not in module.__dict__:
            setattr(module, name, placeholder)
    return module
