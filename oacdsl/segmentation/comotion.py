"""Co-motion: when two instances move as one, and the distance at which they do.

Steps 1–3 of the adaptive touch detector (:mod:`oacdsl.segmentation.adaptive`):
co-motion frames per instance pair (the scan, :mod:`oacdsl.segmentation.scan`), episodes, each
pair's learned contact distance, and the touching intervals grown from the episodes. The scan
reads the whole recording in chunks; memory O(frames) per instance pair that comes within reach
(float32).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from types import MappingProxyType
from typing import NamedTuple

import numpy as np

from oacdsl.errors import SegmentationError
from oacdsl.segmentation.episodes import extend_episode, find_episodes, near_episodes, union_spans
from oacdsl.segmentation.pairs import PairTable
from oacdsl.segmentation.params import AasParams
from oacdsl.segmentation.poses import RigidFill
from oacdsl.segmentation.recording import Recording
from oacdsl.segmentation.scan import Rule, scan_signals
from oacdsl.segmentation.subframe import EdgeTimes, span_edges

__all__ = ["AdaptiveSettings", "CoMotion", "comotion", "frames_within"]


@dataclass(frozen=True)
class AdaptiveSettings:
    """Constants of the adaptive detector (SI units); ``AasParams`` gives d, v, n.

    Attributes:
        static_distance_m: metres, ``d`` of the paper's rule for two objects that never co-move,
            whose own distance is unknown, in the reference demonstration's length (rescaled by the
            scene's, :func:`~oacdsl.segmentation.scales.scale_settings`). 80 mm: liquid poured into
            a bowl (34 mm in the synthetic dough scene) touches it, a fork lying 84 mm beside a bowl
            (KIT Mix) does not, also in a take 15 % smaller; an object resting on top of another
            touches it at any distance (``stacked``), and a hand touches by moving, holding or a
            tool, not by nearness (``static_agents``, off).
        move_speed_m_s: metres per second, both instances must move faster than this
            for co-motion (40 mm/s: four times the marker jitter of a 100 Hz Vicon
            recording, far below a carried object's 0.2–1 m/s).
        rigid_ratio: the median change of their marker distances must stay below
            this fraction of the slower instance's speed (0.5: a held object's
            distances change by a few per cent of its speed; a hand passing an
            object, or two hands moving independently, change them at about the
            full speed).
        margin: the threshold is the episode's median closest distance × (1 + margin)
            (0.15: a grip is not perfectly rigid, and the hand opens a little before
            it leaves).
        lag_s: seconds over which speeds and distance changes are measured (≥ 1 frame),
            so that the test means the same at 10 Hz and at 100 Hz.
        min_episode_s: seconds, the shortest co-motion episode (≥ 1 frame).
        agent_pattern: glob (case-insensitive) naming the agents, the instances that
            hold things (``*hand*``: ``left_hand``, ``right_hand``); used by the tool and
            cross-hand rules of :mod:`oacdsl.segmentation.tooluse`.
        tool_dwell_s: seconds a held object must stay within ``d`` of another object
            for a tool contact (0.5 s: carrying a tool past an object takes less,
            stirring, wiping, cutting take seconds).
        tool_bridge_s: seconds beyond ``d`` that do not end a tool contact (0.2 s: a
            stroke of a whisk or a knife lifting between cuts).
        rest_m: metres a distance may vary and still be "at rest" (the tool roles of
            :mod:`oacdsl.segmentation.toolroles`; 5 mm: marker jitter and a hand's tremor).
        rescale: every speed and duration above (and ``AasParams``' ``v``, ``n``, change
            and merge windows) is taken as the reference demonstration's and rescaled by the
            recording's own pace (:mod:`oacdsl.segmentation.scales`) before segmenting (on:
            a take twice as slow keeps its keyframes; docs/segmentation-adaptive.md). Of the
            lengths only ``d`` (grown, never shrunk) and the tool rule's reach between two objects
            (:func:`~oacdsl.segmentation.scales.tool_reach_m`, also shrunk) follow the scene's.
        fill_gaps: a rigid object's marker missing while three of its markers are seen is
            put where the object's rigid fit places it (:mod:`oacdsl.segmentation.poses`).
        hold_still: a hand at rest on or around a still object touches it
            (:mod:`oacdsl.segmentation.holding`; on by default: on the KIT development clips it
            changes no keyframe, hand F1, tool contact or composed take, and it finds a hand
            holding a bottle still while the other hand turns its lid).
        stacked: an object at rest on top of another touches it, from where it was set down until
            it is lifted off (:mod:`oacdsl.segmentation.stacking`; on: a lid on its bottle, whose
            markers are farther apart than the static distance).
        side_by_side: two objects within the static distance touch only where one's centre is over
            the other's markers (:mod:`oacdsl.segmentation.beside`; on: set down side by side on
            the table they do not touch, liquid poured into a bowl does).
        static_agents: the static distance applies to pairs with an agent too (off: a hand touches
            an object by moving it, holding it still or through a tool, not by being near it; a hand
            resting 81-93 mm beside KIT Wipe's rack from the first frame is 72-84 mm from it in a
            take 10 % smaller).

    The defaults sit inside the range that scores best on the KIT development
    clips (``docs/segmentation-adaptive.md`` lists the sensitivity).
    """

    static_distance_m: float = 0.08
    move_speed_m_s: float = 0.04
    rigid_ratio: float = 0.5
    margin: float = 0.15
    lag_s: float = 0.1
    min_episode_s: float = 0.1
    agent_pattern: str = "*hand*"
    tool_dwell_s: float = 0.5
    tool_bridge_s: float = 0.2
    rest_m: float = 0.005
    rescale: bool = True
    fill_gaps: bool = True
    merge: str = "connected"
    hold_still: bool = True
    stacked: bool = True
    static_agents: bool = False
    side_by_side: bool = True

    def __post_init__(self) -> None:
        for name in ("static_distance_m", "move_speed_m_s", "rigid_ratio", "lag_s", "tool_dwell_s"):
            if not getattr(self, name) > 0:
                raise SegmentationError(f"adaptive: {name} must be positive, got {getattr(self, name)}")
        if self.merge not in ("paper", "connected"):
            raise SegmentationError(f"adaptive: merge must be 'paper' or 'connected', got {self.merge!r}")
        if not (self.margin >= 0 and self.min_episode_s >= 0 and self.tool_bridge_s >= 0):
            raise SegmentationError("adaptive: margin, min_episode_s and tool_bridge_s must be ≥ 0")

    def frames(self, seconds: float, rate_hz: float) -> int:
        """``seconds`` in whole frames at ``rate_hz``, at least 1."""
        return max(1, round(seconds * rate_hz))


def frames_within(seconds: float, rate_hz: float) -> int:
    """The most frames a run lasting at most ``seconds`` holds at ``rate_hz`` (``k`` frames last
    ``k / rate``): ``floor``, not ``round``, so that an excursion a little longer than a bridge is
    not bridged at one rate or pace and cut at another (KIT Stir's let-go of the spoon, 0.25 s of
    the demonstration beyond the grip, 3 frames at 10 Hz: at ×1.6 time rounding let 4 frames pass)."""
    return max(0, int(np.floor(seconds * rate_hz + 1e-9)))


class CoMotion(NamedTuple):
    """What the co-motion scan found.

    Attributes:
        learned: instance pair → (sorted, disjoint frame intervals ``[a, b)`` of touching
            by steps 1–3, the pair's learned distance: the median of its episodes'
            thresholds, metres); only pairs with an episode.
        closest: instance pair → (F,) float32 closest marker distance, metres (inf
            beyond reach, NaN in gaps); every pair that comes within reach.
        speeds: instance (table order) → (F,) float64 median marker speed over ``lag_s``, m/s
            (NaN in gaps; frame ``i`` against frame ``i - lag``, the first frames against frame
            0, frame 0 against frame ``lag``; rigid gaps filled), of the instances asked for.
        edges: instance pair → {frame that begins or ends one of its episodes' extensions: where
            the closest distance crossed the episode's threshold, in frames}
            (:mod:`oacdsl.segmentation.subframe`).
    """

    learned: dict[int, tuple[list[tuple[int, int]], float]]
    closest: dict[int, np.ndarray]
    speeds: Mapping[int, np.ndarray] = MappingProxyType({})
    edges: Mapping[int, Mapping[int, float]] = MappingProxyType({})


def comotion(
    recording: Recording, table: PairTable, params: AasParams, settings: AdaptiveSettings,
    filler: RigidFill | None = None, keep_speeds: Sequence[int] = (),
) -> CoMotion:
    """Co-motion episodes, grown into touching intervals, and each pair's learned distance
    (``filler``: rigid gaps filled chunk by chunk, :class:`~oacdsl.segmentation.poses.RigidFill`;
    ``keep_speeds``: instances whose speeds the scan measured are returned too)."""
    speeds: dict[int, np.ndarray] = {}
    rule = Rule(params.distance_m * (1 + settings.margin), settings.frames(settings.lag_s, recording.rate_hz),
                settings.move_speed_m_s, settings.rigid_ratio)
    signals = scan_signals(recording, table, rule, filler, keep_speeds, speeds)
    _prune_indirect(signals, table)
    min_len = settings.frames(settings.min_episode_s, recording.rate_hz)
    bridge = frames_within(settings.tool_bridge_s, recording.rate_hz)  # a short excursion is no release
    out: dict[int, tuple[list[tuple[int, int]], float]] = {}
    edges: EdgeTimes = {}
    for q, (dmin, carry) in signals.items():
        spans, thresholds = [], []
        for a, b, median in near_episodes(dmin, find_episodes(carry, min_len, bridge), params.distance_m):
            threshold = min(median * (1 + settings.margin), params.distance_m)
            spans.append(extend_episode(dmin, a, b, threshold, bridge))
            thresholds.append(threshold)
        if spans:
            out[q] = (union_spans(spans), float(np.median(thresholds)))
            span_edges(dmin, [(a, b, t) for (a, b), t in zip(spans, thresholds, strict=True)],
                       edges.setdefault(q, {}))
    return CoMotion(out, {q: dmin for q, (dmin, _) in signals.items()}, speeds, edges)


def _prune_indirect(signals: dict[int, tuple[np.ndarray, np.ndarray]], table: PairTable) -> None:
    """Keep co-motion only between neighbours: drop A–B at frames where some C is closer to both.

    A hand holding a cup while the other hand pours milk into it moves with the
    milk too, but through the cup: A–B is the longest side of the triangle A–C–B
    (``max(dist(A, C), dist(C, B)) < dist(A, B)``: the relative neighbourhood graph).
    """
    index = {(int(a), int(b)): q for q, (a, b) in enumerate(table.instance_pairs)}
    n_inst = len(table.instances)
    for q, (dmin, carry) in signals.items():
        frames = carry.nonzero()[0]  # only co-motion frames can be dropped
        if frames.size == 0:
            continue
        a, b = (int(i) for i in table.instance_pairs[q])
        here = dmin[frames]
        drop = np.zeros(frames.size, dtype=bool)
        for c in range(n_inst):
            q1 = index.get((min(a, c), max(a, c)))
            q2 = index.get((min(b, c), max(b, c)))
            if c in (a, b) or q1 not in signals or q2 not in signals:
                continue
            drop |= np.fmax(signals[q1][0][frames], signals[q2][0][frames]) < here  # NaN: not closer
        carry[frames[drop]] = False
