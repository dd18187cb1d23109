"""Where Drake finds this project's models, offline.

Two packages are registered:

* ``gbh_drake``: ``gbh_drake.MODELS_DIR``, the repository's ``models/`` folder in a checkout,
  ``gbh_drake/models/`` inside an installed wheel (the arm URDF, the gripper and table SDFs;
  no ``package.xml``: the folder is registered by path);
* ``pybullet_data``: the data folder of the installed ``pybullet`` wheel, which ships Franka's
  visual and collision meshes (Apache-2.0). It is located with importlib, never downloaded.
"""

from __future__ import annotations

import importlib.util
from pathlib import Path

from pydrake.multibody.parsing import ModelDirectives, PackageMap, Parser, ProcessModelDirectives

from gbh_drake import MODELS_DIR


def pybullet_data_dir() -> Path:
    """The ``pybullet_data`` folder of the installed pybullet wheel."""
    spec = importlib.util.find_spec("pybullet_data")
    if spec is None or not spec.submodule_search_locations:
        raise RuntimeError(
            "the Python package 'pybullet' (which ships pybullet_data/franka_panda meshes) is "
            "not installed; run the README's setup command"
        )
    return Path(next(iter(spec.submodule_search_locations)))


def add_packages(package_map: PackageMap) -> PackageMap:
    """Registers ``gbh_drake`` and ``pybullet_data`` in ``package_map`` (idempotent)."""
    for name, path in (("gbh_drake", MODELS_DIR), ("pybullet_data", pybullet_data_dir())):
        if not package_map.Contains(name):
            package_map.Add(name, str(path))
    return package_map


def make_parser(plant, **kwargs) -> Parser:
    """A ``Parser`` for ``plant`` that resolves ``package://gbh_drake`` and ``package://pybullet_data``.

    Drake's remote model package is never used here: it downloads at run time."""
    parser = Parser(plant, **kwargs)
    add_packages(parser.package_map())
    return parser


def add_fixed_models(parser: Parser, directives) -> None:
    """Adds the fixed models of ``directives`` (a sequence of Drake ``ModelDirective``: arm,
    gripper, table and a user's) to ``parser.plant()``: the one populate function of the
    simulated station and of the planning model, so both are the same robot."""
    add_packages(parser.package_map())
    ProcessModelDirectives(ModelDirectives(directives=list(directives)), parser.plant(), parser)
