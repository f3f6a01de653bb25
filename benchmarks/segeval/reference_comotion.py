"""Co-motion (steps 1–3 of the adaptive detector) frame by frame in Python, for the reference.

The per-frame signals of :func:`oacdsl.segmentation.comotion.comotion` — per instance
pair and frame, the closest marker distance and whether the two move as one — computed
one frame, one instance and one marker pair at a time (float64, lists), then the same
episode steps (pruning, runs, thresholds, extension) as the detector. Used by
:func:`segeval.reference.segment_reference` in mode ``adaptive`` so that
``benchmarks/segmentation.py`` compares like with like.
"""

from __future__ import annotations

import math
import statistics

import numpy as np

from oacdsl.segmentation.comotion import AdaptiveSettings, CoMotion, _prune_indirect, frames_within
from oacdsl.segmentation.episodes import FAR_RATIO, extend_episode, find_episodes, union_spans
from oacdsl.segmentation.pairs import PairTable
from oacdsl.segmentation.params import AasParams
from oacdsl.segmentation.recording import Recording

__all__ = ["comotion_reference"]


def _median(values: list[float]) -> float:
    seen = [v for v in values if not math.isnan(v)]
    return statistics.median(seen) if seen else math.nan


def comotion_reference(
    recording: Recording, table: PairTable, params: AasParams, settings: AdaptiveSettings
) -> CoMotion:
    """The same result as :func:`~oacdsl.segmentation.comotion.comotion`, frame by frame."""
    n_frames = recording.n_frames
    if table.n_instance_pairs == 0 or n_frames < 2:
        return CoMotion({}, {})
    lag = settings.frames(settings.lag_s, recording.rate_hz)
    reach = params.distance_m * (1 + settings.margin)
    pos = recording.positions_m.tolist()
    times = [float(t) for t in recording.times_s]
    members = [
        [int(m) for m in table.marker_order[a:b]]
        for a, b in zip(table.marker_offsets[:-1], table.marker_offsets[1:], strict=True)
    ]
    blocks = [
        [
            (int(table.first[p]), int(table.second[p]))
            for p in range(table.block_offsets[q], table.block_offsets[q + 1])
        ]
        for q in range(table.n_instance_pairs)
    ]
    dmin = [[math.inf] * n_frames for _ in blocks]
    carry = [[False] * n_frames for _ in blocks]
    near = [False] * len(blocks)
    for f in range(n_frames):
        prev = max(f - lag, 0)
        if prev == f:
            prev = min(lag, n_frames - 1)
        dt = abs(times[f] - times[prev])
        speed = [_median([math.dist(pos[f][m], pos[prev][m]) for m in ms]) / dt for ms in members]
        for q, pairs in enumerate(blocks):
            now = [math.dist(pos[f][a], pos[f][b]) for a, b in pairs]
            seen = [d for d in now if not math.isnan(d)]
            closest = min(seen) if seen else math.nan
            if not closest <= reach:  # beyond reach (or unseen): the detector does not scan it
                dmin[q][f] = closest if math.isnan(closest) and near[q] else math.inf
                continue
            near[q] = True
            before = [math.dist(pos[prev][a], pos[prev][b]) for a, b in pairs]
            change = _median([abs(x - y) for x, y in zip(now, before, strict=True)]) / dt
            ia, ib = (int(i) for i in table.instance_pairs[q])
            known = [s for s in (speed[ia], speed[ib]) if not math.isnan(s)]  # as np.fmin: NaN ignored
            slower = min(known) if known else math.nan
            moving = closest < reach and slower > settings.move_speed_m_s
            dmin[q][f] = closest
            carry[q][f] = moving and change < settings.rigid_ratio * slower
    signals = {
        q: (np.asarray(dmin[q], dtype=np.float32), np.asarray(carry[q], dtype=bool))
        for q in range(len(blocks))
        if near[q]
    }
    _prune_indirect(signals, table)
    min_len = settings.frames(settings.min_episode_s, recording.rate_hz)
    bridge = frames_within(settings.tool_bridge_s, recording.rate_hz)
    out: dict[int, tuple[list[tuple[int, int]], float]] = {}
    for q, (d_q, c_q) in signals.items():
        spans, thresholds = [], []
        found = [(a, b, float(np.nanmedian(d_q[a:b]))) for a, b in find_episodes(c_q, min_len, bridge)]
        closest = min((m for _, _, m in found), default=math.inf)
        for a, b, median in found:
            if not (closest < params.distance_m and median <= FAR_RATIO * closest):
                continue  # no co-motion within d, or two hands moving alike far beyond the closest
            threshold = min(median * (1 + settings.margin), params.distance_m)
            spans.append(extend_episode(d_q, a, b, threshold, bridge))
            thresholds.append(threshold)
        if spans:
            out[q] = (union_spans(spans), float(np.median(thresholds)))
    return CoMotion(out, {q: d_q for q, (d_q, _) in signals.items()})
