"""gbh_drake: Grasping by Hanging (Li, Su, Chirikjian) simulated in Drake.

Layout: ``core`` holds the pure geometry (no pydrake), ``perception`` the scanning,
``systems`` the Drake LeafSystems, ``planning`` IK, RRT-Connect and the pick motion, ``objects`` the
object set, ``station.py`` builds the simulation diagram from a ``scenario.Scenario``.

``gbh_drake.run_trial(scenario_or_path, *, overrides=None, meshcat=None)`` runs one trial and
returns its record (:mod:`gbh_drake.api`); ``gbh_drake.grasps(path, ...)`` ranks hook grasps for
a mesh, point cloud or depth images you have, in the robot's base frame
(:mod:`gbh_drake.scan_grasps.api`). Both are imported on first use, so ``import gbh_drake``
stays light.
"""

from importlib.resources import files
from pathlib import Path

__version__ = "0.1.0"

#: Repository root (holds ``models/`` and ``scenarios/``) when running from a checkout (also
#: the editable install of ``./dev.sh setup``); in an installed wheel, the site-packages folder.
REPO_ROOT = Path(__file__).resolve().parent.parent

#: An installed wheel ships ``models/`` and ``scenarios/`` inside the package (setup.py maps them
#: there); a checkout has them at the repository root only.
_PACKAGED = Path(str(files(__name__)))
IN_CHECKOUT = not (_PACKAGED / "models").is_dir()

#: The models of Drake's package ``gbh_drake`` (``package://gbh_drake/...``): the arm URDF, the
#: gripper and table SDFs and the Franka meshes.
MODELS_DIR = REPO_ROOT / "models" if IN_CHECKOUT else _PACKAGED / "models"
#: The shipped scenario files (``default.yaml`` is what ``gbh run`` runs without a file).
SCENARIOS_DIR = REPO_ROOT / "scenarios" if IN_CHECKOUT else _PACKAGED / "scenarios"


def __getattr__(name: str):
    """``run_trial`` and ``grasps`` are imported on first use (they need pydrake)."""
    if name == "run_trial":
        from gbh_drake.api import run_trial

        return run_trial
    if name == "grasps":
        from gbh_drake.scan_grasps.api import grasps

        return grasps
    raise AttributeError(f"module 'gbh_drake' has no attribute {name!r}")
