"""The CageMonitor's rules as a pure function of what it observes (``cage_monitor.observe``):
what counts as lifted, dropped, dragged, touched down, carried, cage and pinch, and the words
for each. The cage test's enclosure is judged on real meshes held in the gripper's frame G (a
mug hung on the bar, a cup with the straight rod inside it)."""

import numpy as np
import pytest
from gbh_shapes import cup_on_the_straight_rod, mug_on_the_bar

from gbh_drake.core.enclosure import loop_enclosure
from gbh_drake.core.gripper import HOOK_GRIPPER
from gbh_drake.messages import HeldBy, Mode, Outcome, PickStatus
from gbh_drake.scenario.schema import MonitorConfig
from gbh_drake.systems.cage_monitor import Observation, _Watch, observe

CFG = MonitorConfig()
CLOSED = np.array([HOOK_GRIPPER.q_closed] * 2 + [0.0, 0, 0, 0])
HOOK = {"bar", "l_finger"}


def judge(mesh):
    """The enclosure of ``mesh`` (in G, where the look's poses would put it) by the loop at
    the look's measured fingers: what the monitor asks once the cage test is over."""
    mesh = mesh.copy()
    mesh.merge_vertices()
    return lambda o: loop_enclosure(mesh.vertices, mesh.faces, *o.hand[:3])


MUG = judge(mug_on_the_bar())


def run(script, enclosure=MUG):
    """Feeds observations (mode, lowest point m, gripper bodies, table touch, hand state) at
    10 ms steps through every phase in order and returns the verdict."""
    w, t = _Watch(), 0.0
    for mode, low, gripper, table, hand in script:
        t += 0.01
        w = observe(w, PickStatus(mode=mode), Observation(
            t=t, p_WO=[0.5, 0.0, low], low=low, gripper=set(gripper), table=table,
            hand=hand, squeeze=70.0), CFG, enclosure=enclosure)
    return w.verdict


def trial(carry_lows, *, carry_gripper=HOOK, hold_low=None, hold_table=False,
          cage_hand=CLOSED, cage_low=None, enclosure=MUG, carry_table=None):
    script = [(Mode.PLAN, 0.0, (), True, CLOSED), (Mode.CLOSE, 0.0, HOOK, True, CLOSED),
              (Mode.LIFT, 0.01, HOOK, True, CLOSED), (Mode.LIFT, 0.06, HOOK, False, CLOSED)]
    script += [(Mode.CARRY, low, carry_gripper if low < 0.01 else HOOK,
                low <= 0.0 if carry_table is None else carry_table, CLOSED)
               for low in carry_lows]
    hold_low = carry_lows[-1] if hold_low is None else hold_low
    script += [(Mode.HOLD, hold_low, HOOK if hold_low > -1 else (), hold_table, CLOSED)]
    cage_low = hold_low if cage_low is None else cage_low
    script += [(Mode.CAGE_TEST, cage_low, HOOK, False, cage_hand),
               (Mode.LOWER, 0.0, HOOK, True, CLOSED), (Mode.DONE, 0.0, (), True, CLOSED)]
    return run(script, enclosure)


def test_carried_on_the_closed_loop_is_a_caged_success():
    v = trial([0.06, 0.07, 0.06])
    assert v.outcome == Outcome.SUCCESS and v.held_by == HeldBy.CAGE and "cage" in v.reason
    assert v.reason.endswith("(its material passes through the loop, which links it)")
    assert v.loop_encloses and v.loop_linked and not v.material_in_gap and v.loop_gap == 0.0
    assert v.material_thickness == pytest.approx(0.01, abs=5e-4)
    assert v.lifted_at > 0 and v.max_clearance == pytest.approx(0.07)
    assert v.released_on_table and v.touching["carry"] == ["bar", "l_finger"]


def test_held_with_the_loop_open_is_a_pinch():
    open_hand = np.array([0.03, 0.03, 0, 0, 0, 0])
    v = trial([0.06], cage_hand=open_hand)
    assert v.outcome == Outcome.SUCCESS and v.held_by == HeldBy.PINCH
    assert "26.0 mm gap is wider than the material" in v.reason and v.loop_linked


def test_a_bar_tip_stopped_on_a_cups_wall_is_a_pinch_not_a_cage():
    """Issue 42: the straight rod inside a cup, the bar's tip stopped on its wall, fingers at
    18.9 mm (closed 17.0: within the 2 mm the finger rule allowed, so it was called a cage)."""
    q = 0.0189
    hand = np.array([q, q, 0, 0, 0, 0])
    v = trial([0.06], cage_hand=hand, enclosure=judge(cup_on_the_straight_rod(q)))
    assert v.loop_closed  # the fingers' rule alone would have said cage
    assert v.outcome == Outcome.SUCCESS and v.held_by == HeldBy.PINCH, v.reason
    assert v.material_in_gap and not v.loop_encloses
    assert "between the bar's tip and the straight rod (a 3.8 mm gap)" in v.reason


def test_the_bar_folded_is_a_pinch_without_asking_the_loop():
    folded = np.array([0.01, 0.01, -0.5 * np.pi, 0, 0, 0])
    asked = []
    v = trial([0.06], cage_hand=folded, enclosure=lambda o: asked.append(o))
    assert v.held_by == HeldBy.PINCH and "two straight rods" in v.reason and not asked


def test_touching_the_table_while_held_after_the_lift_is_its_own_class():
    """Lifted, then the bottom grazes the table during the carry while the bar still holds it,
    and it is carried on: not a success, ``touched_down`` (cage or pinch still recorded), with
    the lowest clearance after the lift and its phase."""
    v = trial([0.06, 0.004, 0.0, 0.05, 0.06], hold_low=0.06)
    assert v.outcome == Outcome.TOUCHED_DOWN and not v.success and v.held_by == HeldBy.CAGE
    assert v.touched_down_phase == "carry" and v.table_touch_while_carried
    assert v.min_clearance_after_lift == 0.0 and v.min_clearance_phase == "carry"
    assert v.reason.startswith("carried to the place, but it touched the table while held "
                               "during the carry")


def test_a_clean_carry_records_its_lowest_clearance_after_the_lift():
    v = trial([0.06, 0.012, 0.05], hold_low=0.055)
    assert v.outcome == Outcome.SUCCESS and not v.touched_down_phase
    assert v.min_clearance_after_lift == pytest.approx(0.012) and v.min_clearance_phase == "carry"
    # The lift's own rise through lifted_height is not a dip: the lowest after the peak counts.
    rise = run([(Mode.LIFT, 0.0, HOOK, True, CLOSED), (Mode.LIFT, 0.021, HOOK, False, CLOSED),
                (Mode.LIFT, 0.06, HOOK, False, CLOSED), (Mode.CARRY, 0.07, HOOK, False, CLOSED),
                (Mode.CARRY, 0.05, HOOK, False, CLOSED), (Mode.HOLD, 0.058, HOOK, False, CLOSED)])
    assert rise.min_clearance_after_lift == pytest.approx(0.05)
    # Free of the gripper for a moment on the table (not held): a drop's business, not this.
    w = trial([0.06, 0.0, 0.06], carry_gripper=(), carry_table=None, hold_low=0.06)
    assert w.outcome == Outcome.SUCCESS and not w.touched_down_phase and w.table_touch_while_carried


def test_falling_free_of_the_gripper_is_a_drop():
    v = trial([0.06] + [0.003] * 25, carry_gripper=(), hold_low=0.0, hold_table=True)
    assert v.outcome == Outcome.DROPPED_DURING_CARRY and v.dropped_phase == "carry"
    assert "dropped during the carry" in v.reason


def test_coming_down_on_the_table_while_hooked_is_dragged_not_dropped():
    """A basket still on the bar whose bottom comes back to the table during the carry."""
    v = trial([0.06, 0.003, 0.0], hold_low=0.0, hold_table=True)
    assert v.outcome == Outcome.NOT_LIFTED and not v.dropped_phase and v.sank_phase == "carry"
    assert "still touching the table" in v.reason and "came back down" in v.reason
    # Contact lost for a few steps (under DROP_CONFIRM) while it hangs on the bar: no drop.
    lows = [0.06, 0.003, 0.0, 0.0]
    w = _Watch()
    for k, (mode, low, gripper) in enumerate(
            [(Mode.LIFT, 0.06, HOOK)] + [(Mode.CARRY, low, ()) for low in lows[1:]]
            + [(Mode.CARRY, 0.0, HOOK)] * 3):
        w = observe(w, PickStatus(mode=mode), Observation(
            t=0.05 * k, p_WO=[0, 0, low], low=low, gripper=set(gripper), table=low <= 0,
            hand=CLOSED, squeeze=0.0), CFG)
    assert not w.dropped and w.verdict.sank_phase == "carry"
    assert "still touching the table" in v.reason and "came back down" in v.reason
    assert "dropped" not in v.reason


def test_hanging_low_but_clear_of_the_table_is_not_called_touching():
    """A bucket hanging 1.6 cm above the table at the place: held, not lifted clear, not
    touching."""
    v = trial([0.05, 0.03, 0.016])
    assert v.outcome == Outcome.NOT_LIFTED and "hanging only 1.6 cm above the table" in v.reason
    assert "touching" not in v.reason


def test_a_gripper_that_came_away_empty():
    script = [(Mode.PLAN, 0.0, (), True, CLOSED), (Mode.LIFT, 0.0, (), True, CLOSED),
              (Mode.CARRY, 0.0, (), True, CLOSED), (Mode.HOLD, 0.0, (), True, CLOSED),
              (Mode.CAGE_TEST, 0.0, (), True, CLOSED), (Mode.DONE, 0.0, (), True, CLOSED)]
    v = run(script)
    assert v.outcome == Outcome.NOT_LIFTED and "came away without it" in v.reason


def test_a_retry_starts_the_lift_record_anew_and_keeps_the_failed_one():
    """A first grasp lifts the object and drops it during the lift; the machine retries
    (``PickStatus.attempts`` grows) and the second grasp carries it: a success, the drop kept
    in ``earlier_attempts``, the reason saying a retry came first."""
    from gbh_drake.messages import Attempt

    failed = Attempt(kind="parallel", rank=0, score=0.5, source="grasps", p_WG=np.zeros(3),
                     c_W=None, load=0.05, time=1.0)
    first = [(Mode.LIFT, 0.05, HOOK, False), (Mode.LIFT, 0.0, (), True)] + \
        [(Mode.LIFT, 0.0, (), True)] * 25
    second = [(Mode.PLAN, 0.0, (), True), (Mode.LIFT, 0.06, HOOK, False),
              (Mode.CARRY, 0.07, HOOK, False), (Mode.HOLD, 0.07, HOOK, False),
              (Mode.CAGE_TEST, 0.07, HOOK, False), (Mode.DONE, 0.0, (), True)]
    w, t = _Watch(), 0.0
    for attempts, script in (([], first), ([failed], second)):
        for mode, low, gripper, table in script:
            t += 0.01
            w = observe(w, PickStatus(mode=mode, attempts=attempts), Observation(
                t=t, p_WO=[0.5, 0.0, low], low=low, gripper=set(gripper), table=table,
                hand=CLOSED, squeeze=70.0), CFG, enclosure=MUG)
        if not attempts:
            assert w.dropped and w.verdict.dropped_phase == "lift"
    v = w.verdict
    assert v.outcome == Outcome.SUCCESS and v.held_by == HeldBy.CAGE, v.reason
    assert not v.dropped_phase and v.max_clearance == pytest.approx(0.07)
    (earlier,) = v.earlier_attempts
    assert earlier["dropped_phase"] == "lift" and earlier["touching"] == {"lift": ["bar", "l_finger"]}
    assert v.reason.endswith("(a retry: 1 earlier grasp came away empty)")


def test_nothing_left_after_a_retry_says_so():
    """Every grasp offered after a retry was skipped (near the one that failed): the reason says
    nothing was left to try, not that none of 0 grasps could be planned."""
    from gbh_drake.messages import Attempt

    failed = Attempt(kind="parallel", rank=0, score=0.5, source="grasps", p_WG=np.zeros(3),
                     c_W=np.zeros(3), load=0.0, time=1.0)
    w = observe(_Watch(), PickStatus(mode=Mode.NO_REACHABLE_GRASP, attempts=[failed], skipped=3),
                Observation(t=0.01, p_WO=[0.5, 0, 0], low=0.0, gripper=set(), table=True,
                            hand=CLOSED, squeeze=0.0), CFG)
    assert w.verdict.outcome == Outcome.NO_REACHABLE_GRASP
    assert w.verdict.reason == ("no grasp left to try (a retry: 1 earlier grasp came away empty; "
                                "3 grasps near it skipped)")
    again = observe(_Watch(), PickStatus(mode=Mode.NO_REACHABLE_GRASP, attempts=[failed],
                                         skipped=3, second_passes=1),
                    Observation(t=0.01, p_WO=[0.5, 0, 0], low=0.0, gripper=set(), table=True,
                                hand=CLOSED, squeeze=0.0), CFG)
    assert again.verdict.reason.endswith(
        "3 grasps near it skipped; nothing else left, those at other poses tried)")


def test_without_the_objects_mesh_the_fingers_decide_and_say_so():
    """A monitor built without ``mesh_O`` (the README's own-diagram example): the fingers'
    closeness decides, as before the enclosure test, and the reason says it was not judged."""
    v = trial([0.06], enclosure=None)
    assert v.held_by == HeldBy.CAGE and "the fingers decided" in v.reason
    assert not v.loop_encloses and v.loop_gap != v.loop_gap  # not judged: nan
    q = 0.0189
    cup = trial([0.06], cage_hand=np.array([q, q, 0, 0, 0, 0]), enclosure=None)
    assert cup.held_by == HeldBy.CAGE  # the finger rule's mistake, kept only without a mesh
    open_hand = trial([0.06], cage_hand=np.array([0.03, 0.03, 0, 0, 0, 0]), enclosure=None)
    assert open_hand.held_by == HeldBy.PINCH and "the loop did not close" in open_hand.reason


@pytest.mark.parametrize(("config", "p_OV", "message"), [
    ({}, np.zeros((4, 3)), "CageMonitor(): config: expected a MonitorConfig (a scenario's "
                           "monitor) or None, got {} (a dict)"),
    (None, np.zeros(3), "CageMonitor(): p_OV: expected an (n, 3) array of finite vertices (m, in "
                        "the body frame), got array([0., 0., 0.]) (a ndarray)"),
    (None, np.full((2, 3), np.nan), "CageMonitor(): p_OV: expected an (n, 3) array of finite "
                                    "vertices (m, in the body frame), got array([[nan, nan, nan], "
                                    "[nan, nan, nan]]) (a ndarray)"),
])
def test_the_monitor_names_an_argument_of_the_wrong_type(config, p_OV, message):
    """(Before the plant is read: an empty dict was taken for no config, silently.)"""
    from gbh_drake.systems import CageMonitor

    with pytest.raises(TypeError) as info:
        CageMonitor(None, "mug_classic", p_OV, config)
    assert str(info.value) == message
