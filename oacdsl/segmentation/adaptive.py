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
   catches contacts without co-motion (liquid poured into a bowl, a second grasp
   of the same object that does not move it).
5. **Tools and hands** (:mod:`oacdsl.segmentation.tooluse`, when the recording has
   agents, instances named like ``*hand*``): an object held by a hand touches the
   object it stays near for ``tool_dwell_s`` (stirring, mixing, wiping, cutting:
   sliding and oscillating contacts), and a hand holding an object does not touch
   an object the other hand holds.

Two instances touch when (1–3), (4) or the tool rule says so, and the cross-hand
rule does not forbid it. The episodes need the whole
recording, so :meth:`AdaptiveDetector.begin` scans it once (chunked, memory
O(frames) per instance pair that ever comes within reach, float32); step 4 runs
chunk by chunk, one robust detector with each marker pair at its own distance. Results do not
depend on the chunk size. The instance-level decision of (1–3) is reported on the
first marker pair of the instance pair; for such a pair the detector follows the
paper's state of all its marker pairs itself and reports only the combined state.
"""

from __future__ import annotations

import numpy as np

from oacdsl.errors import SegmentationError
from oacdsl.segmentation.comotion import AdaptiveSettings, comotion
from oacdsl.segmentation.detectors import DistanceChunk, PairChanges
from oacdsl.segmentation.geometry import BOUND_MARGIN_M
from oacdsl.segmentation.pairs import PairTable
from oacdsl.segmentation.params import AasParams
from oacdsl.segmentation.recording import Recording
from oacdsl.segmentation.robust import RobustDetector
from oacdsl.segmentation.tooluse import agents_of, tool_contacts

__all__ = ["AdaptiveDetector", "AdaptiveSettings", "comotion"]

_NEAR_BIN = 64  # frames per bin of the near-frame index built from the co-motion scan


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
        self._inner: RobustDetector | None = None  # the paper's rule, each pair at its own distance
        # block → (E, 3) [causal frame, kind (1 episode, 2 tool, 3 veto), on?], sorted
        self._events: dict[int, np.ndarray] = {}
        self._event_rows = np.zeros((0, 4), dtype=np.intp)
        self._heads = np.zeros(0, dtype=np.intp)
        self._paper_count = np.zeros(0, dtype=np.int64)  # managed blocks: touching marker pairs
        self._pair_state = np.zeros(0, dtype=bool)  # managed blocks: paper state per marker pair
        self._flags = np.zeros((0, 4), dtype=bool)  # per block: [unused, episode, tool, veto]
        self._combined = np.zeros(0, dtype=bool)
        self._managed = np.zeros(0, dtype=bool)
        self._near_bins: np.ndarray | None = None  # (Q, bins) bool: some frame of the bin within reach

    def begin(self, recording: Recording, table: PairTable) -> None:
        template = RobustDetector(self.params, recording.rate_hz)
        self.history_frames, self.delay_frames = template.history_frames, template.delay_frames
        self._table = table
        self._heads = table.block_offsets[:-1].copy()
        n_q = table.n_instance_pairs
        self._paper_count = np.zeros(n_q, dtype=np.int64)
        self._pair_state = np.zeros(table.n_pairs, dtype=bool)
        self._flags = np.zeros((n_q, 4), dtype=bool)
        self._combined = np.zeros(n_q, dtype=bool)
        found = comotion(recording, table, self.params, self.settings)
        learned = found.learned
        # the paper's rule per pair: at the pair's learned distance, else at the static distance
        by_distance: dict[float, np.ndarray] = {}
        default = np.ones(n_q, dtype=bool)
        for q, (_, threshold) in learned.items():
            key = round(threshold, 4)  # 0.1 mm: pairs with the same distance share a detector
            by_distance.setdefault(key, np.zeros(n_q, dtype=bool))[q] = True
            default[q] = False
        by_distance.setdefault(self.settings.static_distance_m, np.zeros(n_q, dtype=bool))
        by_distance[self.settings.static_distance_m] |= default
        # one detector, each marker pair at its instance pair's distance (float32, as a detector's own d)
        block_d = np.zeros(n_q, dtype=np.float32)
        for distance, blocks in by_distance.items():
            block_d[blocks] = np.float32(distance)
        self._inner = RobustDetector(self.params, recording.rate_hz, pair_distance_m=block_d[table.block])
        self._inner.begin(recording, table)
        self.reach_m = max(by_distance)
        self._near_bins = self._index_near(found.closest, block_d, recording.n_frames)
        tools = tool_contacts(
            table,
            recording.n_frames,
            recording.rate_hz,
            {q: spans for q, (spans, _) in learned.items()},
            found.closest,
            agents_of(table.instances, self.settings.agent_pattern),
            self.params.distance_m,
            self.settings.tool_dwell_s,
            self.settings.tool_bridge_s,
        )
        last = recording.n_frames - 1
        collected: dict[int, list[tuple[int, int, int]]] = {}
        sources = [(1, {q: spans for q, (spans, _) in learned.items()}), (2, tools.added), (3, tools.removed)]
        for kind, per_pair in sources:
            for q, spans in per_pair.items():
                events = []
                for a, b in spans:  # true frames [a, b) → causal frames (+ delay), clamped to the recording
                    on, off = min(a + self.delay_frames, last), min(b + self.delay_frames, last)
                    if b >= recording.n_frames:
                        events.append((on, kind, 1))
                    elif off > on:
                        events += [(on, kind, 1), (off, kind, 0)]
                collected.setdefault(q, []).extend(events)
        self._events = {
            q: np.asarray(sorted(e), dtype=np.intp).reshape(-1, 3) for q, e in collected.items() if e
        }
        # all events as (E, 4) [causal frame, kind, on?, block], sorted by frame: a chunk slices its own
        rows = [np.column_stack([e, np.full(len(e), q, dtype=np.intp)]) for q, e in self._events.items()]
        merged = np.concatenate(rows) if rows else np.zeros((0, 4), dtype=np.intp)
        self._event_rows = merged[np.argsort(merged[:, 0], kind="stable")]
        self._managed = np.zeros(n_q, dtype=bool)  # blocks with events: the detector combines their state
        self._managed[list(self._events)] = True

    def _index_near(self, closest: dict[int, np.ndarray], block_d: np.ndarray,
                    n_frames: int) -> np.ndarray | None:
        """Per instance pair and bin of ``_NEAR_BIN`` frames: is its closest marker distance within
        the pair's own distance (``block_d``, (Q,) metres) somewhere in the bin? ``None`` when the
        scan's reach is shorter than ``reach_m``.

        The scan knows every pair's closest distance at every frame up to its own reach (inf
        beyond it), so a pair whose bins are all False in a chunk has every marker distance
        beyond its distance there: the paper's rule cannot find it close, and the broad phase of
        the main pass need not be run again.
        """
        scan_reach = self.params.distance_m * (1 + self.settings.margin)  # metres, as in comotion._scan
        if self.reach_m is None or self.reach_m > scan_reach:
            return None
        n_bins = -(-n_frames // _NEAR_BIN)
        bins = np.zeros((block_d.size, n_bins), dtype=bool)
        padded = np.full(n_bins * _NEAR_BIN, np.inf, dtype=np.float32)
        for q, dmin in closest.items():
            padded[:n_frames] = dmin
            with np.errstate(invalid="ignore"):  # NaN: no marker visible, not near
                near = padded <= block_d[q] + BOUND_MARGIN_M
            bins[q] = near.reshape(n_bins, _NEAR_BIN).any(axis=1)
        return bins

    def near_blocks(self, lo: int, stop: int, touching: np.ndarray) -> np.ndarray | None:
        """Instance pairs whose distances frames ``lo:stop`` need: within their own distance in
        some frame, touching (``touching``, (Q,) bool), or with a marker pair the paper's rule holds
        touching. ``None``: not known, use the broad phase."""
        if self._near_bins is None or self._table is None or self._inner is None:
            return None
        near = self._near_bins[:, lo // _NEAR_BIN : (stop - 1) // _NEAR_BIN + 1].any(axis=1) | touching
        near[self._table.block[np.flatnonzero(self._inner.state)]] = True
        return np.flatnonzero(near)

    def step(self, chunk: DistanceChunk) -> PairChanges:
        if self._table is None or self._inner is None:
            raise SegmentationError("adaptive detector: step() before begin()")
        inner = self._inner.step(chunk)
        if not self._events:
            return inner
        managed = self._managed[self._table.block[inner.pairs]]
        out_pairs = [inner.pairs[~managed]]
        out_frames = [inner.frames[~managed]]
        out_values = [inner.touching[~managed]]
        # block → [(frame, kind: 0 = paper marker pair p, else event kind, value, p)]
        changes: dict[int, list[tuple[int, int, bool, int]]] = {}
        ours = zip(inner.pairs[managed], inner.frames[managed], inner.touching[managed], strict=True)
        for p, f, v in ours:
            changes.setdefault(int(self._table.block[p]), []).append((int(f), 0, bool(v), int(p)))
        first, last = np.searchsorted(self._event_rows[:, 0], [chunk.start, chunk.stop], side="left")
        for f, kind, v, q in self._event_rows[first:last].tolist():
            changes.setdefault(q, []).append((f, kind, bool(v), -1))
        for q, block_changes in changes.items():
            block_changes.sort()
            for k, (f, kind, v, p) in enumerate(block_changes):
                if kind == 0:
                    if self._pair_state[p] != v:
                        self._pair_state[p] = v
                        self._paper_count[q] += 1 if v else -1
                else:
                    self._flags[q, kind] = v
                if k + 1 < len(block_changes) and block_changes[k + 1][0] == f:
                    continue  # the state after all changes of a frame counts
                flags = self._flags[q]
                state = bool((self._paper_count[q] > 0 or flags[1] or flags[2]) and not flags[3])
                if state != self._combined[q]:
                    self._combined[q] = state
                    out_pairs.append(np.array([self._heads[q]]))
                    out_frames.append(np.array([f]))
                    out_values.append(np.array([state]))
        pairs, frames, values = (
            np.concatenate(out_pairs),
            np.concatenate(out_frames),
            np.concatenate(out_values).astype(bool),
        )
        order = np.lexsort((frames, pairs))
        return PairChanges(pairs[order].astype(np.intp), frames[order].astype(np.intp), values[order])
