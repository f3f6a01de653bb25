"""Adaptive touch detection (mode ``adaptive``): co-motion sets each pair's own threshold.

Markers sit on the back of the hand and on object corners, so "touching" is
30–120 mm depending on the object, and one fixed ``d`` cannot fit every pair: a
``d`` large enough for a bottle held at 119 mm makes a hand resting 100 mm from a
cup "touch" it. This detector learns the distance from the recording itself:

1. **Co-motion.** A held object moves with the hand: both instances move
   (``min(speed_A, speed_B) > move_speed``) while the distances between their
   markers hardly change (median ``|Δ dist| / Δt < rigid_ratio × min speed``) and
   they are within ``d × (1 + margin)`` (``d``: ``AasParams.distance_m``, now the largest
   contact distance). Speeds are measured over ``lag_s``. Runs of such frames of at least
   ``min_episode_s`` are *co-motion episodes*; they count where the pair co-moves within
   ``d`` somewhere and within twice its closest episode's distance
   (:data:`~oacdsl.segmentation.episodes.FAR_RATIO`).
2. **The pair's threshold.** For each episode, the pair's contact distance is the
   median of its closest marker distance during the episode, and its threshold that
   times ``1 + margin`` (at most ``d``).
3. **Extension.** The pair touches from the episode backwards and forwards for as
   long as its closest marker distance stays within that threshold (a gap —
   NaN — neither ends nor starts it): the grasp before the object starts to move,
   the hold after it is set down, until the hand leaves.
3a. **Resting on top** (:mod:`oacdsl.segmentation.stacking`, ``stacked``): an object that
   nobody holds, at rest on top of another (its markers above the other's, its centre over
   them), is an episode of that pair too, extended as in 3 until it is lifted off; a tool
   contact of the pair (5) does not carry it on from there (:mod:`oacdsl.segmentation.liftoff`).
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
rule does not forbid it (:mod:`oacdsl.segmentation.ruleintervals` runs the interval rules,
:mod:`oacdsl.segmentation.combine` combines them with (4) chunk by chunk). The episodes need the whole
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
from oacdsl.segmentation.combine import StateCombiner
from oacdsl.segmentation.comotion import AdaptiveSettings, comotion
from oacdsl.segmentation.detectors import DistanceChunk, PairChanges
from oacdsl.segmentation.geometry import BOUND_MARGIN_M
from oacdsl.segmentation.pairs import PairTable
from oacdsl.segmentation.params import AasParams
from oacdsl.segmentation.poses import RigidFill, fill_rigid_gaps
from oacdsl.segmentation.recording import Recording
from oacdsl.segmentation.robust import RobustDetector
from oacdsl.segmentation.ruleintervals import causal_events, event_rows, rule_intervals
from oacdsl.segmentation.scales import DemoScale, measure, scale_params, scale_settings, tool_reach_m
from oacdsl.segmentation.shapes import ShapeModel
from oacdsl.segmentation.subframe import change_times_s
from oacdsl.segmentation.tooluse import agents_of
from oacdsl.world import Relation

__all__ = ["AdaptiveDetector", "AdaptiveSettings", "comotion"]

_NEAR_BIN = 64  # frames per bin of the near-frame index built from the co-motion scan


class AdaptiveDetector:
    """Co-motion episodes with per-pair thresholds, OR the paper's rule at each pair's distance."""

    def __init__(self, params: AasParams, settings: AdaptiveSettings | None = None) -> None:
        self.settings = settings or AdaptiveSettings()
        self.params = params
        self.scale: DemoScale | None = None  # the recording's scales, once effective_params() ran
        self.filler: RigidFill | None = None  # rigid gaps, filled chunk by chunk (from begin() on)
        self._run = self.settings  # the settings in force: rescaled by effective_params()
        template = RobustDetector(params)  # frames of history and delay: set again in begin()
        self.history_frames = template.history_frames
        self.delay_frames = template.delay_frames
        self.reach_m: float | None = max(params.distance_m, self.settings.static_distance_m)
        #: metres, the tool rule's reach between two objects (``d`` in the scene's length, both ways)
        self.tool_reach_m = params.distance_m
        self._table: PairTable | None = None
        self._inner: RobustDetector | None = None  # the paper's rule, each pair at its own distance
        # block → (E, 3) [causal frame, kind (1 episode, 2 tool, 3 veto), on?], sorted
        self._events: dict[int, np.ndarray] = {}
        self._event_rows = np.zeros((0, 4), dtype=np.intp)
        self._state: StateCombiner | None = None  # the managed blocks' state (from begin() on)
        self._managed = np.zeros(0, dtype=bool)
        self._near_bins: np.ndarray | None = None  # (Q, bins) bool: some frame of the bin within reach
        self._edges: dict[int, dict[int, float]] = {}  # pair → {frame: threshold crossing, frames}
        self._shapes: dict[str, ShapeModel] | None = None  # contacts from geometry (use_shapes)
        #: instance → how contacts were measured (``shape``, ``hand``, ``markers: why``), after begin()
        self.geometry_report: dict[str, str] | None = None
        #: relation → the frames where a held tool's contact with it began by coming into reach (after
        #: begin()): merged with no hand's change (:func:`~oacdsl.segmentation.keyframes.merge_keyframes`)
        self.arrivals: dict[Relation, frozenset[int]] = {}

    def use_shapes(self, shapes: dict[str, ShapeModel]) -> None:
        """Measure contacts from these instances' shapes (:mod:`oacdsl.segmentation.geomcontact`)."""
        self._shapes = shapes

    @property
    def merges_connected(self) -> bool:
        """Merge keyframes of connected changes only, a group at its first change of a hand's
        contact, else at its last frame (``settings.merge``)."""
        return self.settings.merge == "connected"

    def agents(self, instances: tuple[str, ...] | list[str]) -> list[int]:
        """Indices of the agents among ``instances`` (``settings.agent_pattern``)."""
        return list(agents_of(instances, self.settings.agent_pattern))

    def _rigid(self, recording: Recording) -> list[str]:
        """The instances whose gaps are filled: every one but the agents (a hand is not rigid)."""
        agents = set(agents_of(recording.instances, self.settings.agent_pattern))
        return [g for i, g in enumerate(recording.instances) if i not in agents]

    def prepare(self, recording: Recording) -> Recording:
        """``recording`` with its rigid objects' marker gaps filled as :meth:`begin` fills them chunk
        by chunk (a copy; for references and tests), unless ``settings.fill_gaps`` is off."""
        return fill_rigid_gaps(recording, self._rigid(recording)) if self.settings.fill_gaps else recording

    def effective_params(self, recording: Recording, params: AasParams) -> AasParams:
        """``params`` (unresolved: ``frames`` may be automatic) resolved for ``recording``, every
        length, speed and duration rescaled by its scales (:mod:`oacdsl.segmentation.scales`)
        unless ``settings.rescale`` is off; the detector runs with them from :meth:`begin` on."""
        self.tool_reach_m = params.distance_m
        if self.settings.rescale:
            agents = agents_of(recording.instances, self.settings.agent_pattern)
            self.scale = measure(recording, tuple(recording.instances[i] for i in agents))
            self._run = scale_settings(self.settings, self.scale)
            self.tool_reach_m = tool_reach_m(params, self.scale)
            params = scale_params(params, self.scale)
        self.params = params.resolved(recording.rate_hz)
        return self.params

    def begin(self, recording: Recording, table: PairTable) -> None:
        template = RobustDetector(self.params, recording.rate_hz)
        self.history_frames, self.delay_frames = template.history_frames, template.delay_frames
        self._table = table
        self._state = StateCombiner(table)
        n_q = table.n_instance_pairs
        self.filler = RigidFill(recording, self._rigid(recording)) if self.settings.fill_gaps else None
        agents = agents_of(table.instances, self.settings.agent_pattern)
        found = comotion(recording, table, self.params, self._run, self.filler,
                         keep_speeds=agents if self._run.hold_still else ())
        self._edges = {q: dict(e) for q, e in found.edges.items()}
        rules = rule_intervals(recording, table, found, self.params, self._run, agents, self.tool_reach_m,
                               self._shapes)
        if self._shapes is not None:
            self.geometry_report = rules.geometry_report
        self.arrivals = {table.relation(q): frozenset(frames) for q, frames in rules.arrivals.items()}
        # the paper's rule per pair: at the pair's learned distance, else at the static distance
        by_distance: dict[float, np.ndarray] = {}
        default = np.ones(n_q, dtype=bool)
        for q, (_, threshold) in rules.learned.items():
            key = round(threshold, 4)  # 0.1 mm: pairs with the same distance share a detector
            by_distance.setdefault(key, np.zeros(n_q, dtype=bool))[q] = True
            default[q] = False
        if not self._run.static_agents:  # a hand touches by moving, holding or a tool, not by nearness
            default &= ~np.isin(table.instance_pairs, agents).any(axis=1)
        by_distance.setdefault(self._run.static_distance_m, np.zeros(n_q, dtype=bool))
        by_distance[self._run.static_distance_m] |= default
        # one detector, each marker pair at its instance pair's distance (float32, as a detector's own d)
        block_d = np.zeros(n_q, dtype=np.float32)
        for distance, blocks in by_distance.items():
            block_d[blocks] = np.float32(distance)
        self._inner = RobustDetector(self.params, recording.rate_hz, pair_distance_m=block_d[table.block])
        self._inner.begin(recording, table)
        self.reach_m = max(by_distance)
        self._near_bins = self._index_near(found.closest, block_d, recording.n_frames)
        self._events = causal_events(rules, self.delay_frames, recording.n_frames)
        self._event_rows = event_rows(self._events)
        self._managed = np.zeros(n_q, dtype=bool)  # blocks with events: the detector combines their state
        self._managed[list(self._events)] = True

    def change_times_s(self, pairs: np.ndarray, frames: np.ndarray, times_s: np.ndarray) -> np.ndarray:
        """When each change (instance pair ``pairs[i]`` at true frame ``frames[i]``) happened,
        seconds: where a co-motion extension's distance crossed its threshold, else the frame's
        time (:mod:`oacdsl.segmentation.subframe`; after :meth:`begin`)."""
        return change_times_s(self._edges, pairs, frames, times_s)

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
        scan_reach = self.params.distance_m * (1 + self._run.margin)  # metres, the co-motion scan's reach
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
        if self._table is None or self._inner is None or self._state is None:
            raise SegmentationError("adaptive detector: step() before begin()")
        inner = self._inner.step(chunk)
        if not self._events:
            return inner
        managed = self._managed[self._table.block[inner.pairs]]
        first, last = np.searchsorted(self._event_rows[:, 0], [chunk.start, chunk.stop], side="left")
        heads, frames, states = self._state.combine(
            inner.pairs[managed], inner.frames[managed], inner.touching[managed], self._event_rows[first:last]
        )
        pairs = np.concatenate([inner.pairs[~managed], heads])
        frames = np.concatenate([inner.frames[~managed], frames])
        values = np.concatenate([inner.touching[~managed], states]).astype(bool)
        order = np.lexsort((frames, pairs))
        return PairChanges(pairs[order].astype(np.intp), frames[order].astype(np.intp), values[order])
