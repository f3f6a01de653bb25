"""Summary features of an object's path relative to another: what a skill needs to follow it.

Given ``T_target_object`` over a sub-action (metres, seconds), :func:`motion_features`
reports the path length, the extent along the path's principal axes, the dominant
period of an oscillation (stirring circles, wiping strokes) with its number of
cycles and radius, and the tilt the object reaches relative to the target (a pour)
with how long it stays tilted. Frames without a pose (NaN) are left out of lengths
and bridged linearly for the period. numpy only.

Definitions (all in the target's frame):

- **path length**: the length of the object frame's origin's path sampled every
  :data:`SMOOTH_S` seconds from its first posed frame (linearly between posed frames),
  metres: in seconds, not frames, so that a take at 30-240 Hz of a 10 Hz recording measures
  what the recording does (a moving average over frames cut its corners: 5 % shorter), and
  marker jitter, small against a moving object's 0.05 s step, adds next to nothing at any rate.
- **extent**: peak-to-peak of the origin's path along its three principal axes
  (PCA of the positions), largest first, metres.
- **core**: the frames where the object dwells: the longest run of posed frames
  within :data:`CORE_FACTOR` × the median distance of the path from its median point, both
  taken over the path in time (the lines between frames sampled finely), ``core_s`` its
  entry and exit times between frames (:mod:`oacdsl.segmentation.pathcore`: the object
  entering and leaving the target is cut off; a stir is the circles, not the spoon's way into
  the cup). Period, cycles and radius describe the core.
- **period**: the lag of the first peak (at least :data:`MIN_PERIODICITY`) of the
  path's autocorrelation (principal plane, centred, linear trend removed) after it
  first turns negative, refined by a
  parabola through the peak; reported only when the peak lies 3–5.5 times as far as the first zero
  crossing (4 for a sinusoid; white noise crosses anywhere), the core holds
  :data:`MIN_CYCLES` periods or more and its radius is :data:`MIN_RADIUS_M` or more.
  ``cycles`` = the core's duration / period.
- **radius**: the median distance of the path from its centre in the principal plane
  (a circle's radius; half a stroke's length, roughly, for strokes), metres.
- **tilt**: the angle between the object's z axis and the target's z axis, radians
  (0 while both stand as they stood at their reference frame); ``tilt_max_rad`` its
  largest value, ``tilt_time_s`` the time it stays at or above half of that (0 when
  the largest tilt is below :data:`MIN_TILT_RAD`); ``tilt_rise_s`` the time it takes to
  tilt: from the last frame at or below 10 % of the largest tilt before it is first reached
  (the span's start when there is none) to the first frame at or above 90 % of it (None below
  :data:`MIN_TILT_RAD`; a constant-rate tilt over *T* seconds rises in 0.8 *T*).
  ``end_tilt_rad`` the tilt at the last posed frame: how the object ends relative to the
  target (a plate left standing on edge in a rack: about 90°).
- **twist**: the object's net rotation about the target's z axis, radians, signed
  (positive counterclockwise seen from above the target: a right-hand thread's lid
  unscrewed; negative: screwed on): the sum of the frame-to-frame rotations' components
  along that axis, so several turns (a lid regrasped and turned again) add up past 180°;
  a gap is bridged by the rotation across it. 0 when fewer than two frames are posed.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from oacdsl.segmentation.pathcore import CORE_FACTOR, core_entry, core_frames, core_times

__all__ = [
    "CORE_FACTOR",
    "MIN_CYCLES",
    "MIN_PERIODICITY",
    "MIN_RADIUS_M",
    "MIN_TILT_RAD",
    "SMOOTH_S",
    "MotionFeatures",
    "core_entry",
    "core_frames",
    "dominant_period",
    "motion_features",
    "tilt_rise",
    "twist_angle",
]

#: Smallest autocorrelation (0..1) at the period's lag for an oscillation to count.
MIN_PERIODICITY = 0.3
#: Fewest periods the span must hold for a period to be reported.
MIN_CYCLES = 1.5
#: Smallest radius of a reported oscillation, metres: below it the path is jitter of the fit.
MIN_RADIUS_M = 0.005
#: The period's lag over the first zero crossing's lag (4 for a sinusoid).
_ZERO_RATIO = (3.0, 5.5)
#: Time step a path length is measured at, seconds (marker jitter would add length at high
#: frame rates over every frame; a 0.6 s stirring circle loses ~1 %).
SMOOTH_S = 0.05
#: Smallest tilt whose duration is measured, radians (5°: below it the object was not tilted).
MIN_TILT_RAD = math.radians(5.0)
#: Fewest posed frames for a period estimate.
_MIN_SAMPLES = 8


@dataclass(frozen=True)
class MotionFeatures:
    """Features of one object-relative path (SI units; ``None`` where not defined)."""

    duration_s: float
    path_length_m: float
    extent_m: tuple[float, float, float]
    core_s: tuple[float, float]
    period_s: float | None
    cycles: float | None
    radius_m: float
    tilt_max_rad: float
    tilt_time_s: float
    tilt_rise_s: float | None = None
    twist_rad: float = 0.0
    #: the object's tilt (its z axis from the target's) at the last posed frame: how it ends
    end_tilt_rad: float = 0.0

    def to_json(self) -> dict[str, Any]:
        return {
            "duration_s": round(self.duration_s, 6),
            "path_length_m": round(self.path_length_m, 6),
            "extent_m": [round(e, 6) for e in self.extent_m],
            "core_s": [round(c, 6) for c in self.core_s],
            "period_s": None if self.period_s is None else round(self.period_s, 6),
            "cycles": None if self.cycles is None else round(self.cycles, 3),
            "radius_m": round(self.radius_m, 6),
            "tilt_max_rad": round(self.tilt_max_rad, 6),
            "tilt_time_s": round(self.tilt_time_s, 6),
            "tilt_rise_s": None if self.tilt_rise_s is None else round(self.tilt_rise_s, 6),
            "twist_rad": round(self.twist_rad, 6),
            "end_tilt_rad": round(self.end_tilt_rad, 6),
        }


def _principal(points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Centred points (N, 3) → (coordinates along the principal axes (N, 3), axes (3, 3) as rows)."""
    centred = points - points.mean(axis=0)
    _, _, vt = np.linalg.svd(centred, full_matrices=False)
    axes = np.zeros((3, 3))
    axes[: vt.shape[0]] = vt
    return centred @ axes.T, axes


def dominant_period(times_s: np.ndarray, signal: np.ndarray) -> tuple[float | None, float]:
    """The dominant period (seconds) of a (N,) or (N, d) signal and its autocorrelation there.

    Gaps (NaN rows) are bridged linearly; samples are taken as evenly spaced at the
    median step. Returns ``(None, 0.0)`` when no peak passes the module's rules.
    """
    t = np.asarray(times_s, dtype=np.float64)
    x = np.asarray(signal, dtype=np.float64).reshape(len(t), -1)
    ok = np.isfinite(x).all(axis=1)
    if ok.sum() < _MIN_SAMPLES:
        return None, 0.0
    x = np.stack([np.interp(t, t[ok], col[ok]) for col in x.T], axis=1)
    n = len(t)
    dt = float(np.median(np.diff(t)))
    design = np.stack([np.ones(n), t - t.mean()], axis=1)
    x = x - design @ np.linalg.lstsq(design, x, rcond=None)[0]  # centre, remove a linear drift
    spectrum = np.fft.rfft(x, n=2 * n, axis=0)
    acf = np.fft.irfft((spectrum * spectrum.conj()).real, axis=0)[:n].sum(axis=1)
    if acf[0] <= 0:
        return None, 0.0
    acf = acf / acf[0] * n / (n - np.arange(n))  # unbiased, normalised: acf[0] = 1
    max_lag = int(n / MIN_CYCLES)
    negative = np.flatnonzero(acf[1 : max_lag + 1] < 0)
    if negative.size == 0:
        return None, 0.0
    lo = int(negative[0]) + 1
    if lo + 1 > max_lag:
        return None, 0.0
    zero = lo - 1 + acf[lo - 1] / (acf[lo - 1] - acf[lo])  # lag of the first zero crossing
    lags = np.arange(lo, min(max_lag, n - 2) + 1)
    peaks = lags[(acf[lags] >= acf[lags - 1]) & (acf[lags] >= acf[lags + 1]) & (acf[lags] >= MIN_PERIODICITY)]
    if peaks.size == 0:
        return None, float(acf[lo : max_lag + 1].max())
    k = int(peaks[0])  # the first clear peak: the period, not a multiple of it
    peak = float(acf[k])
    if not _ZERO_RATIO[0] <= k / zero <= _ZERO_RATIO[1]:
        return None, peak  # an oscillation crosses zero a quarter period in; noise anywhere
    a, b, c = acf[k - 1], acf[k], acf[k + 1]
    denom = a - 2 * b + c
    shift = 0.5 * (a - c) / denom if denom < 0 else 0.0
    return (k + float(np.clip(shift, -0.5, 0.5))) * dt, peak


def _path_length(times_s: np.ndarray, points: np.ndarray) -> float:
    """Length (m) of the (N, 3) ``points`` at ``times_s`` sampled every :data:`SMOOTH_S` from the
    first, linearly between them (module doc)."""
    t = np.asarray(times_s, dtype=np.float64)
    if len(t) < 2:
        return 0.0
    grid = np.arange(t[0], t[-1], SMOOTH_S)
    grid = np.r_[grid[np.abs(grid - t[-1]) > 1e-9], t[-1]]
    samples = np.stack([np.interp(grid, t, col) for col in points.T], axis=1)
    return float(np.linalg.norm(np.diff(samples, axis=0), axis=1).sum())


def motion_features(times_s: np.ndarray, T_target_object: np.ndarray) -> MotionFeatures:
    """The features of one path (module doc); ``T_target_object`` (N, 4, 4), metres, NaN in gaps."""
    t = np.asarray(times_s, dtype=np.float64)
    T = np.asarray(T_target_object, dtype=np.float64)
    ok = np.isfinite(T[:, 0, 0])
    duration = float(t[-1] - t[0]) if len(t) else 0.0
    if ok.sum() < 2:
        return MotionFeatures(duration, 0.0, (0.0, 0.0, 0.0), (0.0, 0.0), None, None, 0.0, 0.0, 0.0)
    pos = T[ok, :3, 3]
    path = _path_length(t[ok], pos)
    extent = np.ptp(_principal(pos)[0], axis=0)
    a, b = core_frames(T[:, :3, 3], t)
    core = T[a:b, :3, 3]
    core_ok = np.isfinite(core).all(axis=1)
    plane = np.full((b - a, 2), np.nan)
    radius = 0.0
    if core_ok.sum() >= 2:
        plane[core_ok] = _principal(core[core_ok])[0][:, :2]
        radius = float(np.median(np.linalg.norm(plane[core_ok], axis=1)))
    period, _ = dominant_period(t[a:b], plane) if b - a >= _MIN_SAMPLES else (None, 0.0)
    core_s = core_times(T[:, :3, 3], t)
    cycles = (core_s[1] - core_s[0]) / period if period else None
    if cycles is not None and (cycles < MIN_CYCLES or radius < MIN_RADIUS_M):
        period = cycles = None
    tilt = np.arccos(np.clip(T[ok, 2, 2], -1.0, 1.0))  # z axis of the object in the target's frame
    tilt_max = float(tilt.max())
    dt = np.diff(t)
    step = np.r_[dt, dt[-1:]] if len(dt) else np.zeros(1)
    tilt_time = float(step[ok][tilt >= 0.5 * tilt_max].sum()) if tilt_max >= MIN_TILT_RAD else 0.0
    return MotionFeatures(
        duration,
        path,
        (float(extent[0]), float(extent[1]), float(extent[2])),
        core_s,
        period,
        cycles,
        radius,
        tilt_max,
        tilt_time,
        tilt_rise(t[ok], tilt) if tilt_max >= MIN_TILT_RAD else None,
        twist_angle(T[ok, :3, :3]),
        float(tilt[-1]),
    )


def twist_angle(R_target_object: np.ndarray) -> float:
    """The net rotation (rad, signed, counterclockwise about +z positive) of (N, 3, 3) rotations
    about the target's z axis: the sum of each step's rotation vector's z component (module doc)."""
    R = np.asarray(R_target_object, dtype=np.float64)
    if len(R) < 2:
        return 0.0
    step = R[1:] @ np.transpose(R[:-1], (0, 2, 1))  # R_{k+1} R_k^T: the step in the target's frame
    cos = np.clip((np.trace(step, axis1=1, axis2=2) - 1.0) / 2.0, -1.0, 1.0)
    angle = np.arccos(cos)
    axis = np.stack([step[:, 2, 1] - step[:, 1, 2], step[:, 0, 2] - step[:, 2, 0],
                     step[:, 1, 0] - step[:, 0, 1]], axis=1)
    norm = np.linalg.norm(axis, axis=1)
    z = np.where(norm > 1e-12, axis[:, 2] / np.maximum(norm, 1e-12), 0.0)
    return float((angle * z).sum())


def tilt_rise(times_s: np.ndarray, tilt_rad: np.ndarray) -> float:
    """Seconds the tilt takes from 10 % to 90 % of its largest value, on its way to that largest
    value (module doc); the crossings are interpolated linearly between samples."""
    peak = float(tilt_rad.max())

    def crossing(i: int, level: float) -> float:  # between samples i and i + 1
        a, b = float(tilt_rad[i]), float(tilt_rad[i + 1])
        w = (level - a) / (b - a) if b != a else 0.0
        return float(times_s[i] + np.clip(w, 0.0, 1.0) * (times_s[i + 1] - times_s[i]))

    top = int(np.argmax(tilt_rad >= 0.9 * peak))
    end = crossing(top - 1, 0.9 * peak) if top > 0 else float(times_s[0])
    low = np.flatnonzero(tilt_rad[:top] <= 0.1 * peak)
    start = crossing(int(low[-1]), 0.1 * peak) if low.size else float(times_s[0])
    return end - start
