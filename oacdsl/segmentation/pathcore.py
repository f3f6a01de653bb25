"""Where an object's path dwells at its target: the path's *core* (docs/motion.md).

The core is the longest run of posed frames within :data:`CORE_FACTOR` × the median distance
of the path from its median point: the object entering and leaving the target is cut off (a
stir is the circles, not the spoon's way into the cup). A feature read on the core, or from
where the object reaches its target, is a property of the motion, so its measure must not
depend on how the motion was sampled:

- **the median point and distance are those of the path in time**, not of its frames: with
  ``times_s`` given, the path between two consecutive posed frames is taken as the straight
  line a recording interpolates, sampled every :data:`FINE_S` at least (a 10 Hz recording's
  frames are its corners; the same motion at 240 Hz has most of its frames on the lines between
  them, nearer the middle, so a median over frames alone put the bound 10-20 % lower there and
  cut KIT Mix's 3.4 mixing circles to 2.4);
- **the core's ends lie between frames**: where the path crosses the bound on the line between
  the last frame outside and the first inside (:func:`core_entry`, :func:`core_times`).

Without ``times_s`` the frames alone are used (the runtime's keyframe paths). numpy only;
metres, seconds.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["CORE_FACTOR", "EXCURSION_SHARE", "FINE_S", "core_bound", "core_entry", "core_frames",
           "core_times"]

#: The core holds the points within this many median distances of the path's median point.
CORE_FACTOR = 2.5
#: An excursion beyond the bound between two stretches within it, lasting at most this share of
#: the path's frames (of its duration), does not cut the core: the far side of a wide circle.
EXCURSION_SHARE = 0.1
#: Longest time step at which a path between two frames is sampled for the core's bound, s.
FINE_S = 1.0 / 240.0


def _in_time(points: np.ndarray, times_s: np.ndarray) -> np.ndarray:
    """The posed frames of (N, 3) ``points`` and the straight lines between consecutive posed
    frames, sampled every :data:`FINE_S` at most, evenly in time (M, 3)."""
    ok = np.isfinite(points).all(axis=1)
    t = np.asarray(times_s, dtype=np.float64)
    pairs = np.flatnonzero(ok[:-1] & ok[1:])
    if pairs.size == 0:
        return points[ok]
    step = float(np.median(t[pairs + 1] - t[pairs]))
    k = max(1, math.ceil(step / FINE_S - 1e-9))
    s = np.arange(k, dtype=np.float64)[None, :, None] / k
    lines = points[pairs][:, None, :] + s * (points[pairs + 1] - points[pairs])[:, None, :]
    ends = np.ones(len(points), dtype=bool)
    ends[pairs] = False  # a pair's first frame is its line's first sample
    return np.concatenate([lines.reshape(-1, 3), points[ok & ends]])


def core_bound(points: np.ndarray, times_s: np.ndarray | None = None) -> tuple[np.ndarray, float]:
    """(the path's median point (3,), the core's bound: :data:`CORE_FACTOR` × the median distance
    from it, metres) of (N, 3) ``points`` (NaN in gaps), in time when ``times_s`` is given."""
    ok = np.isfinite(points).all(axis=1)
    sample = _in_time(points, times_s) if times_s is not None and len(points) > 1 else points[ok]
    centre = np.median(sample, axis=0)
    return centre, CORE_FACTOR * float(np.median(np.linalg.norm(sample - centre, axis=1)))


def core_frames(points: np.ndarray, times_s: np.ndarray | None = None) -> tuple[int, int]:
    """``[a, b)``: the longest run of rows of (N, 3) ``points`` near their median point (module doc)."""
    ok = np.isfinite(points).all(axis=1)
    if not ok.any():
        return 0, 0
    centre, bound = core_bound(points, times_s)
    dist = np.linalg.norm(points - centre, axis=1)
    far = np.zeros(len(points), dtype=bool)
    far[ok] = dist[ok] > bound
    edges = np.diff(np.r_[0, far.astype(np.int8), 0])
    for a, b in zip(np.flatnonzero(edges == 1), np.flatnonzero(edges == -1), strict=True):
        if 0 < a and b < len(points) and (b - a) <= EXCURSION_SHARE * len(points):
            far[a:b] = False  # a brief excursion between two stretches near: still dwelling
    near = (~far).astype(np.int8)  # a gap does not cut the core
    edges = np.diff(np.r_[0, near, 0])
    starts, stops = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)
    posed = np.r_[0, np.cumsum(ok)]
    k = int(np.argmax(posed[stops] - posed[starts]))  # the run with the most posed frames
    inside = np.flatnonzero(ok[starts[k] : stops[k]]) + starts[k]
    return (int(inside[0]), int(inside[-1]) + 1) if inside.size else (0, 0)


def _crossing(outside: np.ndarray, inside: np.ndarray, centre: np.ndarray, bound: float) -> float:
    """The share (0..1) of the line from ``outside`` to ``inside`` at which its distance from
    ``centre`` falls to ``bound``."""
    d = inside - outside
    o = outside - centre
    a, b, c = float(d @ d), 2.0 * float(o @ d), float(o @ o) - bound * bound
    if a <= 0.0 or c <= 0.0:
        return 1.0 if c > 0.0 else 0.0
    root = (-b - math.sqrt(max(b * b - 4 * a * c, 0.0))) / (2 * a)
    return float(min(max(root, 0.0), 1.0))


def core_entry(points: np.ndarray, times_s: np.ndarray | None = None) -> tuple[int, float]:
    """Where the path of (N, 3) ``points`` enters its core, between frames: ``(a, w)``, the
    core's first frame ``a`` and the share ``w`` (0..1) of the line from frame ``a - 1`` to
    ``a`` at which the path reaches the core's bound (1.0 when frame ``a - 1`` is no posed frame
    outside the core). A quantity read where the object arrives is then read at the same moment
    of the motion whatever the frame rate or the pace, not at whichever frame came first after it."""
    a, _ = core_frames(points, times_s)
    ok = np.isfinite(points).all(axis=1)
    if a == 0 or not ok[a - 1] or not ok[a]:
        return a, 1.0
    centre, bound = core_bound(points, times_s)
    if not np.linalg.norm(points[a - 1] - centre) > bound:
        return a, 1.0
    return a, _crossing(points[a - 1], points[a], centre, bound)


def core_times(points: np.ndarray, times_s: np.ndarray) -> tuple[float, float]:
    """(when the path of (N, 3) ``points`` at ``times_s`` enters its core, when it leaves it),
    seconds, between frames (:func:`core_entry`); (0, 0) without a core."""
    t = np.asarray(times_s, dtype=np.float64)
    a, b = core_frames(points, t)
    if b <= a:
        return 0.0, 0.0
    centre, bound = core_bound(points, t)
    ok = np.isfinite(points).all(axis=1)
    start, end = float(t[a]), float(t[b - 1])
    if a > 0 and ok[a - 1] and np.linalg.norm(points[a - 1] - centre) > bound:
        start = float(t[a - 1] + _crossing(points[a - 1], points[a], centre, bound) * (t[a] - t[a - 1]))
    if b < len(points) and ok[b] and np.linalg.norm(points[b] - centre) > bound:
        end = float(t[b] - _crossing(points[b], points[b - 1], centre, bound) * (t[b] - t[b - 1]))
    return start, end
