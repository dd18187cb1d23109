"""The studio's trial, step by step: place the object and let it settle, scan, detect, look at
one grasp, execute it, go back to the settled object. No page here (:mod:`.controls` draws it).

One trial diagram, :func:`gbh_drake.trial.build_trial`'s, of the studio's scenario
(:func:`.choices.scenario_for`) with the scenario's own grasp method behind
:class:`~gbh_drake.methods.GivenGrasps`: the Scanner, the method's systems (GbH's detector,
synthesizer and scorer, the sampler...), the pick-and-carry machine and the monitor are those
of ``gbh run``; what differs is that the machine executes the grasp chosen here (the given
grasps, held in the context) instead of trying the method's tiers itself. One ``Simulator``
advances it: to the end of settling, then until the Scanner has taken its scan, then, on
Execute, until the machine has finished and the object had ``AFTERMATH`` seconds to come to
rest. The settled and the scanned states are kept (context copies) for Reset.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np
from pydrake.geometry import Meshcat, MeshcatVisualizer
from pydrake.systems.analysis import ApplySimulatorConfig, InitializeParams, Simulator
from pydrake.systems.framework import EventStatus

from gbh_drake.method_spec import Tier
from gbh_drake.methods import GivenGrasps, method_named
from gbh_drake.studio.choices import DROP, Choices, ObjectChoice, overrides, scenario_for
from gbh_drake.trial import Trial, TrialRecord, build_trial, finish_trial, trial_duration

#: Simulated seconds the Scan step waits at most for the Scanner (it scans once the object is
#: still, ``ScanConfig.still_max_wait`` after the settle time at the latest).
SCAN_WAIT = 5.0


@dataclass
class Clock:
    """Wall and CPU seconds of one step (the machine is shared: CPU beside wall)."""

    wall: float = 0.0
    cpu: float = 0.0

    @staticmethod
    def start() -> tuple[float, float]:
        return time.perf_counter(), time.process_time()

    @staticmethod
    def since(start: tuple[float, float]) -> Clock:
        return Clock(time.perf_counter() - start[0], time.process_time() - start[1])

    def __str__(self) -> str:
        return f"{self.wall:.2f} s ({self.cpu:.2f} s CPU)"


@dataclass
class Offered:
    """One grasp the rank slider shows: a grasp the method offered (its ``tier`` and ``rank``
    in it), or, when it offered none, a refused candidate (``rule``: the rule that removed
    it). ``grasp`` has ``X_WG`` and ``kind`` (what Execute hands the machine); ``shown``: the
    ranked :class:`~gbh_drake.scan_grasps.result.Grasp` (waypoints, score terms) for GbH's."""

    tier: Tier | None
    rank: int
    grasp: object
    shown: object = None
    rule: str = ""
    words: str = ""


@dataclass
class Detection:
    """What Detect found (in W): the :class:`~gbh_drake.scan_grasps.result.GraspsResult` of the
    trial's systems, the counted candidates and what each collision rule removed, and the
    grasps the rank slider runs over."""

    result: object
    candidates: list
    rejections: object
    offered: list[Offered]
    clock: Clock = field(default_factory=Clock)


class Session:
    """The studio's trial (see the module docstring). ``base``: the scenario the choices go
    over; ``objects``: what the object control chooses from; ``meshcat``: where the station is
    drawn live (None: nowhere)."""

    def __init__(self, base, objects: list[ObjectChoice], *, meshcat: Meshcat | None = None,
                 choices: Choices | None = None):
        self.base, self.objects, self.meshcat = base, list(objects), meshcat
        self._assets: dict[int, object] = {}
        self._rests: dict[int, object] = {}
        self.choices = choices or Choices()
        if choices is None:
            self.choices = default_choices(base, self.rests(0))
        self.trial: Trial | None = None
        self.simulator: Simulator | None = None
        self.scenario = None
        self.overrides = ""
        self.stage = ""
        """``settled``, ``scanned``, ``detected`` or ``executed`` ("" before anything)."""
        self._saved: dict[str, object] = {}
        self.scan = None
        self.detection: Detection | None = None
        self.record: TrialRecord | None = None
        self._setup = None
        self._plans: dict[int, object] = {}
        self.execute_from = 0.0
        """Simulated s at which the last Execute started (its scan's time)."""

    # ---- the object ---------------------------------------------------------------------------
    def asset(self, index: int | None = None):
        """The chosen object's model (kept per object)."""
        from gbh_drake.modeling.object_asset import load_object_asset

        index = self.choices.object if index is None else index
        if index not in self._assets:
            self._assets[index] = load_object_asset(self.objects[index].config,
                                                    self.base.directory)
        return self._assets[index]

    def rests(self, index: int | None = None):
        """The chosen object's stable resting orientations, most probable first."""
        from gbh_drake.objects import stable_poses

        index = self.choices.object if index is None else index
        if index not in self._rests:
            asset = self.asset(index)
            self._rests[index] = stable_poses(asset.mesh, asset.com_O)
        return self._rests[index]

    def modelled_rest(self, index: int | None = None) -> int:
        """The index of the chosen object's stable rest nearest to its model's orientation (a
        built-in object's is upright)."""
        rests = self.rests(index)
        nearest = rests.nearest()
        return next(i for i, p in enumerate(rests.poses) if p is nearest)

    def scenario_now(self):
        """The scenario of the controls' values (:func:`.choices.scenario_for`); also sets
        :attr:`overrides` (its ``gbh run --set`` text)."""
        choice, c = self.objects[self.choices.object], self.choices
        R_rest = None
        if c.rest != DROP:
            poses = self.rests().poses
            R_rest = np.asarray(poses[min(c.rest, len(poses) - 1)].R, dtype=float)
        self.overrides = overrides(choice, c, R_rest)
        return scenario_for(self.base, choice, c, R_rest)

    # ---- the steps ------------------------------------------------------------------------------
    def place(self) -> Clock:
        """Builds the trial of the controls' values (when they changed since the last build)
        and lets the object settle (to the settle time, before the scan); else goes back to
        the settled object."""
        start = Clock.start()
        scenario = self.scenario_now()
        if self.trial is None or self.overrides != self._built:
            method = GivenGrasps([], method_named(scenario.grasp_method))
            self.trial = build_trial(scenario, meshcat=self.meshcat, asset=self.asset(),
                                     method=method, draw_grasps=False)
            self.scenario, self._built = scenario, self.overrides
            self.simulator = Simulator(self.trial.diagram)
            ApplySimulatorConfig(scenario.simulator_config, self.simulator)
            self.simulator.Initialize()
            self.simulator.AdvanceTo(scenario.settle_time)
            self._saved = {"settled": self.simulator.get_context().Clone()}
        self._restore("settled")
        self._saved = {"settled": self._saved["settled"]}  # a scan comes anew
        self.scan = self.detection = self.record = None
        self._setup, self._plans = None, {}
        self.stage = "settled"
        return Clock.since(start)

    def take_scan(self) -> Clock:
        """Advances until the Scanner has taken its scan (placing the object first if
        needed)."""
        if not self.stage:
            self.place()
        if self.stage != "settled" and "scanned" in self._saved:
            self._restore("scanned")
            self.stage = "scanned" if self.detection is None else "detected"
            return Clock()
        start = Clock.start()
        port = self.trial.scanner.GetOutputPort("mesh_W")
        scanner = self.trial.scanner

        def scanned(context):
            from gbh_drake.systems.scanner import scan_pending

            if scan_pending(port.Eval(scanner.GetMyContextFromRoot(context))):
                return EventStatus.Succeeded()
            return EventStatus.ReachedTermination(scanner, "scanned")

        self.simulator.set_monitor(scanned)
        try:
            self.simulator.AdvanceTo(self.scenario.settle_time + SCAN_WAIT)
        finally:
            self.simulator.clear_monitor()
        self.scan = self._value(port)
        self._saved["scanned"] = self.simulator.get_context().Clone()
        self.stage = "scanned"
        return Clock.since(start)

    def detect(self) -> Detection:
        """Runs the method's systems on the scan (scanning first if needed): the hanging
        structures, the candidates and the rules that removed them, the ranked grasps."""
        from gbh_drake.core.rejections import (
            RULES,
            closest_rejected,
            count_rejections,
            refusal_words,
            removed_by,
        )
        from gbh_drake.scan_grasps.result import N_REFUSED
        from gbh_drake.scan_grasps.run_export import grasps_result

        if self.stage in ("", "settled"):
            self.take_scan()
        if self.detection is not None:
            self.stage = "detected" if self.stage != "executed" else self.stage
            return self.detection
        start = Clock.start()
        trial, context = self.trial, self.simulator.get_context()
        source = trial.source
        result = grasps_result(trial, context, self.scan, np.eye(4))
        candidates = list(self._value(source.candidates) or []) \
            if source.candidates is not None else []
        rejections = count_rejections(candidates, self.scenario.gbh)
        offered = []
        for tier in source.method_tiers or source.tiers:
            if tier.tier is Tier.REGRASP:  # a procedure, not a grasp to show
                continue
            grasps = list(self._value(tier.grasps) or [])
            for rank, g in enumerate(grasps):
                shown = result.grasps[rank] if tier.tier is Tier.GRASPS and \
                    source.candidates is not None and rank < len(result.grasps) else None
                offered.append(Offered(tier.tier, rank, g, shown))
        if not offered and candidates:  # the refused ones that came closest, with their rule
            gbh = self.scenario.gbh
            rule, _ = removed_by(candidates, gbh)
            index = {id(g): k for k, g in enumerate(candidates)}
            for k, g in enumerate(closest_rejected(candidates, gbh, N_REFUSED)):
                name = RULES[rule[index[id(g)]]]
                offered.append(Offered(None, k, g, None, name, refusal_words(g, name, gbh)))
        self.detection = Detection(result, candidates, rejections, offered, Clock.since(start))
        self.stage = "detected"
        return self.detection

    def nearest_refused(self, index: int, k: int = 3) -> list:
        """The ``k`` refused candidates nearest to offered grasp ``index``, with their rules."""
        from gbh_drake.core.rejections import nearest_refused

        offered = self.detection.offered[index]
        if offered.rule:  # itself a refused one: its neighbours among the refused
            k += 1
        near = nearest_refused(self.detection.candidates, self.scenario.gbh,
                               offered.grasp.X_WG, k)
        return [r for r in near if r.candidate is not offered.grasp][:k - (1 if offered.rule
                                                                            else 0)]

    def plan(self, index: int):
        """Whether the planner would execute offered grasp ``index`` from the robot as it
        stands now: its :class:`~gbh_drake.planning.pick.PickPlan`, or the
        :class:`~gbh_drake.planning.pick.Refusal` that says why not (kept per grasp)."""
        if index not in self._plans:
            pick = self.trial.pick
            context = pick.GetMyContextFromRoot(self._saved.get("scanned",
                                                                self.simulator.get_context()))
            if self._setup is None:
                self._setup = pick.pick_setup(context)
            offered = self.detection.offered[index]
            self._plans[index] = pick.plan_grasp(context, offered.grasp, offered.rank,
                                                 self._setup)
        return self._plans[index]

    def execute(self, index: int, *, stop=None, max_time: float | None = None
                ) -> TrialRecord:
        """Simulates the pick of offered grasp ``index`` from the scanned state, live, until
        the machine has finished and the object had ``AFTERMATH`` seconds (at most
        :func:`~gbh_drake.trial.trial_duration`, the scenario's ``max_time`` per pick the
        machine may start; ``stop()`` true ends it sooner); returns the trial's record,
        the monitor's verdict in it."""
        self.detect()
        self._restore("scanned")
        offered = self.detection.offered[index]
        given = self.trial.source.systems["given_grasps"]
        context = self.simulator.get_mutable_context()
        given.set_grasps(given.GetMyMutableContextFromRoot(context), [offered.grasp])
        self.execute_from = context.get_time()
        self.record = finish_trial(self.trial, self.simulator,
                                   max_time or trial_duration(self.trial), stop=stop)
        self.stage = "executed"
        return self.record

    def reset(self) -> Clock:
        """Back to the settled object: the scanned state when there is one (the scan and what
        was detected on it stay), else the settled one; builds anew when the controls
        changed what is placed."""
        start = Clock.start()
        if self.changed:
            return self.place()
        if "scanned" in self._saved:
            self._restore("scanned")
            self.stage = "detected" if self.detection is not None else "scanned"
        else:
            self._restore("settled")
            self.stage = "settled"
        self.record = None
        return Clock.since(start)

    @property
    def changed(self) -> bool:
        """Whether the controls' values differ from what is placed."""
        return self.trial is None or self._overrides_now() != self._built

    def _overrides_now(self) -> str:
        saved = self.overrides
        try:
            self.scenario_now()
            return self.overrides
        finally:
            self.overrides = saved

    # ---- helpers ------------------------------------------------------------------------------
    def _restore(self, name: str) -> None:
        """Puts the simulator back in the saved state ``name`` and redraws the station. (The
        systems' initialization events do not run again: the machine, the hand driver keep the
        saved state.)"""
        context = self.simulator.get_mutable_context()
        context.SetTimeStateAndParametersFrom(self._saved[name])
        self.simulator.Initialize(InitializeParams(suppress_initialization_events=True))
        self.publish()

    def publish(self) -> None:
        """Redraws the station's Meshcat visualisers in the current state."""
        if self.meshcat is None:
            return
        context = self.simulator.get_context()
        for system in self.trial.station.GetSystems():
            if isinstance(system, MeshcatVisualizer):
                system.ForcedPublish(system.GetMyContextFromRoot(context))

    def _value(self, port):
        return port.Eval(port.get_system().GetMyContextFromRoot(self.simulator.get_context()))

    _built = ""


def default_choices(base, rests=None) -> Choices:
    """The controls' first values: the scenario's object where its pose puts it (x, y, yaw;
    the stable rest nearest to its orientation, from ``rests``, its
    :class:`~gbh_drake.objects.stability.StablePoses`), or, for a random pose, in the middle of
    its ranges, its rest drawn from the seed (:data:`DROP`); the scenario's views, method,
    preset and seed."""
    o = base.object
    x, y, yaw, rest = 0.55, 0.0, 0.0, DROP
    if o.random_pose is not None:
        x, y = float(np.mean(o.random_pose.x)), float(np.mean(o.random_pose.y))
        yaw = float(np.mean(o.random_pose.yaw_deg))
    elif o.pose.IsDeterministic():
        from pydrake.math import RollPitchYaw

        X = o.pose.GetDeterministicValue()
        x, y = (float(v) for v in X.translation()[:2])
        yaw = float(np.degrees(RollPitchYaw(X.rotation()).yaw_angle()))
        if rests is not None:
            down_O = X.rotation().inverse().multiply([0.0, 0.0, -1.0])
            rest = next(i for i, p in enumerate(rests.poses) if p is rests.nearest(down_O))
    return Choices(object=0, x=x, y=y, yaw_deg=yaw, rest=rest, views=base.scan.num_views,
                   method=base.grasp_method, preset=base.gbh.preset, seed=int(base.seed))

