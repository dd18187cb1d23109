"""The LeafSystems of gbh_drake, for your own diagrams (typed ports, no hidden globals).

Perception and grasps:

* :class:`Scanner`: depth views fused by TSDF into the object's mesh (``mesh_W``);
* :class:`DepthImageScanner`: the same scan from camera streams (depth images and camera poses
  on input ports, real or simulated);
* :class:`ShapeCompleter`: the scan's unseen side completed by symmetry (beyond the paper);
* :class:`HangabilityDetector` -> :class:`GraspSynthesizer` -> :class:`GraspScorer`: the
  paper's three stages (hanging structures, hook grasps, the ranked best);
* :class:`AntipodalGraspSampler`: the two-straight-rod baseline on the same scan;
* :class:`ScoopSynthesizer` (scoops of flat material) and :class:`RegraspPlanner` (resting
  poses to set the object down in), on the detector's structures (beyond the paper);
* :class:`GraspSearchReport`: why a method offered no grasp (for the monitor);
* :class:`GraspList`: grasps given from outside, held in the context (executed by
  :class:`~gbh_drake.methods.GivenGrasps`).

Execution and judging:

* :class:`PickAndCarry`: the pick-and-place state machine (plans from the measured state);
* :class:`CageMonitor`: the verdict as it evolves (an :class:`Outcome`), cage or pinch;
* :class:`HandDriver` (force-limited fingers) and :class:`WristLoad` (the hand's load), used
  inside the :class:`~gbh_drake.station.Station`;
* :class:`GraspVisualizer`: draws scan, structures and grasps in Meshcat.

Python values travel on ``Value[object]`` ports, which Drake's ``Connect()`` does not check:
:func:`build_checked` builds a diagram and refuses a wire whose model values do not match.
"""

from gbh_drake.systems.scanner import Scanner, no_scan  # noqa: I001  (dependency order)
from gbh_drake.systems.depth_image_scanner import DepthImageScanner
from gbh_drake.systems.stage import AbstractStage
from gbh_drake.systems.shape_completer import ShapeCompleter
from gbh_drake.systems.hangability_detector import Hangability, HangabilityDetector
from gbh_drake.systems.grasp_synthesizer import GraspSynthesizer
from gbh_drake.systems.grasp_scorer import GraspScorer
from gbh_drake.systems.antipodal_sampler import AntipodalGraspSampler
from gbh_drake.systems.scoop_synthesizer import ScoopSynthesizer
from gbh_drake.systems.regrasp_planner import RegraspPlanner
from gbh_drake.systems.hand_driver import HandDriver
from gbh_drake.systems.wrist_load import WristLoad
from gbh_drake.systems.pick_and_carry import PickAndCarry
from gbh_drake.systems.cage_monitor import CageMonitor
from gbh_drake.messages import GraspSearch, HeldBy, Mode, Outcome, PickStatus, Verdict
from gbh_drake.systems.grasp_search import GraspSearchReport, explain_no_grasp
from gbh_drake.systems.grasp_list import GraspList
from gbh_drake.systems.grasp_visualizer import GraspVisualizer
from gbh_drake.systems.ports import build_checked, check_connections

__all__ = [
    "AbstractStage",
    "AntipodalGraspSampler",
    "CageMonitor",
    "DepthImageScanner",
    "GraspList",
    "GraspScorer",
    "GraspSearch",
    "GraspSearchReport",
    "GraspSynthesizer",
    "GraspVisualizer",
    "HandDriver",
    "Hangability",
    "HangabilityDetector",
    "HeldBy",
    "Mode",
    "Outcome",
    "PickAndCarry",
    "PickStatus",
    "RegraspPlanner",
    "Scanner",
    "ScoopSynthesizer",
    "ShapeCompleter",
    "Verdict",
    "WristLoad",
    "build_checked",
    "check_connections",
    "explain_no_grasp",
    "no_scan",
]
