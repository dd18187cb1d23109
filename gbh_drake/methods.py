"""Grasp methods: each one object behind one signature, found by name in a registry.

A method adds its systems to the trial's builder, fed by the scan, and says where its grasps
come from (:class:`GraspSource`): the ports the pick-and-carry machine, the monitor and the
visualiser read. :func:`gbh_drake.trial.build_trial` asks the scenario's method for them and
never which method it has (as vgn's ``clutter_removal.run(grasp_plan_fn)`` runs VGN and GPD
through one call)::

    source = method_named(scenario.grasp_method).add_systems(builder, scenario=scenario,
                                                             seeds=seeds, scan=scan_port)

Shipped (``Scenario.grasp_method``):

* ``gbh`` (:class:`Gbh`): the paper's three stages, the bar deployed;
* ``antipodal`` (:class:`Antipodal`): the two-straight-rod baseline, the bar folded;
* ``gbh_fallback`` (:class:`GbhFallback`): GbH, then an antipodal grasp with the bar folded
  when GbH offers nothing reachable (the revolute joint the paper's Sec. 4 proposes);
* ``gbh_scoop`` (:class:`GbhScoop`, beyond the paper): GbH, then a scoop of material lying flat
  on the table (the wedge gripper's bar slid under it, :mod:`gbh_drake.core.scoop`), then a
  tall scoop (under material taller than the wedge);
* ``gbh_regrasp`` (:class:`GbhRegrasp`, beyond the paper): GbH, then, when it finds a structure
  but no hook grasp of the object as it lies, a regrasp: a pinch sets the object down in a
  resting pose in which GbH can hook it, a re-scan, and GbH on the new scan;
* ``gbh_completed`` (:class:`GbhCompleted`, beyond the paper): GbH on the scan completed by
  symmetry (:mod:`gbh_drake.core.completion`);
* ``gbh_plus`` (:class:`GbhPlus`, beyond the paper): all of it in one: GbH, the scoop, the
  regrasp, the tall scoop, then the antipodal fallback; after a lift that came away empty, one
  retry.

Each method's facts (gripper, bar, retries, its ordered grasp tiers) are its
:class:`~gbh_drake.method_spec.MethodSpec`; a method here only builds the systems that offer
each tier's grasps. :class:`GivenGrasps` executes grasps of your own through another method's
diagram. :func:`register_method` adds a method of your own (and its spec: a scenario can then
name it).
"""

from __future__ import annotations

import abc
import dataclasses
from collections.abc import Sequence
from dataclasses import dataclass, field

from pydrake.systems.framework import DiagramBuilder, OutputPort, System

from gbh_drake.core.gripper import GRIPPERS
from gbh_drake.method_spec import MethodSpec, Tier, method_spec, register_spec
from gbh_drake.scenario import Scenario
from gbh_drake.seeds import Seeds
from gbh_drake.systems.antipodal_sampler import AntipodalGraspSampler
from gbh_drake.systems.grasp_list import GraspList
from gbh_drake.systems.grasp_scorer import GraspScorer
from gbh_drake.systems.grasp_search import GraspSearchReport
from gbh_drake.systems.grasp_synthesizer import GraspSynthesizer
from gbh_drake.systems.hangability_detector import HangabilityDetector
from gbh_drake.systems.regrasp_planner import RegraspPlanner
from gbh_drake.systems.scoop_synthesizer import ScoopSynthesizer
from gbh_drake.systems.shape_completer import ShapeCompleter


@dataclass
class GraspTier:
    """One tier of grasps a method offers (:class:`~gbh_drake.method_spec.Tier`): the output
    port of its grasps (lists of objects with ``X_WG`` and ``kind``, best first) and, for a
    regrasp, the port of the resting poses to set the object down in (its grasps are the
    pinches that do it)."""

    tier: Tier
    grasps: OutputPort
    poses: OutputPort | None = None


@dataclass
class GraspSource:
    """What a method added to the diagram: the output ports the rest of the trial reads.

    ``tiers``: the grasps to try, tier by tier in the method's order (the first is the
    method's own, :attr:`grasps`); ``search``: why there are none
    (:class:`~gbh_drake.messages.GraspSearch`); ``hanging_structures`` and ``candidates``:
    GbH's detector and synthesizer outputs (None for a method without GbH); ``systems``: the
    added systems by name."""

    tiers: list[GraspTier]
    search: OutputPort
    hanging_structures: OutputPort | None = None
    candidates: OutputPort | None = None
    systems: dict[str, System] = field(default_factory=dict)
    method_tiers: list[GraspTier] | None = None
    """The method's own tiers when given grasps replaced them (:class:`GivenGrasps`)."""

    @property
    def grasps(self) -> OutputPort:
        """The method's own grasps (the first tier)."""
        return self.tiers[0].grasps

    def tier(self, tier: Tier) -> GraspTier | None:
        """The tier ``tier`` of this source, or None when the method does not offer it."""
        return next((t for t in self.tiers if t.tier is tier), None)


class GraspMethod(abc.ABC):
    """A way of choosing grasps: its facts are ``spec`` (a
    :class:`~gbh_drake.method_spec.MethodSpec`: name, gripper, bar angle, retries, tiers); it
    builds the systems that offer each of the spec's tiers (:meth:`add_systems`)."""

    spec: MethodSpec

    @property
    def name(self) -> str:
        """The scenario's ``grasp_method``."""
        return self.spec.name

    @abc.abstractmethod
    def add_systems(self, builder: DiagramBuilder, *, scenario: Scenario, seeds: Seeds,
                    scan: OutputPort) -> GraspSource:
        """Adds the method's systems to ``builder``, fed by ``scan`` (the Scanner's
        ``mesh_W``), and returns where its grasps come from: one :class:`GraspTier` per tier of
        its spec, in the spec's order."""


def _add(builder: DiagramBuilder, systems: dict[str, System], name: str, system: System):
    systems[name] = builder.AddNamedSystem(name, system)
    return systems[name]


def add_gbh(builder, scenario: Scenario, seeds: Seeds, scan: OutputPort,
            systems: dict[str, System]) -> GraspScorer:
    """The paper's three stages on ``scan``; returns the scorer (its ``ranked_grasps``)."""
    detector = _add(builder, systems, "hangability_detector",
                    HangabilityDetector(scenario.gbh, seed=seeds.sampling))
    # The hook grasps are checked with the gripper the scenario runs (the wedge's nose too).
    synthesizer = _add(builder, systems, "grasp_synthesizer",
                       GraspSynthesizer(scenario.gbh, GRIPPERS[scenario.gripper]))
    scorer = _add(builder, systems, "grasp_scorer", GraspScorer(scenario.gbh))
    builder.Connect(scan, detector.get_input_port())
    builder.Connect(detector.get_output_port(), synthesizer.get_input_port())
    builder.Connect(synthesizer.get_output_port(), scorer.get_input_port())
    return scorer


def _pinch_params(scenario: Scenario, prefer_hanging: bool):
    """The scenario's antipodal parameters; with ``prefer_hanging`` (the pinch tiers of
    ``gbh_plus`` and ``gbh_regrasp``, beyond the paper) ``prefer_hanging`` and ``side_pass``
    turned on."""
    return dataclasses.replace(scenario.antipodal, prefer_hanging=True, side_pass=True) \
        if prefer_hanging else scenario.antipodal


def add_antipodal(builder, scenario: Scenario, seeds: Seeds, scan: OutputPort,
                  systems: dict[str, System], *,
                  prefer_hanging: bool = False) -> AntipodalGraspSampler:
    """The antipodal sampler on ``scan``, keeping GbH's table clearance; ``prefer_hanging``:
    its pinches ranked first by how little the object swings about the pinch axis, and a
    second pass on the object's sides when the first finds nothing (beyond the paper,
    :attr:`~gbh_drake.core.params.AntipodalParams.prefer_hanging` and ``side_pass``)."""
    sampler = _add(builder, systems, "antipodal_sampler", AntipodalGraspSampler(
        _pinch_params(scenario, prefer_hanging), seed=seeds.grasps,
        ground_clearance=scenario.gbh.ground_clearance))
    builder.Connect(scan, sampler.get_input_port())
    return sampler


def add_scoop(builder, scenario: Scenario, systems: dict[str, System]) -> ScoopSynthesizer:
    """Scoops of the GbH detector's flat structures (the wedge gripper's)."""
    scoop = _add(builder, systems, "scoop_synthesizer",
                 ScoopSynthesizer(scenario.gbh, scenario.scoop))
    builder.Connect(systems["hangability_detector"].get_output_port(), scoop.get_input_port())
    return scoop


def add_regrasp(builder, scenario: Scenario, seeds: Seeds, systems: dict[str, System], *,
                prefer_hanging: bool = False) -> RegraspPlanner:
    """The resting poses in which GbH can hook the scanned object, each with its pinches
    (``prefer_hanging``: those that swing the object least where it is set down first)."""
    planner = _add(builder, systems, "regrasp_planner", RegraspPlanner(
        scenario.gbh, scenario.regrasp, seed=seeds.sampling,
        antipodal=_pinch_params(scenario, prefer_hanging), pinch_seed=seeds.grasps))
    builder.Connect(systems["hangability_detector"].get_output_port(), planner.get_input_port())
    return planner


def add_search(builder, systems: dict[str, System], scan: OutputPort, *, hook: bool,
               scenario: Scenario, fallback: bool = False) -> GraspSearchReport:
    """Why the method has no grasp (for the monitor): ``hook``, it runs GbH (``add_gbh`` first:
    its structures and candidates are counted); ``fallback``, an antipodal fallback was tried
    too. Each ``add_*`` adds its systems to ``builder`` under their names into ``systems``."""
    scoop = systems.get("scoop_synthesizer")
    report = _add(builder, systems, "grasp_search", GraspSearchReport(
        hook=hook, fallback=fallback, params=scenario.gbh, scoop=scoop is not None))
    builder.Connect(scan, report.GetInputPort("scan"))
    if hook:
        builder.Connect(systems["hangability_detector"].get_output_port(),
                        report.GetInputPort("hanging_structures"))
        builder.Connect(systems["grasp_synthesizer"].get_output_port(),
                        report.GetInputPort("grasp_candidates"))
    if scoop is not None:
        builder.Connect(scoop.GetOutputPort("scoops"), report.GetInputPort("scoops"))
    return report


def _gbh_source(systems: dict[str, System], report, *tiers: GraspTier) -> GraspSource:
    ranked = GraspTier(Tier.GRASPS, systems["grasp_scorer"].get_output_port())
    return GraspSource(
        tiers=[ranked, *tiers], search=report.get_output_port(),
        hanging_structures=systems["hangability_detector"].get_output_port(),
        candidates=systems["grasp_synthesizer"].get_output_port(), systems=systems)


class Gbh(GraspMethod):
    """Grasping by Hanging (the paper): hanging structures, hook grasps, the ranked best."""

    spec = method_spec("gbh")

    def add_systems(self, builder, *, scenario, seeds, scan) -> GraspSource:
        systems: dict[str, System] = {}
        add_gbh(builder, scenario, seeds, scan, systems)
        return _gbh_source(systems, add_search(builder, systems, scan, hook=True, scenario=scenario))


class Antipodal(GraspMethod):
    """The learning-free antipodal baseline: two straight rods (the bar folded)."""

    spec = method_spec("antipodal")

    def add_systems(self, builder, *, scenario, seeds, scan) -> GraspSource:
        systems: dict[str, System] = {}
        sampler = add_antipodal(builder, scenario, seeds, scan, systems)
        report = add_search(builder, systems, scan, hook=False, scenario=scenario)
        return GraspSource(tiers=[GraspTier(Tier.GRASPS, sampler.get_output_port())],
                           search=report.get_output_port(), systems=systems)


class GbhFallback(GraspMethod):
    """GbH first; when it offers nothing reachable, the best antipodal grasp, bar folded."""

    spec = method_spec("gbh_fallback")

    def add_systems(self, builder, *, scenario, seeds, scan) -> GraspSource:
        systems: dict[str, System] = {}
        add_gbh(builder, scenario, seeds, scan, systems)
        sampler = add_antipodal(builder, scenario, seeds, scan, systems)
        report = add_search(builder, systems, scan, hook=True, scenario=scenario,
                             fallback=True)
        return _gbh_source(systems, report, GraspTier(Tier.FALLBACK, sampler.get_output_port()))


def _scoop_tiers(scoop: System) -> tuple[GraspTier, GraspTier]:
    """The scoop tier and the tall scoops' tier of a ``ScoopSynthesizer``."""
    return (GraspTier(Tier.SCOOP, scoop.GetOutputPort("scoop_grasps")),
            GraspTier(Tier.TALL_SCOOP, scoop.GetOutputPort("tall_scoop_grasps")))


class GbhScoop(GraspMethod):
    """GbH first; when it offers nothing reachable, a scoop of material lying flat on the table,
    then a tall scoop (beyond the paper; the wedge gripper, ``robot.gripper: wedge``)."""

    spec = method_spec("gbh_scoop")

    def add_systems(self, builder, *, scenario, seeds, scan) -> GraspSource:
        systems: dict[str, System] = {}
        add_gbh(builder, scenario, seeds, scan, systems)
        scoop = add_scoop(builder, scenario, systems)
        report = add_search(builder, systems, scan, hook=True, scenario=scenario)
        return _gbh_source(systems, report, *_scoop_tiers(scoop))


class GbhRegrasp(GraspMethod):
    """GbH first; when it finds a structure but no hook grasp can be executed, a pinch (the bar
    folded) sets the object down in a resting pose in which GbH can hook it, the object is
    scanned again and GbH hooks it there (beyond the paper). Only a hook carries the object."""

    spec = method_spec("gbh_regrasp")

    def add_systems(self, builder, *, scenario, seeds, scan) -> GraspSource:
        systems: dict[str, System] = {}
        add_gbh(builder, scenario, seeds, scan, systems)
        # Its pinches turn the object: those that let it swing least about them first.
        sampler = add_antipodal(builder, scenario, seeds, scan, systems, prefer_hanging=True)
        planner = add_regrasp(builder, scenario, seeds, systems, prefer_hanging=True)
        report = add_search(builder, systems, scan, hook=True, scenario=scenario)
        return _gbh_source(systems, report, GraspTier(Tier.REGRASP, sampler.get_output_port(),
                                                      poses=planner.get_output_port()))


class GbhCompleted(GraspMethod):
    """GbH on the scan completed by shape completion (beyond the paper; the paper's Sec. 4
    remedy for one view): a ``ShapeCompleter`` between the Scanner and GbH's detector. The
    pick plans on the scan as taken."""

    spec = method_spec("gbh_completed")

    def add_systems(self, builder, *, scenario, seeds, scan) -> GraspSource:
        systems: dict[str, System] = {}
        completer = _add(builder, systems, "shape_completer",
                         ShapeCompleter(scenario.completion, seed=seeds.sampling))
        builder.Connect(scan, completer.get_input_port())
        add_gbh(builder, scenario, seeds, completer.get_output_port(), systems)
        return _gbh_source(systems, add_search(builder, systems, scan, hook=True,
                                               scenario=scenario))


class GbhPlus(GraspMethod):
    """Everything in one (beyond the paper): GbH; then a scoop of material lying flat; then a
    regrasp into a pose GbH can hook; then a tall scoop (material taller than the wedge); then
    the antipodal fallback, bar folded; and, when a lift comes away empty, a re-scan and one
    more try (the grasps near the failed one skipped)."""

    spec = method_spec("gbh_plus")

    def add_systems(self, builder, *, scenario, seeds, scan) -> GraspSource:
        systems: dict[str, System] = {}
        add_gbh(builder, scenario, seeds, scan, systems)
        scoop = add_scoop(builder, scenario, systems)
        # Its pinches (the regrasp's and the fallback's) pivot about their axis: those that let
        # the object swing least first.
        sampler = add_antipodal(builder, scenario, seeds, scan, systems, prefer_hanging=True)
        planner = add_regrasp(builder, scenario, seeds, systems, prefer_hanging=True)
        report = add_search(builder, systems, scan, hook=True, scenario=scenario,
                             fallback=True)
        scoops, tall_scoops = _scoop_tiers(scoop)
        return _gbh_source(systems, report, scoops,
                           GraspTier(Tier.REGRASP, sampler.get_output_port(),
                                     poses=planner.get_output_port()),
                           tall_scoops,
                           GraspTier(Tier.FALLBACK, sampler.get_output_port()))


class GivenGrasps(GraspMethod):
    """Executes ``grasps`` (each with ``X_WG`` and ``kind``), through the diagram of ``method``
    (default GbH: its scan analysis still runs and is recorded), instead of its own grasps: a
    grasp of your own through the same planner, physics and judge (one tier: these grasps).
    The method's own tiers stay in the source (``method_tiers``); the given grasps come from a
    :class:`~gbh_drake.systems.grasp_list.GraspList` (``systems["given_grasps"]``), which a
    context may hold others in."""

    def __init__(self, grasps: Sequence, method: GraspMethod | None = None):
        self.method = method or Gbh()
        self.grasps = list(grasps)
        self.spec = dataclasses.replace(self.method.spec, tiers=(Tier.GRASPS,))

    def add_systems(self, builder, *, scenario, seeds, scan) -> GraspSource:
        source = self.method.add_systems(builder, scenario=scenario, seeds=seeds, scan=scan)
        given = _add(builder, source.systems, "given_grasps", GraspList(self.grasps))
        source.method_tiers, source.tiers = source.tiers, [
            GraspTier(Tier.GRASPS, given.get_output_port())]
        return source


_REGISTRY: dict[str, GraspMethod] = {}


def register_method(method: GraspMethod) -> GraspMethod:
    """Adds ``method`` to the registry under its spec's name, and its spec to the specs (a
    scenario can then name it: :func:`gbh_drake.method_spec.register_spec`), replacing one of
    the same name; returns it."""
    spec = getattr(method, "spec", None)
    if not isinstance(spec, MethodSpec):
        raise TypeError(f"{type(method).__name__} has no spec (a MethodSpec)")
    register_spec(spec)
    _REGISTRY[spec.name] = method
    return method


def method_named(name: str) -> GraspMethod:
    """The registered method called ``name``; ``KeyError`` naming the known ones."""
    try:
        return _REGISTRY[name]
    except KeyError:
        raise KeyError(f"no grasp method {name!r} (known: {', '.join(_REGISTRY)})") from None


for _method in (Gbh(), Antipodal(), GbhFallback(), GbhScoop(), GbhRegrasp(), GbhPlus(),
                GbhCompleted()):
    register_method(_method)
