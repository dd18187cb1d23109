"""The ``PickAndCarry`` system: a pick-and-place state machine for the hook gripper.

In the style of the manipulation course's clutter-clearing ``Planner``: the mode lives in
abstract state beside the trajectory it executes, one periodic unrestricted update reads mode,
time and the measured robot state and switches modes, and every output is a pure function of
state and time. Modes, in order::

    SETTLE -> PLAN -> APPROACH -> INSERT -> CLOSE -> LIFT -> CARRY -> HOLD -> CAGE_TEST
           -> LOWER -> RELEASE -> RETREAT -> DONE

(``PickConfig.set_down`` false: CAGE_TEST -> DONE, the object still in the hand)

and, for a regrasp (beyond the paper), before the pick::

    PLAN -> REGRASP_APPROACH -> REGRASP_INSERT -> REGRASP_CLOSE -> REGRASP_LIFT -> REGRASP_TURN
         -> REGRASP_LOWER -> REGRASP_RELEASE -> REGRASP_RETREAT -> REGRASP_HOME -> RESCAN -> PLAN

and, for a retry after a lift that came away empty (beyond the paper)::

    LIFT -> RETRY_RELEASE -> RETRY_HOME -> RESCAN -> PLAN

PLAN reads the method's grasps tier by tier (:class:`~gbh_drake.method_spec.Tier`, in the
order the machine was given: the method's own ``grasps``, then, beyond the paper,
``scoop_grasps`` (the wedge bar slid under material lying on the table), a regrasp,
``tall_scoop_grasps`` (the same under taller material), then ``fallback_grasps`` (an
antipodal grasp with the bar folded); evaluating a tier runs the grasp pipeline on the scan
once) and tries them in order from the measured configuration
(:func:`gbh_drake.planning.choice.choose` over :func:`gbh_drake.planning.pick.plan_pick`),
keeping each refusal's reason. When nothing can be planned the machine ends in NO_GRASP or
NO_REACHABLE_GRASP. A scoop's
INSERT goes on down past the grasp pose until the table pushes the hand up with the scoop's
``press_force`` (the wrist load, as Franka senses it; at most ``press_depth``) and it closes
from there, at table level. When no grasp of ``grasps`` or ``scoop_grasps`` can be planned and
the machine has a regrasp tier (beyond the paper: its ``regrasp_poses`` and ``regrasp_grasps``
inputs), it
plans a regrasp (:func:`gbh_drake.planning.regrasp.plan_regrasp`): it picks the object with one
of ``regrasp_grasps`` (a pinch, the bar folded), turns it into the first of ``regrasp_poses`` the
arm reaches, lowers it until the hand's load drops, lets go, backs off, goes home, asks the
Scanner for a new scan (its ``scan_request`` output) and, once it has it, plans again from the
new scan's grasps; at most ``RegraspParams.max_regrasps`` times. With ``max_retries`` > 0
(beyond the paper), a LIFT that did not add :data:`EMPTY_LOAD` to the hand's vertical load
since the approach came away empty: the fingers open, the arm goes home, the Scanner is asked
for a new scan of where the object was, and PLAN plans anew, skipping the grasps of the hanging
structure that failed (without a structure: those of the same kind where it was; both within
:data:`TRIED_RADIUS`), and when that leaves nothing to plan, going back over them and skipping
only the failed pose's neighbours (:data:`TRIED_ANGLE_DEG`); the failed attempts are kept in
the status (:class:`Attempt`). Once
the retries are used up, a further empty lift goes on to the tiers after the failed grasp's
(:func:`~gbh_drake.planning.choice.tiers_after_empty_lifts`: a fallback pinch still follows
two empty hooks), until no tier is left. CLOSE drives the
fingers toward each other with the hand's grasp force until they stop; CAGE_TEST relaxes the
squeeze to ``cage_test_force`` (a caged object keeps hanging on the closed loop, a pinched one
slides out: the :class:`~gbh_drake.systems.cage_monitor.CageMonitor` judges); RELEASE opens the
fingers over the place position.

The set-down reads the hand's vertical load as it has since the approach, less what the hand's
own mass takes to follow the arm's commanded vertical acceleration. LOWER counts the object as
down only once that load has stayed within a near-zero band (:func:`unloaded_band`: a fraction
of the load carried while held still, or twice its noise then) for ``unloaded_dwell``; a load
that merely fell lowers on (to the planned depth at most), one pressing the object down goes
on down by ``unload_depth`` at most. RELEASE and RETREAT watch the load: when it rises above
the band (the bar is lifting the object again), the hand stops, goes back down (stopping when
it presses), lets the fingers open and withdraws the bar along the hole
(:func:`~gbh_drake.planning.pick.withdraw_path`) before going up: at most ``relift_tries``
times; once more, it goes back down, opens and stops there (the object left standing in the
open hand, never carried off). What it sensed and did is in the status's ``set_down_notes``.
None of it runs before the cage test: the verdict is the same.
"""

from __future__ import annotations

import copy
import math
import time
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
from pydrake.common.value import AbstractValue
from pydrake.math import RigidTransform
from pydrake.multibody.parsing import ModelDirective
from pydrake.systems.framework import BasicVector, LeafSystem

from gbh_drake.core.gripper import BAR_DEPLOYED, BAR_RETRACTED, HOOK_GRIPPER, HookGripperGeometry
from gbh_drake.core.params import RegraspParams, ScoopParams
from gbh_drake.core.pick_config import PickConfig
from gbh_drake.core.results import GraspKind
from gbh_drake.messages import FINAL_MODES, Attempt, Mode, PickStatus
from gbh_drake.method_spec import Tier
from gbh_drake.modeling.names import TABLE
from gbh_drake.perception.scan import ScanResult
from gbh_drake.perception.unseen import scan_unseen
from gbh_drake.planning.choice import Offer, at_failed_pose, choose, tiers_after_empty_lifts
from gbh_drake.planning.model import HandPose, PlanningModel, parse_robot
from gbh_drake.planning.pick import (
    PickPlan,
    PickSetup,
    Refusal,
    plan_pick,
    reach_refusal,
    release_path,
    withdraw_path,
    withdrawn_along,
)
from gbh_drake.planning.regrasp import RegraspPlan, plan_regrasp
from gbh_drake.planning.trajectories import (
    insert_path,
    joint_path,
    linear_move,
    polyline_path,
    sample,
)
from gbh_drake.scenario.schema import HandConfig
from gbh_drake.systems.scanner import no_scan, scan_pending
from gbh_drake.systems.stage import CopiedShallowly

#: Seconds the machine waits after a motion's trajectory ends before the next mode.
DWELL = 0.1
#: Below this hand load (N) lowering cannot sense the set-down and goes to the planned depth.
MIN_SENSED_LOAD = 0.3
#: A lift that adds less than this (N) to the hand's vertical load since the approach came away
#: empty (about 20 g; the object set's lightest, a key ring, weighs 45 g).
EMPTY_LOAD = 0.2
#: m: on a retry, grasps of a hanging structure whose centre lies this close to the centre of
#: the structure a failed grasp hooked, and grasps without a structure whose gripper origin lies
#: this close to a failed one's (same kind), are skipped: what came away empty from an object
#: that barely moved would come away empty again.
TRIED_RADIUS = 0.02
#: s: how long the hand's load must stay below the near-zero band before the hand counts as
#: pressing the object down (a hanging object cannot push the hand up: no swing does that).
PRESS_DWELL = 0.02
#: N: the set-down's near-zero band is never narrower than this (:func:`unloaded_band`).
MIN_BAND = 0.2
#: deg: when a retry's plan finds nothing else, it goes back over the skipped grasps and skips
#: only those of a failed grasp's kind within :data:`TRIED_RADIUS` of its origin and turned by
#: less than this from it: the failed pose and its neighbouring contacts' (GbH's turned
#: approaches land on contacts 10 deg apart), not the structure's other sides.
TRIED_ANGLE_DEG = 20.0


@dataclass
class _State(CopiedShallowly):
    status: PickStatus = field(default_factory=PickStatus)
    arm: object = None
    """The arm's current ``PiecewisePolynomial`` (None: hold ``q_hold``)."""
    arm_dot: object = None
    """Its time derivative."""
    q_hold: np.ndarray = field(default_factory=lambda: np.zeros(7))
    command: np.ndarray = field(default_factory=lambda: np.zeros(3))
    """Hand command [q_target (m), force (N), bar angle (rad)]."""
    until: float = 0.0
    """The current mode's earliest end time (s)."""
    load: float = 0.0
    """The hand's vertical load (N) while the object was held still over the place."""
    release: dict | None = None
    """The release's configurations (``place``, ``opened``, ``down``, ``slide``, ``retreat``)
    when the object was set down before the planned place pose."""
    q_home: np.ndarray = field(default_factory=lambda: np.zeros(7))
    """The arm where it started (where it goes before a re-scan)."""
    load_free: float = 0.0
    """The hand's vertical load (N) at the end of the approach, before it touched the object."""
    scans_asked: int = 0
    """Re-scans asked for (regrasps and retries)."""
    scan_request: np.ndarray = field(default_factory=lambda: np.zeros(4))
    """The ``scan_request`` output: [n, x, y, z] (n: scans asked for since the first)."""
    hold_loads: tuple[float, float, int] = (0.0, 0.0, 0)
    """The hand's vertical load (N) during HOLD: (sum, sum of squares, samples)."""
    band: float = 0.0
    """N: the set-down's near-zero band (:func:`unloaded_band`), fixed after the cage test."""
    side: int = 1
    """Which side of the band the load was last on (:func:`load_side`) ..."""
    since: float = 0.0
    """... since when (s)."""
    relifts: int = 0
    """How often the bar lifted the object again while letting go (and the hand withdrew)."""
    stopped: bool = False
    """Whether the current RELEASE or RETREAT already stopped going down (the hand pressed)."""
    left_in_hand: bool = False
    """Whether the hand, its ``relift_tries`` used, stopped where it is (the object left
    standing, the open hand round it) rather than carry the object off."""


def _check_arguments(*, config, hand, settle_time, period, ground_clearance, max_retries,
                     scan_height) -> None:
    """:class:`PickAndCarry`'s arguments, each named in a ``TypeError``/``ValueError`` (a
    diagram of one's own builds it by hand, without a scenario's checks)."""
    if not isinstance(config, PickConfig):
        raise TypeError(f"PickAndCarry: config must be a PickConfig, got {type(config).__name__}")
    if not isinstance(hand, HandConfig):
        raise TypeError(f"PickAndCarry: hand must be a HandConfig, got {type(hand).__name__}")
    for name, value, low in (("settle_time", settle_time, 0.0), ("period", period, None),
                             ("ground_clearance", ground_clearance, 0.0),
                             ("scan_height", scan_height, None)):
        if isinstance(value, bool) or not isinstance(value, (int, float)) \
                or not math.isfinite(value):
            raise TypeError(f"PickAndCarry: {name} must be a finite number (s or m), got {value!r}")
        if (low is not None and value < low) or (name == "period" and value <= 0):
            raise ValueError(f"PickAndCarry: {name} must be "
                             f"{'positive' if name == 'period' else 'at least 0'}, got {value!r}")
    if isinstance(max_retries, bool) or not isinstance(max_retries, (int, np.integer)) \
            or max_retries < 0:
        raise ValueError(f"PickAndCarry: max_retries must be an integer >= 0, got {max_retries!r}")


class PickAndCarry(LeafSystem):
    """Plans and executes one pick (see the module docstring).

    .. pydrake_system::

        name: PickAndCarry
        input_ports:
        - grasps
        - scoop_grasps (a scoop tier)
        - tall_scoop_grasps (a tall scoop tier)
        - regrasp_poses (a regrasp tier)
        - regrasp_grasps (a regrasp tier)
        - fallback_grasps (a fallback tier)
        - scan
        - panda.state
        - hook_gripper.state
        - hook_gripper.load
        output_ports:
        - panda.desired_state
        - hook_gripper.command
        - status
        - scan_request

    One input per grasp tier it was given (``tiers``, default the ``grasps`` alone), tried in
    that order; a tier's input left unconnected is passed over. ``grasps``, ``scoop_grasps``,
    ``tall_scoop_grasps``, ``fallback_grasps``: lists of grasps, best first, each with ``X_WG``
    (4, 4, the open gripper's pose in W) and ``kind`` (``parallel``,
    ``vertical``, ``scoop`` or ``antipodal``; an antipodal grasp is executed with the bar
    folded). ``regrasp_poses`` (``list[RegraspPose]``, the
    :class:`~gbh_drake.systems.regrasp_planner.RegraspPlanner`'s) and ``regrasp_grasps`` (pinches,
    bar folded): a regrasp (module docstring). ``scan_request`` (4): [n, x, y, z], the n-th
    re-scan asked for and where (connect it to the Scanner's ``scan_request``). ``scan``: the
    :class:`~gbh_drake.perception.scan.ScanResult` (its points set the lift height and its convex
    hull is an obstacle for the transfer). ``panda.state`` (14) and ``hook_gripper.state`` (6):
    the measured robot; ``hook_gripper.load`` (3, N, W): the force the flange exerts on the
    hand (the object's weight while it hangs; lowering stops when it drops).
    ``panda.desired_state`` (14): [q, v] for the arm's joint controllers;
    ``hook_gripper.command`` (3) for the :class:`~gbh_drake.systems.hand_driver.HandDriver`;
    ``status``: a :class:`PickStatus`.
    """

    def __init__(self, directives: Sequence[ModelDirective], config: PickConfig,
                 hand: HandConfig, *, settle_time: float, ground_clearance: float = 0.003,
                 seed: int = 0, bar_angle: float = BAR_DEPLOYED, period: float = 0.01,
                 scoop: ScoopParams | None = None, regrasp: RegraspParams | None = None,
                 scan_height: float = 0.06, max_retries: int = 0,
                 tiers: Sequence[Tier] = (Tier.GRASPS,),
                 gripper: HookGripperGeometry = HOOK_GRIPPER):
        """``directives``: the scenario's fixed models (the planning model is built from them);
        ``settle_time`` (s): when planning starts (the scan is taken then); ``ground_clearance``
        (m): the clearance grasps keep from the table, kept by the segments near the grasp too
        (less the IK's 1 mm tolerance); ``seed``: the planner's seed; ``bar_angle`` (rad): the
        bar's angle before a grasp is chosen; ``period`` (s): how often the machine updates;
        ``scoop``: how a scoop presses on the table (its ``press_force`` and ``press_depth``);
        ``regrasp``: how often the object may be set down anew (``max_regrasps``) and how
        many pinches are planned for per resting pose; ``scan_height`` (m): the height of a
        re-scan's target (the scenario's ``scan_target`` z); ``max_retries``: how often a lift
        that came away empty is followed by a re-scan and a new plan through every tier (0:
        never, the paper; once they are used up, the tiers after the failed one's are tried);
        ``tiers``: the grasp tiers to try, in order (a method's
        :attr:`~gbh_drake.method_spec.MethodSpec.tiers`; the first must be ``grasps``);
        ``gripper``: the hook gripper's geometry (the variant the station runs)."""
        super().__init__()
        _check_arguments(config=config, hand=hand, settle_time=settle_time, period=period,
                         ground_clearance=ground_clearance, max_retries=max_retries,
                         scan_height=scan_height)
        self._directives = list(directives)
        self._config = config
        self._hand = hand
        self._scoop = scoop or ScoopParams()
        self._regrasp = regrasp or RegraspParams()
        self._scan_height = float(scan_height)
        self._max_retries = int(max_retries)
        self._settle_time = float(settle_time)
        self._seed = int(seed)
        self._bar = float(bar_angle)
        self._gripper = gripper
        self._hand_mass = gripper.hand_mass + 2.0 * gripper.finger_mass
        self._tiers = tuple(Tier(tier) for tier in tiers)
        if not self._tiers or self._tiers[0] is not Tier.GRASPS:
            raise ValueError(f"PickAndCarry: tiers must start with grasps, got {tiers}")
        # The fixed models parsed once; each planning model works on its own copy.
        self._robot = parse_robot(self._directives)
        self._near = PlanningModel(self._robot, padding=max(ground_clearance - 1e-3, 0.0))
        self._table_level: PlanningModel | None = None
        self._inputs = {name: self.DeclareAbstractInputPort(name, AbstractValue.Make([]))
                        for tier in self._tiers for name in tier.ports}
        self._scan = self.DeclareAbstractInputPort(
            "scan", AbstractValue.Make(no_scan("not scanned yet")))
        self._arm_state = self.DeclareVectorInputPort("panda.state", 14)
        self._hand_state = self.DeclareVectorInputPort("hook_gripper.state", 6)
        self._load = self.DeclareVectorInputPort("hook_gripper.load", 3)
        self._state = self.DeclareAbstractState(AbstractValue.Make(_State()))
        self.DeclareInitializationUnrestrictedUpdateEvent(self._initialize)
        self.DeclarePeriodicUnrestrictedUpdateEvent(period, 0.0, self._update)
        self.DeclareVectorOutputPort("panda.desired_state", 14, self._calc_arm,
                                     prerequisites_of_calc={self.all_state_ticket(),
                                                            self.time_ticket()})
        self.DeclareVectorOutputPort("hook_gripper.command", 3, self._calc_hand,
                                     prerequisites_of_calc={self.all_state_ticket()})
        self.DeclareAbstractOutputPort("status", lambda: AbstractValue.Make(PickStatus()),
                                       self._calc_status,
                                       prerequisites_of_calc={self.all_state_ticket()})
        self.DeclareVectorOutputPort(
            "scan_request", 4, lambda context, output: output.SetFromVector(
                context.get_abstract_state(self._state).get_value().scan_request),
            prerequisites_of_calc={self.all_state_ticket()})

    @property
    def max_attempts(self) -> int:
        """The most picks this machine may start: its lifts (one per tier that lifts, plus
        ``max_retries``; :func:`~gbh_drake.planning.choice.tiers_after_empty_lifts`) and, with a
        regrasp tier, its regrasps (each a pick, a place and a re-scan). A trial may last its
        ``max_time`` per attempt (:func:`gbh_drake.trial.trial_duration`)."""
        lifts = self._max_retries + sum(tier is not Tier.REGRASP for tier in self._tiers)
        regrasps = self._regrasp.max_regrasps if Tier.REGRASP in self._tiers else 0
        return lifts + regrasps

    # ---- outputs ------------------------------------------------------------------------------
    def _calc_arm(self, context, output: BasicVector) -> None:
        s: _State = context.get_abstract_state(self._state).get_value()
        if s.arm is None:
            output.SetFromVector(np.concatenate([s.q_hold, np.zeros(7)]))
            return
        output.SetFromVector(np.concatenate(sample(s.arm, context.get_time(), s.arm_dot)))

    def _calc_hand(self, context, output: BasicVector) -> None:
        output.SetFromVector(context.get_abstract_state(self._state).get_value().command)

    def _calc_status(self, context, output) -> None:
        output.set_value(context.get_abstract_state(self._state).get_value().status)

    # ---- events ---------------------------------------------------------------------------------
    def _initialize(self, context, state) -> None:
        q = self._arm_state.Eval(context)[:7]
        q_fingers = self._hand_state.Eval(context)[:2]
        s = _State(q_hold=q.copy(), q_home=q.copy(),
                   command=np.array([float(np.mean(q_fingers)), self._hand.force, self._bar]))
        s.status.phase_start[Mode.SETTLE.value] = context.get_time()
        state.get_mutable_abstract_state(self._state).set_value(s)

    def _update(self, context, state) -> None:
        s: _State = copy.copy(context.get_abstract_state(self._state).get_value())
        s.status = copy.copy(s.status)
        s.command = s.command.copy()
        t = context.get_time()
        mode = s.status.mode
        if mode in FINAL_MODES:
            return
        if t < s.until:
            # Some modes watch the robot while they run (DURING, True: changed).
            watch = self.DURING.get(mode)
            if watch is None or not watch(self, context, s, t):
                return
        else:
            self.AFTER[mode](self, context, s, t)
        state.get_mutable_abstract_state(self._state).set_value(s)

    def _enter(self, s: _State, mode: Mode, t: float, *, arm=None, until: float | None = None):
        s.status.mode = mode
        s.status.phase_start = {**s.status.phase_start, mode.value: t}
        if arm is not None:
            s.arm, s.arm_dot = arm, arm.derivative(1)
        s.until = (s.arm.end_time() + DWELL) if (arm is not None and until is None) else \
            (until if until is not None else t)

    def _move(self, s: _State, mode: Mode, t: float, waypoints, **kwargs) -> None:
        self._enter(s, mode, t, arm=joint_path(waypoints, t, **kwargs))

    # Each _after_<mode> runs once the mode's time is up and chooses the next mode (AFTER).
    def _after_settle(self, context, s: _State, t: float) -> None:
        # Plan once the scan is taken (a Scanner may wait for the object to be still).
        if t > self._settle_time and not scan_pending(self._scan.Eval(context)):
            self._enter(s, Mode.PLAN, t)

    def _after_plan(self, context, s: _State, t: float) -> None:
        start = time.perf_counter()
        plan, score, fallback = self._plan(context, s)
        s.status.plan_seconds += time.perf_counter() - start
        if isinstance(plan, RegraspPlan):
            s.status.regrasps = [*s.status.regrasps, plan]
            s.command[2] = BAR_RETRACTED
            q_now = self._arm_state.Eval(context)[:7]
            self._move(s, Mode.REGRASP_APPROACH, t, [q_now, *plan.transfer[1:]])
            return
        if plan is None:
            # No grasp at all, or a re-scan that holds no object (it left the scene after an
            # empty lift): the grasp search says why (an empty scan), not "none could be
            # planned".
            none = s.status.n_grasps == 0 or self._scan.Eval(context).empty
            self._enter(s, Mode.NO_GRASP if none else Mode.NO_REACHABLE_GRASP, t)
            return
        s.status.plan, s.status.score, s.status.fallback = plan, score, fallback
        s.command[2] = plan.bar
        if plan.opening < self._gripper.q_open:  # a narrower pinch: the fingers close to it
            s.command[:2] = [plan.opening, self._hand.force]  # on the way (nan: fully open)
        q_now = self._arm_state.Eval(context)[:7]
        self._move(s, Mode.APPROACH, t, [q_now, *plan.transfer[1:]])

    # The regrasp: pick with a pinch, turn, set down, let go, go home, re-scan.
    def _after_regrasp_approach(self, context, s: _State, t: float) -> None:
        plan = s.status.regrasps[-1]
        self._enter(s, Mode.REGRASP_INSERT, t,
                    arm=insert_path(plan.descent or [plan.q["approach"], plan.q["grasp"]], t))

    def _after_regrasp_insert(self, context, s: _State, t: float) -> None:
        g = self._gripper
        duration = (g.q_open - 0.5 * g.rod_width) / self._hand.speed
        s.command[:2] = [0.5 * g.rod_width, self._hand.force]
        self._enter(s, Mode.REGRASP_CLOSE, t, until=t + duration + 0.3)

    def _after_regrasp_close(self, context, s: _State, t: float) -> None:
        if not self._fingers_stopped(context, s, t, Mode.REGRASP_CLOSE):
            return
        q = s.status.regrasps[-1].q
        self._move(s, Mode.REGRASP_LIFT, t, [q["grasp"], q["lift"]], velocity_scale=0.2)

    def _after_regrasp_lift(self, context, s: _State, t: float) -> None:
        plan = s.status.regrasps[-1]
        move = plan.move or [plan.q["lift"], plan.q["above"]]
        self._enter(s, Mode.REGRASP_TURN, t, arm=polyline_path(move, t, velocity_scale=0.25))

    def _after_regrasp_turn(self, context, s: _State, t: float) -> None:
        s.load = float(self._load.Eval(context)[2])
        q = s.status.regrasps[-1].q
        self._move(s, Mode.REGRASP_LOWER, t, [q["above"], q["place"]], velocity_scale=0.1)

    def _during_regrasp_lower(self, context, s: _State, t: float) -> bool:
        """Stops lowering once the object stands (the hand's load drops) and lets go there."""
        if s.load < MIN_SENSED_LOAD or \
                self._load.Eval(context)[2] > self._config.unloaded_fraction * s.load:
            return False
        self._let_go(s, t, sample(s.arm, t)[0])
        return True

    def _after_regrasp_lower(self, context, s: _State, t: float) -> None:
        self._let_go(s, t, s.status.regrasps[-1].q["place"])

    def _let_go(self, s: _State, t: float, q_at: np.ndarray) -> None:
        g = self._gripper
        s.q_hold, s.arm = np.asarray(q_at, dtype=float), None
        s.command[:2] = [g.q_open, self._hand.force]
        self._enter(s, Mode.REGRASP_RELEASE, t,
                    until=t + (g.q_open - 0.5 * g.rod_width) / self._hand.speed + 0.3)

    def _after_regrasp_release(self, context, s: _State, t: float) -> None:
        back = release_path(self._near, s.q_hold, GraspKind.ANTIPODAL, self._config,
                            BAR_RETRACTED, self._gripper)["retreat"]
        self._move(s, Mode.REGRASP_RETREAT, t, [s.q_hold, back], velocity_scale=0.2)

    def _after_regrasp_retreat(self, context, s: _State, t: float) -> None:
        self._move(s, Mode.REGRASP_HOME, t, [sample(s.arm, t)[0], s.q_home])

    def _after_regrasp_home(self, context, s: _State, t: float) -> None:
        self._rescan(s, t, s.status.regrasps[-1].place_W[:2])

    def _rescan(self, s: _State, t: float, xy) -> None:
        """Holds the arm home and asks the Scanner for a new scan around ``xy`` (W, m)."""
        s.scans_asked += 1
        s.scan_request = np.array([s.scans_asked, xy[0], xy[1], self._scan_height])
        s.command[2] = self._bar
        s.q_hold, s.arm = s.q_home.copy(), None
        self._enter(s, Mode.RESCAN, t)

    def _after_rescan(self, context, s: _State, t: float) -> None:
        if getattr(self._scan.Eval(context), "request", 0) >= s.scans_asked:
            self._enter(s, Mode.PLAN, t)

    # The retry: a lift that came away empty; open, go home, re-scan, plan again.
    def _came_away_empty(self, context, s: _State) -> float | None:
        """What the lift added to the hand's load (N), if it came away empty and a tier is left
        to try (:func:`tiers_after_empty_lifts`)."""
        if not self._tiers_left(s, Tier(s.status.source)):
            return None
        gained = float(self._load.Eval(context)[2]) - s.load_free
        return gained if gained < EMPTY_LOAD else None

    def _tiers_left(self, s: _State, *failing: Tier) -> tuple[Tier, ...]:
        """The tiers the next plan may try, the attempts that came away empty (and
        ``failing``) considered."""
        failed = [*(Tier(a.source) for a in s.status.attempts), *failing]
        return tiers_after_empty_lifts(self._tiers, failed, self._max_retries)

    def _retry(self, context, s: _State, t: float, gained: float) -> None:
        st = s.status
        st.attempts = [*st.attempts, Attempt(
            kind=str(st.plan.kind), rank=st.plan.rank, score=st.score, source=st.source,
            p_WG=np.asarray(st.grasp_X_WG, dtype=float)[:3, 3].copy(), c_W=st.grasp_c_W,
            load=gained, time=t, R_WG=np.asarray(st.grasp_X_WG, dtype=float)[:3, :3].copy())]
        st.plan, st.score, st.fallback, st.source, st.grasp_X_WG, st.grasp_c_W = \
            None, float("nan"), False, "", None, None
        s.q_hold, s.arm = np.asarray(sample(s.arm, t)[0], dtype=float), None
        g = self._gripper
        s.command[:2] = [g.q_open, self._hand.force]
        self._enter(s, Mode.RETRY_RELEASE, t,
                    until=t + (g.q_open - g.q_closed) / self._hand.speed + 0.2)

    def _after_retry_release(self, context, s: _State, t: float) -> None:
        self._move(s, Mode.RETRY_HOME, t, [s.q_hold, s.q_home])

    def _after_retry_home(self, context, s: _State, t: float) -> None:
        points = np.asarray(self._scan.Eval(context).mesh_W.vertices).reshape(-1, 3)
        xy = points[:, :2].mean(axis=0) if len(points) else s.scan_request[1:3]
        self._rescan(s, t, xy)

    def _tried(self, s: _State, grasp) -> bool:
        """Whether ``grasp`` hooks a structure that a failed attempt hooked, or (without a
        structure) lies where a failed one of its kind did (within :data:`TRIED_RADIUS`)."""
        c = _structure_centre(grasp)
        p = np.asarray(grasp.X_WG, dtype=float)[:3, 3]
        for a in s.status.attempts:
            if c is not None and a.c_W is not None:
                if np.linalg.norm(c - a.c_W) <= TRIED_RADIUS:
                    return True
            elif a.kind == GraspKind(grasp.kind) and np.linalg.norm(p - a.p_WG) <= TRIED_RADIUS:
                return True
        return False

    def _fingers_stopped(self, context, s: _State, t: float, mode: Mode) -> bool:
        """Whether the fingers closing since ``mode`` began have stopped (or timed out)."""
        v_fingers = self._hand_state.Eval(context)[3:5]
        timeout = s.status.phase_start[mode.value] + self._gripper.q_open / self._hand.speed + 0.5
        return not (np.max(np.abs(v_fingers)) > 2e-3 and t < timeout)

    def _after_approach(self, context, s: _State, t: float) -> None:
        s.load_free = float(self._load.Eval(context)[2])
        plan = s.status.plan
        # A scoop goes on down until the table pushes back (_during_insert).
        press = self._press_pose(plan) if plan.kind == GraspKind.SCOOP else None
        self._enter(s, Mode.INSERT, t, arm=insert_path(
            plan.descent or [plan.q["approach"], plan.q["grasp"]], t, press))

    def _press_pose(self, plan: PickPlan) -> np.ndarray:
        """The arm where a scoop's press ends at the latest: ``press_depth`` below the grasp."""
        hand = HandPose(self._gripper.q_open, plan.bar)
        X = self._near.X_WG(plan.q["grasp"], hand)
        X_down = RigidTransform(X.rotation(), X.translation() - [0.0, 0.0, self._scoop.press_depth])
        q = self._near.ik(X_down, plan.q["grasp"], hand)
        return plan.q["grasp"] if q is None else q

    def _during_insert(self, context, s: _State, t: float) -> bool:
        """A scoop stops pressing once the table pushes the hand up with ``press_force`` (the
        hand's load points down) and closes from there."""
        plan = s.status.plan
        if plan.kind != GraspKind.SCOOP or t < s.arm.end_time() - self._press_time(s) or \
                -self._load.Eval(context)[2] < self._scoop.press_force:
            return False
        self._close(s, t, sample(s.arm, t)[0])
        return True

    def _press_time(self, s: _State) -> float:
        """Seconds of the insert's last segment (the press) in its trajectory."""
        breaks = s.arm.get_segment_times()
        return breaks[-1] - breaks[-2] if len(breaks) >= 3 else 0.0

    def _after_insert(self, context, s: _State, t: float) -> None:
        plan = s.status.plan
        self._close(s, t, s.arm.value(s.arm.end_time()).ravel() if plan.kind == GraspKind.SCOOP
                    else plan.q["grasp"])

    def _close(self, s: _State, t: float, q_from: np.ndarray) -> None:
        """CLOSE from the arm at ``q_from``: the planned close, or a scoop's from where its
        press stopped (the hand moving along +y_G as each finger travels, at that height)."""
        plan = s.status.plan
        g = self._gripper
        # Hooks: close to the loop's closure (q_closed), squeezing with the force whatever stops
        # the fingers first; pinches: until the rods touch (the material stops them first).
        q_stop = g.q_closed if GraspKind(plan.kind).hooks else 0.5 * g.rod_width
        opening = plan.opening if plan.opening < g.q_open else g.q_open  # nan: fully open
        duration = (opening - q_stop) / self._hand.speed
        s.command[:2] = [q_stop, self._hand.force]
        q_to = plan.q["closed"]
        if plan.kind == GraspKind.SCOOP:
            X = self._near.X_WG(q_from, HandPose(g.q_open, plan.bar))
            X_to = RigidTransform(X.rotation(), X.translation() +
                                  (g.q_open - g.q_closed) * X.rotation().col(1))
            q_to = self._near.ik(X_to, q_from, HandPose(g.q_closed, plan.bar))
            q_to = plan.q["closed"] if q_to is None else q_to
        arm = linear_move(q_from, q_to, t, duration)
        self._enter(s, Mode.CLOSE, t, arm=arm, until=t + duration + 0.3)

    def _after_close(self, context, s: _State, t: float) -> None:
        if not self._fingers_stopped(context, s, t, Mode.CLOSE):
            return  # still closing
        plan = s.status.plan
        self._move(s, Mode.LIFT, t, [plan.q["closed"], plan.q["lift"]], velocity_scale=0.2)

    def _after_lift(self, context, s: _State, t: float) -> None:
        gained = self._came_away_empty(context, s)
        if gained is not None:
            self._retry(context, s, t, gained)
            return
        plan = s.status.plan
        carry = plan.carry or [plan.q["lift"], plan.q["carry"]]  # waypoints at the lift height
        self._enter(s, Mode.CARRY, t, arm=polyline_path(carry, t, velocity_scale=0.25))

    def _after_carry(self, context, s: _State, t: float) -> None:
        self._enter(s, Mode.HOLD, t, until=t + self._config.hold_time)

    def _during_hold(self, context, s: _State, t: float) -> bool:
        """Keeps the hand's vertical load while the object is held still (its mean and noise
        set the set-down's near-zero band)."""
        z = float(self._load.Eval(context)[2])
        total, squares, n = s.hold_loads
        s.hold_loads = (total + z, squares + z * z, n + 1)
        return True

    def _after_hold(self, context, s: _State, t: float) -> None:
        s.load = float(self._load.Eval(context)[2])
        s.command[1] = self._config.cage_test_force
        self._enter(s, Mode.CAGE_TEST, t, until=t + self._config.cage_test_time)

    def _after_cage_test(self, context, s: _State, t: float) -> None:
        plan = s.status.plan
        s.command[1] = self._hand.force
        if self._config.set_down is False or not plan.sets_down:
            # The verdict is final: end holding the object (no set-down asked, or none planned).
            s.q_hold, s.arm = np.asarray(plan.q["carry"], dtype=float), None
            self._enter(s, Mode.DONE, t)
            return
        total, squares, n = s.hold_loads
        mean = total / n if n else s.load
        noise = math.sqrt(max(squares / n - mean * mean, 0.0)) if n else 0.0
        s.band = unloaded_band(mean - s.load_free, noise, self._config.unloaded_band,
                               self._config.unloaded_fraction)
        s.side, s.since = 1, t
        self._move(s, Mode.LOWER, t, [plan.q["carry"], plan.q["place"]], velocity_scale=0.15)

    def _hand_load(self, context, s: _State, t: float) -> float:
        """The hand's vertical load (N) less the empty hand's and less what the hand's own
        mass takes to follow the arm's commanded vertical acceleration (going up, the flange
        pulls harder on the hand, as if it carried something): what the object puts on it."""
        return float(self._load.Eval(context)[2]) - s.load_free - \
            self._hand_mass * self._accel_z(s, t)

    def _accel_z(self, s: _State, t: float, h: float = 0.01) -> float:
        """m/s^2: the gripper's vertical acceleration along the arm's trajectory at ``t``
        (central differences of its height, ``h`` apart; 0 while the arm holds)."""
        if s.arm is None or not s.arm.start_time() < t < s.arm.end_time():
            return 0.0
        hand = HandPose(self._gripper.q_open, s.status.plan.bar)
        z = [self._near.X_WG(sample(s.arm, t + dt)[0], hand).translation()[2]
             for dt in (-h, 0.0, h)]
        return (z[0] - 2.0 * z[1] + z[2]) / (h * h)

    def _load_side(self, context, s: _State, t: float) -> tuple[int, float, bool, float]:
        """The hand's vertical load (N, :meth:`_hand_load`) on which side of the band
        (:func:`load_side`), for how long (s), whether that side is new (the state changed),
        and the load itself (N)."""
        z = self._hand_load(context, s, t)
        side = load_side(z, s.band)
        changed = side != s.side
        if changed:
            s.side, s.since = side, t
        return side, t - s.since, changed, z

    def _note(self, s: _State, t: float, text: str) -> None:
        s.status.set_down_notes = [*s.status.set_down_notes, f"t {t:.2f} s: {text}"]

    def _during_lower(self, context, s: _State, t: float) -> bool:
        """Once the object stands on the table (the hand's load has stayed near zero, within
        the band, for ``unloaded_dwell``), goes on down by ``unload_depth`` only, so that the
        hook hangs free in the hole, and releases there. A load that merely fell (the hook still
        bears part of the weight) lowers on, to the planned depth at most. A hand pressing the
        object down (the load below the band for :data:`PRESS_DWELL`) does not count as down
        either: it goes on down by ``unload_depth`` at most, then releases."""
        if s.release is not None or s.load - s.load_free < MIN_SENSED_LOAD:
            return False
        side, held, changed, z = self._load_side(context, s, t)
        if side > 0 or held < (self._config.unloaded_dwell if side == 0 else PRESS_DWELL):
            return changed
        depth = f"{self._config.unload_depth * 100:.1f} cm"
        self._note(s, t, f"set down (load {z:+.2f} N, band {s.band:.2f} N): {depth} on down"
                   if side == 0 else f"the hand presses the object down (load {z:+.2f} N, band "
                   f"{s.band:.2f} N): not down; {depth} on down at most")
        q_now = sample(s.arm, t)[0]
        plan = s.status.plan
        hand = HandPose(self._gripper.q_closed, plan.bar)
        X = self._near.X_WG(q_now, hand)
        X_down = RigidTransform(X.rotation(), X.translation() -
                                [0.0, 0.0, self._config.unload_depth])
        q_down = self._near.ik(X_down, q_now, hand)
        q_down = q_now if q_down is None else q_down
        s.release = {"place": q_down,
                     **release_path(self._near, q_down, plan.kind, self._config, plan.bar,
                                     self._gripper)}
        self._enter(s, Mode.LOWER, s.status.phase_start[Mode.LOWER.value],
                    arm=joint_path([q_now, q_down], t, velocity_scale=0.1, min_duration=0.3))
        return True

    def _after_lower(self, context, s: _State, t: float) -> None:
        """Open as the grasp closed: in place, or about the straight rod (vertical grasps: the
        arm follows the fingers so that the bar leaves from under the material)."""
        if s.release is None and s.load - s.load_free >= MIN_SENSED_LOAD:
            z = float(self._load.Eval(context)[2]) - s.load_free
            self._note(s, t, f"lowered to the planned depth, the load not near zero "
                             f"({z:+.2f} N, band {s.band:.2f} N)")
        q = s.release or s.status.plan.q
        g = self._gripper
        travel = g.q_open - 0.5 * g.rod_width
        s.command[:2] = [g.q_open, self._hand.force]
        duration = (g.q_open - g.q_closed) / self._hand.speed
        s.side, s.since = 0, t
        self._enter(s, Mode.RELEASE, t, arm=linear_move(q["place"], q["opened"], t, duration),
                    until=t + travel / self._hand.speed + 0.2)

    def _after_release(self, context, s: _State, t: float) -> None:
        if s.left_in_hand:  # the tries used: the hand stays where it let go
            s.q_hold, s.arm = np.asarray(sample(s.arm, t)[0], dtype=float), None
            self._enter(s, Mode.DONE, t)
            return
        q = s.release or s.status.plan.q
        s.side, s.since, s.stopped = 0, t, False  # the load is watched afresh
        self._move(s, Mode.RETREAT, t, [q["opened"], q["down"], q["slide"], q["retreat"]],
                   velocity_scale=0.2)

    def _after_retreat(self, context, s: _State, t: float) -> None:
        s.q_hold = (s.release or s.status.plan.q)["retreat"]
        self._enter(s, Mode.DONE, t)

    def _during_letting_go(self, context, s: _State, t: float) -> bool:
        """RELEASE and RETREAT: once the hand's vertical load has stayed above the near-zero
        band for ``unloaded_dwell`` (the bar is lifting the object again), stops, goes back
        down (``relift_drop`` times the try), lets the fingers open, withdraws the bar out of
        the hole along the way it went in (:func:`~gbh_drake.planning.pick.withdraw_path`) and
        only then goes up; at most ``relift_tries`` times. A hand that presses the object down
        (the load below the band for :data:`PRESS_DWELL`) while it goes back down (a
        withdrawal's RELEASE) stops going down there and withdraws from there."""
        cfg = self._config
        if s.load - s.load_free < MIN_SENSED_LOAD:
            return False
        side, held, changed, z = self._load_side(context, s, t)
        going_down = (s.relifts > 0 or s.left_in_hand) and s.status.mode is Mode.RELEASE
        if going_down and side < 0 and held >= PRESS_DWELL and not s.stopped:
            s.stopped = True
            self._note(s, t, f"the hand presses the object down ({z:+.2f} N) going back down: "
                             "stopped there")
            self._withdraw(s, t, z, drop=0.0, mode=Mode.RELEASE)
            return True
        if going_down or side <= 0 or held < cfg.unloaded_dwell:
            return changed  # a withdrawal's own RELEASE goes down and opens, whatever the load
        if s.relifts >= cfg.relift_tries:  # never carry it off: stop, let it stand, open
            s.left_in_hand = True
            self._note(s, t, f"the bar lifts the object again ({z:+.2f} N) in "
                             f"{s.status.mode.value}; {cfg.relift_tries} tries used: down "
                             f"{cfg.relift_drop * 100:.1f} cm, open and stop there, the object "
                             "left standing in the hand")
            self._withdraw(s, t, z, drop=cfg.relift_drop, mode=Mode.RELEASE)
            return True
        s.relifts += 1
        self._note(s, t, f"the bar lifts the object again ({z:+.2f} N, band {s.band:.2f} N) in "
                         f"{s.status.mode.value}: down {cfg.relift_drop * s.relifts * 100:.1f} "
                         f"cm, open, out along the hole, then up (try {s.relifts} of "
                         f"{cfg.relift_tries})")
        self._withdraw(s, t, z, drop=cfg.relift_drop * s.relifts, mode=Mode.RELEASE)
        return True

    def _withdraw(self, s: _State, t: float, z: float, *, drop: float, mode: Mode) -> None:
        """From the arm where it is now: ``drop`` (m) down, out along the hole's axis (what is
        left of it), then back along -z_G (:func:`withdraw_path`); in ``mode``: RELEASE goes
        down and lets the fingers open first, RETREAT goes on out and up at once."""
        cfg, g = self._config, self._gripper
        plan = s.status.plan
        q = s.release or plan.q
        q_now = sample(s.arm, t)[0]
        open_hand = HandPose(g.q_open, plan.bar)
        X_now = self._near.X_WG(q_now, open_hand)
        if GraspKind(plan.kind).keeps_straight_rod:  # what is left of the opening's own move
            done = withdrawn_along(self._near.X_WG(q["place"], open_hand), X_now)
            shift = max(g.q_open - g.q_closed - done, 0.0)
        elif plan.kind == GraspKind.PARALLEL:  # what is left of the bar's way out of the hole
            shift = max(cfg.withdraw_shift - withdrawn_along(
                self._near.X_WG(q["opened"], open_hand), X_now), 0.0)
        else:
            shift = 0.0
        path = withdraw_path(self._near, q_now, cfg, plan.bar, g, drop=drop, shift=shift)
        s.release = {**q, "place": path["lowered"], "opened": path["lowered"],
                     "down": path["lowered"], "slide": path["out"], "retreat": path["retreat"]}
        s.command[:2] = [g.q_open, self._hand.force]
        s.side, s.since = 0, t
        if mode is Mode.RELEASE and s.stopped:  # stop going down: stay here while it opens
            s.arm = joint_path([q_now, q_now], t, min_duration=0.1)
            s.arm_dot = s.arm.derivative(1)
            return
        if mode is Mode.RETREAT:
            self._move(s, Mode.RETREAT, t, [q_now, path["lowered"], path["out"],
                                            path["retreat"]], velocity_scale=0.2)
            return
        s.stopped = False
        arm = joint_path([q_now, path["lowered"]], t, velocity_scale=0.1, min_duration=0.3)
        travel = g.q_open - 0.5 * g.rod_width
        self._enter(s, Mode.RELEASE, t, arm=arm,
                    until=max(arm.end_time() + DWELL, t + travel / self._hand.speed + 0.2))

    # The machine: what each mode does once its time is up (it chooses the next mode), and
    # what some modes watch while they run (True: the state changed). Every mode but the final
    # ones has an AFTER handler (tests/systems/test_pick_machine.py).
    AFTER = {
        Mode.SETTLE: _after_settle,
        Mode.PLAN: _after_plan,
        Mode.REGRASP_APPROACH: _after_regrasp_approach,
        Mode.REGRASP_INSERT: _after_regrasp_insert,
        Mode.REGRASP_CLOSE: _after_regrasp_close,
        Mode.REGRASP_LIFT: _after_regrasp_lift,
        Mode.REGRASP_TURN: _after_regrasp_turn,
        Mode.REGRASP_LOWER: _after_regrasp_lower,
        Mode.REGRASP_RELEASE: _after_regrasp_release,
        Mode.REGRASP_RETREAT: _after_regrasp_retreat,
        Mode.REGRASP_HOME: _after_regrasp_home,
        Mode.RESCAN: _after_rescan,
        Mode.RETRY_RELEASE: _after_retry_release,
        Mode.RETRY_HOME: _after_retry_home,
        Mode.APPROACH: _after_approach,
        Mode.INSERT: _after_insert,
        Mode.CLOSE: _after_close,
        Mode.LIFT: _after_lift,
        Mode.CARRY: _after_carry,
        Mode.HOLD: _after_hold,
        Mode.CAGE_TEST: _after_cage_test,
        Mode.LOWER: _after_lower,
        Mode.RELEASE: _after_release,
        Mode.RETREAT: _after_retreat,
    }
    DURING = {
        Mode.REGRASP_LOWER: _during_regrasp_lower,
        Mode.INSERT: _during_insert,
        Mode.HOLD: _during_hold,
        Mode.LOWER: _during_lower,
        Mode.RELEASE: _during_letting_go,
        Mode.RETREAT: _during_letting_go,
    }

    # ---- planning -------------------------------------------------------------------------------
    def _plan(self, context, s: _State) -> tuple[PickPlan | RegraspPlan | None, float, bool]:
        """The first plannable grasp of the machine's tiers, in order (:func:`choose`): the plan,
        its grasp's score and whether it came from the fallback tier; every refusal, the
        evaluation and planning times and the counts are recorded in the status."""
        q_start = self._arm_state.Eval(context)[:7]
        scan: ScanResult = self._scan.Eval(context)
        setup: list[PickSetup] = []  # made once, when the first grasp is planned

        def get_setup() -> PickSetup:
            if not setup:
                setup.append(self._setup(scan))
            return setup[0]

        def plan_grasp(tier: Tier, rank: int, grasp) -> PickPlan | Refusal:
            return self._plan_grasp(get_setup(), q_start, rank, grasp)

        def reach(tier: Tier, rank: int, grasp) -> Refusal | None:
            bar = BAR_DEPLOYED if GraspKind(grasp.kind).hooks else BAR_RETRACTED
            return reach_refusal(get_setup(), grasp.X_WG, grasp.kind, rank, q_start, bar)

        def plan_regrasp_(rank: int, X_WG, pose) -> RegraspPlan | Refusal:
            return plan_regrasp(get_setup(), X_WG, pose, rank, q_start, s.q_home)

        choice = choose(
            self._offers(context, self._tiers_left(s)), plan_grasp=plan_grasp,
            plan_regrasp=plan_regrasp_,
            is_plan=lambda result: isinstance(result, PickPlan | RegraspPlan),
            max_grasps=self._config.max_grasps, max_pinches=self._regrasp.max_pinches,
            regrasp_allowed=len(s.status.regrasps) < self._regrasp.max_regrasps,
            skip=lambda grasp: bool(s.status.attempts) and self._tried(s, grasp),
            skip_again=lambda grasp: at_failed_pose(s.status.attempts, grasp, TRIED_RADIUS,
                                                    TRIED_ANGLE_DEG),
            check=lambda tier, grasps: _check_grasps(tier.value, grasps),
            reach=reach if self._config.reach_check else None)
        st = s.status
        st.n_grasps += choice.n_offered
        st.skipped += choice.skipped
        st.second_passes += int(choice.second_pass)
        st.grasps_seconds += choice.offer_seconds
        st.grasp_seconds = [*st.grasp_seconds, *choice.grasp_seconds]
        st.refusals = [*st.refusals, *choice.refusals]
        if choice.regrasp_note:
            st.regrasp_note = choice.regrasp_note
        if isinstance(choice.plan, RegraspPlan):
            return choice.plan, float("nan"), False
        if choice.plan is None:
            return None, float("nan"), False
        st.source = choice.tier.value
        st.grasp_X_WG = np.asarray(choice.grasp.X_WG, dtype=float)
        st.grasp_c_W = _structure_centre(choice.grasp)
        return (choice.plan, float(getattr(choice.grasp, "score", float("nan"))),
                choice.tier is Tier.FALLBACK)

    def plan_grasp(self, context, grasp, rank: int = 0, setup: PickSetup | None = None
                   ) -> PickPlan | Refusal:
        """Plans ``grasp`` (with ``X_WG`` and ``kind``) as PLAN would, from the measured arm on
        the scan in ``context`` (this system's), without executing it: the plan, or the
        :class:`~gbh_drake.planning.pick.Refusal` that says why the planner would not execute
        it. ``setup``: this scan's planning models (:meth:`pick_setup`; made when None)."""
        setup = self.pick_setup(context) if setup is None else setup
        return self._plan_grasp(setup, self._arm_state.Eval(context)[:7], rank, grasp)

    def pick_setup(self, context) -> PickSetup:
        """The planning models and points for the scan in ``context`` (this system's)."""
        return self._setup(self._scan.Eval(context))

    def _plan_grasp(self, setup: PickSetup, q_start: np.ndarray, rank: int, grasp
                    ) -> PickPlan | Refusal:
        """One grasp planned from ``q_start``: the bar set by its kind (hooks deploy it)."""
        bar = BAR_DEPLOYED if GraspKind(grasp.kind).hooks else BAR_RETRACTED
        min_lift = self._scoop.min_lift if grasp.kind == GraspKind.SCOOP else 0.0
        return plan_pick(setup, grasp.X_WG, grasp.kind, rank, q_start, bar, min_lift,
                         pinch_W=_pinch_point(grasp), opening=getattr(grasp, "q_pregrasp", None))

    def _offers(self, context, tiers: Sequence[Tier]) -> list[Offer]:
        """The grasps of ``tiers`` (the machine's, in its order), evaluated when :func:`choose`
        reaches them; a tier whose input is not connected is passed over (the first,
        ``grasps``, must be)."""
        offers = []
        for tier in tiers:
            ports = [self._inputs[name] for name in tier.ports]
            if tier is not Tier.GRASPS and not all(p.HasValue(context) for p in ports):
                continue
            if tier is Tier.REGRASP:
                poses, pinches = ports
                offers.append(Offer(tier, lambda port=pinches: port.Eval(context),
                                    poses=lambda port=poses: port.Eval(context)))
            else:
                offers.append(Offer(tier, lambda port=ports[0]: port.Eval(context)))
        return offers

    def _setup(self, scan: ScanResult) -> PickSetup:
        """Planning models and the scan's points for this pick: the near model, one around the
        scan's hull for the transfer, and (made once, for a scoop) one at table level."""
        points = np.asarray(scan.mesh_W.vertices, dtype=float).reshape(-1, 3)
        far = None
        if self._config.plan_paths and len(points) >= 4:
            far = PlanningModel(self._robot, obstacles=[scan.mesh_W])
        if {Tier.SCOOP, Tier.TALL_SCOOP} & set(self._tiers) and self._table_level is None:
            # A scoop touches the table by design: its last segments are checked against
            # everything else (the arm's own links, other models).
            self._table_level = PlanningModel(self._robot, padding=0.0, ignore_models=(TABLE,))
        com = points.mean(axis=0) if len(points) else np.zeros(3)
        return PickSetup(self._near, far, points, com, self._config, self._seed,
                         table_level=self._table_level, unseen_W=scan_unseen(scan),
                         gripper=self._gripper)


def unloaded_band(carried: float, noise: float, fraction: float, widest: float = 0.4) -> float:
    """N: how near zero the hand's vertical load must be for the object's weight to be off the
    hand: ``fraction`` of the load ``carried`` (N) while it was held still, or twice that load's
    ``noise`` (N, its standard deviation then: a swinging object's is large), or
    :data:`MIN_BAND`, whichever is most, but never wider than ``widest`` of the carried load
    (the ``unloaded_fraction`` that counted the object as set down before; at least
    :data:`MIN_BAND`)."""
    return min(max(fraction * carried, 2.0 * noise, MIN_BAND), max(widest * carried, MIN_BAND))


def load_side(z: float, band: float) -> int:
    """Where the hand's vertical load ``z`` (N, the empty hand's taken off: up is the object
    hanging on the hand) lies for a near-zero ``band`` (N): 1 above it (the hand bears some of
    the object's weight), 0 within it (set down), -1 below it (the hand presses the object
    down)."""
    return 1 if z > band else (-1 if z < -band else 0)


def _pinch_point(grasp) -> np.ndarray | None:
    """(3,) the midpoint (W) of a pinch's contacts (an antipodal grasp's ``p_WA``, ``p_WB``),
    or None."""
    a, b = getattr(grasp, "p_WA", None), getattr(grasp, "p_WB", None)
    return None if a is None or b is None else 0.5 * (np.asarray(a, float) + np.asarray(b, float))


def _structure_centre(grasp) -> np.ndarray | None:
    """(3,) the centre c (W) of the hanging structure ``grasp`` hooks, or None."""
    c = getattr(getattr(grasp, "structure", None), "c", None)
    return None if c is None else np.asarray(c, dtype=float).reshape(3).copy()


def _check_grasps(port: str, grasps) -> None:
    """Refuses, naming the port, grasps the machine cannot execute: each needs ``X_WG`` (4, 4)
    and a ``kind`` among :class:`~gbh_drake.core.results.GraspKind`."""
    if not isinstance(grasps, list | tuple):
        raise TypeError(f"PickAndCarry: input {port!r} expects a list of grasps, got "
                        f"{type(grasps).__name__}")
    for i, grasp in enumerate(grasps):
        X_WG = getattr(grasp, "X_WG", None)
        if X_WG is None or np.shape(X_WG) != (4, 4):
            raise TypeError(f"PickAndCarry: input {port!r}: grasp {i} ({type(grasp).__name__}) "
                            "has no X_WG (the open gripper's pose in W, 4x4)")
        try:
            GraspKind(getattr(grasp, "kind", None))
        except ValueError:
            raise TypeError(f"PickAndCarry: input {port!r}: grasp {i} has kind "
                            f"{getattr(grasp, 'kind', None)!r}; one of "
                            f"{', '.join(k.value for k in GraspKind)}") from None
