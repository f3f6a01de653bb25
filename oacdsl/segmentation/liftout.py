"""Lifted out: a tool lifted out of its target and held above it stops touching it.

The tool rule (:mod:`oacdsl.segmentation.tooluse`) keeps a held object touching another while it
stays within the tool reach ``d``: a spoon lifted out of the cup it stirred, and held above it
(to drip), touched the cup for as long as it stayed within 150 mm. A rest on top ends such a
contact where it is lifted off (:mod:`oacdsl.segmentation.liftoff`); a tool contact has no rest
to tell where the contact was, but it has the tool's own working height. For each tool contact
``[s, e)`` of a tool X (the one of the pair an agent holds there) and its target A:

- **Working height.** ``h``: the height of X's markers above A's, per frame (the median over
  each one's visible markers), metres; the working height is its lowest over the contact (the
  5th percentile, so that a stray frame does not set it).
- **Lifted out.** X is *held above* A where ``h`` exceeds the working height by more than half
  A's size (the median largest distance between its markers: a tool does not work more than half
  its target's size above its deepest point; a spoon lifted out of a cup rises by about the cup's
  depth) while X is still (its centre slower than ``move_speed`` over ``lag``), for at least the
  dwell. The contact ends where X last rose above that height before it was held there, and
  resumes where it comes back below it, if what is left lasts the dwell (dipped in again).

A tool carried away rises and moves: it is not held above, and the tool reach ends its contact
as before. Everything is in the recording's own lengths (half the target's size, the detector's
rescaled speed, dwell and lag): scale, rotation about the vertical, mirror and pace do not change
it; it needs z up.
"""

from __future__ import annotations

import warnings

import numpy as np

from oacdsl.segmentation.episodes import true_runs
from oacdsl.segmentation.pairs import PairTable

__all__ = ["cut_at_lift_outs", "size_m"]

Spans = list[tuple[int, int]]
WORK_PERCENTILE = 5.0  # the working height: this percentile of the tool's height over the contact


def _columns(table: PairTable, instance: int) -> np.ndarray:
    return table.marker_order[table.marker_offsets[instance] : table.marker_offsets[instance + 1]]


def size_m(positions_m: np.ndarray, table: PairTable, instance: int, stride: int = 1) -> float:
    """``instance``'s size: the median over frames (every ``stride``-th) of the largest distance
    between its visible markers, metres (NaN: never two seen)."""
    p = positions_m[::max(1, stride), _columns(table, instance)].astype(np.float64)
    d = np.linalg.norm(p[:, :, None] - p[:, None], axis=3)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # frames without two markers: NaN
        return float(np.nanmedian(np.nanmax(d.reshape(d.shape[0], -1), axis=1)))


def _median(positions_m: np.ndarray, table: PairTable, instance: int, s: int, e: int) -> np.ndarray:
    """(e - s, 3) per-frame median of ``instance``'s visible markers, metres (NaN where none is)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        return np.asarray(np.nanmedian(positions_m[s:e, _columns(table, instance)], axis=1), dtype=np.float64)


def cut_at_lift_outs(
    spans: Spans, tool: int, target: int, wielded: np.ndarray, positions_m: np.ndarray, table: PairTable,
    target_size_m: float, dwell: int, lag: int, move_speed_m_s: float, rate_hz: float,
) -> Spans:
    """A pair's tool contacts ``spans``, each one in which ``tool`` is wielded (``wielded``, (F,)
    bool: an agent holds it, for most of the contact) and lifted out of ``target`` (its size
    ``target_size_m``, :func:`size_m`) and held above it ended there, and resumed where it comes
    back down (module doc); ``dwell``, ``lag``: frames."""
    out: Spans = []
    for s, e in spans:
        if e - s < 2 * dwell or not np.isfinite(target_size_m) or wielded[s:e].mean() < 0.5:
            out.append((s, e))
            continue
        x, a = _median(positions_m, table, tool, s, e), _median(positions_m, table, target, s, e)
        h = x[:, 2] - a[:, 2]
        if not np.isfinite(h).any():
            out.append((s, e))
            continue
        work = float(np.nanpercentile(h, WORK_PERCENTILE))
        with np.errstate(invalid="ignore"):
            above = h > work + target_size_m / 2
        speed = np.full(e - s, np.inf)
        if e - s > lag:
            speed[lag:] = np.linalg.norm(x[lag:] - x[:-lag], axis=1) * rate_hz / lag
        with np.errstate(invalid="ignore"):
            held = above & (speed < move_speed_m_s)
        start = s
        for a_run, b_run in true_runs(held):
            if b_run - a_run < dwell or s + a_run < start:
                continue
            rise = a_run
            while rise > 0 and above[rise - 1]:
                rise -= 1  # where it rose above the height it is held at
            if s + rise > start:
                out.append((start, s + rise))
            below = np.flatnonzero(~above[b_run:])  # comes back down
            start = e if below.size == 0 else s + b_run + int(below[0])
            if e - start < dwell:
                start = e
        if start < e:
            out.append((start, e))
    return out
