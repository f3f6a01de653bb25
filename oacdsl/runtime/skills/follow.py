"""``follow``: a sub-action from the demonstration alone.

The held object ``o`` is moved along the path the demonstration showed relative to the
target ``t`` (the step's ``path [ … ]``, written by the composer; docs/runtime.md, "follow"):
its reference point (the middle of its declared markers, else of its height: what the closed
loop's virtual markers see) relative to ``t``'s, in ``t``'s frame turned so that x points
from ``t`` to where ``o`` starts. :func:`~oacdsl.runtime.retarget.retarget` fits the path to
the robot (from where ``o`` is, into ``t``'s room, rotations and speed capped). Before it
moves, the whole-body IK is asked for its keyframes with the other hand's goal as it will be:
when it cannot reach them, the orientation becomes a soft wish, then the path is shrunk
towards its middle (:data:`~oacdsl.runtime.retarget.FOLLOW`), before the skill gives up. ``t``
is read where it is at every keyframe (a cup the other hand holds may drift).

The step's predicted effect decides the contact: when it says ``o <-> t``, the path ends with
its core, and the core starts with a guarded approach along ``t``'s axis until they touch (or
the wrist feels ``force``); the rest of the path is shifted by what that found and pressed
``press`` on, and at the end ``o`` must touch ``t`` (one more guarded approach mends a contact
lost on the way). In a container the core's lowest keyframe is put where they touched. On a
solid target the core starts with ``o``'s lowest end over ``t``'s box, and runs from where
they touched, never deeper (:func:`~oacdsl.runtime.retarget.floored`: the demonstrator's knife
went into the cucumber), lowered while they do not touch (the slide's seek,
:data:`~oacdsl.runtime.motion.TUNING`): the demonstration keeps them together there. When it
says ``not o <-> t``, ``o`` must be off ``t`` at the end (raised straight up until it is).
The other hand keeps an idle hand's hold, or, when it holds something other than a container
``t``, its goal fixed (as ``touch``). The core's demonstrated turns are scaled down until the
object keeps clear of that hand (:mod:`oacdsl.runtime.follow_clear`). A turn about the object's
own axis beyond ``turn``, where it can rest on ``t``, is split into pieces with regrasps on
``t`` in between (:mod:`oacdsl.runtime.follow_turns`,
:mod:`~oacdsl.runtime.skills.follow_regrasp`); an object that starts on ``t`` and is to leave
it follows the core from where it rests.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from oacdsl.errors import RuntimeFailure
from oacdsl.runtime.bodies import Body
from oacdsl.runtime.follow_clear import clear_of_hand
from oacdsl.runtime.follow_turns import split, wound
from oacdsl.runtime.motion import TUNING
from oacdsl.runtime.motion.both import mover
from oacdsl.runtime.retarget import FOLLOW, MIN_OFFSET_M, Retargeted, floored, retarget, shifted
from oacdsl.runtime.shapes import lowest_z, world_corners
from oacdsl.runtime.skills.base import SkillContext
from oacdsl.runtime.skills.follow_reach import reachable
from oacdsl.runtime.skills.follow_regrasp import Regrasps, rests_on
from oacdsl.runtime.skills.follow_top import END_SPAN_M, lowest_end, on_top, onto_top
from oacdsl.runtime.skills.follow_wall import WallSeek, clear_of_rim
from oacdsl.runtime.transforms import MIN_JERK_PEAK, make_T, rot_z

__all__ = ["follow", "reference_point"]


def reference_point(body: Body) -> np.ndarray:
    """The point of an object a path follows, in its frame (m): its declared markers' middle,
    else half its height on its axis."""
    if body.points:
        return np.mean(np.asarray(body.points, dtype=np.float64), axis=0)
    return np.array([0.0, 0.0, 0.5 * body.height])


def follow(ctx: SkillContext, hand: str, obj: str, target: str, *, path: Sequence[Sequence[float]] = (),
           speed: float = 0.25, turn: float = math.radians(30.0), press: float = 0.003,
           force: float = 10.0) -> None:
    """Move the held ``obj`` along ``path`` relative to ``target`` (module doc); ``speed`` m/s,
    ``turn`` rad, ``press`` m, ``force`` N."""
    world, ctl = ctx.world, ctx.ctl
    side = ctx.require_held(hand, obj)
    if target not in world.layout.bodies or not ctx.body(target).solids:
        raise RuntimeFailure(f"follow: {target!r} is no object of the scene")
    if len(path) < 2:
        raise RuntimeFailure(
            f"follow: no path to follow for {obj} relative to {target}: compose the OAC from a"
            " demonstration (oacc compose / reproduce) or write 'path [ … ]' on the step"
        )
    body_o, body_t = ctx.body(obj), ctx.body(target)
    ref_o, ref_t = reference_point(body_o), reference_point(body_t)
    t_obj, obj_in_hand = ctx.held_pose(side, obj)
    grasp_in_obj = np.linalg.inv(obj_in_hand)

    def frame(phi: float) -> tuple[np.ndarray, np.ndarray]:
        t = world.body_pose(target)
        return t[:3, :3] @ ref_t + t[:3, 3], t[:3, :3] @ rot_z(phi)

    origin, r_t = frame(0.0)
    rel = r_t.T @ (t_obj[:3, :3] @ ref_o + t_obj[:3, 3] - origin)
    phi = math.atan2(float(rel[1]), float(rel[0])) if float(np.linalg.norm(rel[:2])) >= MIN_OFFSET_M else 0.0
    r_f = frame(phi)[1]
    r0 = r_f.T @ t_obj[:3, :3]  # the object's orientation at the start, in the turned frame
    room = None
    if body_t.container:
        room = max(body_t.inner_radius - body_o.radius - FOLLOW.wall_gap_m, 0.0)
    elif body_t.radius > 0:
        room = max(body_t.radius - FOLLOW.overhang * body_o.radius, 0.0)
    touch = ctx.expected is None or ctx.expected.touches(obj, target)
    # it starts on the target and is to leave it (a lid to unscrew): the core from where it rests
    resting = not touch and world.touching(obj, target)
    # a turn about its own axis beyond ``turn`` in pieces, regrasping on the target in between
    # (follow_turns), where it can rest there: round, standing upright on a solid top as wide
    axis_f = r0[:, 2] if turn > 0 and rests_on(body_o, body_t, t_obj, world.body_pose(target)) else None
    plan, cuts = split(retarget(np.asarray(path, dtype=np.float64), room_m=room, speed_m_s=speed,
                                turn_rad=turn, stay=touch, twist_axis=axis_f,
                                core_speed_m_s=FOLLOW.contact_speed_m_s if touch else None,
                                inside=touch and body_t.container, resting=resting),
                       turn, TUNING.turn_min_stroke_s)

    def pose_at(r: Retargeted, k: int, lift_m: float = 0.0) -> np.ndarray:
        """T_world_obj at keyframe ``k``, raised ``lift_m`` along the target's axis."""
        o, rf = frame(phi)
        rot = rf @ r.rotation(k) @ r0
        return make_T(rot, o + rf @ (r.positions_m[k] + np.array([0.0, 0.0, lift_m])) - rot @ ref_o)

    def hand_at(r: Retargeted, k: int, lift_m: float = 0.0) -> np.ndarray:
        """The hand at keyframe ``k`` as planned: turned back about the object's axis by the
        regrasps before it."""
        return pose_at(r, k, lift_m) @ make_T(rot_z(-wound(r, cuts, k)), np.zeros(3)) @ grasp_in_obj

    # the object's reference point in the grasp frame (homogeneous)
    ref_in_grasp = np.append(obj_in_hand[:3, :3] @ ref_o + obj_in_hand[:3, 3], 1.0)
    other = "l" if side == "r" else "r"
    keep = None
    if world.held.get(other) is not None and not (world.held.get(other) == target and body_t.container):
        keep = ctl.ik.goal(other)
    # half the room away from the other hand when it holds a container target (frame coords)
    away = None
    if world.held.get(other) == target and room and body_t.container:
        o, rf = frame(phi)
        d = rf.T @ (o - world.frame_pose(f"grasp_{other}")[:3, 3])
        d[2] = 0.0
        away = d / max(float(np.linalg.norm(d)), 1e-9) * room / 2
    # the core starts with the object's lowest point ``hover`` above the target's top: the
    # demonstrator's objects (and their markers) are not the robot's, so how high the path runs
    # comes from the contact, not from the markers
    c = plan.core
    top = float(world_corners(body_t, world.body_pose(target))[:, 2].max())
    if away is not None:  # two hands close together collide: the core on the target's far half
        plan = shifted(plan, away, room)
    if body_t.container and room is not None and not resting:  # (resting: the core from where it is)
        # the object's lowest end (a spoon's bowl, not its markers' middle) goes into the container:
        # the core moved so that the end starts within the room of the axis
        end = lowest_end(body_o, pose_at(plan, c))
        o, rf = frame(phi)
        tip = (rf.T @ (end - o))[:2]
        over = float(np.linalg.norm(tip))
        if over > room:
            plan = shifted(plan, np.append(-tip * (1 - room / over), 0.0), room)
    elif room is not None and not resting:
        # a solid target: the object's lowest end (a knife's edge) starts over the target's top,
        # which the room about its middle does not see (a cucumber 15 cm long, 4.5 cm wide)
        holder = world.frame_pose(f"grasp_{other}")[:3, 3] if world.held.get(other) == target else None
        move = onto_top(body_o, pose_at(plan, c), body_t, world.body_pose(target), frame(phi)[1], holder)
        plan = shifted(plan, move, None if holder is not None else room)
        plan = on_top(plan, body_o, pose_at(plan, c), body_t, world.body_pose(target), frame(phi)[1], holder)
    plan = clear_of_hand(world, other, body_o, plan,
                          lambda r, k: pose_at(r, k, top - lowest_z(body_o, pose_at(r, c))))

    def ref_height() -> float:
        """The object's reference point above the target's, along its axis, now (m)."""
        o, rf = frame(phi)
        return float((rf.T @ (world.body_pose(obj)[:3, :3] @ ref_o + world.body_pose(obj)[:3, 3] - o))[2])

    def start_lift(r: Retargeted) -> float:
        """How far the core is raised: its lowest point ``hover_m`` over the target's top, or,
        resting on it, from where it rests (pressed on, the hand's fingers round a lid let go
        of for a regrasp reached the bottle)."""
        if resting:
            return ref_height() - float(r.positions_m[r.core, 2])
        return top + FOLLOW.hover_m - lowest_z(body_o, pose_at(r, r.core))

    lift = start_lift(plan)
    plan, weight = reachable(ctx, side, keep, plan, lambda r, k, _: hand_at(r, k, lift),
                              f"the path of {obj} relative to {target}",
                              lambda v: frame(phi)[1].T @ v, room, ref_in_grasp)
    go = mover(ctl, side, keep, weight)

    met = [False]  # the two touched during an approach (a tool that bounced off still found it)
    # in a container it is to touch: the hand kept clear of the rim, the contact from the wall
    # where the floor is out of reach (follow_wall)
    in_container = touch and body_t.container
    clear = clear_of_rim(ctx, side, target) if in_container else (lambda pose: pose)

    def touching() -> bool:
        return world.touching(obj, target)

    def met_now() -> bool:
        now = touching()
        met[0] = met[0] or now
        return now

    def approach(depth: float) -> None:
        """Down along the target's axis by up to ``depth`` (m) until touching or felt."""
        axis = frame(phi)[1][:, 2]
        now = ctl.ik.goal(side)
        go(clear(make_T(now[:3, :3], now[:3, 3] - depth * axis)),
           MIN_JERK_PEAK * depth / FOLLOW.approach_speed_m_s,
           guard=lambda: met_now() or float(np.linalg.norm(ctl.force_change(side))) > force)

    lift = start_lift(plan)
    ctl.activity = f"bringing {obj} to {target}"
    if resting:
        go(hand_at(plan, c, lift), FOLLOW.settle_s)
    for pose, seconds in [] if resting else ctx.carry_path(side, hand_at(plan, c, lift), {obj, target}):
        if seconds > 0:
            go(pose, seconds)
    if touch and not touching():
        ctl.activity = f"bringing {obj} onto {target}"
        ctl.wait(FOLLOW.settle_s, until=lambda: ctl.ik.residual(side).position_m < FOLLOW.reach_m / 2)
        approach(FOLLOW.hover_m + body_t.height)
        if room and lowest_z(body_o, world.body_pose(obj)) > top - END_SPAN_M:
            # on the rim of a container it fits into, not in: over the axis by as much as its end
            # is off it, and down again (one as wide as the opening, a carton on a cup, rests on it)
            end = lowest_end(body_o, world.body_pose(obj))
            o, rf = frame(phi)
            off = end - o - float((end - o) @ rf[:, 2]) * rf[:, 2]
            now = ctl.ik.goal(side)
            go(make_T(now[:3, :3], now[:3, 3] - off + FOLLOW.hover_m / 2 * rf[:, 2]), FOLLOW.settle_s)
            approach(FOLLOW.hover_m + body_t.height)
        if body_t.container:
            # the rest of the core from where they touch, its lowest keyframe there; not touching
            # (the hand kept clear of the rim above the floor), from where it is
            lift = ref_height() - (press if touching() else 0.0) - float(plan.positions_m[c:, 2].min())
        elif met[0] or touching():  # a solid target: from where they touched, pressed on, never deeper
            plan = floored(plan)
            lift = ref_height() - press - float(plan.positions_m[c, 2])
    ctl.activity = f"following the demonstrated path of {obj} at {target}"
    seek = touch and not body_t.container  # on a solid target the core keeps the contact (module doc)
    sink = 0.0
    turns = None
    if cuts:  # a turn beyond the wrist: in pieces, regrasping in between (follow_regrasp)
        turns = Regrasps(ctx, side, obj, target, keep, plan, cuts, lambda k: pose_at(plan, k, lift - sink))
    grip = grasp_in_obj if turns is None else turns.start(grasp_in_obj)  # (a regrasp changes it)
    wall = WallSeek(ctx, side, obj, target, [pose_at(plan, k, lift) for k in range(c, len(plan.times_s))]
                    ) if in_container else None
    for k in range(c + 1, len(plan.times_s)):
        dt = float(plan.times_s[k] - plan.times_s[k - 1])
        if seek and not touching():
            sink = min(sink + TUNING.seek_speed_m_s * dt, TUNING.seek_max_m)
        if wall is not None:
            wall.grow(dt)
            obj_at = pose_at(plan, k, lift)
            go(clear(wall.pushed(obj_at) @ grip), dt)
            continue
        go(pose_at(plan, k, lift - sink) @ grip, dt)
        if turns is not None:
            grip = turns.after(k, grip)
    if turns is not None:
        turns.check()
    if touch:
        if not ctl.wait(FOLLOW.rest_s, until=touching) and not touching():
            # lost on the way: from above the core's middle, down again until they touch
            mid = np.median(plan.positions_m[c:], axis=0)
            k = c + int(np.argmin(np.linalg.norm(plan.positions_m[c:] - mid, axis=1)))
            go(pose_at(plan, k, lift + FOLLOW.hover_m) @ grip, FOLLOW.settle_s)
            approach(2 * FOLLOW.hover_m + body_t.height)
        if not ctl.wait(FOLLOW.rest_s, until=touching) and not touching():
            raise RuntimeFailure(f"follow: {obj} does not touch {target} at the end of its path")
    elif touching():
        now = ctl.ik.goal(side)
        go(make_T(now[:3, :3], now[:3, 3] + np.array([0.0, 0.0, FOLLOW.hover_m + body_t.height])),
           MIN_JERK_PEAK * (FOLLOW.hover_m + body_t.height) / FOLLOW.approach_speed_m_s,
           guard=lambda: not touching())
        if touching():
            raise RuntimeFailure(f"follow: {obj} still touches {target} at the end of its path")
    if world.held[side] != obj:
        raise RuntimeFailure(f"follow: {hand} lost {obj}")
