"""``twist``: turn a held object about its own axis while it touches another (a lid on a bottle).

The object is first brought onto the target as :func:`~oacdsl.runtime.skills.touch.touch`
does, when it does not touch it yet (a lid put on the bottle the other hand holds). It
is then turned by ``angle`` about its own z axis (the axis every shape of the language
stands on; positive: counterclockwise seen from above, as a right-hand thread's lid is
unscrewed; negative: screwed on), in ``duration`` (at least what its strokes and regrasps
need, about :data:`REGRASP_S` each). Each stroke also brings the object's axis back onto the
target's and keeps it pressed lightly on the target's top. A hand turns at most ``stroke``
at a time, as a person's does: between strokes it lets go (the fingers open, the thumb
stays), rises, turns back and takes the object again, which stays on the target. Before it
lets go, the hand slides the object, still held and pressed on, onto the middle of the
target's top (:func:`centre`: the arm lags a turning hand by centimetres, and an object
let go off the middle tipped over the edge). While the other
hand holds something (the bottle), its goal stays fixed, as strong a task as the turning
hand's. With ``lift`` the object is then raised that far off the target (a lid unscrewed
and taken off); without, it stays on the target, touching it (the OAC's effect ``o <-> t``).

The skill measures how far the object really turned (about the same axis, over each stroke
and each regrasp, which turns it back a few degrees), makes up for the difference with more
strokes (up to :data:`MAX_STROKES` times as many as ``angle`` needs), and fails when it
turned less than :data:`MIN_TURNED` of ``angle``, or the other way.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from oacdsl.errors import RuntimeFailure
from oacdsl.runtime.hands import CLOSED, OPEN, PINCH_CLOSED, finger_joint_names
from oacdsl.runtime.motion import TUNING, Motion, OtherHand
from oacdsl.runtime.skills.base import SkillContext
from oacdsl.runtime.skills.grasp import SQUEEZE_RAD
from oacdsl.runtime.skills.shapes import corners, lowest_z, world_corners
from oacdsl.runtime.skills.touch import bring_onto
from oacdsl.runtime.transforms import make_T, rot_axis

__all__ = ["twist", "TWIST_RAD", "TWIST_S", "STROKE_RAD", "MIN_TURNED"]

#: Default turn, rad (half a turn: a screw lid comes loose).
TWIST_RAD = math.pi
#: Default time for the whole turn (strokes and regrasps), s.
TWIST_S = 3.0
#: Most a hand turns the object before it regrasps, rad (ARMAR-III's left hand over a bottle
#: it holds with the right one keeps its place through 40°, not through 60°).
STROKE_RAD = math.radians(40.0)
#: Close enough to ``angle`` to stop turning, rad.
ENOUGH_RAD = math.radians(8.0)
#: Most strokes, as a multiple of those ``angle`` needs: a stroke turns the object some 10 %
#: less than the hand, and a regrasp can turn it back a few degrees; more strokes make it up.
MAX_STROKES = 2
#: Least part of ``angle`` the object must really turn.
MIN_TURNED = 0.6
#: Shortest time for one stroke, s.
MIN_STROKE_S = 0.6
#: Times of a regrasp's parts: the fingers open, the hand rises, turns back, comes down, s.
OPEN_S, RISE_S, BACK_S, DOWN_S = 0.4, 0.4, 0.5, 0.4
#: About what a regrasp takes, closing the fingers included, s.
REGRASP_S = OPEN_S + RISE_S + BACK_S + DOWN_S + 0.4
#: How far below where it let go the palm is aimed while the fingers open, m.
HOLD_DOWN_M = 0.005
#: How far the hand's grasp centre may be off the object's axis before the first stroke, m
#: (farther, the hand is first set on the axis: a lid taken 4 cm off it swung the hand round
#: out of reach and slid off its bottle).
OFF_AXIS_M = 0.015
#: How far the opened hand rises off the object before it turns back (the folded thumb of a
#: hand from above hangs below the palm: 2 cm dragged the object along), m.
RISE_M = 0.05
#: How far the hand presses the object onto the target while it turns, m.
PRESS_M = 0.003
#: How far down an object that lost the target is set on it before the hand lets go, m.
SEAT_M = 0.01
#: How far the object's axis may be off the target's when the hand lets go of it, m (the
#: arm lags a turning hand by up to 3 cm sideways: a lid let go 4 cm off its bottle's axis
#: tipped over the edge as the hand rose).
CENTRE_M = 0.005
#: Most moves that bring the held object back onto the target's axis before it is let go.
CENTRE_TRIES = 4
#: Time of each such move, s.
CENTRE_S = 0.25


def _angle_about(axis: np.ndarray, r_from: np.ndarray, r_to: np.ndarray) -> float:
    """Signed angle (rad) of the rotation ``r_to r_from^T`` about ``axis`` (world, unit)."""
    step = r_to @ r_from.T
    vec = np.array([step[2, 1] - step[1, 2], step[0, 2] - step[2, 0], step[1, 0] - step[0, 1]])
    angle = math.acos(float(np.clip((np.trace(step) - 1.0) / 2.0, -1.0, 1.0)))
    norm = float(np.linalg.norm(vec))
    return angle * float(vec @ axis) / norm if norm > 1e-12 else 0.0


def _raised(pose: np.ndarray, dz: float) -> np.ndarray:
    return make_T(pose[:3, :3], pose[:3, 3] + np.array([0.0, 0.0, dz]))


def _turned(pose: np.ndarray, axis: np.ndarray, centre: np.ndarray, angle: float) -> np.ndarray:
    """``pose`` (T_world_frame) turned by ``angle`` (rad) about the line through ``centre`` along ``axis``."""
    r = rot_axis(axis, angle)
    return make_T(r @ pose[:3, :3], centre + r @ (pose[:3, 3] - centre))


def put_on(ctx: SkillContext, m: Motion, obj: str, target: str) -> None:
    """Bring the held ``obj`` over the middle of ``target`` (the axes in line: a lid over a
    bottle's neck, wherever the other hand holds the bottle) and down until they touch; press."""
    if not bring_onto(ctx, m, obj, target, TUNING.hover_m, TUNING.obstacle_force_n):
        raise RuntimeFailure(f"twist: {obj} did not reach {target} (the wrist felt {m.force_n():.0f} N)")
    m.press()


def _off_axis(ctx: SkillContext, obj: str, target: str, axis: np.ndarray) -> np.ndarray:
    """Where ``obj``'s origin (the middle of its base) is off the middle of ``target``'s top,
    across ``axis`` (world, m). The top's middle, not the target's origin: a bottle held in a
    hand leans a few degrees, and 18 cm up that is 1–2 cm."""
    t_target = ctx.world.body_pose(target)
    top = t_target[:3, 3] + t_target[:3, 2] * float(corners(ctx.body(target))[:, 2].max())
    off = ctx.world.body_pose(obj)[:3, 3] - top
    return off - float(off @ axis) * axis


def centre(
    ctx: SkillContext, side: str, obj: str, target: str, axis: np.ndarray, go: Callable[..., object]
) -> float:
    """Slide the held ``obj`` back onto ``target``'s axis, its lowest point kept pressed on
    ``target``'s top (closed loop: the arm's own error is measured on the object and made up
    for, move after move); returns how far off the axis it stays, m."""
    world, ctl = ctx.world, ctx.ctl
    for _ in range(CENTRE_TRIES):
        off = _off_axis(ctx, obj, target, axis)
        if float(np.linalg.norm(off)) <= CENTRE_M and world.touching(obj, target):
            break
        ctl.activity = f"setting {obj} on the middle of {target}"
        low = lowest_z(ctx.body(obj), world.body_pose(obj))
        top = float(world_corners(ctx.body(target), world.body_pose(target))[:, 2].max())
        here = ctl.ik.goal(side)
        goal = make_T(here[:3, :3], here[:3, 3] - off)
        # down from where the hand really is (not from its target, which may be lower already)
        goal[2, 3] = world.frame_pose(f"grasp_{side}")[2, 3] - (low - top) - PRESS_M
        go(goal, CENTRE_S)
        ctl.wait(0.1)
    return float(np.linalg.norm(_off_axis(ctx, obj, target, axis)))


def _close_on(ctx: SkillContext, side: str, hand: str, obj: str, closed: dict[str, float]) -> None:
    """Close hand ``side`` until its fingers touch ``obj``, then keep them pressing lightly."""
    world, ctl = ctx.world, ctx.ctl
    ctl.set_fingers(side, closed)
    ctl.wait(TUNING.close_s, until=lambda: world.fingers_touch(side, obj))
    if not world.fingers_touch(side, obj):
        raise RuntimeFailure(f"twist: {hand} could not take {obj} again after turning it")
    names = finger_joint_names(side)
    now = world.joint_positions()
    ctl.set_fingers(side, {j: min(now[q] + SQUEEZE_RAD, closed[j]) for j, q in names.items()})


def twist(
    ctx: SkillContext,
    hand: str,
    obj: str,
    target: str,
    *,
    angle: float = TWIST_RAD,
    duration: float = TWIST_S,
    stroke: float = STROKE_RAD,
    lift: float = 0.0,
) -> None:
    """Turn the held ``obj`` by ``angle`` (rad) about its own axis on ``target`` in ``duration``
    (s), at most ``stroke`` (rad) per grasp; then raise it ``lift`` (m) off ``target``."""
    world, ctl = ctx.world, ctx.ctl
    side = ctx.require_held(hand, obj)
    if target not in world.layout.bodies or not ctx.body(target).solids:
        raise RuntimeFailure(f"twist: {target!r} is no object of the scene")
    other = "l" if side == "r" else "r"
    m = Motion(ctx, side, OtherHand.STEADY if world.held.get(other) is not None else OtherHand.IDLE)
    go = m.go

    if not world.touching(obj, target):
        put_on(ctx, m, obj, target)

    t_obj = world.body_pose(obj)
    axis = t_obj[:3, 2].copy()
    n = max(1, math.ceil(abs(angle) / max(stroke, 1e-6) - 1e-9))
    turn_s = max(MIN_STROKE_S, (duration - (n - 1) * REGRASP_S) / n)
    grasp = ctx.grasp_for(obj)
    closed = PINCH_CLOSED if grasp.type == "pinch" else CLOSED
    turned = 0.0
    # every stroke starts from the hand's first pose over the object, moved with the object:
    # a hand that did not quite follow a stroke would otherwise turn back too far, stroke after
    # stroke; that pose has the hand's grasp centre on the object's axis
    first = ctl.ik.goal(side)
    origin = world.body_pose(obj)[:3, 3].copy()
    aside = world.frame_pose(f"grasp_{side}")[:3, 3] - origin
    aside -= float(aside @ axis) * axis
    first[:3, 3] -= aside

    def retake() -> None:
        """Let go of the object (on the target), and take it again from the first pose."""
        ctl.activity = f"taking {obj} again"
        centre(ctx, side, obj, target, axis, go)
        ctl.activity = f"taking {obj} again"
        if not world.touching(obj, target):  # set it down on the target before letting go
            here = ctl.ik.goal(side)
            go(_raised(here, -SEAT_M), 0.3, lambda: world.touching(obj, target))
        world.release(side)
        # the palm holds it down while only the fingers open; the thumb stays where it is
        # (opened, or turned back to a folded thumb, it pushed a light object off the target;
        # fingers opening without the palm pressing turned it back by up to 16°)
        go(_raised(ctl.ik.target(side), -HOLD_DOWN_M), 0.2)
        names = finger_joint_names(side)
        now = world.joint_positions()
        ctl.set_fingers(side, {j: OPEN[j] if j.startswith("fingers") else now[q] for j, q in names.items()})
        ctl.wait(OPEN_S)
        rest = world.frame_pose(f"grasp_{side}")  # where the hand really is: it rests on the object
        go(_raised(rest, RISE_M), RISE_S)
        again = first.copy()
        shift = world.body_pose(obj)[:3, 3] - origin
        again[:3, 3] += shift - float(shift @ axis) * axis
        again[:3, 3] += float((rest[:3, 3] - again[:3, 3]) @ axis) * axis
        go(_raised(again, RISE_M), BACK_S)
        go(again, DOWN_S)
        _close_on(ctx, side, hand, obj, closed)
        world.weld(side, obj)

    if float(np.linalg.norm(aside)) > OFF_AXIS_M:  # turning would swing the hand round the axis
        retake()
    last = world.body_pose(obj)[:3, :3].copy()
    for k in range(MAX_STROKES * n):
        ctl.activity = f"turning {obj} on {target} (stroke {k + 1})"
        here = ctl.ik.goal(side)
        t_now = world.body_pose(obj)
        turned += _angle_about(axis, last, t_now[:3, :3])  # what the regrasp turned it (back)
        # what is left, in equal strokes of at most ``stroke``
        left = angle - turned
        step = left / max(1, math.ceil(abs(left) / max(stroke, 1e-6) - 1e-9))
        # turned about its own axis, and brought back onto the target's (it drifts a little
        # with each regrasp)
        off = _off_axis(ctx, obj, target, axis)
        goal = _turned(here, axis, t_now[:3, 3], step)
        goal[:3, 3] -= off
        # and kept on the target: its lowest point pressed a little below the target's top
        low = lowest_z(ctx.body(obj), t_now)
        top = float(world_corners(ctx.body(target), world.body_pose(target))[:, 2].max())
        goal[2, 3] -= low - top + PRESS_M
        go(goal, turn_s)
        ctl.wait(0.1)
        last = world.body_pose(obj)[:3, :3].copy()
        turned += _angle_about(axis, t_now[:3, :3], last)
        if abs(angle - turned) <= ENOUGH_RAD or k == MAX_STROKES * n - 1:
            break
        retake()
    if not world.touching(hand, obj):  # the weld holds it; the relation needs the fingers on it
        _close_on(ctx, side, hand, obj, closed)
    if turned * angle < 0 or abs(turned) < MIN_TURNED * abs(angle):
        raise RuntimeFailure(
            f"twist: {obj} turned {math.degrees(turned):.0f}° of {math.degrees(angle):.0f}° on {target}"
        )
    if lift > 0:
        ctl.activity = f"taking {obj} off {target}"
        here = ctl.ik.goal(side)
        go(make_T(here[:3, :3], here[:3, 3] + np.array([0.0, 0.0, lift])), 1.0)
        ctl.wait(0.3)
        if world.touching(obj, target):
            raise RuntimeFailure(f"twist: {obj} still touches {target} after rising {lift * 100:.0f} cm")
        if not world.touching(hand, obj):
            _close_on(ctx, side, hand, obj, closed)
        return
    if not ctl.wait(0.3, until=lambda: world.touching(obj, target)) and not world.touching(obj, target):
        raise RuntimeFailure(f"twist: {obj} no longer touches {target} after turning")
