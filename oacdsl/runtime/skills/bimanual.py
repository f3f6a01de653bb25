"""``grasp_both`` and ``place_both``: both arms at once.

The whole-body IK has a task per hand; here both are active and move together, each
along its own way, in lockstep (a phase ends when the slower hand is there). Each hand's
grasp is planned and checked as :func:`~oacdsl.runtime.skills.grasp.reach_and_grasp`
plans it, each place as :func:`~oacdsl.runtime.skills.place.place` does; each hand's
guard (its contact, its wrist force) stops that hand alone, so the two hands' contacts
may happen at different instants. Both hands may take the same object (a wide bowl by
both sides): it is then lifted and set down by both together.
"""

from __future__ import annotations

from collections.abc import Mapping
from functools import partial

import numpy as np

from oacdsl.errors import RuntimeFailure
from oacdsl.runtime.control import Controller
from oacdsl.runtime.grasping import GraspPlan
from oacdsl.runtime.handgap import hands_gap
from oacdsl.runtime.hands import OPEN, TOP_PRESHAPE
from oacdsl.runtime.motion import TUNING, down, withdrawal
from oacdsl.runtime.motion.both import lockstep, move_both, paced
from oacdsl.runtime.motion.detour import boxes, first_to_carry
from oacdsl.runtime.skills.base import REACH_TOLERANCE_M, SkillContext, cm
from oacdsl.runtime.skills.grasp import (
    HANDS_APART_M,
    GraspMotion,
    ease_off,
    grasp_candidates,
    lifted,
    plan_grasp,
    preshape,
    secure,
)
from oacdsl.runtime.skills.hold_up import hold_in_front
from oacdsl.runtime.skills.place import set_down_pose
from oacdsl.runtime.transforms import MIN_JERK_PEAK
from oacdsl.skills import SIGNATURES

__all__ = ["grasp_both", "place_both", "reach_both"]

GRASP_BOTH, PLACE_BOTH = SIGNATURES["grasp_both"].defaults(), SIGNATURES["place_both"].defaults()
HOLD_UP = SIGNATURES["hold_up"].defaults()
#: How many of each hand's reachable grasps are paired up.
PAIR_CANDIDATES = 4


def _felt(ctl: Controller, side: str, force: float) -> bool:
    """The wrist of ``side`` felt more than ``force`` (N) since its motion began."""
    return float(np.linalg.norm(ctl.force_change(side))) > force


def _set_on(ctx: SkillContext, side: str, obj: str, force: float) -> bool:
    """The wrist of ``side`` felt more than ``force`` (N) and its ``obj`` rests on something.
    Both hands go down at once: the jolt of one object meeting the table reaches the other
    wrist through the body (a knife still 3 cm up was let go of and fell over)."""
    return _felt(ctx.ctl, side, force) and ctx.world.supported(obj)


def reach_both(ctx: SkillContext, targets: Mapping[str, np.ndarray]) -> float:
    """The larger residual (m, angle weighted 0.1 m/rad) of a static whole-body solve
    with both hands at ``targets`` (side → T_world_grasp); the IK is left as it was."""
    return ctx.ctl.ik.try_reach_both(targets)


def _pair(ctx: SkillContext, a: tuple[str, str], b: tuple[str, str]) -> tuple[GraspPlan, GraspPlan]:
    """The first pair of grasps (each among its hand's first reachable few) that the
    whole-body IK reaches together with :data:`HANDS_APART_M` between the two hands."""
    options = []
    shapes = (preshape(ctx, a[1]), preshape(ctx, b[1]))
    for hand, obj in (a, b):
        side = ctx.side(hand)
        shared = a[1] == b[1]  # one object in both hands: each takes it on its own side
        candidates = grasp_candidates(ctx, hand, obj, shared)
        reachable = [p for p in candidates if ctx.reach_error(side, p.grasp) < REACH_TOLERANCE_M]
        if not reachable:  # the usual out-of-reach failure, naming the closest miss
            ctx.first_reachable(side, [(p.grasp, p) for p in candidates], obj)
        options.append((side, reachable[:PAIR_CANDIDATES]))
    (s1, c1), (s2, c2) = options
    pairs = sorted(((i, j) for i in range(len(c1)) for j in range(len(c2))), key=lambda ij: (sum(ij), ij))
    best: tuple[float, GraspPlan, GraspPlan] | None = None
    widest = 0.0
    for i, j in pairs:
        p1, p2 = c1[i], c2[j]
        gap = hands_gap((s1, p1.grasp, shapes[0]), (s2, p2.grasp, shapes[1]))
        widest = max(widest, gap)
        if gap < HANDS_APART_M:
            continue
        err = reach_both(ctx, {s1: p1.grasp, s2: p2.grasp})
        if err < REACH_TOLERANCE_M:
            return p1, p2
        if best is None or err < best[0]:
            best = (err, p1, p2)
    if best is None or best[0] > 2 * REACH_TOLERANCE_M:
        why = (
            f"the best whole-body IK solution for both leaves a hand off by {cm(best[0])}"
            if best is not None
            else f"no pair of their grasps leaves {cm(HANDS_APART_M)} between the hands"
            f" (at most {widest * 100:.1f} cm)" + (_shared_hint(ctx, a[1]) if a[1] == b[1] else "")
        )
        raise RuntimeFailure(f"{a[0]} cannot grasp {a[1]} while {b[0]} grasps {b[1]}: {why}")
    return best[1], best[2]


def _shared_hint(ctx: SkillContext, obj: str) -> str:
    """How one object in both hands is taken, for the failure above."""
    x, y, z = (float(v) + 0.0 for v in ctx.grasp_for(obj).offset)
    return (f"; one object in both hands is taken at its grasp offset ({x:g}, {y:g}, {z:g}) and at"
            f" ({0.0 - x:g}, {0.0 - y:g}, {z:g}), each hand on its own side, and it stands with its x"
            " axis away from the robot: an offset along y, to the robot's left, puts the hands apart")


def _sides(ctx: SkillContext, h1: str, h2: str, what: str) -> tuple[str, str]:
    s1, s2 = ctx.side(h1), ctx.side(h2)
    if s1 == s2:
        raise RuntimeFailure(f"{what} needs two different hands ({h1} given twice)")
    return s1, s2


def grasp_both(
    ctx: SkillContext, h1: str, o1: str, h2: str, o2: str, *, lift: float = GRASP_BOTH["lift"]
) -> None:
    """Grasp ``o1`` with ``h1`` and ``o2`` with ``h2`` at the same time, then lift both by ``lift``
    (m). Together only when the whole-body IK keeps both hands on their ways (slowed by the
    tuning's ``pace_factor`` if need be: :func:`~oacdsl.runtime.motion.both.paced`); else one
    after the other. Both reaching far across the table at once, the torso bent to its limits
    and a hand sagged 17 cm below its way onto a rack (92 N) or stayed 12 cm above its grasp."""
    world = ctx.world
    _sides(ctx, h1, h2, "grasp_both")
    for hand in (h1, h2):
        held = world.held[ctx.side(hand)]
        if held is not None:
            raise RuntimeFailure(f"{hand} already holds {held}")
    p1, p2 = _pair(ctx, (h1, o1), (h2, o2))
    apart = p1.grasp[:3, 3] - p2.grasp[:3, 3]
    try:
        _grasp_pair(ctx, (h1, o1, p1), (h2, o2, p2), lift)
    except RuntimeFailure as failure:
        if o1 == o2 and abs(float(apart[1])) < abs(float(apart[0])):  # one hand behind the other
            raise RuntimeFailure(f"{failure}{_shared_hint(ctx, o1)}") from None
        raise


def _grasp_pair(ctx: SkillContext, a: tuple[str, str, GraspPlan], b: tuple[str, str, GraspPlan],
                lift: float) -> None:
    """:func:`grasp_both` once its pair of grasps is chosen."""
    ctl = ctx.ctl
    (h1, o1, p1), (h2, o2, p2) = a, b
    motions = [plan_grasp(ctx, h1, o1, p1), plan_grasp(ctx, h2, o2, p2)]
    slower = TUNING.pace_factor
    ways = {m.side: _way(m) for m in motions}
    together = paced(ctl, ways, REACH_TOLERANCE_M, slower, TUNING.settle_s)
    if together is not None:
        _take(ctx, motions, together, lift)
        return
    first, second = motions  # one after the other, each at a pace its arm keeps to its way
    _take(ctx, [first], _pace(ctx, first), lift)
    pace = paced(ctl, {second.side: _way(second)}, REACH_TOLERANCE_M, slower, TUNING.settle_s)
    if pace is None and not first.handover:
        # the first object held where it was taken keeps that arm stretched and the torso bent
        # (a plate far out on the table: the other hand then stayed 9 cm from the sponge):
        # brought in front of the robot on its hand's side first, as high as ``hold_up`` holds it
        hold_in_front(ctx, h1, o1, up=max(HOLD_UP["lift"] - lift, 0.0))
        second = plan_grasp(ctx, h2, o2)  # its own first reachable grasp from there
    _take(ctx, [second], pace or _pace(ctx, second), lift)


def _pace(ctx: SkillContext, m: GraspMotion) -> float:
    """How much slower than planned hand ``m`` reaches alone so that it keeps to its way (the
    slowest of the tuning's ``pace_factor`` when none does)."""
    slower = TUNING.pace_factor
    return paced(ctx.ctl, {m.side: _way(m)}, REACH_TOLERANCE_M, slower, TUNING.settle_s) or slower[-1]


def _way(m: GraspMotion) -> list[tuple[np.ndarray, float]]:
    """The way of a grasp's hand: its waypoints, then its approach to the grasp pose."""
    return [*m.waypoints, (m.plan.grasp, m.approach_s)]


def _take(ctx: SkillContext, motions: list[GraspMotion], slower: float, lift: float) -> None:
    """Each hand of ``motions`` grasps its object, together, the motions ``slower`` times as long
    as planned, then lifts it by ``lift`` (m)."""
    world, ctl = ctx.world, ctx.ctl
    names = " and ".join(m.obj for m in motions)
    ctl.activity = f"reaching for {names}"
    for m in motions:
        if m.grasp.approach == "top":
            ctl.set_fingers(m.side, TOP_PRESHAPE)
    lockstep(ctl, {m.side: [(pose, t * slower) for pose, t in m.waypoints] for m in motions})
    ctl.activity = f"approaching {names}"
    move_both(
        ctl,
        {m.side: m.plan.end for m in motions},
        slower * max(m.approach_s for m in motions),
        {m.side: partial(m.arrived, world) for m in motions},
    )
    eased = {m.side: e for m in motions if (e := ease_off(ctx, m)) is not None}
    if eased:
        move_both(ctl, eased, TUNING.press_s)
    ctl.activity = " and ".join(f"closing {m.hand} on {m.obj}" for m in motions)
    for m in motions:
        ctl.set_fingers(m.side, m.closed)
    # each hand is welded the moment its fingers touch (a closing finger pushes a light object away)
    pending = list(motions)

    def weld_touching() -> bool:
        for m in [m for m in pending if m.holding(world)]:
            secure(ctx, m)
            pending.remove(m)
        return not pending

    ctl.wait(TUNING.close_s, until=weld_touching)
    for m in pending:
        secure(ctx, m)  # raises with the reason
    ctl.wait(TUNING.settle_s)
    up = {m.side: lifted(ctx, m.side, lift) for m in motions if not m.handover}
    if up:
        ctl.activity = f"lifting {names}"
        move_both(ctl, up, TUNING.lift_s)


def _carry_both(ctx: SkillContext, objs: dict[str, str], hover: dict[str, np.ndarray],
                paths: dict[str, list[tuple[np.ndarray, float]]], supports: dict[str, set[str]]) -> None:
    """Both hands to their ``hover`` poses: along ``paths`` together, each planned as if the
    other's object were gone (it leaves), when the two hands and what they carry keep clear of
    each other on the way (:func:`~oacdsl.runtime.motion.detour.first_to_carry`); else one after
    the other, each way planned round the other hand's object where it is then (held up: the
    carry's detour and slant keep clear of it)."""
    sides = list(objs)
    starts = [ctx.ctl.ik.goal(s) for s in sides]
    first = first_to_carry([boxes(ctx.world, s) for s in sides], starts, [paths[s] for s in sides])
    if first is None:
        lockstep(ctx.ctl, paths)
        return
    for side in (sides[first], sides[1 - first]):
        ctx.ctl.activity = f"carrying {objs[side]}"
        lockstep(ctx.ctl, {side: ctx.carry_path(side, hover[side], {objs[side]} | supports[side])})


def place_both(
    ctx: SkillContext, h1: str, o1: str, h2: str, o2: str, *, force: float = PLACE_BOTH["force"]
) -> None:
    """Set down ``o1`` held by ``h1`` and ``o2`` held by ``h2`` at the same time (where each
    step's predicted effect says, as ``place``); each descent stops when its wrist feels
    ``force`` (N) with its object on the support, and both are still a moment before they let
    go. One object held by both hands is set down where it is."""
    world, ctl = ctx.world, ctx.ctl
    sides = _sides(ctx, h1, h2, "place_both")
    for hand, obj in ((h1, o1), (h2, o2)):
        ctx.require_held(hand, obj)
    picks = {s: ctx.picked.get(s) for s in sides}
    ctl.activity = f"carrying {o1} and {o2}"
    hover: dict[str, np.ndarray] = {}
    if o1 == o2:  # one object in both hands: straight down from where it is
        hover = {s: ctl.ik.goal(s) for s in sides}
    else:
        paths, supports = {}, {}
        for side, obj in zip(sides, (o1, o2), strict=True):
            pose, where, support = set_down_pose(ctx, side, obj, picks[side], {o1, o2} - {obj})
            ctx.check_reachable(side, pose, f"the place of {obj} on {where}")
            hover[side], supports[side] = pose, {support} if support else set()
            paths[side] = ctx.carry_path(side, pose, {o1, o2} | supports[side])
        _carry_both(ctx, dict(zip(sides, (o1, o2), strict=True)), hover, paths, supports)
        ctl.wait(TUNING.carry_pause_s)
    ctl.activity = f"setting {o1} and {o2} down"
    depth = TUNING.hover_m + TUNING.support_search_m
    felt = move_both(
        ctl,
        {s: down(t, depth) for s, t in hover.items()},
        MIN_JERK_PEAK * depth / TUNING.set_down_speed_m_s,
        {s: partial(_set_on, ctx, s, o, force) for s, o in zip(sides, (o1, o2), strict=True)},
        # as ``place``: a hand that felt the support keeps pressing by its arm's lag; stopped
        # where it really is, the arm, relieved, rose and lifted its object a few mm off the
        # support, and a knife standing on its blade, let go of there, dropped and tipped over
        stop_at_model=True,
    )
    if o1 == o2 and any(felt.values()):
        felt = dict.fromkeys(sides, True)  # the support took the object from both hands
    missing = [h for h, s in ((h1, sides[0]), (h2, sides[1])) if not felt[s]]
    if missing:
        raise RuntimeFailure(
            f"the wrist of {' and '.join(missing)} felt no support after lowering {cm(depth)}"
        )
    ctl.wait(TUNING.settle_s)  # as ``place``: the arms, which lag their commands, come to rest
    ctl.activity = f"releasing {o1} and {o2}"
    for s in sides:
        world.release(s)
    for s in sides:
        ctl.set_fingers(s, OPEN)
    ctl.wait(TUNING.open_s)
    ctl.activity = "withdrawing"
    paths = {
        s: withdrawal(ctl.ik.frame(f"grasp_{s}"), p.approach if p is not None else None)
        for s, p in ((s, ctx.picked.get(s)) for s in picks)  # as set down (turned to a free spot)
    }
    for s in sides:
        ctx.picked.pop(s, None)
    lockstep(ctl, paths)
