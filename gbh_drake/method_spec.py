"""What a grasp method is, as data: one :class:`MethodSpec` per method, in one registry.

A method's facts live here and nowhere else: its gripper variant, the bar's angle before a grasp
is chosen, how often an empty lift is retried, whether it goes beyond the paper, and the ordered
**tiers** of grasps it offers the pick-and-carry machine (its own grasps first, then, when none
of those can be executed, the next tier: a scoop, a regrasp, a tall scoop, a fallback pinch).
The scenario validates ``grasp_method`` against the registry, the station reads the bar's
angle, the trial gives the machine the tiers, the report reads ``beyond_paper``; only
:mod:`gbh_drake.methods` knows how a method's systems are built (its ``add_systems``)::

    spec = method_spec("gbh_plus")
    spec.tiers   # (Tier.GRASPS, Tier.SCOOP, Tier.REGRASP, Tier.TALL_SCOOP, Tier.FALLBACK)

A method of your own: :func:`gbh_drake.methods.register_method` registers its spec here, so a
scenario can name it (in the process that registered it).

This module is on the ground floor: it imports nothing of the pipeline, and no Drake.
"""

from __future__ import annotations

import enum
from dataclasses import dataclass

from gbh_drake.core.gripper import BAR_DEPLOYED, BAR_RETRACTED


class Tier(enum.StrEnum):
    """A kind of grasp a method offers the pick-and-carry machine, by its input port(s).

    The machine tries a method's tiers in the spec's order and executes the first grasp it can
    plan: every grasp of a tier is tried before the next tier is looked at."""

    GRASPS = "grasps"
    """The method's own grasps, best first (GbH's ranked hooks, or the baseline's pinches)."""
    SCOOP = "scoop_grasps"
    """Scoops of material lying flat on the table (the wedge bar slid under it)."""
    TALL_SCOOP = "tall_scoop_grasps"
    """Scoops of material taller than the wedge (a thick ring lying flat): lifted onto the bar
    when its underside is round, pushed and pinched when it is square, which the scan cannot
    tell (:mod:`gbh_drake.core.scoop`, *tall scoops*); so tried after the surer tiers."""
    REGRASP = "regrasp"
    """A pinch that sets the object down in a pose GbH can hook, then a re-scan (two ports:
    ``regrasp_poses`` and ``regrasp_grasps``)."""
    FALLBACK = "fallback_grasps"
    """Pinches with the bar folded, when nothing else could be planned."""

    @property
    def ports(self) -> tuple[str, ...]:
        """The pick-and-carry machine's input ports of this tier."""
        return ("regrasp_poses", "regrasp_grasps") if self is Tier.REGRASP else (self.value,)


@dataclass(frozen=True)
class MethodSpec:
    """One grasp method's facts (see the module docstring)."""

    name: str
    """The scenario's ``grasp_method``."""
    description: str
    """One line: what the method does."""
    tiers: tuple[Tier, ...] = (Tier.GRASPS,)
    """The grasp tiers the machine tries, in order (the first is always ``grasps``)."""
    gripper: str = "paper"
    """The gripper variant ``robot.gripper: auto`` gives it (``paper`` or ``wedge``)."""
    needs_gripper: bool = False
    """Whether it refuses any other variant than ``gripper`` (the scoop needs the wedge)."""
    bar_angle: float = BAR_DEPLOYED
    """rad: the bar before a grasp is chosen (each executed grasp then sets it by its kind)."""
    max_retries: int = 0
    """How often a lift that came away empty is followed by a re-scan and a new plan, unless
    the scenario's ``pick.max_retries`` says otherwise (0: one attempt, as in the paper); once
    they are used up, the tiers after the failed grasp's are still tried
    (:func:`gbh_drake.planning.choice.tiers_after_empty_lifts`)."""
    beyond_paper: bool = False
    """Whether the method goes beyond the paper's (reported in their own section)."""
    hooks: bool = True
    """Whether it runs GbH (hanging structures, hook grasps); False: the baseline's pinches only."""

    def __post_init__(self) -> None:
        if not self.name:
            raise ValueError("a method needs a name")
        if not self.tiers or self.tiers[0] is not Tier.GRASPS or \
                len(set(self.tiers)) != len(self.tiers):
            raise ValueError(f"method {self.name!r}: tiers must start with grasps and not "
                             f"repeat, got {[str(t) for t in self.tiers]}")


_SPECS: dict[str, MethodSpec] = {}


def register_spec(spec: MethodSpec) -> MethodSpec:
    """Adds ``spec`` under its name (replacing one of the same name) and returns it."""
    _SPECS[spec.name] = spec
    return spec


def method_spec(name: str) -> MethodSpec:
    """The spec of the method ``name``; ``KeyError`` naming the known ones."""
    try:
        return _SPECS[name]
    except KeyError:
        raise KeyError(f"no grasp method {name!r} (known: {', '.join(_SPECS)})") from None


def method_names() -> tuple[str, ...]:
    """The registered methods' names, in registration order."""
    return tuple(_SPECS)


for _spec in (
    MethodSpec("gbh", "Grasping by Hanging (the paper): hanging structures, hook grasps, the "
               "ranked best"),
    MethodSpec("antipodal", "the learning-free antipodal baseline: two straight rods (the bar "
               "folded)", bar_angle=BAR_RETRACTED, hooks=False),
    MethodSpec("gbh_fallback", "GbH first; when it offers nothing reachable, the best antipodal "
               "grasp, bar folded (the paper's Sec. 4 proposal)",
               tiers=(Tier.GRASPS, Tier.FALLBACK)),
    MethodSpec("gbh_scoop", "GbH first; then a scoop of material lying flat on the table (the "
               "wedge gripper), then one of taller material (a thick ring)",
               tiers=(Tier.GRASPS, Tier.SCOOP, Tier.TALL_SCOOP), gripper="wedge",
               needs_gripper=True, beyond_paper=True),
    MethodSpec("gbh_regrasp", "GbH first; then a pinch sets the object down in a pose GbH can "
               "hook, a re-scan, and GbH hooks it there", tiers=(Tier.GRASPS, Tier.REGRASP),
               beyond_paper=True),
    MethodSpec("gbh_plus", "GbH, the scoop, the regrasp, the scoop of taller material, then the "
               "antipodal fallback; one retry after a lift that came away empty, then the tiers "
               "after the failed one",
               tiers=(Tier.GRASPS, Tier.SCOOP, Tier.REGRASP, Tier.TALL_SCOOP, Tier.FALLBACK),
               gripper="wedge",
               needs_gripper=True, max_retries=1, beyond_paper=True),
    MethodSpec("gbh_completed", "GbH on the scan completed by symmetry: the unseen side of a "
               "body of revolution added, the unseen space it calls free with confidence taken "
               "as free (the paper's future work, shape completion)", beyond_paper=True),
):
    register_spec(_spec)
