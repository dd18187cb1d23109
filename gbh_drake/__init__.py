"""gbh_drake: Grasping by Hanging (Li, Su, Chirikjian) simulated in Drake.

Layout: ``core`` holds the pure geometry (no pydrake), ``perception`` the scanning,
``systems`` the Drake LeafSystems, ``planning`` IK, RRT-Connect and the pick motion, ``objects`` the
object set, ``station.py`` builds the simulation diagram from a ``scenario.Scenario``.
"""

from pathlib import Path

__version__ = "0.1.0"

#: Repository root (holds ``models/`` and ``scenarios/``) when running from a checkout.
REPO_ROOT = Path(__file__).resolve().parent.parent
MODELS_DIR = REPO_ROOT / "models"
SCENARIOS_DIR = REPO_ROOT / "scenarios"
