"""The ``CageMonitor`` system: watches the object, the gripper and their contacts, and judges.

It reads the plant's body poses and contact results every ``period`` seconds and keeps a
running record (abstract state): when the object was lifted, whether and when it dropped and in
which phase of the :class:`~gbh_drake.systems.pick_and_carry.PickAndCarry` machine, which gripper
bodies touched it, the fingers' squeeze force, whether the hook's loop was closed. Its output is
the :class:`Verdict` as it stands; once the machine has finished it is final.

The rules (paper Sec. 3.1: a trial succeeds only if the object is picked up and transported
without falling), fixed in :class:`~gbh_drake.scenario.schema.MonitorConfig` before any experiment:

* lifted: the object's lowest point is ``lifted_height`` above the table (z = 0 of W);
* dropped: once lifted, its lowest point falls back below half of that (it lies on the table)
  and no gripper body touches it for ``DROP_CONFIRM`` (0.2 s; the drop's time is when that
  began); if one still does, it came down while held (dragged: "sank",
  not dropped, and judged by the next rule);
* success: lifted during the lift or the carry, never dropped, still lifted at the end of
  the hold over the place position (all with the full grasp force), and, after it was lifted,
  never back on the table while held: one that touched the table while a gripper body still
  held it (during the lift, the carry or the hold) was dragged, not carried clear, and is
  reported as its own outcome, ``touched_down`` (with the lowest height the object came back
  down to after it was lifted and its phase, ``min_clearance_after_lift`` and
  ``min_clearance_phase``, recorded for every trial);
* held by a cage or by a pinch, decided in the cage test: the squeeze is relaxed to a few
  newtons; an object still hanging at the end of it was caged when the hook's loop, at the
  measured fingers, encloses its material there (:func:`gbh_drake.core.enclosure.loop_enclosure`
  on the object's mesh where the plant has it: material passes through the loop's hole, the
  loop does not pass through the material, and the gap between the bar's tip and the straight
  rod is narrower than the material; whether the loop also links it is recorded); one still
  held otherwise (the bar folded, the material between the bar's tip and the straight rod, no
  material in the hole), or that slid out, was pinched. (The fingers' closeness alone once
  decided it: a bar tip stopped on a cup's wall, 1.9 mm from closed, with the straight rod
  inside the cup, counted as a cage.) docs/cage_test.md says more.

Only contact holds the object: it is a free body throughout, never welded or attached.
"""

from __future__ import annotations

import copy
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
from pydrake.common.value import AbstractValue
from pydrake.math import RigidTransform, RollPitchYaw
from pydrake.multibody.plant import ContactResults, MultibodyPlant
from pydrake.systems.framework import LeafSystem

from gbh_drake.core.arguments import argument_problem, require
from gbh_drake.core.enclosure import LoopEnclosure, loop_enclosure, mesh_edges
from gbh_drake.core.gripper import HOOK_GRIPPER, HookGripperGeometry
from gbh_drake.core.lazy import lazy_module
from gbh_drake.messages import (
    GraspSearch,
    HeldBy,
    Mode,
    Outcome,
    PickStatus,
    Verdict,
    verdict_final,
)
from gbh_drake.modeling.names import GRIPPER, TABLE
from gbh_drake.scenario.schema import MonitorConfig
from gbh_drake.systems.stage import CopiedShallowly

trimesh = lazy_module("trimesh")

#: A lifted object that is back on the table is dropped once no gripper body has touched it
#: for this long (s): a basket still hanging on the bar loses contact for a step now and then.
DROP_CONFIRM = 0.2

#: Said of a cage test whose enclosure was not judged (a monitor without the object's mesh).
NOT_JUDGED = "the fingers decided: the monitor had no object mesh to judge what the loop encloses"
#: Phases in which the object should be in the air.
_AIRBORNE = (Mode.LIFT, Mode.CARRY, Mode.HOLD, Mode.CAGE_TEST)
#: Phases whose end decides success (the cage test only decides cage or pinch).
_CARRIED = (Mode.LIFT, Mode.CARRY, Mode.HOLD)


@dataclass
class _Watch(CopiedShallowly):
    """The running record (abstract state)."""

    verdict: Verdict = field(default_factory=Verdict)
    lifted: bool = False
    dropped: bool = False
    table_in_hold: bool = False
    free_since: float = float("nan")
    free_phase: str = ""
    """Since when (and from which phase) the lifted object has been down and free of the
    gripper (a drop once it lasts ``DROP_CONFIRM``)."""
    force_sum: float = 0.0
    force_n: int = 0
    last_phase: str = ""
    attempts: int = 0
    """The machine's failed attempts seen so far (each retry starts the lift's record anew)."""
    cage_look: Observation | None = None
    """The last look during the cage test (its enclosure is judged once the test is over)."""
    enclosure_text: str = ""
    """What the loop enclosed, in words (for the reason; "" until judged)."""


class CageMonitor(LeafSystem):
    """Judges the trial as it runs (see the module docstring).

    .. pydrake_system::

        name: CageMonitor
        input_ports:
        - body_poses
        - contact_results
        - hook_gripper.state
        - hook_gripper.actuation
        - pick_status
        - grasp_search (optional)
        output_ports:
        - verdict

    ``body_poses``, ``contact_results``: the plant's outputs. ``hook_gripper.state`` (6) and
    ``hook_gripper.actuation`` (3, N and N m): the gripper's measured state and its actuators'
    efforts. ``pick_status``: the :class:`PickStatus` of the machine. ``grasp_search``: a
    :class:`GraspSearch`, read only when the machine had no grasp to try (unconnected: the
    outcome is ``no_grasp_found``). ``verdict``: a :class:`Verdict`.
    """

    def __init__(self, plant: MultibodyPlant, object_body_name: str, p_OV: np.ndarray,
                 config: MonitorConfig | None = None, *, bar_deployed_max: float = 0.1,
                 mesh_O: trimesh.Trimesh | None = None,
                 gripper: HookGripperGeometry = HOOK_GRIPPER):
        """``plant``: the station's plant (read for body indices and geometry only);
        ``object_body_name``: the free object's body; ``p_OV`` (n, 3): its vertices in its
        body frame (its convex hull's suffice); ``bar_deployed_max`` (rad): the bar counts as
        deployed below this angle magnitude; ``mesh_O``: the object's surface in its body frame
        (what the loop must enclose for a cage; None: the fingers decide, within
        ``config.closed_tolerance`` of closed, and the reason says so); ``gripper``:
        the hook gripper's geometry (the variant the station runs)."""
        super().__init__()
        require("CageMonitor", "config", config, (MonitorConfig, type(None)),
                "a MonitorConfig (a scenario's monitor) or None")
        if np.ndim(p_OV) != 2 or np.shape(p_OV)[1] != 3 or not len(p_OV) or \
                not np.all(np.isfinite(np.asarray(p_OV, dtype=float))):
            raise TypeError(argument_problem("CageMonitor", "p_OV", "an (n, 3) array of finite "
                                             "vertices (m, in the body frame)", p_OV))
        self._config = config or MonitorConfig()
        self._p_OV = np.asarray(p_OV, dtype=float).reshape(-1, 3)
        self._bar_max = bar_deployed_max
        self._gripper = gripper
        self._mesh = None
        if mesh_O is not None:  # vertices shared between faces (the enclosure's edge graph)
            mesh = trimesh.Trimesh(np.asarray(mesh_O.vertices), np.asarray(mesh_O.faces),
                                   process=True)
            self._mesh = (np.asarray(mesh.vertices), np.asarray(mesh.faces),
                          mesh_edges(mesh.faces))
        # Its own model instance's body: a gripper body may have the same name (a user's
        # mesh file bar.obj makes an object named "bar").
        body = plant.GetBodyByName(object_body_name, plant.GetModelInstanceByName(
            object_body_name)) if plant.HasModelInstanceNamed(object_body_name) \
            else plant.GetBodyByName(object_body_name)
        self._object = body.index()
        gripper = plant.GetModelInstanceByName(GRIPPER)
        frame_G = plant.GetFrameByName("G", gripper)
        self._hand_body = frame_G.body().index()
        self._X_HG = frame_G.GetFixedPoseInBodyFrame().GetAsMatrix4()
        self._gripper_bodies = {plant.get_body(i).index(): plant.get_body(i).name()
                                for i in plant.GetBodyIndices(gripper)}
        self._table_bodies = {plant.get_body(i).index()
                              for i in plant.GetBodyIndices(plant.GetModelInstanceByName(TABLE))}
        inspector_ids = {}
        for index in [self._object, *self._gripper_bodies, *self._table_bodies]:
            for gid in plant.GetCollisionGeometriesForBody(plant.get_body(index)):
                inspector_ids[gid] = index
        self._geometry_body = inspector_ids
        self._poses = self.DeclareAbstractInputPort("body_poses",
                                                    AbstractValue.Make([RigidTransform()]))
        self._contacts = self.DeclareAbstractInputPort("contact_results",
                                                       AbstractValue.Make(ContactResults()))
        self._hand = self.DeclareVectorInputPort("hook_gripper.state", 6)
        self._actuation = self.DeclareVectorInputPort("hook_gripper.actuation", 3)
        self._status = self.DeclareAbstractInputPort("pick_status",
                                                     AbstractValue.Make(PickStatus()))
        self._search = self.DeclareAbstractInputPort("grasp_search",
                                                     AbstractValue.Make(GraspSearch()))
        self._watch = self.DeclareAbstractState(AbstractValue.Make(_Watch()))
        self.DeclarePeriodicUnrestrictedUpdateEvent(self._config.period, 0.0, self._update)
        self.DeclareAbstractOutputPort("verdict", lambda: AbstractValue.Make(Verdict()),
                                       self._calc_verdict,
                                       prerequisites_of_calc={self.all_state_ticket()})

    def _calc_verdict(self, context, output) -> None:
        output.set_value(context.get_abstract_state(self._watch).get_value().verdict)

    # ---- observation ------------------------------------------------------------------------
    def lowest_point(self, X_WO: RigidTransform) -> float:
        """Height (m) of the object's lowest point above the table (z = 0 of W)."""
        R, p = X_WO.rotation().matrix(), X_WO.translation()
        return float((self._p_OV @ R[2] + p[2]).min())

    def touching(self, contacts: ContactResults) -> tuple[set[str], bool]:
        """Names of the gripper bodies in contact with the object, and whether the table is."""
        gripper, table = set(), False
        for a, b in self._contact_pairs(contacts):
            other = b if a == self._object else a if b == self._object else None
            if other is None:
                continue
            if other in self._gripper_bodies:
                gripper.add(self._gripper_bodies[other])
            elif other in self._table_bodies:
                table = True
        return gripper, table

    def _contact_pairs(self, contacts: ContactResults):
        for i in range(contacts.num_hydroelastic_contacts()):
            surface = contacts.hydroelastic_contact_info(i).contact_surface()
            yield (self._geometry_body.get(surface.id_M()),
                   self._geometry_body.get(surface.id_N()))
        for i in range(contacts.num_point_pair_contacts()):
            info = contacts.point_pair_contact_info(i)
            yield info.bodyA_index(), info.bodyB_index()

    # ---- judging ----------------------------------------------------------------------------------
    def _update(self, context, state) -> None:
        w: _Watch = context.get_abstract_state(self._watch).get_value()
        status: PickStatus = self._status.Eval(context)
        mode = status.mode
        if mode in (Mode.NO_GRASP, Mode.NO_REACHABLE_GRASP) and w.last_phase == mode.value:
            return
        poses = self._poses.Eval(context)
        X_WO = poses[int(self._object)]
        gripper, table = self.touching(self._contacts.Eval(context))
        squeeze = float(-np.mean(self._actuation.Eval(context)[:2]))
        # (Read only now: evaluating it earlier would run the grasp pipeline before the scan.)
        search = self._search.Eval(context) if mode == Mode.NO_GRASP and \
            self._search.HasValue(context) else GraspSearch()
        w = observe(w, status, Observation(
            t=context.get_time(), p_WO=X_WO.translation().tolist(),
            low=self.lowest_point(X_WO), gripper=gripper, table=table,
            hand=np.asarray(self._hand.Eval(context)), squeeze=squeeze,
            pose=[*X_WO.translation().tolist(),
                  *RollPitchYaw(X_WO.rotation()).vector().tolist()],
            X_WO=X_WO.GetAsMatrix4(),
            X_WG=poses[int(self._hand_body)].GetAsMatrix4() @ self._X_HG),
            self._config, self._bar_max, search,
            self.enclosure if self._mesh is not None else None)
        state.get_mutable_abstract_state(self._watch).set_value(w)

    def enclosure(self, o: Observation) -> LoopEnclosure:
        """What the loop encloses of the object at look ``o`` (its poses and the gripper's
        measured state, :func:`~gbh_drake.core.enclosure.loop_enclosure`)."""
        V, F, edges = self._mesh
        X_GO = np.linalg.inv(o.X_WG) @ o.X_WO
        return loop_enclosure(V @ X_GO[:3, :3].T + X_GO[:3, 3], F, float(o.hand[0]),
                              float(o.hand[1]), float(o.hand[2]), self._gripper, edges=edges)

@dataclass
class Observation:
    """One look at the scene: time (s), the object's origin p_WO (m), its lowest point's height
    above the table ``low`` (m), the gripper bodies touching it, whether the table does, the
    gripper's state ``hand`` (6: [q_straight, q_l, bar, their rates]) and the fingers' squeeze
    (N, positive closing); ``pose``: the object's x, y, z (m), roll, pitch, yaw (rad)."""

    t: float
    p_WO: list[float]
    low: float
    gripper: set[str]
    table: bool
    hand: np.ndarray
    squeeze: float
    pose: list[float] = field(default_factory=list)
    X_WO: np.ndarray | None = None
    """(4, 4) the object's pose (None: not given)."""
    X_WG: np.ndarray | None = None
    """(4, 4) the gripper frame G's pose (None: not given)."""


def observe(w: _Watch, status: PickStatus, o: Observation, cfg: MonitorConfig,
            bar_deployed_max: float = 0.1, search: GraspSearch | None = None,
            enclosure: Callable[[Observation], LoopEnclosure] | None = None) -> _Watch:
    """The record after observation ``o`` in the machine's ``status`` (a new record; ``w`` is
    not changed); ``search``: why there was no grasp, when the machine had none;
    ``enclosure``: what the loop encloses of the object at a look (the monitor's
    :meth:`CageMonitor.enclosure`), asked once, of the cage test's last look, when the test is
    over (None: the fingers decide, :data:`NOT_JUDGED`). Pure: the monitor's rules without a
    diagram.

    A lifted object whose lowest point comes back below half of ``lifted_height`` has dropped if
    no gripper body touches it for ``DROP_CONFIRM``; if one does, it has come down onto the
    table while still held (recorded as ``sank_at`` / ``sank_phase``: dragged, not dropped)."""
    w = copy.copy(w)
    w.verdict = v = copy.copy(w.verdict)  # (its lists and dicts are replaced, never mutated)
    mode, t, low, gripper, table = status.mode, o.t, o.low, o.gripper, o.table
    if len(status.attempts) > w.attempts:
        _start_again(w)
    if gripper:
        seen = set(v.touching.get(mode.value, [])) | gripper
        v.touching = {**v.touching, mode.value: sorted(seen)}
    if mode == Mode.PLAN and w.last_phase != Mode.PLAN.value:
        v.settled_at = v.settled_at or list(o.p_WO)
        v.planned_poses = [*v.planned_poses, list(o.pose)]
    if mode in _AIRBORNE and not w.dropped:
        if not w.lifted and low >= cfg.lifted_height and mode in _CARRIED:
            w.lifted, v.lifted_at = True, t
        if w.lifted:
            # Back down from the highest it had reached (not the rise through lifted_height).
            if mode in _CARRIED and low < v.max_clearance and \
                    not (low >= v.min_clearance_after_lift):
                v.min_clearance_after_lift, v.min_clearance_phase = low, mode.value
            v.max_clearance = max(v.max_clearance, low)
            if mode in _CARRIED and table:
                v.table_touch_while_carried = True
                if gripper and not v.touched_down_phase:
                    v.touched_down_at, v.touched_down_phase = t, mode.value
            if low >= 0.5 * cfg.lifted_height or gripper:
                w.free_since, w.free_phase = float("nan"), ""
            if low < 0.5 * cfg.lifted_height:
                if gripper:
                    if not v.sank_phase:
                        v.sank_at, v.sank_phase = t, mode.value
                else:
                    if not w.free_phase:
                        w.free_since, w.free_phase = t, mode.value
                    if t - w.free_since >= DROP_CONFIRM - 1e-9:
                        w.dropped, v.dropped_at, v.dropped_phase = \
                            True, w.free_since, w.free_phase
    if mode in (Mode.CARRY, Mode.HOLD):
        w.force_sum += o.squeeze
        w.force_n += 1
        v.squeeze_force = w.force_sum / w.force_n
    if mode == Mode.HOLD:
        v.clearance_after_hold = low
        w.table_in_hold = w.table_in_hold or table
    if mode == Mode.CAGE_TEST:
        hand = o.hand
        v.finger_q_cage_test = float(np.mean(hand[:2]))
        closed = HOOK_GRIPPER.q_closed + cfg.closed_tolerance
        v.bar_deployed = bool(abs(hand[2]) < bar_deployed_max)
        v.loop_closed = bool(np.all(hand[:2] <= closed) and v.bar_deployed)
        v.cage_test_held = bool(not w.dropped and low >= 0.5 * cfg.lifted_height and gripper)
        w.cage_look = o
    elif w.cage_look is not None and verdict_final(mode):
        if enclosure is not None and v.bar_deployed:
            e = enclosure(w.cage_look)
            v.loop_encloses, v.loop_linked, v.material_in_gap = e.encloses, e.linked, e.crossed
            v.loop_gap = e.gap
            v.material_thickness = e.thickness if np.isfinite(e.thickness) else float("nan")
            w.enclosure_text = e.text()
        w.cage_look = None
    if mode == Mode.DONE:
        v.released_at = list(o.p_WO)
        v.released_pose = list(o.pose)
        v.released_standing = bool(table and low < cfg.lifted_height)
        v.released_on_table = v.released_standing and not gripper
    conclude(w, status, cfg, search)
    w.last_phase = mode.value
    return w


#: The phases of one attempt at the pick (their contacts are kept per attempt).
_PICK_PHASES = (Mode.APPROACH.value, Mode.INSERT.value, Mode.CLOSE.value, Mode.LIFT.value)


def _start_again(w: _Watch) -> None:
    """A retry: the failed attempt's lift record is kept in ``earlier_attempts`` and the lift's
    record starts anew (in place: ``w`` and its verdict are this observation's copies)."""
    v = w.verdict
    v.earlier_attempts = [*v.earlier_attempts, {
        "lifted_at": v.lifted_at, "dropped_at": v.dropped_at, "dropped_phase": v.dropped_phase,
        "max_clearance": v.max_clearance,
        "touching": {k: p for k, p in v.touching.items() if k in _PICK_PHASES}}]
    v.touching = {k: p for k, p in v.touching.items() if k not in _PICK_PHASES}
    v.lifted_at = v.dropped_at = v.sank_at = v.touched_down_at = float("nan")
    v.min_clearance_after_lift = float("nan")
    v.dropped_phase = v.sank_phase = v.touched_down_phase = v.min_clearance_phase = ""
    v.max_clearance = 0.0
    v.table_touch_while_carried = False
    w.lifted = w.dropped = False
    w.free_since, w.free_phase = float("nan"), ""
    w.attempts += 1


def conclude(w: _Watch, status: PickStatus, cfg: MonitorConfig,
             search: GraspSearch | None = None) -> None:
    """Outcome, held_by and reason from the record (final once the machine finished); with no
    grasp to try, ``search`` says why; the reason ends with the retries, if there were any."""
    _conclude(w, status, cfg, search)
    if status.attempts:
        n = len(status.attempts)
        w.verdict.reason += (
            f" (a retry: {n} earlier grasp{'s' if n > 1 else ''} came away empty"
            + (f"; {status.skipped} grasps near {'them' if n > 1 else 'it'} skipped"
               if status.skipped else "")
            + ("; nothing else left, those at other poses tried" if status.second_passes
               else "") + ")")


def _conclude(w: _Watch, status: PickStatus, cfg: MonitorConfig,
              search: GraspSearch | None = None) -> None:
    v = w.verdict
    mode = status.mode
    regrasp = f"; regrasp: {status.regrasp_note}" if status.regrasp_note else ""
    if mode == Mode.NO_GRASP:
        search = search or GraspSearch()
        v.outcome, v.reason = search.outcome, search.reason + regrasp
        return
    if mode == Mode.NO_REACHABLE_GRASP:
        counts: dict[str, int] = {}
        for r in status.refusals:
            counts[r.key] = counts.get(r.key, 0) + 1
        why = ", ".join(f"{k} x{n}" for k, n in sorted(counts.items()))
        v.outcome = Outcome.NO_REACHABLE_GRASP
        v.reason = (f"none of the {len(status.refusals)} grasps tried could be planned ({why})"
                    if status.refusals else "no grasp left to try") + regrasp
        return
    order = [m.value for m in Mode]
    reached = order.index(mode.value)
    if reached <= order.index(Mode.HOLD.value):
        v.outcome, v.success = Outcome.INCOMPLETE, False
        v.reason = f"the pick is in its {mode.value} phase"
        return
    if w.dropped and v.dropped_phase in (Mode.LIFT.value, Mode.CARRY.value, Mode.HOLD.value):
        v.outcome = Outcome.DROPPED_DURING_LIFT if v.dropped_phase == Mode.LIFT.value else \
            Outcome.DROPPED_DURING_CARRY
        v.success, v.held_by = False, HeldBy.NONE
        v.reason = f"dropped during the {v.dropped_phase} at t = {v.dropped_at:.2f} s"
        return
    if not w.lifted or not (v.clearance_after_hold >= cfg.lifted_height):
        v.outcome, v.success, v.held_by = Outcome.NOT_LIFTED, False, HeldBy.NONE
        held = v.touching.get(Mode.HOLD.value)
        sank = (f"; it came back down onto the table during the {v.sank_phase} at "
                f"t = {v.sank_at:.2f} s" if v.sank_phase else "")
        if held and w.table_in_hold:
            v.reason = (f"held by the gripper ({', '.join(held)}) but still touching the "
                        "table at the place: dragged, not lifted clear (lowest point "
                        f"{100 * v.clearance_after_hold:.1f} cm){sank}")
        elif held:
            v.reason = (f"held by the gripper ({', '.join(held)}) but hanging only "
                        f"{100 * v.clearance_after_hold:.1f} cm above the table at the place, "
                        f"under the {100 * cfg.lifted_height:.0f} cm that lifted means{sank}")
        else:
            v.reason = "the object was not lifted: the gripper came away without it"
        return
    touched = bool(v.touched_down_phase)
    v.outcome, v.success = (Outcome.TOUCHED_DOWN, False) if touched else (Outcome.SUCCESS, True)
    carried = "carried to the place, but it touched the table while held during the " \
        f"{v.touched_down_phase} at t = {v.touched_down_at:.2f} s (dragged, not carried " \
        "clear)" if touched else "picked and carried"
    if mode == Mode.CAGE_TEST:
        v.held_by, v.reason = HeldBy.NONE, f"{carried}; the cage test is running"
        return
    judged = bool(w.enclosure_text)
    # Without the object's mesh (a monitor built without ``mesh_O``) the fingers decide, as
    # before the enclosure test, and the reason says so.
    encloses = v.loop_encloses if judged else v.loop_closed
    caged = v.cage_test_held and v.bar_deployed and encloses
    v.held_by = HeldBy.CAGE if caged else HeldBy.PINCH
    fingers = (f"fingers at {1000 * v.finger_q_cage_test:.1f} mm, closed at "
               f"{1000 * HOOK_GRIPPER.q_closed:.1f} mm")
    if caged and not judged:
        v.reason = (f"{carried}; held by a cage: it stayed on the closed loop with the squeeze "
                    f"relaxed ({fingers}; {NOT_JUDGED})")
    elif caged:
        v.reason = (f"{carried}; held by a cage: it stayed in the loop with the squeeze "
                    f"relaxed, and the loop encloses it ({w.enclosure_text})")
    elif v.cage_test_held and not v.bar_deployed:
        v.reason = f"{carried}; held by a pinch between the two straight rods (the bar " \
                   "folded), still held with the squeeze relaxed"
    elif v.cage_test_held:
        why = w.enclosure_text or f"the loop did not close ({NOT_JUDGED})"
        v.reason = f"{carried}; held by a pinch: {why} ({fingers})"
    else:
        v.reason = f"{carried}; held by a pinch: it slid out when the squeeze was relaxed"
