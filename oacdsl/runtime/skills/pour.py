"""``pour``: tilt the held container over a target container until its balls have left.

The cup's rim point facing the target (the *lip*) is brought above the target, a few
centimetres off its centre, and the cup is turned about a horizontal axis through the
lip until it is upside down enough for every ball to fall out; then it is turned back.
The direction the cup comes from is the nearest of a few azimuths around the target whose
tilt the whole-body IK follows at the control loop's pace with the arm's links clear of the
table and the objects (:mod:`oacdsl.runtime.armroom`). The pour succeeds
when at least :data:`SUCCESS_FRACTION` of the liquid's balls end inside the target,
counted by the simulation.

A target held by the other hand stays where it was: that hand's task keeps its goal, as
strong as the pouring hand's. A narrow target (a cup) is poured into from over its near
inner wall, lower and with a slower tilt where the balls roll out. A source resting on the
target (a carton put onto the cup) is first slid onto its near rim, away from the other
hand, and rests there a moment.

The pouring hand keeps clear of the target: its palm and fingers reach around and past
the cup they hold (a side grasp of a 7 cm carton: some 4 cm past its far side and up to
its rim), so at every step of the tilt the lip is raised as much as the hand's collision
boxes need to stay :data:`~oacdsl.runtime.motion.tuning.Tuning.rim_clearance_m` above the
target's rim where they are over it, and no more: the hand passes over the rim half-way
through the tilt, the balls leave the lip later, from its usual height (KIT Pour: the
right thumb met the cup while pouring). The source and the pouring hand keep
:data:`~oacdsl.runtime.motion.tuning.Tuning.hands_clearance_m` from the collision boxes of the
palm, fingers and thumb of a hand that holds the target, as they are: boxes beside them need
no lift, boxes over them are passed over (:mod:`oacdsl.runtime.boxlift`). A round source (no
spout) is first turned about its axis, by up to a quarter turn either way, when its lip can then
roll the balls out lower (its hand beside the lip rather than over the target: the carton of KIT
Pour mirrored, turned 60°, rolled its balls out 2.5 cm above the rim of the cup the other hand
held instead of 10.7 cm, where balls bounced out); the arm's reach decides, else it is poured
as it is held. Over a wide target
each step is raised by what the arm's measured lag needs: the hand taken to be as far off its
next goal as it is off its last one now, the cup held there must still clear the rim (at the
demonstrated pace the hand lags 1.5-2 cm below its goal as the tilt begins, and the cup came
down on the bowl's rim). Both lifts change no faster than ``Tuning.pour_lift_speed_m_s``
(:mod:`oacdsl.runtime.pourlift`): made within one step, they jerked the cup up 9 cm and down
again, and a ball thrown up in it left the lip at 1.1 m/s, over the bowl's far rim.

When the other hand holds something else, the emptied source is carried back to where it
was brought from, out of the target's way: the other hand may work over the target next
(two hands at once), and an idle hand yields to the torso as the other one works.
"""

from __future__ import annotations

import math

import numpy as np

from oacdsl.errors import RuntimeFailure
from oacdsl.runtime.armroom import arm_room
from oacdsl.runtime.boxlift import lift_to_clear
from oacdsl.runtime.control import CONTROL_DT_S
from oacdsl.runtime.motion import TUNING, Motion, OtherHand, raised
from oacdsl.runtime.pourlift import follow_lift, ramped_lift
from oacdsl.runtime.shapes import hand_corners, world_corners
from oacdsl.runtime.skills.base import REACH_TOLERANCE_M, SkillContext
from oacdsl.runtime.spout import spout_direction
from oacdsl.runtime.transforms import make_T, rot_axis
from oacdsl.skills import SIGNATURES

__all__ = ["pour", "spout_direction", "SUCCESS_FRACTION", "SIGNATURE"]

SIGNATURE = SIGNATURES["pour"]
D = SIGNATURE.defaults()

#: Share of the balls that must land in the target container.
SUCCESS_FRACTION = 0.9
#: Longest wait, tilted, for the source to empty, s.
EMPTY_S = 2.0
#: The lip's extra height above where it tilts, before tilting, m.
LIP_START_EXTRA_M = 0.07
#: Where the lip is over the target: this far from its centre towards the cup, m.
LIP_FROM_CENTRE_M = 0.03
#: A target narrower than this (inner radius, m) is a *narrow* one (a cup, not a bowl): the
#: balls leave the tilted source with some speed and would fly over its far rim or hit its
#: floor hard, so the lip goes over the target's near inner wall, :data:`NARROW_LIP_ABOVE_RIM_M`
#: above its rim, and the tilt beyond :data:`SLOW_FROM_RAD` (where the balls roll out) is
#: :data:`NARROW_SLOWDOWN` times slower.
NARROW_TARGET_M = 0.05
NARROW_LIP_ABOVE_RIM_M = 0.015
SLOW_FROM_RAD = math.radians(85.0)
NARROW_SLOWDOWN = 4.0
#: Poses the tilt is made of (the way back: half as many).
STEPS = 40


def _cup_pose(
    base_r: np.ndarray, lip_local: np.ndarray, lip_world: np.ndarray, axis: np.ndarray, angle: float
) -> np.ndarray:
    r = rot_axis(axis, angle) @ base_r
    return make_T(r, lip_world - r @ lip_local)


def pour(
    ctx: SkillContext,
    hand: str,
    source: str,
    liquid: str,
    target: str,
    *,
    tilt: float = D["tilt"],
    duration: float = D["duration"],
    height: float = D["height"],
) -> None:
    """Pour ``liquid`` from the held ``source`` into ``target``: the lip ``height`` (m) above the
    target's rim, turned to ``tilt`` (rad) over ``duration`` (s)."""
    world, ctl = ctx.world, ctx.ctl
    side = ctx.require_held(hand, source)
    if liquid not in world.built.balls:
        raise RuntimeFailure(f"pour: {liquid!r} is not a liquid of the scene")
    total = len(world.built.balls[liquid])
    t_cup, cup_in_hand = ctx.held_pose(side, source)
    cup, bowl = ctx.body(source), ctx.body(target)
    if not cup.container:
        raise RuntimeFailure(f"pour: {source!r} is no container (its shape has no shell)")
    t_bowl = world.body_pose(target)  # where it is now: on the table or in the other hand
    centre, rim_z = t_bowl[:3, 3], t_bowl[2, 3] + bowl.rim_height
    narrow = bowl.inner_radius < NARROW_TARGET_M
    off_centre = bowl.inner_radius if narrow else min(LIP_FROM_CENTRE_M, 0.5 * bowl.inner_radius)
    if narrow:
        height = min(height, NARROW_LIP_ABOVE_RIM_M)
    # the cup kept upright with its current heading (or turned about its axis, see turns()); a
    # cup with an opening in its top (a carton's spout) turned so that the opening faces the target
    yaw = math.atan2(t_cup[1, 0], t_cup[0, 0])
    spout = spout_direction(cup)

    def heading(u: np.ndarray, turn: float) -> np.ndarray:
        if spout is None:
            return rot_axis((0.0, 0.0, 1.0), yaw + turn)
        return rot_axis((0.0, 0.0, 1.0), math.atan2(-u[1], -u[0]) - math.atan2(spout[1], spout[0]))

    def hand_at(u: np.ndarray, angle: float, lift: float, turn: float = 0.0) -> np.ndarray:
        base_r = heading(u, turn)
        lip_local = base_r.T @ (-u * cup.rim_radius) + np.array([0.0, 0.0, cup.rim_height])
        lip = np.array([*(centre[:2] + u[:2] * off_centre), rim_z + height + lift])
        axis = np.cross(u, (0.0, 0.0, 1.0))
        return _cup_pose(base_r, lip_local, lip, axis, angle) @ np.linalg.inv(cup_in_hand)

    floor_z = t_bowl[2, 3] + bowl.floor
    neighbours = ctx.obstacles({source, target})  # the other objects standing on the table
    hand_pts = hand_corners(world, side)
    holder = ctx.other_holder(side, target)
    keep = world.frame_pose(f"grasp_{holder}") if holder is not None else None
    # the other hand holding the target keeps its place: the source and this hand keep
    # TUNING.hands_clearance_m from its palm, fingers and thumb as they are (a box beside one of
    # them needs no lift, a box over it goes over it)
    holder_pts = np.zeros((0, 3)) if keep is None or holder is None else (
        hand_corners(world, holder) @ keep[:3, :3].T + keep[:3, 3])

    def over_holder(pts: np.ndarray, from_m: float = 0.0) -> float:
        """The least lift (m, at least ``from_m``) of the boxes with corners ``pts`` (world) after
        which they keep :data:`TUNING.hands_clearance_m` from the other hand's."""
        return lift_to_clear(pts, holder_pts, TUNING.hands_clearance_m, from_m) if len(holder_pts) else from_m

    def need(u: np.ndarray, s: float, base: float, turn: float = 0.0) -> float:
        """How much higher (m) than ``base`` above its place the lip must be at ``s`` of the
        tilt (:func:`need_at` of the hand's pose there)."""
        return need_at(hand_at(u, tilt * s, base, turn))

    def need_at(t_hand: np.ndarray) -> float:
        """How much higher (m) the hand at ``t_hand`` must be so that the cup stays above the
        target's rim where it is over the wall or beyond it and above its floor inside it, and
        the pouring hand (its palm and fingers reach around and past the cup) stays
        :data:`TUNING.rim_clearance_m` above the rim wherever it is over the target or its rim;
        the cup and the hand as far above the top of any other object standing on the table
        wherever they are over it (a cup set down 10 cm beside the bowl met the palm of the hand
        that brought the other cup over the bowl);
        both keep :data:`TUNING.hands_clearance_m` from the boxes of a hand that holds the
        target (:func:`~oacdsl.runtime.boxlift.lift_to_clear`)."""
        pts = world_corners(cup, t_hand @ cup_in_hand)
        d = np.hypot(pts[:, 0] - centre[0], pts[:, 1] - centre[1])
        near = d < bowl.rim_radius + TUNING.end_margin_m
        low = np.where(d < bowl.inner_radius - TUNING.end_margin_m, floor_z, rim_z) + TUNING.end_margin_m
        out = float((low - pts[:, 2])[near].max()) if near.any() else 0.0
        hand = hand_pts @ t_hand[:3, :3].T + t_hand[:3, 3]
        over = np.hypot(hand[:, 0] - centre[0], hand[:, 1] - centre[1])
        near = over < bowl.rim_radius + TUNING.rim_clearance_m
        if near.any():
            out = max(out, float((rim_z + TUNING.rim_clearance_m - hand[:, 2])[near].max()))
        both = np.vstack([pts, hand])
        for xy, radius, top in neighbours:  # over another object, as over the target's rim
            near = np.hypot(both[:, 0] - xy[0], both[:, 1] - xy[1]) < radius + TUNING.rim_clearance_m
            if near.any():
                out = max(out, float((top + TUNING.rim_clearance_m - both[:, 2])[near].max()))
        return over_holder(both, max(out, 0))

    def extra_at(u: np.ndarray, s: float, base: float, turn: float = 0.0) -> float:
        """How much more than ``base`` (m) the lip must rise at ``s`` of the tilt: as much as
        :func:`need` asks there and half a tilt step either side."""
        around = (min(1.0, max(0.0, s + ds)) for ds in (-1.0 / STEPS, 0.0, 1.0 / STEPS))
        return max(0.0, *(need(u, s_k, base, turn) for s_k in around))

    def lifted(u: np.ndarray, s: float, base: float, turn: float = 0.0) -> np.ndarray:
        """The hand's pose at ``s`` of the tilt, the lip ``base`` higher than its place and as
        much more as :func:`extra_at` asks (the lip is as low as the hand allows at every
        tilt: where the balls leave it is over the rim)."""
        return hand_at(u, tilt * s, base + extra_at(u, s, base, turn), turn)

    def tilt_path(u: np.ndarray, turn: float = 0.0) -> list[np.ndarray]:
        """The hand's poses at the ``STEPS + 1`` steps of the tilt: the lip comes down from its
        start height over the first half of the tilt, raised as :func:`extra_at` asks, that
        raise changing no faster than :data:`TUNING.pour_lift_speed_m_s` (begun before the step
        that needs it and ended after: the hand's boxes passing over the bowl's rim asked for
        2.3 cm within one step, and the cup jerked up with the liquid in it)."""
        s = np.arange(STEPS + 1) / STEPS
        base = LIP_START_EXTRA_M * np.maximum(0.0, 1.0 - 2.0 * s)
        extra = np.array([extra_at(u, s_k, b_k, turn) for s_k, b_k in zip(s, base, strict=True)])
        at_s = np.concatenate([[0.0], np.cumsum([step_s(s_k) for s_k in s[1:]])])
        extra = ramped_lift(extra, at_s, TUNING.pour_lift_speed_m_s)
        return [hand_at(u, tilt * s_k, b_k + e_k, turn) for s_k, b_k, e_k in zip(s, base, extra, strict=True)]

    def roll_out_lift(u: np.ndarray, turn: float) -> float:
        """The highest the lip must rise (m) above its place while the balls roll out (the tilt
        from :data:`SLOW_FROM_RAD` on), the source turned ``turn`` (rad) about its axis."""
        rolling = (k / STEPS for k in range(1, STEPS + 1) if tilt * k / STEPS >= SLOW_FROM_RAD)
        return max(need(u, s, 0.0, turn) for s in rolling)

    def turns(u: np.ndarray) -> list[float]:
        """The turns of a round source about its axis to try from side ``u``: the one after which
        the lip rolls the balls out lowest, when it is :data:`TUNING.pour_turn_gain_m` lower than
        with the source as it is held, then no turn (a source with a spout faces it to the target)."""
        if spout is None and tilt > SLOW_FROM_RAD:
            most = round(TUNING.pour_turn_most_rad / TUNING.pour_turn_step_rad)
            ways = [k * TUNING.pour_turn_step_rad for k in range(1, most + 1)]
            lifts = {t: roll_out_lift(u, t) for t in (0.0, *ways, *(-w for w in ways))}
            best = min(lifts, key=lambda t: (lifts[t], abs(t)))
            if lifts[best] < lifts[0.0] - TUNING.pour_turn_gain_m:
                return [best, 0.0]
        return [0.0]

    def step_s(s: float) -> float:
        """Time (s) of the tilt's step to ``s``: slower where the balls roll out into a narrow target."""
        return (NARROW_SLOWDOWN if narrow and tilt * s > SLOW_FROM_RAD else 1.0) * duration / STEPS

    ctl.activity = f"planning to pour {liquid} into {target}"
    to_cup = t_cup[:2, 3] - centre[:2]
    home = math.atan2(to_cup[1], to_cup[0])
    candidates = sorted((home + k * math.pi / 4 for k in range(-3, 5)), key=lambda a: abs(a - home))
    # the nearest side to where the cup is from which the arm follows the tilt at its pace (the
    # IK stepped as the control loop steps it: near the edge of its reach it lags the tilt by
    # centimetres, and balls miss) with its links clear of the table and the objects there (the
    # IK sees neither: tilting the cup across its body, an arm laid its forearm on the bowl and
    # its elbow on the table)
    ticks = [TUNING.pose_solve_tries] + [
        max(1, round(step_s(k / STEPS) / CONTROL_DT_S)) for k in range(1, STEPS + 1)]
    # each side tried with a round source turned about its axis so that its lip rolls the balls
    # out lowest (its hand reaching less over the target: 2 cm instead of 10 cm above the rim of
    # the cup the other hand held, KIT Pour mirrored, where balls bounced out), then as it is held
    units = (np.array([math.cos(a), math.sin(a), 0.0]) for a in candidates)
    ways = ((u, turn) for u in units for turn in turns(u))
    best: tuple[float, np.ndarray, float, list[np.ndarray]] | None = None
    for u, turn in ways:
        path = tilt_path(u, turn)
        postures = ctl.ik.reach_postures(side, path, ticks)
        err = max(r.miss_m for r, _ in postures)
        if best is None or err < best[0]:
            best = (err, u, turn, path)
        rooms = (arm_room(world, side, postures[k][1], {source}) for k in (0, STEPS // 2, STEPS))
        if err < REACH_TOLERANCE_M and all(room >= TUNING.arm_room_m for room in rooms):
            best = (err, u, turn, path)
            break
    if best is None or best[0] > 3 * REACH_TOLERANCE_M:
        raise RuntimeFailure(
            f"cannot pour from {source} into {target}: no tilted pose over {target} is in reach"
            f" of {hand} (best leaves the hand {best[0] * 100 if best else float('nan'):.0f} cm off)"
        )
    u, turn, path = best[1], best[2], best[3]

    # a hand holding the target keeps it where it was (its goal fixed, as strong a task as the
    # pouring hand's: the whole-body IK would otherwise let it drift with the torso as the source tilts)
    m = Motion(ctx, side, OtherHand.STEADY if holder is not None else OtherHand.IDLE, keep=keep)

    def go(goal: np.ndarray, seconds: float) -> None:
        """Move the hand to ``goal``, over a wide target raised as much as the arm's measured lag
        needs: where the hand is now against where it was sent (the wrist turns before the
        shoulder and the elbow follow: tilting at the demonstrated pace the hand is 1.5-2 cm below
        its goal) is taken to hold at ``goal`` too, and the cup held there must still clear the
        target's rim."""
        sent, now = m.here(), world.frame_pose(f"grasp_{side}")
        expect = make_T(now[:3, :3] @ sent[:3, :3].T @ goal[:3, :3], goal[:3, 3] + now[:3, 3] - sent[:3, 3])
        # not over a narrow target: its lip hugs the near wall, and raised there by the lag, the
        # carton of KIT Pour (seed 4) sent a ball past the cup. The lift changes no faster than
        # TUNING.pour_lift_speed_m_s: the lag is measured against the lifted goal, and a lift
        # made in one tick fed itself (the cup jerked up 9 cm and down, throwing a ball out)
        want = 0.0 if narrow else max(0.0, need_at(expect))
        lift[0] = follow_lift(lift[0], want, seconds, TUNING.pour_lift_speed_m_s)
        m.go(raised(goal, lift[0]), seconds)

    lift = [0.0]  # the lift (m) go() gives the lip now

    if world.touching(source, target):
        # slid outwards (towards the pouring side), its base's middle over the near rim, out of
        # the way of the other hand, before the pour lifts it
        ctl.activity = f"resting {source} on {target}"
        t_src = world.body_pose(source)
        t_src[:2, 3] = centre[:2] + u[:2] * bowl.rim_radius
        t_go = t_src @ np.linalg.inv(cup_in_hand)
        slid = np.vstack([world_corners(cup, t_src), hand_pts @ t_go[:3, :3].T + t_go[:3, 3]])
        if not over_holder(slid):
            m.go(t_go, TUNING.shift_s)  # else it rests where it is: the slide would meet the other hand
        m.hold_still()
    ctl.activity = f"bringing {source} over {target}"
    came_from = m.here()
    m.carry(path[0], {source, target}, TUNING.work_carry_s)
    ctl.activity = f"pouring {liquid} into {target}"
    for k in range(1, STEPS + 1):
        go(path[k], step_s(k / STEPS))
    m.hold_still(EMPTY_S, until=lambda: world.balls_inside(source, liquid) == 0)
    m.hold_still(TUNING.shift_s)
    back = STEPS // 2
    for k in range(1, back + 1):
        s = 1.0 - k / back
        go(lifted(u, s, LIP_START_EXTRA_M * (1.0 - s), turn), 1.0 / back)
    inside = world.balls_inside(target, liquid)
    if inside < SUCCESS_FRACTION * total:
        left = world.balls_inside(source, liquid)
        raise RuntimeFailure(
            f"pour: only {inside} of {total} balls of {liquid} ended in {target}"
            f" ({left} still in {source}; needed {math.ceil(SUCCESS_FRACTION * total)})"
        )
    other = world.held.get("l" if side == "r" else "r")
    if other is not None and other != target and not _over(came_from, centre, bowl.rim_radius + cup.radius):
        # the other hand holds something else: it may work over the target next (two hands at
        # once); the emptied source, held up over the target, would be in its way (and an idle
        # hand yields to the torso as the other works): it goes back where it was brought from
        ctl.activity = f"taking {source} off {target}"
        m.carry(came_from, {source, target}, TUNING.work_carry_s)


def _over(t_hand: np.ndarray, centre: np.ndarray, radius_m: float) -> bool:
    """Whether the hand pose ``t_hand`` is within ``radius_m`` of ``centre`` seen from above."""
    return bool(np.hypot(*(t_hand[:2, 3] - centre[:2])) < radius_m)
