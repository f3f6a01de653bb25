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
from oacdsl.segmentation.poses import RigidFill
from oacdsl.segmentation.recording import Recording

__all__ = [
    "BOUND_BLOCK_FRAMES",
    "BOUND_MARGIN_M",
    "MAX_CHUNK_DISTANCE_BYTES",
    "ChunkGeometry",
    "chunk_frames_for",
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

    def __init__(self, recording: Recording, table: PairTable, filler: RigidFill | None = None) -> None:
        self.recording = recording
        self.table = table
        self.filler = None if filler is None or filler.empty else filler  # rigid gaps, filled per chunk
        self.centre = _centre(recording.positions_m)
        blocks = np.diff(table.block_offsets)
        #: marker pairs of the largest instance pair: the size of a scratch buffer per frame
        self.max_block_pairs = int(blocks.max()) if blocks.size else 0
        order = table.marker_order  # the recording's own marker order: no gather
        self._in_order = bool(order.size == recording.positions_m.shape[1]
                              and np.array_equal(order, np.arange(order.size)))
        # a recording marker's row in the coordinates (-1: in no instance pair)
        self._row_of = np.full(recording.positions_m.shape[1], -1, dtype=np.intp)
        self._row_of[order] = np.arange(order.size)

    def coordinates(self, lo: int, hi: int, out: np.ndarray | None = None,
                    instances: np.ndarray | None = None) -> np.ndarray:
        """(3, M', hi - lo) float32 centred coordinates of frames ``lo:hi``, metres (NaN = gap);
        written into ``out`` when given (a buffer of that shape, reused across chunks). ``instances``:
        (I,) bool, only these instances' markers are needed (the other rows are left unset)."""
        if out is None:
            out = np.empty((3, self.table.marker_order.size, hi - lo), dtype=np.float32)
        positions = self.recording.positions_m[lo:hi]
        # centre in float64, then round once to float32, (F, M, 3) → (3, M, F) in one pass, in slabs
        # of frames that stay in cache (the transposed reads of a long block do not)
        centre = self.centre[:, None, None]
        for r0, r1 in self._marker_runs(instances):
            if self._in_order:
                rows = positions[:, r0:r1]
            else:
                rows = positions[:, self.table.marker_order[r0:r1]]
            for a in range(0, hi - lo, _COORD_SLAB):
                b = min(hi - lo, a + _COORD_SLAB)
                np.subtract(rows[a:b].transpose(2, 1, 0), centre, out=out[:, r0:r1, a:b], casting="unsafe")
        if self.filler is not None:  # rigid gaps: the filled positions, rounded as the others
            for frames, markers, values in self.filler.cells(lo, hi):
                at, which = np.nonzero(~np.isnan(values[..., 0]))  # the cells filled (NaN: seen)
                rows_of = self._row_of[markers[which]]
                keep = rows_of >= 0
                filled = np.subtract(values[at[keep], which[keep]], self.centre, dtype=np.float64)
                out[:, rows_of[keep], frames[at[keep]]] = filled.T.astype(np.float32)
        return out

    def _marker_runs(self, instances: np.ndarray | None) -> list[tuple[int, int]]:
        """Runs ``[r0, r1)`` of coordinate rows (``marker_order``) holding the markers of ``instances``
        ((I,) bool; None: all), neighbouring instances joined."""
        offsets = self.table.marker_offsets
        if instances is None:
            return [(0, int(offsets[-1]))]
        edges = np.flatnonzero(np.diff(np.concatenate(([False], instances, [False]))))
        return [(int(offsets[a]), int(offsets[b])) for a, b in zip(edges[::2], edges[1::2], strict=True)]

    def marker_boxes(self, x: np.ndarray, block: int = BOUND_BLOCK_FRAMES) -> tuple[np.ndarray, np.ndarray]:
        """Per marker and run of ``block`` frames, the axis-aligned box of its positions: ``(lo, hi)``,
        each (3, M', blocks) float32, metres (NaN where the marker is unseen in the whole run)."""
        n_blocks = -(-x.shape[2] // block)
        lo = np.full(x.shape[:2] + (n_blocks,), np.nan, dtype=np.float32)
        hi = lo.copy()
        for k in range(min(block, x.shape[2])):  # frame k of every block; NaN ignored
            part = x[:, :, k::block]
            m = part.shape[2]
            np.fmin(lo[:, :, :m], part, out=lo[:, :, :m])
            np.fmax(hi[:, :, :m], part, out=hi[:, :, :m])
        return lo, hi

    def instance_boxes(self, boxes: tuple[np.ndarray, np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
        """Per instance and run of frames, the box of all its markers, (3, I, blocks) each, from
        :meth:`marker_boxes`."""
        lo, hi = boxes
        spans = [
            (np.fmin.reduce(lo[:, a:b], axis=1), np.fmax.reduce(hi[:, a:b], axis=1))
            for a, b in pairwise(self.table.marker_offsets)
        ]
        return np.stack([s[0] for s in spans], axis=1), np.stack([s[1] for s in spans], axis=1)

    def _frame_boxes(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Per instance and frame, the box of its markers: ``(lo, hi)``, each (3, I, R) float32
        (NaN where none is seen)."""
        offsets = self.table.marker_offsets
        lo = np.empty((3, offsets.size - 1, x.shape[2]), dtype=np.float32)
        hi = np.empty_like(lo)
        for i, (a, b) in enumerate(pairwise(offsets.tolist())):
            np.fmin.reduce(x[:, a:b], axis=1, out=lo[:, i])
            np.fmax.reduce(x[:, a:b], axis=1, out=hi[:, i])
        return lo, hi

    def lower_bounds(self, x: np.ndarray, block: int = BOUND_BLOCK_FRAMES,
                     boxes: tuple[np.ndarray, np.ndarray] | None = None) -> np.ndarray:
        """(Q,) per instance pair, a lower bound of all its marker distances in the chunk, metres.

        Per run of ``block`` frames, each instance's markers lie in an axis-aligned
        box; two boxes' gap bounds every distance between their markers in those
        frames. NaN when the two instances are never both visible. ``boxes``: this
        chunk's :meth:`marker_boxes` when the caller has them.
        """
        t = self.table
        if t.n_instance_pairs == 0:
            return np.zeros(0, dtype=np.float32)
        if boxes is None:  # each instance's box directly: its markers' extremes per frame, then per run
            box_lo, box_hi = _run_boxes(*self._frame_boxes(x), block)
        else:
            box_lo, box_hi = self.instance_boxes(boxes)
        a, b = t.instance_pairs[:, 0], t.instance_pairs[:, 1]
        return _gap(box_lo[:, a], box_hi[:, a], box_lo[:, b], box_hi[:, b])

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

    def near_distances(self, x: np.ndarray, blocks: np.ndarray, reach_m: float, touching: np.ndarray,
                       boxes: tuple[np.ndarray, np.ndarray]) -> tuple[np.ndarray, np.ndarray]:
        """As :meth:`distances`, but only of the marker pairs that can come within ``reach_m`` in the
        chunk or are ``touching`` ((P,) bool per marker pair, table order).

        Per instance pair ``(A, B)``, a marker of A whose box (:meth:`marker_boxes`) stays
        farther than ``reach_m`` from B's box in every run of frames is farther than that from
        every marker of B in every frame, and the other way round; the pairs of the markers left
        (a cross product: every touching pair among them) are computed exactly as
        :meth:`distances` computes them, bit for bit. A detector that only needs the pairs within
        reach, and the pairs it holds touching, gets the same answer from either.
        """
        t = self.table
        lo, hi = boxes
        box_lo, box_hi = self.instance_boxes(boxes)
        # (first pair of the block, first marker of A, of B, |B|, the markers of A and of B chosen)
        chosen: list[tuple[int, int, int, int, np.ndarray, np.ndarray]] = []
        for q in blocks:
            ia, ib = (int(v) for v in t.instance_pairs[q])
            a0, a1 = int(t.marker_offsets[ia]), int(t.marker_offsets[ia + 1])
            b0, b1 = int(t.marker_offsets[ib]), int(t.marker_offsets[ib + 1])
            with np.errstate(invalid="ignore"):
                near_a = _gap(lo[:, a0:a1], hi[:, a0:a1], box_lo[:, ib, None], box_hi[:, ib, None]) <= reach_m
                near_b = _gap(lo[:, b0:b1], hi[:, b0:b1], box_lo[:, ia, None], box_hi[:, ia, None]) <= reach_m
            off = int(t.block_offsets[q])
            held = np.flatnonzero(touching[off : int(t.block_offsets[q + 1])])
            near_a[held // (b1 - b0)] = True
            near_b[held % (b1 - b0)] = True
            ra, rb = np.flatnonzero(near_a), np.flatnonzero(near_b)
            if ra.size and rb.size:
                chosen.append((off, a0, b0, b1 - b0, ra, rb))
        n_rows = x.shape[2]
        total = sum(ra.size * rb.size for *_, ra, rb in chosen)
        pairs = np.empty(total, dtype=np.intp)
        out = np.empty((total, n_rows), dtype=np.float32)
        largest = max((ra.size * rb.size for *_, ra, rb in chosen), default=0)
        tmp = np.empty(largest * n_rows, dtype=np.float32)
        row = 0
        for off, a0, b0, kb, ra, rb in chosen:  # as squared(), on the rows chosen
            size = ra.size * rb.size
            xa, xb = x[:, a0 + ra], x[:, b0 + rb]
            blk = out[row : row + size].reshape(ra.size, rb.size, n_rows)
            scratch = tmp[: size * n_rows].reshape(ra.size, rb.size, n_rows)
            np.subtract(xa[0, :, None, :], xb[0, None, :, :], out=blk)
            np.square(blk, out=blk)
            for k in (1, 2):
                np.subtract(xa[k, :, None, :], xb[k, None, :, :], out=scratch)
                np.square(scratch, out=scratch)
                blk += scratch
            pairs[row : row + size] = (off + ra[:, None] * kb + rb[None, :]).reshape(-1)
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


def _run_boxes(lo: np.ndarray, hi: np.ndarray, block: int) -> tuple[np.ndarray, np.ndarray]:
    """Per row and run of ``block`` frames, the extremes of (…, R) ``lo`` and ``hi`` over the run's
    frames, NaN ignored: ``(lo, hi)``, each (…, runs). The minimum and maximum of a set of values do
    not depend on how it is grouped: the same values as :meth:`ChunkGeometry.instance_boxes` of
    :meth:`ChunkGeometry.marker_boxes`."""
    n_runs = -(-lo.shape[-1] // block)
    out_lo = np.full(lo.shape[:-1] + (n_runs,), np.nan, dtype=lo.dtype)
    out_hi = out_lo.copy()
    for k in range(min(block, lo.shape[-1])):  # frame k of every run; NaN ignored
        m = -(-(lo.shape[-1] - k) // block)
        np.fmin(out_lo[..., :m], lo[..., k::block], out=out_lo[..., :m])
        np.fmax(out_hi[..., :m], hi[..., k::block], out=out_hi[..., :m])
    return out_lo, out_hi


def _gap(lo_a: np.ndarray, hi_a: np.ndarray, lo_b: np.ndarray, hi_b: np.ndarray) -> np.ndarray:
    """The smallest over the last axis (runs of frames) of the gap between boxes ``a`` and ``b``
    ((3, …, blocks) float32 each), metres; NaN when no run sees both."""
    gap = np.maximum(lo_b - hi_a, lo_a - hi_b)
    np.maximum(gap, np.float32(0), out=gap)  # NaN stays NaN
    return np.fmin.reduce(np.sqrt(np.einsum("k...,k...->...", gap, gap)), axis=-1)


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
