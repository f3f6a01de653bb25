"""A demonstrated path as ``follow`` takes it: keyframes of the moved object's pose relative
to its target, in the target's frame *turned* about its z axis so that x points from the
target towards where the object is at the path's start.

That frame needs nothing but the two objects: the robot builds it the same way from where
its own objects are when the step starts (``oacdsl/runtime/retarget.py``), so the path is
repeated from whichever side the robot's hand comes, whatever the motion capture's axes
(docs/runtime.md, "follow"). Rotations are relative to the object's orientation at the
path's start, about the turned target frame's axes (a rotation vector, axis × angle):
the demonstrator's and the robot's object frames differ (a spoon lying on the table against
one standing), their changes relative to the target do not.

Units: seconds, metres, radians. numpy only.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["KEYFRAME_S", "MIN_OFFSET_M", "from_rotvec", "rotvec", "turn_z", "turned_path", "twist_of"]

#: Keyframes are recording frames at least this far apart, seconds (10 Hz: every KIT frame).
KEYFRAME_S = 0.1
#: Below this horizontal distance between target and object at the start, the frame is not
#: turned (the direction would be noise), metres.
MIN_OFFSET_M = 0.01


def rotvec(rot: np.ndarray) -> np.ndarray:
    """Rotation vector (axis × angle, radians) of a rotation matrix (3, 3)."""
    angle = math.acos(max(-1.0, min(1.0, (float(np.trace(rot)) - 1.0) / 2.0)))
    if angle < 1e-9:
        return np.zeros(3)
    axis = np.array([rot[2, 1] - rot[1, 2], rot[0, 2] - rot[2, 0], rot[1, 0] - rot[0, 1]])
    if math.pi - angle < 1e-6:  # half a turn: the axis from the symmetric part
        sym = (rot + np.eye(3)) / 2.0
        axis = sym[:, int(np.argmax(np.diag(sym)))]
    norm = float(np.linalg.norm(axis))
    return axis / norm * angle if norm > 0 else np.zeros(3)


def from_rotvec(v: np.ndarray) -> np.ndarray:
    """Rotation matrix of a rotation vector (radians), Rodrigues' formula."""
    angle = float(np.linalg.norm(v))
    if angle < 1e-12:
        return np.eye(3)
    k = np.asarray(v, dtype=np.float64) / angle
    kx = np.array([[0.0, -k[2], k[1]], [k[2], 0.0, -k[0]], [-k[1], k[0], 0.0]])
    result: np.ndarray = np.eye(3) + math.sin(angle) * kx + (1.0 - math.cos(angle)) * (kx @ kx)
    return result


def twist_of(rotations: np.ndarray, axis: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``(twists_rad (n,), swings (n, 3, 3))`` of rotations (n, 3, 3) about the unit ``axis``
    (the frame the rotations act in): rotation k = swing k @ (turn by twist k about ``axis``).
    Twists are unwrapped from keyframe to keyframe (each step taken as the shorter way round:
    keyframes 0.1 s apart turn far less than half a turn), so they go beyond ±π."""
    a = np.asarray(axis, dtype=np.float64) / float(np.linalg.norm(axis))
    wrapped = np.empty(len(rotations))
    for k, rot in enumerate(rotations):
        v = rotvec(rot)
        angle = float(np.linalg.norm(v))
        along = math.sin(angle / 2.0) * float(v @ a) / angle if angle > 1e-12 else 0.0
        wrapped[k] = 2.0 * math.atan2(along, math.cos(angle / 2.0))
    steps = (np.diff(wrapped) + math.pi) % (2.0 * math.pi) - math.pi
    twists = np.r_[wrapped[:1], wrapped[0] + np.cumsum(steps)]
    swings = np.array([rot @ from_rotvec(-t * a) for rot, t in zip(rotations, twists, strict=True)])
    return twists, swings


def turn_z(angle_rad: float) -> np.ndarray:
    """Rotation about z by ``angle_rad``."""
    c, s = math.cos(angle_rad), math.sin(angle_rad)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def turned_path(times_s: np.ndarray, T_target_object: np.ndarray, keyframe_s: float = KEYFRAME_S
                ) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
    """``(t_s (n,), positions_m (n, 3), rotvecs_rad (n, 3))`` of the posed frames of a path, at
    least ``keyframe_s`` apart (the first and the last always kept); times from 0, positions in
    the turned target frame, rotations relative to the first keyframe (module doc). None when
    fewer than two frames have a pose."""
    ok = np.isfinite(T_target_object[:, 0, 0])
    idx = np.flatnonzero(ok)
    if len(idx) < 2:
        return None
    keep = [int(idx[0])]
    for i in idx[1:]:
        if times_s[i] - times_s[keep[-1]] >= keyframe_s - 1e-9:
            keep.append(int(i))
    if keep[-1] != idx[-1]:
        keep.append(int(idx[-1]))
    T = T_target_object[keep]
    start = T[0, :2, 3]
    far = float(np.linalg.norm(start)) >= MIN_OFFSET_M
    phi = math.atan2(float(start[1]), float(start[0])) if far else 0.0
    back = turn_z(-phi)
    positions = T[:, :3, 3] @ back.T
    r0 = T[0, :3, :3]
    rotations = np.array([rotvec(back @ (r @ r0.T) @ back.T) for r in T[:, :3, :3]])
    return np.asarray(times_s[keep] - times_s[keep[0]], dtype=np.float64), positions, rotations
