"""Rigid-body trajectories for synthetic demonstrations: poses, minimum-jerk moves, attachment.

A :class:`Track` holds the pose of one rigid body at every frame of a fixed time
grid: positions (F, 3) in metres, world frame, and rotation matrices (F, 3, 3)
``R_world_body``. A track is written front to back: each call fills the frames
from its cursor up to a given time, starting from the pose of the last filled
frame, so that a story reads as a sequence of motions. Human-like timing comes
from the minimum-jerk profile (Flash & Hogan 1985), the usual model of
point-to-point hand motion.
"""

from __future__ import annotations

from collections.abc import Callable
from math import comb

import numpy as np

__all__ = [
    "Track",
    "min_jerk",
    "rot_x",
    "rot_y",
    "rot_z",
    "slerp_matrices",
]


def rot_x(angle_rad: float) -> np.ndarray:
    """Rotation matrix about x by ``angle_rad`` (radians)."""
    c, s = np.cos(angle_rad), np.sin(angle_rad)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


def rot_y(angle_rad: float) -> np.ndarray:
    """Rotation matrix about y by ``angle_rad`` (radians); positive tips +z towards +x."""
    c, s = np.cos(angle_rad), np.sin(angle_rad)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


def rot_z(angle_rad: float) -> np.ndarray:
    """Rotation matrix about z by ``angle_rad`` (radians)."""
    c, s = np.cos(angle_rad), np.sin(angle_rad)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def min_jerk(tau: np.ndarray) -> np.ndarray:
    """Minimum-jerk progress 10τ³ − 15τ⁴ + 6τ⁵ for τ in [0, 1] (clipped outside)."""
    t = np.clip(tau, 0.0, 1.0)
    return t**3 * (10.0 - 15.0 * t + 6.0 * t**2)


def _cut_profile(u: np.ndarray, start_tau: float, end_tau: float) -> np.ndarray:
    """The part τ ∈ [start_tau, end_tau] of the minimum-jerk profile, rescaled to 0 → 1 over u ∈ [0, 1]."""
    s0, s1 = float(min_jerk(np.array(start_tau))), float(min_jerk(np.array(end_tau)))
    return (min_jerk(start_tau + (end_tau - start_tau) * np.clip(u, 0.0, 1.0)) - s0) / (s1 - s0)


def _quat_from_matrix(r: np.ndarray) -> np.ndarray:
    """Unit quaternion (w, x, y, z) of one rotation matrix (Shepperd's method)."""
    tr = float(np.trace(r))
    if tr > 0.0:
        s = 2.0 * np.sqrt(tr + 1.0)
        q = [0.25 * s, (r[2, 1] - r[1, 2]) / s, (r[0, 2] - r[2, 0]) / s, (r[1, 0] - r[0, 1]) / s]
    else:
        i = int(np.argmax(np.diag(r)))
        j, k = (i + 1) % 3, (i + 2) % 3
        s = 2.0 * np.sqrt(1.0 + r[i, i] - r[j, j] - r[k, k])
        q = [0.0, 0.0, 0.0, 0.0]
        q[0] = (r[k, j] - r[j, k]) / s
        q[1 + i] = 0.25 * s
        q[1 + j] = (r[j, i] + r[i, j]) / s
        q[1 + k] = (r[k, i] + r[i, k]) / s
    out = np.asarray(q, dtype=float)
    return out / np.linalg.norm(out)


def _matrices_from_quats(q: np.ndarray) -> np.ndarray:
    """(N, 3, 3) rotation matrices from (N, 4) unit quaternions (w, x, y, z)."""
    w, x, y, z = q[:, 0], q[:, 1], q[:, 2], q[:, 3]
    return np.stack(
        [
            np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], -1),
            np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], -1),
            np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], -1),
        ],
        axis=-2,
    )


def slerp_matrices(r0: np.ndarray, r1: np.ndarray, s: np.ndarray) -> np.ndarray:
    """(N, 3, 3) rotations along the shortest arc from ``r0`` (s = 0) to ``r1`` (s = 1)."""
    q0, q1 = _quat_from_matrix(r0), _quat_from_matrix(r1)
    dot = float(np.dot(q0, q1))
    if dot < 0.0:
        q1, dot = -q1, -dot
    s = np.asarray(s, dtype=float)[:, None]
    if dot > 0.9995:
        q = q0 + s * (q1 - q0)
    else:
        theta = np.arccos(dot)
        q = (np.sin((1.0 - s) * theta) * q0 + np.sin(s * theta) * q1) / np.sin(theta)
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    return _matrices_from_quats(q)


class Track:
    """The pose of one rigid body on a time grid, written front to back.

    ``times_s`` is the shared (F,) grid, seconds. After construction frame 0
    holds the initial pose; every method fills frames ``cursor … frame(t1_s)``.
    """

    def __init__(
        self, name: str, times_s: np.ndarray, position_m: np.ndarray, rotation: np.ndarray | None = None
    ) -> None:
        self.name = name
        self.times_s = times_s
        n = times_s.shape[0]
        self.rate_hz = (n - 1) / (times_s[-1] - times_s[0]) if n > 1 else 1.0
        self.position_m = np.full((n, 3), np.nan)
        self.rotation = np.full((n, 3, 3), np.nan)
        self.position_m[0] = position_m
        self.rotation[0] = np.eye(3) if rotation is None else rotation
        self.cursor = 1

    # -- reading ---------------------------------------------------------------------------
    def frame(self, t_s: float) -> int:
        """Index of the grid frame nearest to time ``t_s`` (seconds)."""
        return int(round((t_s - self.times_s[0]) * self.rate_hz))

    @property
    def last_pose(self) -> tuple[np.ndarray, np.ndarray]:
        """(position, rotation) of the last filled frame."""
        return self.position_m[self.cursor - 1].copy(), self.rotation[self.cursor - 1].copy()

    @property
    def now_s(self) -> float:
        """Time of the last filled frame, seconds."""
        return float(self.times_s[self.cursor - 1])

    def world_points(self, local_m: np.ndarray) -> np.ndarray:
        """(F, k, 3) world positions of body-fixed points ``local_m`` (k, 3)."""
        return self.position_m[:, None, :] + np.einsum("fij,kj->fki", self.rotation, local_m)

    # -- writing ---------------------------------------------------------------------------
    def _span(self, t1_s: float) -> np.ndarray:
        f1 = min(self.frame(t1_s), self.times_s.shape[0] - 1)
        if f1 < self.cursor:
            raise ValueError(f"track {self.name}: time {t1_s:.3f} s is not after {self.now_s:.3f} s")
        return np.arange(self.cursor, f1 + 1)

    def hold(self, t1_s: float) -> Track:
        """Keep the last pose until ``t1_s``."""
        frames = self._span(t1_s)
        p, r = self.last_pose
        self.position_m[frames] = p
        self.rotation[frames] = r
        self.cursor = frames[-1] + 1
        return self

    def move(
        self,
        t1_s: float,
        position_m: np.ndarray | None = None,
        rotation: np.ndarray | None = None,
        pivot_m: np.ndarray | None = None,
        via_m: np.ndarray | None = None,
        start_tau: float = 0.0,
        end_tau: float = 1.0,
        turn_until: float = 1.0,
    ) -> Track:
        """Minimum-jerk move from the last pose to a target pose reached at ``t1_s``.

        ``position_m`` is the target of the body point ``pivot_m`` (body frame,
        default the origin), which travels on a straight line while the rotation
        follows the shortest arc: tilting a cup about its lip keeps the lip on a line.
        With ``via_m`` (world, m; one control point (3,) or several (k, 3)) the point
        travels on the Bézier curve with those control points instead: it leaves
        towards the first and arrives from the direction of the last (a hand
        approaching a handle along the handle's axis).

        ``start_tau``/``end_tau`` cut the minimum-jerk profile: with ``end_tau`` < 1
        the body still moves when it reaches the target and stops there at once,
        as a hand stopped by the handle it grasps or a cup by the table; with
        ``start_tau`` > 0 it leaves at once (a hand letting go). ``turn_until`` < 1
        finishes the rotation (its own minimum-jerk profile) at that fraction of the
        duration, so that the last part of the move is a pure translation.
        """
        frames = self._span(t1_s)
        p0, r0 = self.last_pose
        r1 = r0 if rotation is None else np.asarray(rotation, dtype=float)
        pivot = np.zeros(3) if pivot_m is None else np.asarray(pivot_m, dtype=float)
        a0 = p0 + r0 @ pivot
        a1 = a0 if position_m is None else np.asarray(position_m, dtype=float)
        t0 = self.now_s
        u = (self.times_s[frames] - t0) / max(t1_s - t0, 1e-9)
        s = _cut_profile(u, start_tau, end_tau)
        rots = slerp_matrices(r0, r1, s if turn_until >= 1.0 else min_jerk(u / turn_until))
        if via_m is None:
            anchor = a0 + s[:, None] * (a1 - a0)
        else:
            ctrl = np.vstack([a0, np.asarray(via_m, dtype=float).reshape(-1, 3), a1])
            deg = ctrl.shape[0] - 1
            w = s[:, None]
            anchor = sum(comb(deg, i) * w**i * (1.0 - w) ** (deg - i) * ctrl[i] for i in range(deg + 1))
        self.position_m[frames] = anchor - rots @ pivot
        self.rotation[frames] = rots
        self.cursor = frames[-1] + 1
        return self

    def follow(self, parent: Track, t1_s: float) -> Track:
        """Move rigidly with ``parent`` until ``t1_s``, keeping the relative pose of the last frame.

        ``parent`` must already be written up to ``t1_s``.
        """
        frames = self._span(t1_s)
        if parent.cursor <= frames[-1]:
            raise ValueError(f"track {self.name} follows {parent.name}, which ends at {parent.now_s:.3f} s")
        k = self.cursor - 1
        r_parent_self = parent.rotation[k].T @ self.rotation[k]
        p_parent_self = parent.rotation[k].T @ (self.position_m[k] - parent.position_m[k])
        self.position_m[frames] = parent.position_m[frames] + parent.rotation[frames] @ p_parent_self
        self.rotation[frames] = parent.rotation[frames] @ r_parent_self
        self.cursor = frames[-1] + 1
        return self

    def path(self, t1_s: float, fn: Callable[[np.ndarray], np.ndarray]) -> Track:
        """Fill positions with ``fn(t)`` ((N,) seconds → (N, 3) metres), keeping the rotation."""
        frames = self._span(t1_s)
        _, r = self.last_pose
        self.position_m[frames] = fn(self.times_s[frames])
        self.rotation[frames] = r
        self.cursor = frames[-1] + 1
        return self

    def finish(self) -> Track:
        """Hold the last pose to the end of the grid."""
        if self.cursor < self.times_s.shape[0]:
            self.hold(float(self.times_s[-1]))
        return self
