"""Holding still: a hand that comes to rest on or around a still object touches it.

Co-motion (:mod:`oacdsl.segmentation.comotion`) sees a grasp only when the object moves with
the hand; a hand holding a bottle still while the other hand turns its lid never moves it.
This rule, an option of the adaptive detector (``AdaptiveSettings.hold_still``), adds a contact
between agent H and object X on the frames where

- both are still (the median marker speed of each below ``move_speed_m_s``),
- H's closest marker is within half of X's size (its largest marker distance, median over
  frames; markers sit on an object's surface, so a hand around it has its markers within about
  half its extent of the object's), and never farther than ``d``,
- the stillness began with H arriving *at X*: within ``tool_dwell_s`` before it H moved, and
  during its approach (that ``tool_dwell_s``, and the whole motion it ends, since H last rested or
  held something else) its distance to X fell
  by more than a quarter of X's size (a hand resting beside an object from the start, or coming
  to rest beside it as it retreats, has not taken hold of it; a hand slowing down as it reaches
  an object at 10 Hz closes less than that in its last half second),

for at least ``tool_dwell_s``, while H holds nothing else (co-motion: a hand that sets a plate
into a rack and rests there holding it has not taken hold of the rack). Memory O(frames) per
agent × object pair within reach.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

from oacdsl.segmentation.episodes import true_runs
from oacdsl.segmentation.medians import median_rows
from oacdsl.segmentation.pairs import PairTable
from oacdsl.segmentation.recording import Recording
from oacdsl.segmentation.scales import instance_size_m

__all__ = ["median_speeds", "resting_holds"]

Spans = list[tuple[int, int]]


def median_speeds(points_m: np.ndarray, times_s: np.ndarray, lag: int) -> np.ndarray:
    """(F,) median marker speed over ``lag`` frames of an instance's markers ``points_m`` (F, k, 3),
    m/s (NaN in gaps)."""
    n = points_m.shape[0]
    out = np.full(n, np.nan)
    if n > lag:
        with np.errstate(invalid="ignore"):
            diff = points_m[lag:] - points_m[:-lag]
            step = np.sqrt(diff[..., 0] * diff[..., 0] + diff[..., 1] * diff[..., 1]
                           + diff[..., 2] * diff[..., 2])  # (F - lag, k), as np.linalg.norm(axis=2)
            speed = median_rows(np.ascontiguousarray(step.T)) / (times_s[lag:] - times_s[:-lag])
        out[lag:] = speed
        out[:lag] = speed[0]
    return out



def resting_holds(recording: Recording, table: PairTable, closest: Mapping[int, np.ndarray],
                  agents: Sequence[int], reach_m: float, move_speed_m_s: float, lag_s: float,
                  dwell_s: float, speeds: Mapping[int, np.ndarray] | None = None,
                  held: Mapping[int, Spans] | None = None) -> dict[int, Spans]:
    """Instance pair → frame intervals ``[a, b)`` of holding still (module doc).

    ``closest``: pair → (F,) closest marker distance, metres (inf beyond reach, NaN in gaps);
    ``reach_m``: ``d``; speeds over ``lag_s``; ``dwell_s``: the shortest hold and how recently
    the hand must have moved; ``speeds``: instance → its speeds as the co-motion scan measured
    them (:class:`~oacdsl.segmentation.comotion.CoMotion`; the same values from frame ``lag`` on,
    not measured again), used for the agents, whose markers no gap filling moves; ``held``: pair →
    intervals of touching by co-motion: a hand holding another object is not taking hold of X.
    """
    if not agents:
        return {}
    rate = recording.rate_hz
    lag = max(1, round(lag_s * rate))
    dwell = max(1, round(dwell_s * rate))
    names = table.instances
    times = np.asarray(recording.times_s, dtype=np.float64)
    index = {(int(a), int(b)): q for q, (a, b) in enumerate(table.instance_pairs)}
    points: dict[int, np.ndarray] = {}
    still: dict[int, np.ndarray] = {}
    sizes: dict[int, float] = {}

    def positions(i: int) -> np.ndarray:
        if i not in points:
            points[i] = recording.group_positions(names[i])
        return points[i]

    def is_still(i: int) -> np.ndarray:
        if i not in still:
            given = speeds.get(i) if speeds is not None and i in agents else None
            if given is not None and given.size > lag:  # as _speeds: the first frames take frame lag's
                speed = given.copy()
                speed[:lag] = given[lag]
            else:
                speed = median_speeds(positions(i), times, lag)
            with np.errstate(invalid="ignore"):
                still[i] = speed < move_speed_m_s
        return still[i]

    def busy(h: int, x: int) -> np.ndarray:
        """(F,) agent ``h`` holds an object other than ``x`` (co-motion, ``held``)."""
        mask = np.zeros(recording.n_frames, dtype=bool)
        for o in range(len(names)):
            q = index.get((min(h, o), max(h, o)))
            if o != x and o not in agents and held is not None and q is not None:
                for a, b in held.get(q, []):
                    mask[a:b] = True
        return mask

    out: dict[int, Spans] = {}
    for h in agents:
        for x in range(len(names)):
            q = index.get((min(h, x), max(h, x)))
            if x in agents or q is None or q not in closest:
                continue
            d = closest[q]
            with np.errstate(invalid="ignore"):  # a hold needs dwell frames within d of a still hand
                candidate = (d <= reach_m) & is_still(h)
            if not any(b - a >= dwell for a, b in true_runs(candidate)):
                continue
            if x not in sizes:
                sizes[x] = instance_size_m(positions(x))
            size = sizes[x]
            if not np.isfinite(size):
                continue
            with np.errstate(invalid="ignore"):
                near = d <= min(size / 2, reach_m)
            other = busy(h, x)
            resting = near & is_still(h) & is_still(x) & ~other
            moved = ~is_still(h)
            spans = []
            for a, b in true_runs(resting):
                start = max(0, a - dwell)  # the approach: the last dwell, and the motion it ends
                if start > 0 and moved[start - 1]:  # since the hand last rested or held something else
                    rested = np.flatnonzero(~moved[:start] | other[:start])
                    start = int(rested[-1]) + 1 if rested.size else 0
                before = d[start:a]
                came = before[np.isfinite(before)]  # H came to X: its distance fell into the hold
                if (b - a >= dwell and a > 0 and moved[max(0, a - dwell):a].any() and came.size
                        and came.max() - d[a] > size / 4):
                    spans.append((a, b))
            if spans:
                out[q] = spans
    return out
