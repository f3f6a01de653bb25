"""Other takes and corrupted copies of a recording, for the verifier's tests.

The takes (rotated, translated, stretched, resampled, mirrored) follow the names of the
take generator (``oacdsl/segmentation/takes.py``); the corruptions change one thing of a
demonstration that ``oacc verify`` must reject by the right check. Every function returns
a new :class:`Recording`.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from oacdsl.segmentation.recording import Recording

# --- takes -------------------------------------------------------------------------------


def _centre_xy(rec: Recording) -> np.ndarray:
    pts = rec.positions_m.reshape(-1, 3)
    return np.nanmean(pts[:, :2], axis=0)


def rotated(rec: Recording, angle_rad: float, about_xy_m: np.ndarray | None = None) -> Recording:
    """Rotated about the vertical through ``about_xy_m`` (default: the markers' mean xy)."""
    c = _centre_xy(rec) if about_xy_m is None else np.asarray(about_xy_m, dtype=float)
    cos, sin = np.cos(angle_rad), np.sin(angle_rad)
    p = rec.positions_m.copy()
    x, y = p[..., 0] - c[0], p[..., 1] - c[1]
    p[..., 0], p[..., 1] = c[0] + cos * x - sin * y, c[1] + sin * x + cos * y
    return replace(rec, positions_m=p)


def translated(rec: Recording, offset_m: tuple[float, float, float]) -> Recording:
    return replace(rec, positions_m=rec.positions_m + np.asarray(offset_m, dtype=float))


def _interpolated(rec: Recording, old_t: np.ndarray, new_t: np.ndarray, rate_hz: float) -> Recording:
    """Positions linearly interpolated at ``new_t`` (on the old time axis ``old_t``); a sample
    next to a gap is a gap."""
    p = rec.positions_m
    idx = np.clip(np.searchsorted(old_t, new_t, side="right") - 1, 0, len(old_t) - 2)
    w = ((new_t - old_t[idx]) / (old_t[idx + 1] - old_t[idx]))[:, None, None]
    out = (1 - w) * p[idx] + w * p[idx + 1]
    times = np.arange(len(new_t)) / rate_hz
    return replace(rec, rate_hz=rate_hz, times_s=times, positions_m=out)


def stretched(rec: Recording, factor: float) -> Recording:
    """Time × ``factor`` (2 = twice as slow), the same frame rate."""
    t = rec.times_s - rec.times_s[0]
    n = int(np.floor(t[-1] * factor * rec.rate_hz)) + 1
    new_t = np.arange(n) / rec.rate_hz / factor
    return _interpolated(rec, t, np.minimum(new_t, t[-1]), rec.rate_hz)


def resampled(rec: Recording, rate_hz: float) -> Recording:
    """The same motion sampled at ``rate_hz``."""
    t = rec.times_s - rec.times_s[0]
    n = int(np.floor(t[-1] * rate_hz)) + 1
    return _interpolated(rec, t, np.arange(n) / rate_hz, rate_hz)


def mirrored(rec: Recording, left: str = "left_hand", right: str = "right_hand") -> Recording:
    """Reflected across the vertical plane x = mean x; the two hands' groups exchanged."""
    c = _centre_xy(rec)
    p = rec.positions_m.copy()
    p[..., 0] = 2 * c[0] - p[..., 0]
    groups = dict(rec.groups)
    groups[left], groups[right] = rec.groups[right], rec.groups[left]
    return replace(rec, positions_m=p, groups=groups)


# --- corruptions ---------------------------------------------------------------------------


def _with_group(rec: Recording, name: str, frames: slice, new: np.ndarray) -> Recording:
    p = rec.positions_m.copy()
    idx = list(rec.groups[name])
    block = p[frames]
    block[:, idx, :] = new
    p[frames] = block
    return replace(rec, positions_m=p)


def _centroids(pts: np.ndarray) -> np.ndarray:
    return np.nanmean(pts, axis=1)


def turned_on_side(rec: Recording, name: str, from_frame: int) -> Recording:
    """``name`` rotated 90° about a horizontal axis through its centroid from ``from_frame`` on,
    lowered so that its lowest marker stays where it was."""
    pts = rec.group_positions(name)[from_frame:]
    c = _centroids(pts)[:, None, :]
    rot = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]])  # 90° about x
    new = (pts - c) @ rot.T + c
    new[..., 2] += np.nanmin(pts[..., 2], axis=1)[:, None] - np.nanmin(new[..., 2], axis=1)[:, None]
    return _with_group(rec, name, slice(from_frame, None), new)


def moved_back(rec: Recording, name: str, from_frame: int) -> Recording:
    """``name`` from ``from_frame`` on shifted horizontally so that it ends where it started."""
    pts = rec.group_positions(name)
    shift = np.nanmean(pts[0], axis=0) - np.nanmean(pts[-1], axis=0)
    shift[2] = 0.0
    return _with_group(rec, name, slice(from_frame, None), pts[from_frame:] + shift)


def lifted(rec: Recording, names: list[str], start: int, stop: int, height_m: float = 0.4) -> Recording:
    """``names`` (a tool and the hand holding it) raised by ``height_m`` over frames
    [start, stop), ramping up and down over a tenth of the span."""
    n = stop - start
    ramp = max(1, n // 10)
    lift = np.minimum(1.0, np.minimum(np.arange(n) + 1, n - np.arange(n)) / ramp) * height_m
    out = rec
    for name in names:
        pts = out.group_positions(name)[start:stop].copy()
        pts[..., 2] += lift[:, None]
        out = _with_group(out, name, slice(start, stop), pts)
    return out


def straightened(rec: Recording, names: list[str], start: int, stop: int) -> Recording:
    """The first of ``names`` travels [start, stop) on a straight line at constant speed from
    where it was at ``start`` to where it was at ``stop``, orientation unchanged frame by frame;
    the others (its hand) are carried along by the same offset."""
    c = _centroids(rec.group_positions(names[0])[start:stop])
    w = np.linspace(0.0, 1.0, stop - start)[:, None]
    line = (1 - w) * c[0] + w * c[-1]
    offset = (line - c)[:, None, :]
    out = rec
    for name in names:
        out = _with_group(out, name, slice(start, stop), out.group_positions(name)[start:stop] + offset)
    return out


def unturned(rec: Recording, names: list[str], start: int, stop: int) -> Recording:
    """The first of ``names`` keeps its orientation at ``start`` over [start, stop) (its markers
    ride along with its centroid); the others follow its centroid."""
    pts = rec.group_positions(names[0])
    c = _centroids(pts[start:stop])
    rigid = pts[start] - np.nanmean(pts[start], axis=0)
    new = rigid[None] + c[:, None, :]
    out = _with_group(rec, names[0], slice(start, stop), new)
    return out
