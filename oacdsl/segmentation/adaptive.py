"""Adaptive touch detection (mode ``adaptive``): co-motion sets each pair's own threshold.

Markers sit on the back of the hand and on object corners, so "touching" is
30–120 mm depending on the object, and one fixed ``d`` cannot fit every pair: a
``d`` large enough for a bottle held at 119 mm makes a hand resting 100 mm from a
cup "touch" it. This detector learns the distance from the recording itself:

1. **Co-motion.** A held object moves with the hand: both instances move
   (``min(speed_A, speed_B) > move_speed``) while the distances between their
   markers hardly change (median ``|Δ dist| / Δt < rigid_ratio × min speed``) and
   they are within ``d`` (``AasParams.distance_m``, now the largest contact
   distance). Speeds are measured over ``lag_s``. Runs of such frames of at least
   ``min_episode_s`` are *co-motion episodes*.
2. **The pair's threshold.** For each episode, the pair's contact distance is the
   median of its closest marker distance during the episode, and its threshold that
   times ``1 + margin`` (at most ``d``).
3. **Extension.** The pair touches from the episode backwards and forwards for as
   long as its closest marker distance stays within that threshold (a gap —
   NaN — neither ends nor starts it): the grasp before the object starts to move,
   the hold after it is set down, until the hand leaves.
4. **The paper's rule per pair.** Eq. 1 / Eq. 2 (the paper's ``v`` and ``n``, marker
   pair by marker pair, gaps as in the paper's mode), with the distance change estimated
   over a window in seconds (:class:`~oacdsl.segmentation.robust.RobustDetector`), run at each pair's own
   distance: the learned one (the median of its episodes' thresholds) for a pair
   that co-moves somewhere in the recording, else ``static_distance_m``. This
   catches contacts without co-motion (a mixer stirring in a bowl, liquid poured
   into a bowl, a second grasp of the same object that does not move it).

Two instances touch when (1–3) or (4) says so. The episodes need the whole
recording, so :meth:`AdaptiveDetector.begin` scans it once (chunked, memory
O(frames) per instance pair that ever comes within reach, float32); step 4 runs
chunk by chunk with one paper detector per distinct distance. Results do not
depend on the chunk size. The instance-level decision of (1–3) is reported on the
first marker pair of the instance pair, OR-ed with the paper's state of that pair.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from oacdsl.errors import SegmentationError
from oacdsl.segmentation.comotion import AdaptiveSettings, comotion
from oacdsl.segmentation.detectors import DistanceChunk, PairChanges
from oacdsl.segmentation.pairs import PairTable
from oacdsl.segmentation.params import AasParams
from oacdsl.segmentation.recording import Recording
from oacdsl.segmentation.robust import RobustDetector

__all__ = ["AdaptiveDetector", "AdaptiveSettings", "comotion"]


class AdaptiveDetector:
    """Co-motion episodes with per-pair thresholds, OR the paper's rule at each pair's distance."""

    def __init__(self, params: AasParams, settings: AdaptiveSettings | None = None) -> None:
        self.settings = settings or AdaptiveSettings()
        self.params = params
        template = RobustDetector(params)  # frames of history and delay: set again in begin()
        self.history_frames = template.history_frames
        self.delay_frames = template.delay_frames
        self.reach_m: float | None = max(params.distance_m, self.settings.static_distance_m)
        self._table: PairTable | None = None
        self._inner: list[tuple[RobustDetector, np.ndarray]] = []  # (detector, (Q,) bool: its blocks)
        self._events: dict[int, np.ndarray] = {}  # block → (E, 2) [causal frame, on?], sorted
        self._heads = np.zeros(0, dtype=np.intp)
        self._paper_head = np.zeros(0, dtype=bool)  # paper state of each block's first marker pair
        self._combined = np.zeros(0, dtype=bool)
        self._episode = np.zeros(0, dtype=bool)

    def begin(self, recording: Recording, table: PairTable) -> None:
        template = RobustDetector(self.params, recording.rate_hz)
        self.history_frames, self.delay_frames = template.history_frames, template.delay_frames
        self._table = table
        self._heads = table.block_offsets[:-1].copy()
        n_q = table.n_instance_pairs
        self._paper_head = np.zeros(n_q, dtype=bool)
        self._combined = np.zeros(n_q, dtype=bool)
        self._episode = np.zeros(n_q, dtype=bool)
        learned = comotion(recording, table, self.params, self.settings)
        # the paper's rule per pair: at the pair's learned distance, else at the static distance
        by_distance: dict[float, np.ndarray] = {}
        default = np.ones(n_q, dtype=bool)
        for q, (_, threshold) in learned.items():
            key = round(threshold, 4)  # 0.1 mm: pairs with the same distance share a detector
            by_distance.setdefault(key, np.zeros(n_q, dtype=bool))[q] = True
            default[q] = False
        by_distance.setdefault(self.settings.static_distance_m, np.zeros(n_q, dtype=bool))
        by_distance[self.settings.static_distance_m] |= default
        self._inner = []
        for distance, blocks in sorted(by_distance.items()):
            detector = RobustDetector(replace(self.params, distance_m=distance), recording.rate_hz)
            detector.begin(recording, table)
            self._inner.append((detector, blocks))
        self.reach_m = max(by_distance)
        last = recording.n_frames - 1
        self._events = {}
        for q, (spans, _) in learned.items():
            events = []
            for a, b in spans:  # true frames [a, b) → causal frames (+ delay), clamped to the recording
                on, off = min(a + self.delay_frames, last), min(b + self.delay_frames, last)
                if b >= recording.n_frames:
                    events.append((on, 1))
                elif off > on:
                    events += [(on, 1), (off, 0)]
            if events:
                self._events[q] = np.asarray(events, dtype=np.intp)

    def step(self, chunk: DistanceChunk) -> PairChanges:
        if self._table is None:
            raise SegmentationError("adaptive detector: step() before begin()")
        block = self._table.block[chunk.pairs]
        parts = []
        for detector, blocks in self._inner:
            rows = blocks[block]
            if rows.any():  # a detector without pairs in the chunk has nothing that can change
                sub = replace(chunk, pairs=chunk.pairs[rows], dist_m=chunk.dist_m[rows])
                parts.append(detector.step(sub))
        inner = PairChanges(
            np.concatenate([p.pairs for p in parts]) if parts else np.zeros(0, dtype=np.intp),
            np.concatenate([p.frames for p in parts]) if parts else np.zeros(0, dtype=np.intp),
            np.concatenate([p.touching for p in parts]) if parts else np.zeros(0, dtype=bool),
        )
        if not self._events:
            return inner
        block_of_head = {int(self._heads[q]): q for q in self._events}
        is_head = np.isin(inner.pairs, list(block_of_head))
        out_pairs = [inner.pairs[~is_head]]
        out_frames = [inner.frames[~is_head]]
        out_values = [inner.touching[~is_head]]
        # block → [(frame, kind: 0 = paper 1 = episode, new value)]
        head_changes: dict[int, list[tuple[int, int, bool]]] = {}
        heads = zip(inner.pairs[is_head], inner.frames[is_head], inner.touching[is_head], strict=True)
        for p, f, v in heads:
            head_changes.setdefault(block_of_head[int(p)], []).append((int(f), 0, bool(v)))
        for q, events in self._events.items():
            inside = (events[:, 0] >= chunk.start) & (events[:, 0] < chunk.stop)
            for f, v in events[inside]:
                head_changes.setdefault(q, []).append((int(f), 1, bool(v)))
        for q, changes in head_changes.items():
            for f, kind, v in sorted(changes):
                if kind == 0:
                    self._paper_head[q] = v
                else:
                    self._episode[q] = v
                state = bool(self._paper_head[q] or self._episode[q])
                if state != self._combined[q]:
                    self._combined[q] = state
                    out_pairs.append(np.array([self._heads[q]]))
                    out_frames.append(np.array([f]))
                    out_values.append(np.array([state]))
        pairs, frames, values = (np.concatenate(out_pairs), np.concatenate(out_frames),
                                 np.concatenate(out_values).astype(bool))
        order = np.lexsort((frames, pairs))
        return PairChanges(pairs[order].astype(np.intp), frames[order].astype(np.intp), values[order])
