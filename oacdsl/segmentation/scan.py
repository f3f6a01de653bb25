"""The co-motion scan: per instance pair and frame, its closest marker distance and whether the
two move as one (step 1 of the adaptive detector, :mod:`oacdsl.segmentation.comotion`).

The recording is read once, in chunks of frames (each re-reading the ``lag`` frames before it):
per chunk, the instances' speeds (the median of their markers' speeds over ``lag``, rigid gaps
filled), a broad phase (:mod:`oacdsl.segmentation.geometry`) for the instance pairs that can come
within reach, and for each of those its marker distances, their minimum, and where both move
(``min(speed_A, speed_B) > move_speed``) within reach, whether their distances hold (the median
``|Δ dist| / Δt`` below ``rigid_ratio ×`` the slower speed).

Speeds are needed only for a chunk's own frames (the frames re-read before it only supply the
distances ``lag`` frames back), and are computed in slabs of frames that stay in cache, into
buffers kept across chunks. Memory: O(frames) per instance pair that comes within reach, float32,
and O(chunk × markers) of working buffers.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import NamedTuple

import numpy as np

from oacdsl.segmentation.geometry import BOUND_MARGIN_M, ChunkGeometry, chunk_frames_for
from oacdsl.segmentation.medians import median_rows, nanmedian0
from oacdsl.segmentation.pairs import PairTable
from oacdsl.segmentation.poses import RigidFill
from oacdsl.segmentation.recording import Recording

__all__ = ["SCAN_FRAMES", "Rule", "scan_signals"]

#: Frames per chunk of the scan.
SCAN_FRAMES = 4096
_SLAB = 256  # frames of marker speeds computed at a time (their working arrays stay in cache)

Signals = dict[int, tuple[np.ndarray, np.ndarray]]


class Rule(NamedTuple):
    """When two instances co-move (:class:`~oacdsl.segmentation.comotion.AdaptiveSettings`).

    Attributes:
        reach_m: metres, the closest marker distance must be below this (``d × (1 + margin)``).
        lag: frames over which speeds and distance changes are measured (≥ 1).
        move_speed_m_s: both instances move faster than this.
        rigid_ratio: the median ``|Δ dist| / Δt`` stays below this fraction of the slower speed.
    """

    reach_m: float
    lag: int
    move_speed_m_s: float
    rigid_ratio: float


def scan_signals(
    recording: Recording, table: PairTable, rule: Rule, filler: RigidFill | None = None,
    keep_speeds: Sequence[int] = (), speeds: dict[int, np.ndarray] | None = None,
) -> Signals:
    """Per instance pair that comes within ``rule.reach_m``: closest distance (F,) float32 metres
    (inf in chunks beyond reach, NaN in gaps) and co-motion frames (F,) bool; into ``speeds``, the
    speeds of the instances ``keep_speeds`` (:class:`~oacdsl.segmentation.comotion.CoMotion`)."""
    n_frames, n_q = recording.n_frames, table.n_instance_pairs
    if n_q == 0 or n_frames < 2:
        return {}
    kept = {i: np.empty(n_frames) for i in keep_speeds}
    if speeds is not None:
        speeds.update(kept)
    geometry = ChunkGeometry(recording, table, filler)
    lag = rule.lag
    times = np.asarray(recording.times_s, dtype=np.float64)
    groups = [
        table.marker_order[a:b]
        for a, b in zip(table.marker_offsets[:-1], table.marker_offsets[1:], strict=True)
    ]
    dmin: dict[int, np.ndarray] = {}
    carry: dict[int, np.ndarray] = {}
    step = chunk_frames_for(2 * geometry.max_block_pairs, SCAN_FRAMES, lag)  # two scratch buffers
    work = _Buffers(recording, geometry, min(n_frames, step + lag), lag)
    with np.errstate(invalid="ignore"):  # NaN: a gap
        for start in range(0, n_frames, step):
            stop = min(n_frames, start + step)
            _scan_chunk(recording, table, rule, geometry, work, groups, times, start, stop, dmin, carry, kept)
    return {q: (dmin[q], carry[q]) for q in dmin}


class _Buffers:
    """Working arrays of the scan, allocated once for its largest chunk (``rows`` frames)."""

    def __init__(self, recording: Recording, geometry: ChunkGeometry, rows: int, lag: int) -> None:
        n_markers = recording.positions_m.shape[1]
        self.coordinates = np.empty((3, geometry.table.marker_order.size, rows), dtype=np.float32)
        self.squared = geometry.scratch(rows)
        self.scratch = geometry.scratch(rows)
        self.steps = np.empty((n_markers, rows))  # (M, R) metres: each marker's step over lag
        slab = min(_SLAB, rows)
        self.filled = np.empty((slab + lag, n_markers, 3))  # a slab's positions, gaps filled
        self.diff = np.empty((slab, n_markers, 3))
        self.sum = np.empty((slab, n_markers))
        self.term = np.empty((slab, n_markers))


def _scan_chunk(
    recording: Recording, table: PairTable, rule: Rule, geometry: ChunkGeometry, work: _Buffers,
    groups: list[np.ndarray], times: np.ndarray, start: int, stop: int,
    dmin: dict[int, np.ndarray], carry: dict[int, np.ndarray],
    kept: Mapping[int, np.ndarray],
) -> None:
    """:func:`scan_signals` of frames ``start:stop`` (reading ``lag`` frames before), into ``dmin``,
    ``carry`` and the instance speeds ``kept``."""
    n_frames, lag, reach = recording.n_frames, rule.lag, rule.reach_m
    lo = max(0, start - lag)
    # rates over `lag` frames; the first frames of the recording use frame 0 (frame 0: frame `lag`)
    rows = np.arange(start, stop)
    prev = np.maximum(rows - lag, 0)
    prev[prev == rows] = min(lag, n_frames - 1)
    x, steps = _read(recording, geometry, work, lo, rows, prev, lag)
    blocks = (geometry.lower_bounds(x) <= reach + BOUND_MARGIN_M).nonzero()[0]
    if blocks.size == 0 and not kept:
        return
    dt = np.abs(times[rows] - times[prev])
    speeds = [median_rows(steps[m]) / dt for m in groups]  # per instance (table order), m/s
    for i, into in kept.items():
        into[start:stop] = speeds[i]
    out = slice(start - lo, stop - lo)
    prev_col = prev - lo  # column of each output frame's frame `lag` before, in the chunk
    for q in blocks.tolist():
        # one pair's squared marker distances, (P_q, R) frames lo..stop-1, while in cache; the
        # square root is taken only where needed (sqrt is monotonic: the same values)
        sq = geometry.squared(x, q, work.squared, work.scratch)
        closest = np.sqrt(np.fmin.reduce(sq[:, out], axis=0))
        a, b = table.instance_pairs[q]
        slower = np.fmin(speeds[a], speeds[b])
        moving = (closest < reach) & (slower > rule.move_speed_m_s)  # within d: near_episodes
        is_carry = moving.copy()
        cols = moving.nonzero()[0]  # the distance change matters only where both move
        if cols.size:
            change = np.abs(np.sqrt(sq[:, cols + out.start]) - np.sqrt(sq[:, prev_col[cols]]))
            is_carry[cols] = nanmedian0(change) / dt[cols] < rule.rigid_ratio * slower[cols]
        if q not in dmin:
            dmin[q] = np.full(n_frames, np.inf, dtype=np.float32)
            carry[q] = np.zeros(n_frames, dtype=bool)
        dmin[q][start:stop] = closest
        carry[q][start:stop] = is_carry


def _read(recording: Recording, geometry: ChunkGeometry, work: _Buffers, lo: int, rows: np.ndarray,
          prev: np.ndarray, lag: int) -> tuple[np.ndarray, np.ndarray]:
    """Frames ``lo:stop`` read for the scan: ``(coordinates, steps)``, the chunk's (3, M', R) float32
    coordinates (:meth:`~oacdsl.segmentation.geometry.ChunkGeometry.coordinates`) and (M, len(rows))
    how far each marker moved from frame ``prev[i]`` to frame ``rows[i]``, metres (NaN in gaps; rigid
    gaps filled), ``rows`` the chunk's own frames (consecutive, up to ``stop``). Both from the same
    slab of frames at a time, while it is in cache."""
    stop = int(rows[-1]) + 1
    x = work.coordinates[:, :, : stop - lo]
    steps = work.steps[:, : rows.size]
    start = int(rows[0])
    if not start >= lag > 0:  # the first frames: against frame 0 (and frame 0 against frame `lag`)
        geometry.coordinates(lo, stop, out=x)
        first, last = int(min(prev.min(), start)), int(max(prev.max(), stop - 1)) + 1
        filler = geometry.filler
        positions = recording.positions_m[first:last] if filler is None else filler.rows(first, last)
        diff = positions[rows - first] - positions[prev - first]  # (R, M, 3)
        steps[:] = np.sqrt(diff[..., 0] * diff[..., 0] + diff[..., 1] * diff[..., 1]
                           + diff[..., 2] * diff[..., 2]).T
        return x, steps
    for a in range(lo, stop, _SLAB):  # every frame against the one `lag` before: plain slices
        b = min(stop, a + _SLAB)
        geometry.coordinates(a, b, out=x[:, :, a - lo : b - lo])
        if b > start:
            own = max(a, start)
            moved = _steps(recording.positions_m, geometry.filler, own, b, lag, work)
            steps[:, own - start : b - start] = moved.T
    return x, steps


def _steps(positions: np.ndarray, filler: RigidFill | None, a: int, b: int, lag: int,
           work: _Buffers) -> np.ndarray:
    """(b - a, M) metres each marker moved from frame ``i - lag`` to frame ``i``, for frames
    ``a:b`` (``a ≥ lag``), gaps filled by ``filler``: as ``np.linalg.norm(diff, axis=-1)``."""
    n = b - a
    source = positions[a - lag : b]
    cells = list(filler.cells(a - lag, b)) if filler is not None else []
    if cells:  # as RigidFill.rows: the filled positions where a marker is missing
        filled = work.filled[: n + lag]
        np.copyto(filled, source)
        for frames, idx, values in cells:
            at = (frames[:, None], idx)
            filled[at] = np.where(np.isnan(values), filled[at], values)
        source = filled
    diff, total, term = work.diff[:n], work.sum[:n], work.term[:n]
    np.subtract(source[lag:], source[:n], out=diff)
    np.multiply(diff[..., 0], diff[..., 0], out=total)
    np.multiply(diff[..., 1], diff[..., 1], out=term)
    total += term
    np.multiply(diff[..., 2], diff[..., 2], out=term)
    total += term
    return np.sqrt(total, out=total)
