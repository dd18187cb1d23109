"""The plan choice: the first grasp that can be planned, tier by tier (pure: no Drake system).

A method offers its grasps in ordered tiers (:class:`~gbh_drake.method_spec.Tier`: its own,
then a scoop, a regrasp, a tall scoop, a fallback pinch). :func:`choose` tries every grasp of a
tier, best first, before it looks at the next tier; a tier's grasps are evaluated only when it
is reached (evaluating GbH's or the sampler's output runs them on the scan). Planning one grasp
is the caller's (:func:`gbh_drake.planning.pick.plan_pick` from the measured arm, or
:func:`gbh_drake.planning.regrasp.plan_regrasp`); every refusal is kept, in order, and the wall
time of each evaluation and of each grasp planned is measured.

The :class:`~gbh_drake.systems.pick_and_carry.PickAndCarry` machine calls it at PLAN::

    choice = choose([Offer(Tier.GRASPS, lambda: ranked), Offer(Tier.FALLBACK, lambda: pinches)],
                    plan_grasp=..., plan_regrasp=..., max_grasps=10, reach=...)

After lifts that came away empty (beyond the paper: a method with retries), which tiers the
next PLAN may try is :func:`tiers_after_empty_lifts`: every tier while the retries last, then
the tiers after the one whose grasp came away empty last, until none is left. A retry skips
the grasps near the failed one (the caller's ``skip``: the same hanging structure); when that
leaves nothing to plan, a second pass (``skip_again``) skips only the failed grasp's own pose
and its neighbours (a key ring lying flat has one structure: a scoop from another side may
hold where the first slipped off), rather than ending the trial with grasps untried.

**The cut by reach** (beyond the paper): with ``reach``, a cheap check (the IK of the grasp
pose from the measured arm, the first step of planning it) runs first, and a grasp the arm
cannot reach is refused without counting toward ``max_grasps``: of a tier's ranked grasps (GbH
offers ``GbhParams.top_k``: 40, preset ``paper`` 10), the best ``max_grasps`` the arm reaches
are planned. Without it, the first ``max_grasps`` are (the paper's ten: a pot on its side with
all ten on the far handle is never hooked by the near one).
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np

from gbh_drake.core.geometry import rotation_angle
from gbh_drake.method_spec import Tier


@dataclass
class Offer:
    """One tier's grasps, evaluated on first need: ``grasps()`` returns a list, best first (for
    a regrasp: the pinches that turn the object); ``poses()``, a regrasp's resting poses (each
    with ``pinches``, its own pinches' X_WG, tried before the tier's)."""

    tier: Tier
    grasps: Callable[[], Sequence]
    poses: Callable[[], Sequence] | None = None


@dataclass
class Choice:
    """What :func:`choose` found: ``plan`` (None: nothing could be planned) with the ``tier``,
    ``rank`` and ``grasp`` it came from (a regrasp's grasp is its pinch's X_WG); ``refusals``
    of every grasp tried before, in order; ``n_offered``: grasps the grasp tiers offered (not
    counting a regrasp's pinches); ``skipped``: grasps ``skip`` ruled out; wall seconds of the
    offers' evaluation (``offer_seconds``) and of each grasp planned (``grasp_seconds``);
    ``regrasp_note``: why a regrasp tier that was reached planned none ("" otherwise)."""

    plan: object | None = None
    tier: Tier | None = None
    rank: int = -1
    grasp: object | None = None
    refusals: list = field(default_factory=list)
    n_offered: int = 0
    skipped: int = 0
    unreached: int = 0
    offer_seconds: float = 0.0
    grasp_seconds: list[float] = field(default_factory=list)
    regrasp_note: str = ""
    second_pass: bool = False
    """A second pass ran (``skip_again``): the first planned nothing and skipped grasps."""


def choose(offers: Sequence[Offer], *, plan_grasp: Callable, plan_regrasp: Callable | None = None,
           is_plan: Callable[[object], bool], max_grasps: int, max_pinches: int = 0,
           regrasp_allowed: bool = True, skip: Callable[[object], bool] = lambda grasp: False,
           check: Callable[[Tier, Sequence], None] = lambda tier, grasps: None,
           reach: Callable[[Tier, int, object], object | None] | None = None,
           skip_again: Callable[[object], bool] | None = None) -> Choice:
    """The first plannable grasp of ``offers``, tier by tier (see the module docstring).

    ``plan_grasp(tier, rank, grasp)`` and ``plan_regrasp(rank, X_WG, pose)`` return a plan
    (``is_plan`` true) or a refusal; only the first ``max_grasps`` grasps of a tier are tried
    (skipped ones count), and of a regrasp ``max_pinches`` pinches per resting pose of each
    kind; ``regrasp_allowed`` false passes over a regrasp tier (the object was regrasped often
    enough); ``check(tier, grasps)`` may refuse an offer that cannot be executed (raise);
    ``reach(tier, rank, grasp)``: None when the arm reaches the grasp, else its refusal, kept
    in order; such a grasp does not count toward ``max_grasps`` (module docstring).
    ``skip_again``: when nothing could be planned and ``skip`` ruled grasps out, a second pass
    over the grasp tiers (no regrasp) skips only what it rules out (module docstring: a retry's
    second pass); its refusals follow the first pass's."""
    choice = _choose(offers, plan_grasp=plan_grasp, plan_regrasp=plan_regrasp,
                     is_plan=is_plan, max_grasps=max_grasps, max_pinches=max_pinches,
                     regrasp_allowed=regrasp_allowed, skip=skip, check=check, reach=reach)
    if choice.plan is not None or not choice.skipped or skip_again is None:
        return choice
    again = _choose([o for o in offers if o.tier is not Tier.REGRASP], plan_grasp=plan_grasp,
                    plan_regrasp=None, is_plan=is_plan, max_grasps=max_grasps, max_pinches=0,
                    regrasp_allowed=False, skip=skip_again, check=check, reach=reach)
    choice.plan, choice.tier, choice.rank, choice.grasp = \
        again.plan, again.tier, again.rank, again.grasp
    choice.refusals += again.refusals
    choice.unreached += again.unreached
    choice.offer_seconds += again.offer_seconds
    choice.grasp_seconds += again.grasp_seconds
    choice.second_pass = True
    return choice


def _choose(offers: Sequence[Offer], *, plan_grasp: Callable, plan_regrasp: Callable | None,
            is_plan: Callable[[object], bool], max_grasps: int, max_pinches: int,
            regrasp_allowed: bool, skip: Callable[[object], bool],
            check: Callable[[Tier, Sequence], None],
            reach: Callable[[Tier, int, object], object | None] | None) -> Choice:
    """One pass of :func:`choose` over ``offers``."""
    choice = Choice()
    for offer in offers:
        if offer.tier is Tier.REGRASP:
            if regrasp_allowed and plan_regrasp is not None and \
                    _regrasp(offer, choice, plan_regrasp, is_plan, max_pinches):
                return choice
            continue
        start = time.perf_counter()
        grasps = list(offer.grasps())
        choice.offer_seconds += time.perf_counter() - start
        check(offer.tier, grasps)
        choice.n_offered += len(grasps)
        counted = 0
        for rank, grasp in enumerate(grasps if reach is not None else grasps[:max_grasps]):
            if counted >= max_grasps:
                break
            if skip(grasp):
                choice.skipped += 1
                counted += 1
                continue
            start = time.perf_counter()
            if reach is not None:
                refusal = reach(offer.tier, rank, grasp)
                if refusal is not None:
                    choice.grasp_seconds.append(time.perf_counter() - start)
                    choice.refusals.append(refusal)
                    choice.unreached += 1
                    continue
            counted += 1
            result = plan_grasp(offer.tier, rank, grasp)
            choice.grasp_seconds.append(time.perf_counter() - start)
            if _try(choice, result, is_plan, offer.tier, rank, grasp):
                return choice
    return choice


def tiers_after_empty_lifts(tiers: Sequence[Tier], failed: Sequence[Tier],
                            max_retries: int) -> tuple[Tier, ...]:
    """The tiers a plan may try after lifts that came away empty from grasps of the tiers
    ``failed`` (in order; the grasps themselves are skipped by the caller's ``skip``), for a
    method that retries ``max_retries`` times (0: the paper's one attempt).

    No empty lift yet: every tier. Without retries: none (the trial ends). While the retries
    last (at most ``max_retries`` empty lifts): every tier again, the failed grasps skipped.
    After that, each further empty lift moves on to the tiers after the one whose grasp came
    away empty last (a method's fallback pinch still follows two empty hooks), until no tier is
    left: at most ``max_retries + len(tiers)`` attempts."""
    tiers = tuple(tiers)
    if not failed:
        return tiers
    if max_retries <= 0:
        return ()
    if len(failed) <= max_retries:
        return tiers
    last = failed[-1]
    return tiers[tiers.index(last) + 1:] if last in tiers else ()


def at_failed_pose(attempts: Sequence, grasp, radius: float, angle_deg: float) -> bool:
    """Whether ``grasp`` (``X_WG``, ``kind``) lies where one of ``attempts`` (each with
    ``kind``, ``p_WG`` and ``R_WG``, W) came away empty: the same kind, origins within
    ``radius`` (m), turned by less than ``angle_deg`` (an attempt without ``R_WG``: by any
    angle). A retry's second pass skips these (:func:`choose`'s ``skip_again``)."""
    X_WG = np.asarray(grasp.X_WG, dtype=float)
    for a in attempts:
        if str(a.kind) != str(grasp.kind) or np.linalg.norm(X_WG[:3, 3] - a.p_WG) > radius:
            continue
        if a.R_WG is None or rotation_angle(a.R_WG, X_WG[:3, :3]) < angle_deg:
            return True
    return False


def _try(choice: Choice, result, is_plan, tier: Tier, rank: int, grasp) -> bool:
    """Records ``result``: the plan (True) or one more refusal (False)."""
    if is_plan(result):
        choice.plan, choice.tier, choice.rank, choice.grasp = result, tier, rank, grasp
        return True
    choice.refusals.append(result)
    return False


def _regrasp(offer: Offer, choice: Choice, plan_regrasp, is_plan, max_pinches: int) -> bool:
    """A regrasp tier: resting poses best first, each with its own pinches first, then the
    tier's; True when one was planned."""
    start = time.perf_counter()
    poses = list(offer.poses()) if offer.poses is not None else []
    pinches = list(offer.grasps())[:max_pinches]
    choice.offer_seconds += time.perf_counter() - start
    if not poses or not pinches:
        choice.regrasp_note = ("no resting pose offers a hook grasp" if not poses else
                               "no pinch to turn the object with")
        return False
    for pose in poses:
        mine = list(pose.pinches or [])[:max_pinches]
        for rank, X_WG in enumerate([*mine, *(g.X_WG for g in pinches)]):
            start = time.perf_counter()
            result = plan_regrasp(rank, X_WG, pose)
            choice.grasp_seconds.append(time.perf_counter() - start)
            if _try(choice, result, is_plan, Tier.REGRASP, rank, X_WG):
                return True
    choice.regrasp_note = (f"none of {len(poses)} resting poses x {len(pinches)} pinches "
                           "could be planned")
    return False
