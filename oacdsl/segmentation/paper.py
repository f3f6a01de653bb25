"""The paper's touch detector: Eq. 1 and Eq. 2 of Wächter et al. (2013), per marker pair.

Vectorised over pairs and frames of a chunk; no per-frame state array and no
sequential scan: the state of a pair can only flip where a run of ``n`` close
frames (or of ``n`` far frames) *begins to be complete*, and those rising edges
are few, so the flips are found among them.
"""

from __future__ import annotations

import numpy as np

from oacdsl.segmentation.detectors import DistanceChunk, PairChanges
from oacdsl.segmentation.pairs import PairTable
from oacdsl.segmentation.params import AasParams
from oacdsl.segmentation.recording import Recording
from oacdsl.segmentation.runs import flips, windows

__all__ = ["PaperDetector"]


class PaperDetector:
    """Eq. 1 / Eq. 2 per marker pair.

    Per frame ``i`` (with ``Δt = t[i] - t[i-1]``):

    - *close*: ``dist[i] < d`` and ``|dist[i] - dist[i-1]| < v Δt``;
    - *far*: ``dist[i] > d`` or ``|dist[i] - dist[i-1]| > v Δt``;
    - a gap (NaN) in frame ``i-1`` leaves the change unknown: the frame is far when
      ``dist[i] > d`` and unknown otherwise; a gap in frame ``i`` makes it unknown;
      so is a value exactly at its threshold.

    Frame 0 has no predecessor and takes the distance change of frame 1.
    Non-touching → touching at ``n0`` when frames ``n0 .. n0+n-1`` are all close;
    touching → non-touching at ``n1`` when frames ``n1 .. n1+n-1`` are all far. An
    unknown frame belongs to no run, so a gap neither starts nor ends touching.
    The change is known at frame ``n0+n-1``: ``delay_frames = n - 1``.
    """

    def __init__(self, params: AasParams) -> None:
        self.d = np.float32(params.distance_m)
        self.v = float(params.speed_m_s)
        self.n = params.n
        self.history_frames = self.n  # n-1 for the run, one more for the distance change
        self.delay_frames = self.n - 1
        self.reach_m: float | None = float(params.distance_m)
        self._state = np.zeros(0, dtype=bool)

    def begin(self, recording: Recording, table: PairTable) -> None:
        self._state = np.zeros(table.n_pairs, dtype=bool)

    @property
    def pair_state(self) -> np.ndarray:
        """(P,) bool: the marker pairs touching now. A pair that is not touching and stays
        farther than ``reach_m`` in a chunk cannot change there, so the segmenter gives this
        detector only the marker pairs within reach and these (``ChunkGeometry.near_distances``)."""
        return self._state

    def step(self, chunk: DistanceChunk) -> PairChanges:
        n, h = self.n, chunk.history
        n_out = chunk.stop - chunk.start
        state0 = self._state[chunk.pairs]
        first_col = max(0, h - n + 1)  # frames that can be part of a run ending at an output frame
        near = (chunk.dist_m[:, first_col:] < self.d).any(axis=1) | state0
        sel = np.flatnonzero(near)
        if sel.size == 0:
            return PairChanges.none()
        dist = chunk.dist_m[sel] if sel.size < near.size else chunk.dist_m
        cur, change, limit, base = self._distance_changes(dist, chunk.times_s, chunk.start == h)
        # column j of cur/change describes frame chunk.start - h + base + j
        first = h - base  # column of the first output frame
        s0 = state0[sel]
        pairs = chunk.pairs[sel]
        with np.errstate(invalid="ignore"):
            close_n = windows((cur < self.d) & (change < limit), first, n_out, n)
            # a pair that does not touch and never completes a close run cannot flip
            busy = s0 | close_n.any(axis=1)
            if not busy.all():
                cur, change, close_n = cur[busy], change[busy], close_n[busy]
                s0, pairs = s0[busy], pairs[busy]
            far_n = windows((cur > self.d) | (change > limit), first, n_out, n)
        rows, cols, value = flips(close_n, far_n, s0)
        if rows.size:
            last = np.flatnonzero(np.r_[rows[1:] != rows[:-1], True])
            self._state[pairs[rows[last]]] = value[last]
        return PairChanges(pairs[rows], cols + chunk.start, value)

    def _distance_changes(
        self, dist: np.ndarray, times: np.ndarray, at_recording_start: bool
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, int]:
        """``(dist, |Δdist|, v·Δt, base)`` per described frame; ``base`` = column of the first (0 or 1).

        Frame 0 has no predecessor and takes the change of frame 1 (NaN in a one-frame recording).
        """
        change = np.abs(dist[:, 1:] - dist[:, :-1])
        limit = (self.v * np.diff(times)).astype(np.float32)
        if not at_recording_start:
            return dist[:, 1:], change, limit, 1
        if dist.shape[1] < 2:
            return dist, np.full(dist.shape, np.nan, dtype=np.float32), np.zeros(1, dtype=np.float32), 0
        return dist, np.concatenate([change[:, :1], change], axis=1), np.r_[limit[:1], limit], 0
