"""A demonstrated path brought into the robot's reach (``follow``; docs/runtime.md).

The path (``path [ … ]`` of a ``follow`` step: keyframes of time, position and rotation
vector, :mod:`oacdsl.segmentation.followpath`) is the moved object's reference point
relative to the target, in the target's frame turned so that x points from the target to
where the object started. :func:`retarget` changes it as little as the robot needs:

1. **the core**: where the path dwells at the target
   (:func:`~oacdsl.segmentation.motionfeatures.core_frames`); the keyframes before it are the
   demonstrator's way in, from where their object was, which the robot's need not share: the
   skill carries the object to the core's first keyframe over what stands in the way
   (``SkillContext.carry_path``) and follows the path from there;
2. **fitted to the target**: across the target's axis the core is scaled about its middle
   (never up) until it stays within ``room_m`` of the axis (a container's inside less the
   tool's own half width), and its middle moved in as far as needed;
3. **rotations**: relative to the core's first keyframe, about the target frame's axes (the
   object keeps the orientation the robot's grasp gave it until then: the demonstrator's
   object frame need not be the robot's, a spoon lying on the table against one standing),
   scaled down when they exceed ``turn_rad`` (a turn about the object's own axis that it may be
   let go of and taken again for is kept whole, :mod:`~oacdsl.runtime.follow_turns`);
4. **speed**: a segment faster than ``speed_m_s`` (in the core ``core_speed_m_s``) or
   :data:`TURN_SPEED_RAD_S` is slowed to it; the rest keeps the demonstrated timing; every
   segment lasts at least :data:`MIN_SEGMENT_S` (two control ticks);
5. **where it ends**: when the object is to stay at the target (``stay``), the path ends
   with its core (the demonstrated way out belongs to the next sub-action).

:func:`floored` keeps the core from going deeper into the target than where the two touch
(the demonstrator's knife went into the cucumber; the robot's cannot). :func:`shrunk` and
:func:`shifted` give the variants the skill tries when the whole-body IK
cannot reach the path. numpy only; metres, radians, seconds.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from oacdsl.errors import RuntimeFailure
from oacdsl.segmentation.followpath import MIN_OFFSET_M, from_rotvec, rotvec, twist_of
from oacdsl.segmentation.motionfeatures import core_frames

__all__ = [
    "FOLLOW",
    "MIN_OFFSET_M",
    "MIN_SEGMENT_S",
    "TURN_SPEED_RAD_S",
    "FollowTuning",
    "floored",
    "boxed",
    "Retargeted",
    "retarget",
    "shifted",
    "shrunk",
]

#: Fastest turn of the held object, rad/s (the arms' joint speed limit is 1.5 rad/s).
TURN_SPEED_RAD_S = 1.5
#: Shortest segment between two keyframes, s (two 20 ms control ticks).
MIN_SEGMENT_S = 0.04


@dataclass(frozen=True)
class FollowTuning:
    """The numbers ``follow`` (:mod:`oacdsl.runtime.skills.follow`) moves by, in one record (SI)."""

    #: Speed of a guarded approach along the target's axis, m/s.
    approach_speed_m_s: float = 0.05
    #: Fastest the object moves in the core while it is to touch the target, m/s: faster, a held
    #: surface is pushed out of the other hand (65 N at its wrist) and the closed loop's virtual
    #: markers (10 cm/s distance change) lose the contact (docs/runtime.md, wipe).
    contact_speed_m_s: float = 0.05
    #: Height of the object's lowest point above the target's top where the core starts, m.
    hover_m: float = 0.04
    #: Factors a path the whole-body IK cannot reach is shrunk by about its core's middle, in order.
    shrink: tuple[float, ...] = (1.0, 0.7, 0.4)
    #: Orientation weights tried, in order: the usual, then the orientation a soft wish (an arm
    #: that cannot hold a sponge flat over a plate the other hand holds still gets it there, tilted).
    orientation_weights: tuple[float, ...] = (0.3, 0.02)
    #: How far the IK may leave the hand from a keyframe, m and rad (twice a skill's usual: the path
    #: is a demonstration's, not a pose the task needs exactly; a guarded approach closes the gap).
    reach_m: float = 0.04
    reach_rad: float = 0.5
    #: Beyond this (m) the path is out of reach; between ``reach_m`` and it the closest variant
    #: is followed as closely as the soft IK gets (the step's effect judges the outcome).
    give_up_m: float = 0.12
    #: Time the hand gets to catch up with the path before the guarded approach, s.
    settle_s: float = 1.0
    #: Rest once the path is over, for the contact to show (or its loss), s.
    rest_s: float = 0.3
    #: Horizontal room left on a target that is no container, as a share of the object's radius.
    overhang: float = 0.5
    #: Kept between the object's widest part and a container's inner wall, m.
    wall_gap_m: float = 0.005
    #: How far inside a solid target's edges the object's lowest end starts its core, m.
    top_margin_m: float = 0.01
    #: Kept between the held object along the core and the other hand's collision boxes, m; the
    #: core's turns are scaled by ``clear_turns`` in order until it is (the least-touching otherwise).
    hand_clearance_m: float = 0.01
    clear_turns: tuple[float, ...] = (1.0, 0.5, 0.0)
    #: Most the object's axis may lean from the target's for it to be let go of on the target and
    #: taken again between the pieces of a turn beyond ``turn`` (follow_turns), rad.
    rest_tilt_rad: float = 0.35
    #: Least share of the path's turn about its own axis the object must really make when split.
    least_turned: float = 0.6


#: The defaults ``follow`` uses.
FOLLOW = FollowTuning()


@dataclass(frozen=True)
class Retargeted:
    """The path the robot follows, in the turned target frame.

    Attributes:
        times_s: (n,) keyframe times from 0, after slowing.
        positions_m: (n, 3) the object's reference point.
        rotations: (n, 3, 3) its rotation since the start, about the frame's axes.
        core: index of the first keyframe of the core (the way in ends there).
        scale: the factor the core was scaled by across the target's axis (≤ 1).
        turn_scale: the factor rotations were scaled by (≤ 1).
        slowed_s: how much longer the path takes than demonstrated.
        twist_axis: the object's own axis at the core's start (frame, unit) when its turns about
            it are kept whole (:mod:`~oacdsl.runtime.follow_turns`), else None.
        twists_rad: (n,) then the object's turn about ``twist_axis`` since the core's start,
            any angle (``rotations`` is then the rest of each rotation, the swing).
    """

    times_s: np.ndarray
    positions_m: np.ndarray
    rotations: np.ndarray
    core: int
    scale: float
    turn_scale: float
    slowed_s: float
    twist_axis: np.ndarray | None = None
    twists_rad: np.ndarray | None = None

    def rotation(self, k: int) -> np.ndarray:
        """The object's whole rotation at keyframe ``k`` (3, 3): the swing, then the twist."""
        if self.twist_axis is None or self.twists_rad is None:
            return self.rotations[k]
        turn: np.ndarray = self.rotations[k] @ from_rotvec(float(self.twists_rad[k]) * self.twist_axis)
        return turn


def _min_jerk(s: np.ndarray) -> np.ndarray:
    s = np.clip(s, 0.0, 1.0)
    result: np.ndarray = s**3 * (10.0 - 15.0 * s + 6.0 * s**2)
    return result


def retarget(path: np.ndarray, *, room_m: float | None, speed_m_s: float, turn_rad: float,
             stay: bool = False, core_speed_m_s: float | None = None,
             twist_axis: np.ndarray | None = None, inside: bool = False,
             resting: bool = False) -> Retargeted:
    """The robot's path from ``path`` ((n, 7): t, x, y, z, rx, ry, rz; SI; turned target frame),
    see the module doc. ``stay``: the object is to end at the target (the step's effect keeps them
    touching): the path ends with its core, the way out of the demonstration's span left out;
    ``core_speed_m_s``: a lower cap in the core (where the object works on the target);
    ``twist_axis``: the object's own axis (frame, unit) when it may be let go of and taken again
    on the target: a turn about it beyond ``turn_rad`` is then kept whole (to be split by
    regrasps, :mod:`~oacdsl.runtime.follow_turns`), only the rest of the rotation capped;
    ``inside``: the whole object is to stay within ``room_m`` (in a container): the core's
    rotations are scaled with its positions (a spoon rocked ±8° about its handle's middle moves
    its bowl ±1.4 cm, more than the 1 cm a cup leaves it: scaled alone, the positions' circles
    were lost in the rocking); ``resting``: the object rests on the target at the start (a lid
    to unscrew): the core starts with the path (the dwell found from the reference point's
    distances alone cut a turn in place: a lid's markers off its axis circle as it turns, and
    of a 720° unscrew the core kept the last 139°)."""
    path = np.asarray(path, dtype=np.float64)
    if path.ndim != 2 or path.shape[1] != 7 or len(path) < 2:
        raise RuntimeFailure(f"follow: a path needs two or more keyframes of 7 numbers, not {path.shape}")
    if np.any(np.diff(path[:, 0]) <= 0):
        raise RuntimeFailure("follow: the path's keyframe times do not increase")
    a, b = core_frames(path[:, 1:4])
    if resting:  # no way in: at the target from the first keyframe
        a = 0
    if stay and b > max(a, 1):
        path = path[:b]
    t, pos, rv = path[:, 0] - path[0, 0], path[:, 1:4].copy(), path[:, 4:7].copy()
    a = max(a, 1)
    w = _min_jerk((t - t[0]) / max(t[a] - t[0], 1e-9))
    scale = 1.0
    if room_m is not None:
        core = pos[a:, :2]
        middle = np.median(core, axis=0)
        spread = float(np.max(np.linalg.norm(core - middle, axis=1), initial=0.0))
        if spread > room_m:
            scale = room_m / spread
        reach = max(room_m - scale * spread, 0.0)
        off = float(np.linalg.norm(middle))
        moved = middle * (reach / off) if off > reach else middle
        k = w[:, None]  # the way in blends from the start into the fitted core
        pos[:, :2] = (1.0 - k) * pos[:, :2] + k * (moved + scale * (pos[:, :2] - middle))
    # rotations relative to the core's first keyframe; none on the way in (the robot's object
    # keeps the orientation its grasp gave it, which need not be the demonstrator's)
    at_core = from_rotvec(rv[a]).T
    rv = np.array([rotvec(from_rotvec(r) @ at_core) if k >= a else np.zeros(3) for k, r in enumerate(rv)])
    twists = None
    if twist_axis is not None and turn_rad > 0:
        twists, swings = twist_of(np.array([from_rotvec(r) for r in rv]), twist_axis)
        if float(np.max(np.abs(twists))) > turn_rad:
            rv = np.array([rotvec(m) for m in swings])
        else:
            twists = None
    angles = np.linalg.norm(rv, axis=1)
    turn_scale = 1.0 if angles.max() <= turn_rad else turn_rad / float(angles.max())
    if inside:  # the whole object kept in the room: its turns shrunk with its positions
        turn_scale = min(turn_scale, scale)
    rotations = np.array([from_rotvec(turn_scale * r) for r in rv])
    whole = rotations
    if twists is not None:
        whole = np.array([m @ from_rotvec(t * twist_axis) for m, t in zip(rotations, twists, strict=True)])
    dt = np.diff(t)
    dist = np.linalg.norm(np.diff(pos, axis=0), axis=1)
    dang = np.array([np.arccos(np.clip((np.trace(whole[k].T @ whole[k + 1]) - 1.0) / 2.0, -1.0, 1.0))
                     for k in range(len(whole) - 1)])
    cap = np.full_like(dt, speed_m_s)
    if core_speed_m_s is not None:
        cap[a:] = min(speed_m_s, core_speed_m_s)
    need = np.maximum.reduce([dt, dist / cap, dang / TURN_SPEED_RAD_S, np.full_like(dt, MIN_SEGMENT_S)])
    times = np.r_[0.0, np.cumsum(need)]
    axis = None if twists is None else np.asarray(twist_axis, dtype=np.float64)
    return Retargeted(times, pos, rotations, a, scale, turn_scale, float(times[-1] - t[-1]), axis, twists)


def shrunk(r: Retargeted, factor: float) -> Retargeted:
    """``r`` with its core shrunk by ``factor`` about the core's middle (all three axes) and its
    rotations by the same factor: a path the arm cannot reach, brought closer to its middle."""
    middle = np.median(r.positions_m[r.core:], axis=0)
    w = np.zeros(len(r.times_s))
    w[r.core:] = 1.0
    w[: r.core] = np.linspace(0.0, 1.0, r.core + 1)[:-1]
    pos = r.positions_m + w[:, None] * (factor - 1.0) * (r.positions_m - middle)
    rot = np.array([from_rotvec(factor * rotvec(m)) for m in r.rotations])
    return replace(r, positions_m=pos, rotations=rot, scale=r.scale * factor,
                   turn_scale=r.turn_scale * factor)


def shifted(r: Retargeted, offset_m: np.ndarray, room_m: float | None) -> Retargeted:
    """``r`` with its core moved by ``offset_m`` (3,) across the target's axis (the way in blends
    into it): towards where the arm can go, as far as the core's middle stays within ``room_m`` of
    the axis (the object still over or in the target), the core shrunk about its middle so that
    all of it does."""
    off = np.array([float(offset_m[0]), float(offset_m[1]), 0.0])
    pos = r.positions_m.copy()
    middle = np.median(pos[r.core:, :2], axis=0)
    scale = 1.0
    if room_m is not None:
        moved = middle + off[:2]
        if float(np.linalg.norm(moved)) > room_m:
            moved = moved * (room_m / float(np.linalg.norm(moved)))
        off[:2] = moved - middle
        # the core shrunk about its middle as far as it would leave the room
        spread = float(np.max(np.linalg.norm(pos[r.core:, :2] - middle, axis=1), initial=0.0))
        left = room_m - float(np.linalg.norm(moved))
        if spread > left:
            scale = max(left, 0.0) / spread
    w = np.ones(len(r.times_s))
    w[: r.core] = np.linspace(0.0, 1.0, r.core + 1)[:-1]
    pos[:, :2] = pos[:, :2] + w[:, None] * ((scale - 1.0) * (pos[:, :2] - middle) + off[:2])
    return replace(r, positions_m=pos, scale=r.scale * scale)


def floored(r: Retargeted) -> Retargeted:
    """``r`` with every keyframe of the core that is lower (along the target's axis) than the
    core's first one raised to it. The robot's object touches its target at the core's first
    keyframe (a guarded approach found it); a demonstrated path that goes deeper went into
    something soft (a knife cutting a cucumber, a spoon in a liquid) which the robot's rigid
    target is not: there the robot stays on it, pressed, rather than have the rest of the core
    lifted off it by the depth it cannot go."""
    pos = r.positions_m.copy()
    pos[r.core :, 2] = np.maximum(pos[r.core :, 2], pos[r.core, 2])
    return replace(r, positions_m=pos)



def boxed(r: Retargeted, to_box: np.ndarray, offset_m: np.ndarray, lo_m: np.ndarray,
          hi_m: np.ndarray, far: tuple[int, float] | None = None) -> Retargeted:
    """``r`` with its core fitted into a rectangle on a solid target's top: ``to_box`` (2, 2)
    turns the frame's xy into the rectangle's, where the point that must stay inside (the
    object's lowest end) is at ``to_box @ p + offset_m`` for a keyframe at ``p``; along each of
    the rectangle's axes the core is shrunk about its middle until it spans at most
    ``hi_m - lo_m``, then moved in as little as needed (the way in blends into it). A cucumber
    is 15 cm long and 4.5 cm wide: the room about its middle (``room_m``) does not see that
    a knife drawn 5 cm across it leaves it. ``far`` = (axis, sign): the core then goes as far
    to that side along that axis of the rectangle as it can (the end of a cucumber away from
    the hand that holds it)."""
    pos = r.positions_m.copy()
    q = pos[r.core :, :2] @ to_box.T + offset_m
    middle = 0.5 * (q.min(axis=0) + q.max(axis=0))
    span = q.max(axis=0) - q.min(axis=0)
    scale = np.where(span > hi_m - lo_m, np.maximum(hi_m - lo_m, 0.0) / np.maximum(span, 1e-12), 1.0)
    q = middle + (q - middle) * scale
    q += np.clip(q.min(axis=0), lo_m, None) - q.min(axis=0)  # the low side in
    q -= np.maximum(q.max(axis=0) - hi_m, 0.0)  # the high side in
    if far is not None:
        a, sign = far
        q[:, a] += float(hi_m[a] - q[:, a].max()) if sign > 0 else float(lo_m[a] - q[:, a].min())
    core = (q - offset_m) @ to_box  # to_box is a rotation: its inverse is its transpose
    delta = np.zeros((len(r.times_s), 2))
    delta[r.core :] = core - pos[r.core :, :2]
    delta[: r.core] = np.linspace(0.0, 1.0, r.core + 1)[:-1, None] * delta[r.core]
    pos[:, :2] += delta
    return replace(r, positions_m=pos, scale=r.scale * float(scale.min()))
