"""Marker-pair distances of a block of frames, vectorised, with a cheap broad phase.

A chunk of frames is converted once to float32 coordinates relative to a fixed
centre (so float32 keeps micrometre resolution wherever the world origin is),
laid out ``(3, markers, frames)`` with frames contiguous. Distances are computed
per instance pair as one broadcast ``(|A|, |B|, frames)`` block, no Python loop
over marker pairs. The broad phase bounds every marker-pair distance of an
instance pair from below by the gap between the two instances' bounding boxes
over a few frames; a pair whose bound stays above a reach in the whole chunk
need not be computed at all (all its distances exceed the reach).

Every number depends only on its own frame and the fixed centre, never on where
a chunk starts, so chunked and single-pass results are bit-identical.
"""

from __future__ import annotations

from itertools import pairwise

import numpy as np

from oacdsl.segmentation.pairs import PairTable
from oacdsl.segmentation.recording import Recording

__all__ = [
    "BOUND_BLOCK_FRAMES",
    "BOUND_MARGIN_M",
    "MAX_CHUNK_DISTANCE_BYTES",
    "ChunkGeometry",
    "chunk_frames_for",
    "closest_distances",
]

#: Safety margin, metres, added to the reach in the broad phase against float32 rounding.
BOUND_MARGIN_M = 1e-3
#: Frames per bounding box of the broad phase (short: a fast hand's box stays small).
BOUND_BLOCK_FRAMES = 8
_COORD_SLAB = 1024  # frames converted at a time by ChunkGeometry.coordinates
#: Bytes of float32 marker-pair distances one chunk of frames may hold (pairs × frames × 4):
#: chunks get fewer frames when there are many pairs, so memory does not grow with them.
MAX_CHUNK_DISTANCE_BYTES = 128 * 2**20


def chunk_frames_for(n_pairs: int, wanted: int, history: int = 0) -> int:
    """Frames per chunk, at most ``wanted`` and at least 1, such that ``(frames + history) ×
    n_pairs`` float32 distances fit in :data:`MAX_CHUNK_DISTANCE_BYTES` (when they can)."""
    fit = MAX_CHUNK_DISTANCE_BYTES // (4 * max(n_pairs, 1)) - history
    return max(1, min(wanted, fit))


class ChunkGeometry:
    """Computes distances for frame ranges of one recording."""

    def __init__(self, recording: Recording, table: PairTable) -> None:
        self.recording = recording
        self.table = table
        self.centre = _centre(recording.positions_m)
        blocks = np.diff(table.block_offsets)
        #: marker pairs of the largest instance pair: the size of a scratch buffer per frame
        self.max_block_pairs = int(blocks.max()) if blocks.size else 0
        order = table.marker_order  # the recording's own marker order: no gather
        self._in_order = bool(order.size == recording.positions_m.shape[1]
                              and np.array_equal(order, np.arange(order.size)))

    def coordinates(self, lo: int, hi: int) -> np.ndarray:
        """(3, M', hi - lo) float32 centred coordinates of frames ``lo:hi``, metres (NaN = gap)."""
        out = np.empty((3, self.table.marker_order.size, hi - lo), dtype=np.float32)
        rows = self.recording.positions_m[lo:hi]
        if not self._in_order:
            rows = rows[:, self.table.marker_order]
        # centre in float64, then round once to float32, (F, M, 3) → (3, M, F) in one pass, in slabs
        # of frames that stay in cache (the transposed reads of a long block do not)
        centre = self.centre[:, None, None]
        for a in range(0, hi - lo, _COORD_SLAB):
            b = min(hi - lo, a + _COORD_SLAB)
            np.subtract(rows[a:b].transpose(2, 1, 0), centre, out=out[:, :, a:b], casting="unsafe")
        return out

    def lower_bounds(self, x: np.ndarray, block: int = BOUND_BLOCK_FRAMES) -> np.ndarray:
        """(Q,) per instance pair, a lower bound of all its marker distances in the chunk, metres.

        Per run of ``block`` frames, each instance's markers lie in an axis-aligned
        box; two boxes' gap bounds every distance between their markers in those
        frames. NaN when the two instances are never both visible.
        """
        t = self.table
        if t.n_instance_pairs == 0:
            return np.zeros(0, dtype=np.float32)
        n_blocks = -(-x.shape[2] // block)
        lo = np.full(x.shape[:2] + (n_blocks,), np.nan, dtype=np.float32)
        hi = lo.copy()
        for k in range(min(block, x.shape[2])):  # frame k of every block; NaN ignored
            part = x[:, :, k::block]
            m = part.shape[2]
            np.fmin(lo[:, :, :m], part, out=lo[:, :, :m])
            np.fmax(hi[:, :, :m], part, out=hi[:, :, :m])
        spans = [
            (np.fmin.reduce(lo[:, a:b], axis=1), np.fmax.reduce(hi[:, a:b], axis=1))
            for a, b in pairwise(t.marker_offsets)
        ]
        box_lo = np.stack([s[0] for s in spans], axis=1)  # (3, I, blocks)
        box_hi = np.stack([s[1] for s in spans], axis=1)
        a, b = t.instance_pairs[:, 0], t.instance_pairs[:, 1]
        gap = np.maximum(box_lo[:, b] - box_hi[:, a], box_lo[:, a] - box_hi[:, b])
        np.maximum(gap, np.float32(0), out=gap)  # NaN stays NaN
        return np.fmin.reduce(np.sqrt(np.einsum("kqn,kqn->qn", gap, gap)), axis=1)

    def distances(self, x: np.ndarray, blocks: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Distances of all marker pairs of the instance pairs ``blocks``.

        Returns ``(pairs, dist)``: (A,) marker-pair indices (table order) and (A, R)
        float32 distances in metres, NaN where a marker is missing.
        """
        t = self.table
        pairs = t.block_pairs(blocks)
        n_rows = x.shape[2]
        out = np.empty((pairs.size, n_rows), dtype=np.float32)
        tmp = self.scratch(n_rows)
        row = 0
        for q in blocks:
            size = self.squared(x, int(q), out[row:], tmp).shape[0]
            row += size
        np.sqrt(out, out=out)
        return pairs, out

    def scratch(self, n_rows: int) -> np.ndarray:
        """A float32 buffer large enough for :meth:`squared`'s ``tmp`` (and ``out``) on ``n_rows`` frames."""
        return np.empty(self.max_block_pairs * n_rows, dtype=np.float32)

    def squared(self, x: np.ndarray, q: int, out: np.ndarray, tmp: np.ndarray) -> np.ndarray:
        """Squared distances (m²) of the marker pairs of instance pair ``q``, written to the first
        ``|A| |B|`` rows of ``out`` ((≥ |A| |B|, R) float32, or a flat buffer) and returned as
        (|A| |B|, R), table order; ``tmp``: a :meth:`scratch` buffer. The square roots of these are
        :meth:`distances`' values, bit for bit."""
        t = self.table
        n_rows = x.shape[2]
        ia, ib = t.instance_pairs[q]
        sa = slice(t.marker_offsets[ia], t.marker_offsets[ia + 1])
        sb = slice(t.marker_offsets[ib], t.marker_offsets[ib + 1])
        ka, kb = sa.stop - sa.start, sb.stop - sb.start
        flat = out.reshape(-1)[: ka * kb * n_rows]
        blk = flat.reshape(ka, kb, n_rows)
        scratch = tmp[: ka * kb * n_rows].reshape(ka, kb, n_rows)
        np.subtract(x[0, sa, None, :], x[0, None, sb, :], out=blk)
        np.square(blk, out=blk)
        for k in (1, 2):
            np.subtract(x[k, sa, None, :], x[k, None, sb, :], out=scratch)
            np.square(scratch, out=scratch)
            blk += scratch
        return flat.reshape(ka * kb, n_rows)


def _centre(positions: np.ndarray) -> np.ndarray:
    """(3,) float64: the mean of the first frame that has a visible marker (zeros if none)."""
    step = 1024
    for lo in range(0, positions.shape[0], step):
        block = positions[lo : lo + step]
        rows = np.flatnonzero(~np.isnan(block[..., 0]).all(axis=1))
        if rows.size:
            frame = block[rows[0]]
            return np.asarray(frame[~np.isnan(frame[:, 0])].mean(axis=0), dtype=np.float64)
    return np.zeros(3, dtype=np.float64)


def closest_distances(
    recording: Recording,
    table: PairTable | None = None,
    chunk_frames: int = 4096,
    reach_m: float | None = None,
) -> tuple[PairTable, np.ndarray]:
    """Per instance pair and frame, the smallest marker-pair distance, metres.

    Returns the pair table and a (Q, F) float32 array, NaN where no marker pair of
    the two instances is visible, and (with ``reach_m``) in chunks where the pair
    stays farther apart than ``reach_m``. Memory O(Q × F); for plots and reports.
    """
    table = table or PairTable.of(recording)
    geometry = ChunkGeometry(recording, table)
    n_q = table.n_instance_pairs
    out = np.full((n_q, recording.n_frames), np.nan, dtype=np.float32)
    if n_q == 0:
        return table, out
    blocks = np.arange(n_q, dtype=np.intp)
    chunk_frames = chunk_frames_for(table.n_pairs + geometry.max_block_pairs, chunk_frames)
    for lo in range(0, recording.n_frames, chunk_frames):
        hi = min(recording.n_frames, lo + chunk_frames)
        x = geometry.coordinates(lo, hi)
        if reach_m is not None:
            with np.errstate(invalid="ignore"):
                blocks = np.flatnonzero(geometry.lower_bounds(x) <= reach_m + BOUND_MARGIN_M)
        if blocks.size == 0:
            continue
        pairs, dist = geometry.distances(x, blocks)
        heads = np.flatnonzero(np.r_[True, table.block[pairs[1:]] != table.block[pairs[:-1]]])
        out[blocks, lo:hi] = np.fmin.reduceat(dist, heads, axis=0)
    return table, out
