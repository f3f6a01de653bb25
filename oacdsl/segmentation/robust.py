"""The robust touch detector (mode ``robust``, and step 4 of ``adaptive``): Eq. 1 / Eq. 2 in
physical time.

The same rule as the paper's (:mod:`~oacdsl.segmentation.paper`) with one change: the
distance change of frame ``i`` is the least-squares slope of the distance over a centred
window of ``change_window_s`` seconds (:mod:`~oacdsl.segmentation.slope`), not the
one-frame difference. ``n`` is ``hold_s`` seconds of frames (``AasParams.frames`` when
given). Per marker pair and frame ``i``:

- *close*: ``dist[i] < d`` and ``|slope[i]| < v``;
- *far*: ``dist[i] > d`` or ``|slope[i]| > v``;
- *unknown*: ``dist[i]`` missing (a gap), or the slope unknown (fewer than half the window's
  samples visible) and ``dist[i] <= d``, or a value exactly at its threshold.

Runs of ``n`` close (far) frames start (end) touching at the run's first frame, as in
Eq. 1 / Eq. 2; an unknown frame belongs to no run. The slope of frame ``i`` needs the
frames up to ``i + half``, so a change is known ``n - 1 + half`` frames after the frame it
is labelled at (``delay_frames``); the last ``half`` frames of a recording are never
decided (their window is incomplete).
"""

from __future__ import annotations

import numpy as np

from oacdsl.segmentation.detectors import DistanceChunk, PairChanges
from oacdsl.segmentation.pairs import PairTable
from oacdsl.segmentation.params import AasParams
from oacdsl.segmentation.recording import Recording
from oacdsl.segmentation.runs import flips, windows
from oacdsl.segmentation.slope import windowed_slope_at

__all__ = ["RobustDetector"]


class RobustDetector:
    """Eq. 1 / Eq. 2 per marker pair with a windowed least-squares distance change.

    ``params`` must be resolved for the recording's rate (``frames`` set); the half
    window is taken from ``params.change_window_s`` at ``rate_hz`` (default: from
    :meth:`begin`'s recording).
    """

    def __init__(
        self, params: AasParams, rate_hz: float | None = None, pair_distance_m: np.ndarray | None = None
    ) -> None:
        self.params = params
        self.d = np.float32(params.distance_m)
        # (P,) float32 metres: each marker pair's own ``d`` (the adaptive detector's), else ``d``
        self._pair_d = None if pair_distance_m is None else np.asarray(pair_distance_m, dtype=np.float32)
        self.v = float(params.speed_m_s)
        self.n = params.n
        self.reach_m: float | None = float(params.distance_m)
        self._state = np.zeros(0, dtype=bool)
        self._set_rate(rate_hz)

    def _set_rate(self, rate_hz: float | None) -> None:
        self.half = self.params.half_window(rate_hz) if rate_hz else 1
        # the slope of the first frame of a run needs `half` frames before it
        self.history_frames = self.n - 1 + 2 * self.half
        self.delay_frames = self.n - 1 + self.half

    def begin(self, recording: Recording, table: PairTable) -> None:
        self._set_rate(recording.rate_hz)
        self._state = np.zeros(table.n_pairs, dtype=bool)

    @property
    def state(self) -> np.ndarray:
        """(P,) bool: each marker pair's touching state after the chunks stepped so far."""
        return self._state

    def step(self, chunk: DistanceChunk) -> PairChanges:
        with np.errstate(invalid="ignore"):  # NaN distances (gaps) compare false
            return self._step(chunk)

    def _step(self, chunk: DistanceChunk) -> PairChanges:
        n, h, half = self.n, chunk.history, self.half
        n_out = chunk.stop - chunk.start
        state0 = self._state[chunk.pairs]
        first_col = max(0, h - n + 1 - 2 * half)  # columns that feed a run ending at an output frame
        row_d = None if self._pair_d is None else self._pair_d[chunk.pairs][:, None]  # (A, 1)
        d = self.d if row_d is None else row_d
        below = chunk.dist_m < d  # (A, R): the distance condition of "close"
        near = below[:, first_col:].any(axis=1) | state0
        sel = near.nonzero()[0]
        if sel.size == 0:
            return PairChanges.none()
        below = below[sel]
        # neither touching nor below d for n frames in a row: no run of n close frames, no flip
        causal = np.zeros(below.shape, dtype=bool)  # column c: frame c - half, as in _conditions
        causal[:, half:] = below[:, :max(0, below.shape[1] - half)]
        busy = state0[sel] | windows(causal, h, n_out, n).any(axis=1)
        rows = sel[busy]
        if rows.size == 0:
            return PairChanges.none()
        dist = chunk.dist_m[rows] if rows.size < near.size else chunk.dist_m
        s0, pairs = state0[rows], chunk.pairs[rows]
        if row_d is not None:
            d = row_d[rows]
        close, far = self._conditions(dist, chunk.times_s, d)
        close_n = windows(close, h, n_out, n)
        far_n = windows(far, h, n_out, n)
        rows, cols, value = flips(close_n, far_n, s0)
        if rows.size:
            last = np.flatnonzero(np.concatenate((rows[1:] != rows[:-1], [True])))
            self._state[pairs[rows[last]]] = value[last]
        return PairChanges(pairs[rows], cols + chunk.start, value)

    def _conditions(
        self, dist: np.ndarray, times: np.ndarray, d: np.floating | np.ndarray
    ) -> tuple[np.ndarray, np.ndarray]:
        """(close, far), (A, R) bool, by *causal* column: column ``c`` describes frame ``c - half``.

        ``d``: metres, the distance threshold (scalar, or (A, 1) one per row).

        Columns whose frame lies before the chunk's first column are False (not part of any run).
        The slope is fitted only where it decides: at frames within ``d`` (beyond it a frame
        is far, in a gap unknown, whatever the slope).
        """
        half = self.half
        n_rows, width = dist.shape
        close = np.zeros(dist.shape, dtype=bool)
        far = np.zeros(dist.shape, dtype=bool)
        body = max(0, width - half)  # frames whose window ends inside the chunk
        cur = dist[:, :body]
        far[:, half:] = cur > d
        rows, cols = np.divmod((cur <= d).ravel().nonzero()[0], body)  # NaN: neither; 2-D nonzero is slower
        rate = np.abs(windowed_slope_at(dist, times, half, rows, cols))
        flat = rows * width + cols  # the requested cells in dist (C order), the same in close and far
        limit = d if np.ndim(d) == 0 else np.asarray(d).reshape(-1)[rows]
        close.ravel()[flat + half] = (dist.ravel()[flat] < limit) & (rate < self.v)
        far.ravel()[flat + half] = rate > self.v
        return close, far
