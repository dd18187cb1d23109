"""The studio's page: Drake's Meshcat controls over a :class:`~gbh_drake.studio.session.Session`.

As Drake's ``JointSliders`` and teleop examples do, the controls are added with ``AddSlider``
and ``AddButton`` and read by polling (``GetSliderValue``, ``GetButtonClicks``): :meth:`Studio.step`
reads them once and does what they ask; :meth:`Studio.run` steps until Ctrl-C. In the panel's
order:

* sliders ``object`` (the studio's objects, by index: the panel's text names it), ``x (m)``,
  ``y (m)``, ``yaw (deg)``, ``rest (-1 drop)`` (a stable resting orientation, most probable
  first, or -1: drawn from the seed), ``views``, ``method`` (the registered methods, by index),
  ``preset (1 paper)`` and ``seed``: what the next Reset places (the scenario they make is
  ``gbh run --set`` text, printed on the terminal);
* buttons ``Reset`` (place the object and let it settle; with nothing changed, back to the
  settled object: its scan and detection stay), ``Scan`` (the cameras' frusta and the fused
  scan), ``Free space`` (what the cameras saw free round the scan, on and off), ``Detect``
  (hanging structures, what each rule removed, the ranked grasps) and ``Execute`` (the pick of
  the grasp on the rank slider, live; Reset stops it); each does the steps before it when they
  are not done;
* slider ``rank`` (after Detect): one offered grasp at a time, open and closed, its score's
  terms, whether the planner would execute it and why not, the refused candidates nearest to
  it with the rule that removed each (when nothing was offered: the refused candidates that
  came closest);
* the text: what each step found, and the verdict (:mod:`gbh_drake.viz.panel_text`).
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass

from pydrake.geometry import Meshcat

from gbh_drake.method_spec import method_names
from gbh_drake.studio import page
from gbh_drake.studio.choices import DROP, PRESETS
from gbh_drake.studio.session import Clock, Session
from gbh_drake.viz.panel_text import PanelText

#: The buttons, in the panel's order.
BUTTONS = ("Reset", "Scan", "Free space", "Detect", "Execute")
#: The rank slider's name.
RANK = "rank"


@dataclass(frozen=True)
class Slider:
    """A slider of the studio: its name, range and step (the field's unit), and the field of
    :class:`Choices` it sets (``to``/``of`` convert between the slider's number and the
    field's value). A value outside the range stretches it (:meth:`span`)."""

    name: str
    min: float
    max: float
    step: float
    field: str
    to: Callable = float
    of: Callable = float

    def span(self, value: float) -> tuple[float, float]:
        """The slider's (min, max) when it starts at ``value``: its range stretched to hold
        ``value`` (Drake's ``AddSlider`` clamps: a scenario's seed 1234 would become 99)."""
        return min(self.min, value), max(self.max, value)


def sliders(session: Session) -> list[Slider]:
    """The studio's sliders for ``session`` (the rest's range is the chosen object's)."""
    methods = method_names()
    return [
        Slider("object", 0, len(session.objects) - 1, 1, "object", int, float),
        Slider("x (m)", 0.30, 0.80, 0.005, "x"),
        Slider("y (m)", -0.35, 0.35, 0.005, "y"),
        Slider("yaw (deg)", -180, 180, 1, "yaw_deg"),
        Slider("rest (-1 drop)", DROP, max(len(session.rests().poses) - 1, 0), 1, "rest", int,
               float),
        Slider("views", 1, 20, 1, "views", int, float),
        Slider("method", 0, len(methods) - 1, 1, "method", lambda v: methods[int(v)],
               lambda m: float(methods.index(m))),
        Slider("preset (1 paper)", 0, len(PRESETS) - 1, 1, "preset",
               lambda v: PRESETS[int(v)], lambda p: float(PRESETS.index(p))),
        Slider("seed", 0, 99, 1, "seed", int, float),
    ]


class Studio:
    """The page of ``session`` in ``meshcat`` (see the module docstring). ``say``: where the
    studio says what it does besides the page (default: print)."""

    def __init__(self, session: Session, meshcat: Meshcat, *, say: Callable[[str], None] = print):
        self.session, self.meshcat, self.say = session, meshcat, say
        self.text = PanelText(meshcat)
        self.rank = 0
        self.free_space = False
        self._clicks: dict[str, int] = {}
        """Each button's clicks done (-1: clicked before the panel was rebuilt, still to do)."""
        self._sliders: list[Slider] = []
        self._shown: dict[str, float] = {}
        """Each slider's value as last shown or read (the field is set when it moves)."""
        self._lines: dict[str, list[str]] = {}
        self.timings: dict[str, Clock] = {}
        """The last step of each kind: ``place``, ``scan``, ``detect``, ``grasp`` (the redraw
        of the rank slider's grasp), ``plan``, ``execute``, ``reset``."""
        self.layout()

    # ---- the panel ---------------------------------------------------------------------------
    def layout(self) -> None:
        """(Re)builds the panel: every control, in order, at the current values. A button
        clicked meanwhile (while a step ran) stays to do: the rebuilt one starts at 0."""
        shown = set(self.meshcat.GetButtonNames())
        owed = {n for n in BUTTONS if n in shown and
                self.meshcat.GetButtonClicks(n) > self._clicks.get(n, 0)}
        self.meshcat.DeleteAddedControls()
        self.text.forget()
        self._sliders = sliders(self.session)
        c = self.session.choices
        for s in self._sliders:  # the field keeps its value off the slider's grid
            value = s.of(getattr(c, s.field))
            self._shown[s.name] = self.meshcat.AddSlider(s.name, *s.span(value), s.step, value)
        for name in BUTTONS:
            self.meshcat.AddButton(name)
        self._clicks = {n: -1 if n in owed else 0 for n in BUTTONS}
        offered = self._offered()
        if offered:
            self.rank = min(self.rank, len(offered) - 1)
            self.meshcat.AddSlider(RANK, 0, len(offered) - 1, 1, self.rank)
        self._show()

    def _offered(self) -> list:
        d = self.session.detection
        return d.offered if d is not None else []

    def _show(self) -> None:
        lines = [line for part in ("place", "scan", "detect", "grasp", "plan", "verdict",
                                   "note") for line in self._lines.get(part, [])]
        self.text.show(lines or ["press Reset to place the object, or Scan"])

    def _say(self, part: str, lines: list[str]) -> None:
        self._lines[part] = lines
        self._show()

    def _forget(self, *parts: str) -> None:
        for part in parts:
            self._lines.pop(part, None)

    # ---- the loop ----------------------------------------------------------------------------
    def run(self, poll: float = 0.05) -> None:
        """Steps until interrupted (Ctrl-C: KeyboardInterrupt propagates)."""
        while True:
            if not self.step():
                time.sleep(poll)

    def step(self) -> list[str]:
        """Reads the controls once and does what they ask; returns what was done (slider
        names, ``rank``, button names) in order."""
        done = self._read_sliders()
        offered = self._offered()
        if offered and RANK in self.meshcat.GetSliderNames():
            rank = int(round(self.meshcat.GetSliderValue(RANK)))
            if rank != self.rank and rank < len(offered):
                self.select(rank)
                done.append(RANK)
        for name in BUTTONS:
            clicks = self.meshcat.GetButtonClicks(name)
            if clicks > self._clicks.get(name, 0):
                self._clicks[name] = clicks
                self.press(name)
                done.append(name)
        return done

    def _read_sliders(self) -> list[str]:
        c, changed = self.session.choices, []
        for s in self._sliders:  # moved since shown: Drake rounds what it shows to the step
            value = self.meshcat.GetSliderValue(s.name)
            if value != self._shown[s.name]:
                self._shown[s.name] = value
                if s.to(value) != getattr(c, s.field):
                    setattr(c, s.field, s.to(value))
                    changed.append(s.name)
        if "object" in changed:  # another object: its own rests, the one nearest its model's
            c.rest = self.session.modelled_rest()
            self._say("note", [f"object: {self.session.objects[c.object].label}"])
            self.layout()
        if changed and self.session.changed:
            self._say("note", [f"object: {self.session.objects[c.object].label}",
                               "changed: Reset or Scan places it"])
        return changed

    # ---- the actions -------------------------------------------------------------------------
    def press(self, name: str) -> None:
        """What the button ``name`` does (module docstring); a bad choice (an object that
        cannot be loaded, a scenario the checks refuse) is said on the page, not raised."""
        from gbh_drake.objects.mesh_io import MeshImportError
        from gbh_drake.objects.sets import ObjectSetError
        from gbh_drake.scenario import ScenarioError

        try:
            {"Reset": self.reset, "Scan": self.scan, "Free space": self.toggle_free_space,
             "Detect": self.detect, "Execute": self.execute}[name]()
        except (ScenarioError, MeshImportError, ObjectSetError) as e:
            self._say("note", [f"error: {e}"])

    def reset(self) -> None:
        """Places the object anew when the controls changed, else back to the settled object."""
        s = self.session
        if s.changed or not s.stage:
            self._place()
            return
        self.timings["reset"] = s.reset()
        self._forget("verdict", "note")
        self._show()

    def _place(self) -> None:
        s = self.session
        clock = s.place()
        self.timings["place"] = clock
        self.say(f"placed: gbh run --set '{s.overrides}'")
        page.clear(self.meshcat)
        page.frame_object(self.meshcat, s)
        self.free_space = False
        self._lines = {"place": page.placed_lines(s, clock)}
        self.layout()

    def scan(self) -> None:
        """Places the object if needed, then the scan: the cameras and the fused scan (a scan
        already taken is shown again, with what was detected on it)."""
        s = self.session
        if s.changed or not s.stage:
            self._place()
        clock = s.take_scan()
        self.timings["scan"] = clock
        cameras = page.draw_scan(self.meshcat, s.scan)
        page.frame_object(self.meshcat, s, cameras)
        if self.free_space:
            page.draw_free_space(self.meshcat, s.scan)
        self._forget("verdict", "note")
        self._lines["scan"] = page.scan_lines(s.scan, clock)
        if s.detection is None:
            self._forget("detect", "grasp", "plan")
            self._show()
        else:
            self._show_detection(self.rank)

    def toggle_free_space(self) -> None:
        """Draws (or removes) what the cameras saw free round the scan."""
        s = self.session
        if s.scan is None:
            self.scan()
        self.free_space = not self.free_space
        if self.free_space:
            n = page.draw_free_space(self.meshcat, s.scan)
            self._say("note", [f"free space: {n} points seen free round the scan"])
        else:
            page.clear(self.meshcat, "free_space")
            self._forget("note")
            self._show()

    def detect(self) -> None:
        """Scans if needed, then the method's systems on the scan: structures, rules, grasps."""
        s = self.session
        if s.changed or s.scan is None:
            self.scan()
        detection = s.detect()
        self.timings["detect"] = detection.clock
        page.frame_object(self.meshcat, s)
        self._forget("grasp", "plan", "verdict", "note")
        self._show_detection(0)

    def _show_detection(self, rank: int) -> None:
        """Draws the session's detection and its offered grasp ``rank`` (the panel laid out
        anew, with the rank slider)."""
        detection = self.session.detection
        page.draw_detection(self.meshcat, detection)
        self._lines["detect"] = page.detection_lines(detection)
        self.rank = min(rank, max(len(detection.offered) - 1, 0))
        self.layout()
        if detection.offered:
            self.select(self.rank)

    def select(self, rank: int, *, plan: bool = True) -> None:
        """Shows offered grasp ``rank`` (and, with ``plan``, then says whether the planner
        would execute it: the redraw comes first, the planning after)."""
        s = self.session
        start = Clock.start()
        self.rank = rank
        near = s.nearest_refused(rank)
        page.draw_offered(self.meshcat, s, rank, near)
        self._forget("plan", "verdict")
        self._say("grasp", page.offered_lines(s, rank, near))
        self.meshcat.Flush()
        self.timings["grasp"] = Clock.since(start)
        if plan and not s.detection.offered[rank].rule:
            start = Clock.start()
            self._say("plan", page.plan_lines(s.plan(rank)))
            self.timings["plan"] = Clock.since(start)

    def execute(self, *, max_time: float | None = None) -> None:
        """Detects if needed, then simulates the pick of the rank slider's grasp, live; the
        verdict goes on the page. Reset (pressed meanwhile) stops it."""
        s = self.session
        if s.changed or s.detection is None:
            self.detect()
        offered = s.detection.offered
        if not offered or offered[min(self.rank, len(offered) - 1)].rule:
            self._say("verdict", ["nothing to execute: the method offered no grasp (the rank "
                                  "slider shows refused candidates)"])
            return
        self._say("verdict", [f"executing grasp {self.rank + 1}..."])
        self.meshcat.Flush()
        start = Clock.start()
        seen = self._clicks["Reset"]
        record = s.execute(self.rank, max_time=max_time,
                           stop=lambda: self.meshcat.GetButtonClicks("Reset") > seen)
        self.timings["execute"] = Clock.since(start)
        if self.meshcat.GetButtonClicks("Reset") > seen:  # no verdict: the next step resets
            lines = page.stopped_lines(record, s.execute_from)
        else:
            lines = page.verdict_lines(record, s.execute_from)
        self.say(" ".join(lines))
        self._say("verdict", lines)

