"""Corrupted copies of a recording, for the verifier's tests: each changes one thing of a
demonstration that ``oacc verify`` must reject by the right check (other takes, which it must
accept, come from the take generator, ``oacdsl/segmentation/takes.py``). Every function
returns a new :class:`Recording`.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from oacdsl.segmentation.recording import Recording

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


def turned_upside_down(rec: Recording, name: str, from_frame: int) -> Recording:
    """``name`` rotated 180° about a horizontal axis through its centroid from ``from_frame`` on,
    lowered or raised so that its lowest marker stays where it was."""
    pts = rec.group_positions(name)[from_frame:]
    c = _centroids(pts)[:, None, :]
    rot = np.diag([1.0, -1.0, -1.0])  # 180° about x
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
