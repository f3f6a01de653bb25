"""Per-marker-pair touch detection, pluggable: the paper's Eq. 1 / Eq. 2 and room for others.

The segmenter (:func:`oacdsl.segmentation.aas.segment`) feeds a detector the
distances of one chunk of frames at a time; the detector answers when each
marker pair starts and stops touching; the segmenter reduces that to instances
("instances touch while any pair of their markers touches"). A detector is any
object with the :class:`TouchDetector` attributes and methods; :data:`DETECTORS`
maps a mode name to ``"module:factory"`` where ``factory(params)`` builds one
(imported only when used). A detector that computes a dense per-frame state can
answer with :meth:`PairChanges.from_states`.

Index convention (all detectors): a change is reported at the *causal* frame,
the frame from which on it is known. A detector that can decide a change only
``delay_frames`` after the frame it belongs to (the paper labels a change at
the first frame ``n0`` of the ``n`` frames that confirm it) declares that delay,
and the segmenter moves every change back by it.
"""

from __future__ import annotations

import importlib
from dataclasses import dataclass
from typing import Protocol

import numpy as np

from oacdsl.errors import SegmentationError, did_you_mean
from oacdsl.segmentation.pairs import PairTable
from oacdsl.segmentation.params import AasParams
from oacdsl.segmentation.recording import Recording

__all__ = ["DETECTORS", "DistanceChunk", "PairChanges", "TouchDetector", "make_detector"]

#: Mode name → ``"module:factory"``; ``factory(params: AasParams) -> TouchDetector``.
DETECTORS: dict[str, str] = {
    "paper": "oacdsl.segmentation.paper:PaperDetector",
    "adaptive": "oacdsl.segmentation.adaptive:AdaptiveDetector",
    "robust": "oacdsl.segmentation.robust:RobustDetector",
}


@dataclass(frozen=True)
class DistanceChunk:
    """The distances of one chunk of frames, as a detector sees them.

    Columns ``0 .. history-1`` are frames before ``start`` (context, already
    answered); columns ``history ..`` are the output frames ``start .. stop-1``.

    Attributes:
        start, stop: the output frames (recording frame indices, 0-based, stop exclusive).
        history: context columns before ``start`` (fewer than asked at the recording start).
        times_s: (R,) float64 frame times, seconds.
        pairs: (A,) marker-pair indices into the :class:`PairTable`, increasing.
        dist_m: (A, R) float32 distances, metres; NaN where a marker is missing.
        positions_m: (R, M, 3) float64 view of the recording's positions for these frames.

    The first chunk holds at least two frames when the recording has two.
    Pairs that are not in ``pairs`` were left out by the broad phase: their
    instances stay farther apart than the detector's ``reach_m`` in every frame and
    they are not touching. Without a reach, every pair is present. A detector that
    has the optional ``pair_state`` ((P,) bool, the marker pairs it holds touching)
    gets, of the instance pairs within reach, only the marker pairs that can come
    within reach or are touching (the others stay farther than ``reach_m`` throughout).
    """

    start: int
    stop: int
    history: int
    times_s: np.ndarray
    pairs: np.ndarray
    dist_m: np.ndarray
    positions_m: np.ndarray


@dataclass(frozen=True)
class PairChanges:
    """A detector's answer for one chunk: every change of a marker pair's touching state.

    Attributes:
        pairs: (K,) marker-pair indices.
        frames: (K,) causal frames of the changes (recording frame indices).
        touching: (K,) bool, the state from that frame on.

    Sorted by pair, then frame; each entry flips its pair's state.
    """

    pairs: np.ndarray
    frames: np.ndarray
    touching: np.ndarray

    @classmethod
    def none(cls) -> PairChanges:
        empty = np.zeros(0, dtype=np.intp)
        return cls(empty, empty.copy(), np.zeros(0, dtype=bool))

    @classmethod
    def from_states(
        cls, pairs: np.ndarray, states: np.ndarray, before: np.ndarray, start: int
    ) -> PairChanges:
        """From dense states: (A,) ``pairs``, (A, C) ``states`` at frames ``start ..``, (A,) ``before``."""
        previous = np.concatenate([before[:, None], states[:, :-1]], axis=1)
        rows, cols = np.divmod(np.flatnonzero(states != previous), max(states.shape[1], 1))
        return cls(pairs[rows], cols + start, states[rows, cols])


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
        """Reset the state for a new recording (may also pre-scan it); no pair touches."""

    def step(self, chunk: DistanceChunk) -> PairChanges:
        """The changes of the pairs' touching state at the chunk's output frames."""
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
