"""Small rigid-transform helpers (4×4 homogeneous matrices, metres and radians)."""

from __future__ import annotations

import math

import mujoco
import numpy as np

__all__ = [
    "MIN_JERK_PEAK",
    "rot_x",
    "rot_y",
    "rot_z",
    "rot_axis",
    "make_T",
    "min_jerk",
    "interpolate",
    "quat_from_matrix",
    "matrix_from_quat",
    "raised",
    "down",
]


def rot_axis(axis: np.ndarray | tuple[float, float, float], angle: float) -> np.ndarray:
    """Rotation matrix of ``angle`` (rad) about ``axis`` (any length > 0)."""
    a = np.asarray(axis, dtype=float)
    a = a / np.linalg.norm(a)
    k = np.array([[0.0, -a[2], a[1]], [a[2], 0.0, -a[0]], [-a[1], a[0], 0.0]])
    return np.eye(3) + math.sin(angle) * k + (1.0 - math.cos(angle)) * (k @ k)


def rot_x(a: float) -> np.ndarray:
    return rot_axis((1.0, 0.0, 0.0), a)


def rot_y(a: float) -> np.ndarray:
    return rot_axis((0.0, 1.0, 0.0), a)


def rot_z(a: float) -> np.ndarray:
    return rot_axis((0.0, 0.0, 1.0), a)


def make_T(
    r: np.ndarray | None = None, p: np.ndarray | tuple[float, float, float] | None = None
) -> np.ndarray:
    """T from a rotation ``r`` (3×3) and a position ``p`` (3,)."""
    t = np.eye(4)
    if r is not None:
        t[:3, :3] = r
    if p is not None:
        t[:3, 3] = p
    return t


#: Peak over mean speed of a :func:`min_jerk` motion (its largest slope, at s = 1/2): a
#: motion over a distance d at peak speed v takes ``MIN_JERK_PEAK * d / v``.
MIN_JERK_PEAK = 15.0 / 8.0


def min_jerk(s: float) -> float:
    """Minimum-jerk time scaling of a phase ``s`` in [0, 1]."""
    s = min(max(s, 0.0), 1.0)
    return s * s * s * (10.0 - 15.0 * s + 6.0 * s * s)


def quat_from_matrix(r: np.ndarray) -> np.ndarray:
    """Unit quaternion (w, x, y, z) of a rotation matrix."""
    q = np.empty(4)
    mujoco.mju_mat2Quat(q, np.ascontiguousarray(r, dtype=float).reshape(9))
    return q


def matrix_from_quat(q: np.ndarray) -> np.ndarray:
    """Rotation matrix of a quaternion (w, x, y, z), normalised first."""
    r = np.empty(9)
    mujoco.mju_quat2Mat(r, q / np.linalg.norm(q))
    return r.reshape(3, 3)


def interpolate(t0: np.ndarray, t1: np.ndarray, s: float) -> np.ndarray:
    """Pose between ``t0`` (s = 0) and ``t1`` (s = 1): linear position, slerp rotation."""
    q0, q1 = quat_from_matrix(t0[:3, :3]), quat_from_matrix(t1[:3, :3])
    dot = float(np.dot(q0, q1))
    if dot < 0.0:
        q1, dot = -q1, -dot
    if dot > 0.9995:
        q = q0 + s * (q1 - q0)
    else:
        theta = math.acos(dot)
        q = (math.sin((1 - s) * theta) * q0 + math.sin(s * theta) * q1) / math.sin(theta)
    return make_T(matrix_from_quat(q), (1 - s) * t0[:3, 3] + s * t1[:3, 3])


def raised(pose: np.ndarray, dz_m: float) -> np.ndarray:
    """``pose`` (T_world_frame) moved ``dz_m`` up (down when negative)."""
    return make_T(pose[:3, :3], pose[:3, 3] + np.array([0.0, 0.0, dz_m]))


def down(pose: np.ndarray, depth_m: float) -> np.ndarray:
    """``pose`` moved ``depth_m`` down."""
    return raised(pose, -depth_m)
