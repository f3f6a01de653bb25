"""Resting on top: an object left at rest on top of another touches it.

A pair of objects that never moves together has no distance of its own to learn from
co-motion (:mod:`oacdsl.segmentation.comotion`), and a fixed one does not fit: a lid's markers
on its bottle sit 77 mm from the bottle's (markers on the bottle's shoulder, the lid's on its
top), more than a hand resting *beside* an object is from it. Physically the case needs no
distance: an object that nobody holds and that rests with all its markers above another's,
over that object's footprint, is carried by it. So, an option of the adaptive detector
(``AdaptiveSettings.stacked``), for two objects X and Y (not agents) on the frames where

- X and Y are both still (their median marker speed below ``move_speed_m_s``) and no agent
  holds X (co-motion, steps 1–3),
- X's lowest marker is at least as high as Y's highest one, and the centre of X's markers lies
  over Y: inside the convex hull of Y's markers seen from above (both from the median marker
  positions of the rest, so that noise does not decide),

for at least ``tool_dwell_s``, X *rests on* Y. The rest teaches the pair its distance as a
co-motion episode does (the median closest marker distance of the rest × (1 + ``margin``), at
most ``d``), and the contact grows from the rest both ways while the closest distance stays
within it (:func:`~oacdsl.segmentation.episodes.extend_episode`, excursions up to ``tool_bridge_s``
bridged): back to where X was set down, forward while it is turned or held in place on Y, until
it is lifted off. Nothing here depends on where the markers sit on either object, on the scene's
scale, the frame rate, the pace (durations are the detector's rescaled ones), a rotation about
the vertical or the mirror; it needs the vertical (z up, as every reader gives it).

Containers are not covered (a liquid in a cup sits below the cup's rim markers): their contents
touch by co-motion or the paper's rule at the static distance. Memory O(frames) per object pair
within reach that ever meets the height condition.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

from oacdsl.segmentation.comotion import frames_within
from oacdsl.segmentation.episodes import extend_episode, true_runs, union_spans
from oacdsl.segmentation.holding import median_speeds
from oacdsl.segmentation.pairs import PairTable
from oacdsl.segmentation.recording import Recording, column_index

__all__ = ["inside_hull", "resting_on_top", "with_rests"]

Spans = list[tuple[int, int]]



def _hull(points: np.ndarray) -> list[tuple[float, ...]]:
    """The convex hull of (k, 2) points, counterclockwise (Andrew's monotone chain): its corners
    (all the points when fewer than three)."""
    pts = sorted(set(map(tuple, points.tolist())))
    if len(pts) < 3:
        return pts

    def cross(o: tuple[float, ...], a: tuple[float, ...], b: tuple[float, ...]) -> float:
        return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])

    lower: list[tuple[float, ...]] = []
    for p in pts:
        while len(lower) >= 2 and cross(lower[-2], lower[-1], p) <= 0:
            lower.pop()
        lower.append(p)
    upper: list[tuple[float, ...]] = []
    for p in reversed(pts):
        while len(upper) >= 2 and cross(upper[-2], upper[-1], p) <= 0:
            upper.pop()
        upper.append(p)
    return lower[:-1] + upper[:-1]


def inside_hull(point_xy: np.ndarray, points_xy: np.ndarray) -> bool:
    """Is ``point_xy`` (2,) inside (or on) the convex hull of ``points_xy`` (k, 2)? False when the
    hull has no area (fewer than three markers, or all on a line)."""
    hull = _hull(points_xy)
    if len(hull) < 3:
        return False
    # each edge's cross product with the point, in float64 as numpy's would be: a few corners,
    # cheaper in Python than as arrays
    px, py = (float(v) for v in point_xy[:2])
    for (ax, ay), (bx, by) in zip(hull, hull[1:] + hull[:1], strict=True):
        if not (bx - ax) * (py - ay) - (by - ay) * (px - ax) >= 0:  # NaN: not inside
            return False
    return True


def resting_on_top(
    recording: Recording,
    table: PairTable,
    closest: Mapping[int, np.ndarray],
    held: Mapping[int, Spans],
    agents: Sequence[int],
    reach_m: float,
    move_speed_m_s: float,
    lag_s: float,
    dwell_s: float,
    bridge_s: float,
    margin: float,
) -> dict[int, tuple[Spans, float]]:
    """Object pair → (frame intervals ``[a, b)`` of touching grown from its rests on top, the pair's
    distance learned from them: the median of the rests' thresholds, metres) (module doc).

    ``closest``: pair → (F,) closest marker distance, metres (inf beyond reach, NaN in gaps);
    ``held``: pair → intervals of touching by co-motion (only agent–object pairs are read: who
    holds what); ``reach_m``: ``d``, the most a learned distance may be; speeds over ``lag_s``;
    ``dwell_s``: the shortest rest; ``bridge_s``: excursions that do not end the contact;
    ``margin``: as co-motion's.
    """
    agent_set = set(agents)
    n_frames = recording.n_frames
    if n_frames < 2:
        return {}
    rate = recording.rate_hz
    lag = max(1, round(lag_s * rate))
    dwell = max(1, round(dwell_s * rate))
    bridge = frames_within(bridge_s, rate)
    names = table.instances
    index = {(int(a), int(b)): q for q, (a, b) in enumerate(table.instance_pairs)}
    times = np.asarray(recording.times_s, dtype=np.float64)
    cache: dict[tuple[str, int], np.ndarray] = {}
    shapes: dict[int, tuple[np.ndarray, ...]] = {}
    columns = {i: np.asarray(recording.groups[names[i]], dtype=np.intp) for i in range(len(names))}
    # an instance's markers as a slice where they are consecutive (the usual layout): a strided
    # view, read without numpy's fancy indexing (the same values)
    take = {i: column_index(c) for i, c in columns.items()}

    def points(i: int, frames: np.ndarray | slice) -> np.ndarray:
        """(R, k, 3) instance ``i``'s markers at ``frames``."""
        if isinstance(frames, slice):
            return recording.positions_m[frames, take[i]]
        cols = take[i]
        if isinstance(cols, slice):
            return recording.positions_m[frames, cols]
        return recording.positions_m[frames[:, None], cols]

    # the frames the cheap tests look at, the grid: one per lag_s (frames 0, lag, 2 lag, …)

    def shape(i: int) -> tuple[np.ndarray, ...]:
        """Per frame of the grid, instance ``i``'s lowest and highest marker height, the centre of
        its markers seen from above (G, 2) and the squared radius of the disk around it that holds
        them (NaN where no marker is seen): the tests before :func:`_on_top`'s hull."""
        if i not in shapes:
            # the grid's frames as a strided slice (a fifth of the time of indexing by
            # ``arange(0, F, lag)``); (3, k, G): each reduction over the k markers runs along whole
            # rows of frames (the same values, in the same order, as over the (G, k) axis)
            x, y, z = np.ascontiguousarray(recording.positions_m[::lag, take[i]].transpose(2, 1, 0))
            seen = np.isfinite(x)
            with np.errstate(invalid="ignore", divide="ignore"):
                count = seen.sum(axis=0)
                cx = np.where(seen, x, 0.0).sum(axis=0) / count
                cy = np.where(seen, y, 0.0).sum(axis=0) / count
                ox, oy = x - cx, y - cy
                shapes[i] = (np.fmin.reduce(z, axis=0), np.fmax.reduce(z, axis=0), np.stack([cx, cy], axis=1),
                             np.fmax.reduce(ox ** 2 + oy ** 2, axis=0))
        return shapes[i]

    def free(i: int) -> np.ndarray:
        """(F,) no agent holds instance ``i``."""
        if ("free", i) not in cache:
            mask = np.ones(n_frames, dtype=bool)
            for h in agent_set:
                for a, b in held.get(index.get((min(h, i), max(h, i)), -1), []):
                    mask[a:b] = False
            cache[("free", i)] = mask
        return cache[("free", i)]

    def still(i: int, s: int, e: int) -> np.ndarray:
        """(e - s,) instance ``i`` still at frames ``s:e`` (its speeds as over the whole recording)."""
        lo = max(0, s - lag)
        with np.errstate(invalid="ignore"):
            return median_speeds(points(i, slice(lo, e)), times[lo:e], lag)[s - lo:] < move_speed_m_s

    found: dict[int, tuple[Spans, list[float]]] = {}
    for q, dmin in closest.items():
        a, b = (int(i) for i in table.instance_pairs[q])
        if a in agent_set or b in agent_set:
            continue
        for top, base in ((a, b), (b, a)):
            if columns[base].size < 3:
                continue  # no footprint to rest on
            (low, _, centre, _), (_, high, middle, radius2) = shape(top), shape(base)
            gap = centre - middle
            with np.errstate(invalid="ignore"):  # NaN: unknown, not above; each grid frame for its lag_s
                over = (low >= high) & (gap[:, 0] ** 2 + gap[:, 1] ** 2 <= radius2)
            if over.sum() * lag < dwell:
                continue
            with np.errstate(invalid="ignore"):  # NaN: a gap, unknown
                above = (dmin <= reach_m) & free(top) & np.repeat(over, lag)[:n_frames]
            for s, e in true_runs(above):
                if e - s < dwell:
                    continue
                resting = still(top, s, e) & still(base, s, e)
                for s2, e2 in true_runs(resting):
                    r0, r1 = s + s2, s + e2
                    if r1 - r0 < dwell:
                        continue
                    rest = np.unique(np.linspace(r0, r1 - 1, min(r1 - r0, REST_SAMPLES)).astype(np.intp))
                    if not _on_top(points(top, rest), points(base, rest)):
                        continue
                    with np.errstate(invalid="ignore"):
                        rest_m = float(np.nanmedian(dmin[r0:r1]))
                    if not np.isfinite(rest_m):
                        continue
                    threshold = min(rest_m * (1 + margin), reach_m)
                    spans, thresholds = found.setdefault(q, ([], []))
                    spans.append(extend_episode(dmin, r0, r1, threshold, bridge))
                    thresholds.append(threshold)
    return {q: (union_spans(spans), float(np.median(thresholds))) for q, (spans, thresholds) in found.items()}


#: Frames of a rest, evenly spread, whose median positions decide :func:`_on_top` (the objects are
#: still: more frames add nothing but time).
REST_SAMPLES = 15


def _median_pose(points_m: np.ndarray) -> np.ndarray:
    """(k, 3) median over frames of (F, k, 3) marker positions, NaN ignored (NaN: never seen)."""
    flat = np.sort(points_m.reshape(points_m.shape[0], -1), axis=0)  # NaN sort last
    count = np.isfinite(flat).sum(axis=0)
    cols = np.arange(flat.shape[1])
    low, high = np.maximum(count - 1, 0) // 2, np.minimum(count // 2, flat.shape[0] - 1)
    median = np.where(count > 0, (flat[low, cols] + flat[high, cols]) / 2, np.nan)
    return median.reshape(points_m.shape[1:])


def _on_top(top_m: np.ndarray, base_m: np.ndarray) -> bool:
    """Does an object at ``top_m`` ((F, k, 3) markers over a rest: at most :data:`REST_SAMPLES` of
    its frames, evenly spread) lie on top of one at ``base_m``:
    its lowest marker at least as high as the other's highest, its centre over the other's
    markers' hull seen from above (median positions over the rest)?"""
    with np.errstate(invalid="ignore"):  # a marker never seen in the rest: NaN
        both = _median_pose(np.concatenate([top_m, base_m], axis=1))  # each marker's own median
    top, base = both[: top_m.shape[1]], both[top_m.shape[1] :]
    top, base = top[np.isfinite(top).all(axis=1)], base[np.isfinite(base).all(axis=1)]
    if top.shape[0] == 0 or base.shape[0] < 3:
        return False
    return bool(top[:, 2].min() >= base[:, 2].max()) and inside_hull(top[:, :2].mean(axis=0), base[:, :2])


def with_rests(learned: Mapping[int, tuple[Spans, float]],
               rests: Mapping[int, tuple[Spans, float]]) -> dict[int, tuple[Spans, float]]:
    """Co-motion's ``learned`` (pair → (intervals, distance)) with the rests on top added: a pair's
    intervals joined; its distance co-motion's where it co-moves, else its rests'."""
    out = dict(learned)
    for q, (spans, threshold) in rests.items():
        if q in out:
            own, distance = out[q]
            out[q] = (union_spans([*own, *spans]), distance)
        else:
            out[q] = (spans, threshold)
    return out
