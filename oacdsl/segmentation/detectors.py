"""Per-marker-pair touch detection, pluggable: the paper's Eq. 1 / Eq. 2 and room for others.

The segmenter (:func:`oacdsl.segmentation.aas.segment`) feeds a detector the
distances of one chunk of frames at a time and reduces the per-pair answers to
instances. A detector is any object with the :class:`TouchDetector` attributes
and methods; :data:`DETECTORS` maps a mode name to ``"module:factory"`` where
``factory(params)`` builds one (imported only when used).

Index convention (all detectors): ``step`` answers the *causal* state of each
pair at every output frame, i.e. what is known once that frame has been seen.
A detector that decides a change only ``delay_frames`` after the frame it
belongs to (the paper labels a change at the first frame ``n0`` of the ``n``
frames that confirm it) declares that delay, and the segmenter moves every
change back by it.
"""

from __future__ import annotations

import importlib
from dataclasses import dataclass, field
from typing import Protocol

import numpy as np

from oacdsl.errors import SegmentationError, did_you_mean
from oacdsl.segmentation.pairs import PairTable
from oacdsl.segmentation.params import AasParams
from oacdsl.segmentation.recording import Recording

__all__ = ["DETECTORS", "ChunkStates", "DistanceChunk", "PaperDetector", "TouchDetector", "make_detector"]

#: Mode name → ``"module:factory"``; ``factory(params: AasParams) -> TouchDetector``.
DETECTORS: dict[str, str] = {
    "paper": "oacdsl.segmentation.detectors:PaperDetector",
}


@dataclass(frozen=True)
class DistanceChunk:
    """The distances of one chunk of frames, as a detector sees them.

    Rows ``0 .. history-1`` are frames before ``start`` (context, already answered);
    rows ``history ..`` are the output frames ``start .. stop-1``.

    Attributes:
        start, stop: the output frames (recording frame indices, 0-based, stop exclusive).
        history: how many context rows precede ``start`` (fewer than asked at the recording start).
        times_s: (R,) float64 frame times, seconds.
        pairs: (A,) marker-pair indices into the :class:`PairTable`, increasing.
        dist_m: (A, R) float32 distances, metres; NaN where a marker is missing.
        positions_m: (R, M, 3) float64 view of the recording's positions for these rows.

    The first chunk holds at least two frames when the recording has two.
    Pairs that are not in ``pairs`` were left out by the broad phase: their
    instances stay farther apart than the detector's ``reach_m`` in every row and
    they are not touching. Without a reach, every pair is present.
    """

    start: int
    stop: int
    history: int
    times_s: np.ndarray
    pairs: np.ndarray
    dist_m: np.ndarray
    positions_m: np.ndarray


@dataclass(frozen=True)
class ChunkStates:
    """A detector's answer for one chunk: causal touching state per pair and output frame.

    Attributes:
        pairs: (A',) increasing marker-pair indices whose state varies (or may vary).
        states: (A', stop - start) bool, their states.
        steady: marker-pair indices touching at every output frame of the chunk.

    Every pair in neither list does not touch at any output frame of the chunk.
    """

    pairs: np.ndarray
    states: np.ndarray
    steady: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.intp))


class TouchDetector(Protocol):
    """What the segmenter needs from a touch detector (see the module docstring)."""

    #: Context frames wanted before each chunk.
    history_frames: int
    #: Frames between the frame a change belongs to and the frame it is known.
    delay_frames: int
    #: Pairs whose instances stay farther apart than this (metres) cannot start touching
    #: in a chunk and may be left out; ``None`` = give me every pair.
    reach_m: float | None

    def begin(self, recording: Recording, table: PairTable) -> None:
        """Reset the state for a new recording (may also pre-scan it)."""

    def step(self, chunk: DistanceChunk) -> ChunkStates:
        """The causal touching state of the pairs at the chunk's output frames."""
        ...


def make_detector(params: AasParams) -> TouchDetector:
    """Build the detector of ``params.mode``; an unknown mode lists the known ones."""
    target = DETECTORS.get(params.mode)
    if target is None:
        hint = did_you_mean(params.mode, DETECTORS)
        raise SegmentationError(f"unknown segmentation mode {params.mode!r}{hint}")
    module, _, name = target.partition(":")
    factory = getattr(importlib.import_module(module), name)
    detector: TouchDetector = factory(params)
    return detector


class PaperDetector:
    """Eq. 1 and Eq. 2 of Wächter et al. (2013), per marker pair.

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

    def step(self, chunk: DistanceChunk) -> ChunkStates:
        n, h = self.n, chunk.history
        n_out = chunk.stop - chunk.start
        state0 = self._state[chunk.pairs]
        first_row = max(0, h - n + 1)  # rows that can be part of a run ending at an output frame
        near = (chunk.dist_m[:, first_row:] < self.d).any(axis=1) | state0
        sel = np.flatnonzero(near)
        self._state[:] = False
        if sel.size == 0:
            return ChunkStates(np.zeros(0, dtype=np.intp), np.zeros((0, n_out), dtype=bool))
        dist = chunk.dist_m[sel] if sel.size < near.size else chunk.dist_m
        close, far, base = self._frame_conditions(dist, chunk.times_s, at_recording_start=chunk.start == h)
        # `close[:, j]` describes frame chunk.start - h + base + j; runs end at output frames.
        first = h - base  # column of the first output frame
        close_n = _runs(close, first, n_out, n)
        far_n = _runs(far, first, n_out, n)
        s0 = state0[sel]
        pairs = chunk.pairs[sel]
        # most pairs keep one state for the whole chunk: no latch needed for them
        steady_on = s0 & ~far_n.any(axis=1)
        varies = ~steady_on & (s0 | close_n.any(axis=1))
        states = _latch(close_n[varies], far_n[varies], s0[varies])
        self._state[pairs[steady_on]] = True
        self._state[pairs[varies]] = states[:, -1]
        return ChunkStates(pairs[varies], states, pairs[steady_on])

    def _frame_conditions(self, dist: np.ndarray, times: np.ndarray,
                          *, at_recording_start: bool) -> tuple[np.ndarray, np.ndarray, int]:
        """close/far per pair and frame; ``base`` = row of the first column (0 or 1)."""
        cur = dist[:, 1:]
        change = np.abs(cur - dist[:, :-1])
        limit = (self.v * np.diff(times)).astype(np.float32)
        with np.errstate(invalid="ignore"):
            close = (cur < self.d) & (change < limit)
            far = (cur > self.d) | (change > limit)
            if not at_recording_start:
                return close, far, 1
            if dist.shape[1] < 2:  # one frame: no distance change known
                empty = np.zeros((dist.shape[0], 1), dtype=bool)
                return empty, empty.copy(), 0
            # frame 0 takes the distance change of frame 1
            close0 = (dist[:, :1] < self.d) & (change[:, :1] < limit[0])
            far0 = (dist[:, :1] > self.d) | (change[:, :1] > limit[0])
        return np.concatenate([close0, close], axis=1), np.concatenate([far0, far], axis=1), 0


def _runs(cond: np.ndarray, first: int, n_out: int, n: int) -> np.ndarray:
    """(A, n_out): ``cond`` held in the ``n`` columns ending at each output column."""
    if first < n - 1:  # recording start: pad with "did not hold"
        pad = n - 1 - first
        cond = np.concatenate([np.zeros((cond.shape[0], pad), dtype=bool), cond], axis=1)
        first += pad
    out = cond[:, first:first + n_out].copy()
    for k in range(1, n):
        out &= cond[:, first - k:first - k + n_out]
    return out


def _latch(sets: np.ndarray, resets: np.ndarray, state0: np.ndarray) -> np.ndarray:
    """Set/reset flip-flop along axis 1: the state after the latest event, else ``state0``.

    ``sets`` and ``resets`` are never true together (close and far exclude each other).
    """
    n_out = sets.shape[1]
    dtype = np.int16 if n_out < np.iinfo(np.int16).max else np.int32
    idx = np.arange(n_out, dtype=dtype)
    last_set = np.where(sets, idx, dtype(-2))
    last_reset = np.where(resets, idx, dtype(-2))
    # the carried state acts as an event just before the chunk
    np.maximum(last_set[:, 0], np.where(state0, dtype(-1), dtype(-2)), out=last_set[:, 0])
    np.maximum(last_reset[:, 0], np.where(state0, dtype(-2), dtype(-1)), out=last_reset[:, 0])
    np.maximum.accumulate(last_set, axis=1, out=last_set)
    np.maximum.accumulate(last_reset, axis=1, out=last_reset)
    result: np.ndarray = last_set > last_reset
    return result
