"""A straightforward per-frame Python implementation of the AAS, for tests and benchmarks.

It follows the rules literally, one frame and one marker pair at a time, with
run counters: slow (pure Python, float64) but easy to check by eye. The fast
:func:`oacdsl.segmentation.segment` must give the same keyframes; the benchmark
``benchmarks/segmentation.py`` measures how much faster that one is.

Modes: ``paper`` (Eq. 1 / Eq. 2 as printed), ``robust`` (the distance change as the
least-squares slope over the frames within ``±half`` of each frame, summed frame by
frame), and ``adaptive``: the robust rule per marker pair at each instance pair's own
distance (zero for a pair with an agent: ``static_agents``), OR the co-motion, rest-on-top, tool
and holding-still intervals, AND NOT the cross-hand vetoes; co-motion frame by frame in
:func:`~segeval.reference_comotion.comotion_reference`, the tool rule
(:func:`~oacdsl.segmentation.tooluse.tool_contacts`, interval logic over those per-frame signals)
and the rest-on-top rule (:func:`~oacdsl.segmentation.stacking.resting_on_top`, ended at a lift-off:
:func:`~oacdsl.segmentation.liftoff.lift_offs`) shared with the detector.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from oacdsl.segmentation.keyframes import merge_keyframes
from oacdsl.segmentation.params import AasParams
from oacdsl.segmentation.recording import Recording
from oacdsl.segmentation.result import Keyframe, Segmentation
from oacdsl.world import WorldState, relation

__all__ = ["pair_frames", "segment_reference"]


def segment_reference(recording: Recording, params: AasParams | None = None,
                      settings: Any = None) -> Segmentation:
    """Keyframes by Eq. 1 / Eq. 2, frame by frame.

    Same conventions as :class:`~oacdsl.segmentation.detectors.PaperDetector`.
    """
    given = params or AasParams()
    params = given.resolved(recording.rate_hz)
    if params.mode == "adaptive":  # the same rescaled constants as the detector
        from oacdsl.segmentation.adaptive import AdaptiveDetector

        detector = AdaptiveDetector(params, settings)
        recording = detector.prepare(recording)
        params = detector.effective_params(recording, given)
        return _robust_reference(recording, params, detector._run, detector.tool_reach_m)
    if params.mode != "paper":
        return _robust_reference(recording, params)
    d, v, n = params.distance_m, params.speed_m_s, params.n
    names = sorted(recording.groups)
    pairs: list[tuple[int, int, tuple[str, str]]] = []
    for i, a in enumerate(names):
        for b in names[i + 1 :]:
            for ma in recording.groups[a]:
                for mb in recording.groups[b]:
                    pairs.append((ma, mb, relation(a, b)))
    pos = recording.positions_m.tolist()
    times = [float(t) for t in recording.times_s]
    n_frames = len(times)

    def distance(frame: int, ma: int, mb: int) -> float:
        pa, pb = pos[frame][ma], pos[frame][mb]
        return math.sqrt((pa[0] - pb[0]) ** 2 + (pa[1] - pb[1]) ** 2 + (pa[2] - pb[2]) ** 2)

    touching = [False] * len(pairs)
    close_run = [0] * len(pairs)
    far_run = [0] * len(pairs)
    previous = [distance(1 if n_frames > 1 else 0, ma, mb) for ma, mb, _ in pairs]
    changes: list[tuple[int, int, bool]] = []  # (frame n0 or n1, pair, new state)
    for i in range(n_frames):
        # frame 0 takes the distance change of frame 1 (its "previous" is frame 1)
        limit = v * (times[i] - times[i - 1] if i > 0 else times[1] - times[0] if n_frames > 1 else 0.0)
        for p, (ma, mb, _) in enumerate(pairs):
            dist = distance(i, ma, mb)
            change = abs(dist - previous[p]) if n_frames > 1 else math.nan
            previous[p] = dist
            if math.isnan(dist):
                close = far = False
            elif math.isnan(change):  # the other frame is a gap: only the distance is known
                close = False
                far = dist > d
            else:
                close = dist < d and change < limit
                far = dist > d or change > limit
            close_run[p] = close_run[p] + 1 if close else 0
            far_run[p] = far_run[p] + 1 if far else 0
            if not touching[p] and close_run[p] >= n:
                touching[p] = True
                changes.append((i - n + 1, p, True))
            elif touching[p] and far_run[p] >= n:
                touching[p] = False
                changes.append((i - n + 1, p, False))

    # per-frame world states from the labelled pair states
    changes.sort(key=lambda c: c[0])
    pair_state = [False] * len(pairs)
    instances = frozenset(names)
    keyframes: list[Keyframe] = []
    k = 0
    for i in range(n_frames):
        while k < len(changes) and changes[k][0] <= i:
            pair_state[changes[k][1]] = changes[k][2]
            k += 1
        rels = frozenset(pairs[p][2] for p in range(len(pairs)) if pair_state[p])
        state = WorldState(instances, rels)
        if not keyframes or state != keyframes[-1].state:
            keyframes.append(Keyframe(i, times[i], state))
    merged = merge_keyframes(keyframes, params.merge_s)
    return Segmentation(
        recording.source,
        float(recording.rate_hz),
        n_frames,
        recording.instances,
        tuple(merged),
        params.to_dict(),
    )


def _robust_reference(recording: Recording, params: AasParams, settings: Any = None,
                      tool_reach_m: float | None = None) -> Segmentation:
    """Modes ``robust`` and ``adaptive``, frame by frame (see the module docstring); ``tool_reach_m``:
    the tool rule's reach between two objects (the detector's; None: ``d``)."""
    from oacdsl.segmentation.beside import side_by_side
    from oacdsl.segmentation.comotion import AdaptiveSettings
    from oacdsl.segmentation.episodes import union_spans
    from oacdsl.segmentation.holding import resting_holds
    from oacdsl.segmentation.liftoff import LiftOff, lift_offs, set_down_beside
    from oacdsl.segmentation.pairs import PairTable
    from oacdsl.segmentation.stacking import resting_on_top, with_rests
    from oacdsl.segmentation.tooluse import LiftOut, agents_of, tool_contacts
    from segeval.reference_comotion import comotion_reference

    v, n, half = params.speed_m_s, params.n, params.half_window(recording.rate_hz)
    table = PairTable.of(recording)
    n_frames = recording.n_frames
    distance = [params.distance_m] * table.n_instance_pairs
    # per instance pair: intervals that add touching (co-motion, tools) and that veto it (cross-hand)
    spans: dict[int, list[tuple[int, int]]] = {}
    vetoes: dict[int, list[tuple[int, int]]] = {}
    arrivals: dict[tuple[str, str], frozenset[int]] = {}  # tool contacts that began by arriving
    if params.mode == "adaptive":
        settings = settings or AdaptiveSettings()
        agents = agents_of(table.instances, settings.agent_pattern)
        distance = [0.0 if not settings.static_agents and (int(a) in agents or int(b) in agents)
                    else settings.static_distance_m for a, b in table.instance_pairs]
        delay = n - 1 + half
        found = comotion_reference(recording, table, params, settings)
        learned = found.learned
        lifts: dict[int, list[LiftOff]] = {}
        if settings.stacked:  # an object at rest on top of another until lifted off (the detector's rules)
            rests = resting_on_top(
                recording, table, found.closest, {q: i for q, (i, _) in learned.items()},
                agents_of(table.instances, settings.agent_pattern), params.distance_m,
                settings.move_speed_m_s, settings.lag_s, settings.tool_dwell_s, settings.tool_bridge_s,
                settings.margin)
            learned = with_rests(learned, rests)
            dwell = settings.frames(settings.tool_dwell_s, recording.rate_hz)
            lifts = lift_offs(recording, table, rests, dwell, settings.margin)
        reach = params.distance_m if tool_reach_m is None else tool_reach_m
        held = {q: intervals for q, (intervals, _) in learned.items()}
        tools = tool_contacts(
            table,
            n_frames,
            recording.rate_hz,
            held,
            found.closest,
            agents_of(table.instances, settings.agent_pattern),
            reach,
            settings.tool_dwell_s,
            settings.tool_bridge_s,
            settings.rest_m,
            reach * (1 + settings.margin),
            recording.positions_m,
            settings.frames(settings.lag_s, recording.rate_hz),
            lifts,
            LiftOut(settings.frames(settings.lag_s, recording.rate_hz), settings.move_speed_m_s),
        )
        for q, (_, threshold) in learned.items():
            distance[q] = round(threshold, 4)
        holds: dict[int, list[tuple[int, int]]] = {}
        if settings.hold_still:  # a hand at rest on or around a still object (the detector's rule)
            agents = agents_of(table.instances, settings.agent_pattern)
            holds = resting_holds(recording, table, found.closest, agents, params.distance_m,
                                  settings.move_speed_m_s, settings.lag_s, settings.tool_dwell_s,
                                  held=held)
        starts = {q: {a for a, _ in union_spans([*tools.added.get(q, []), *holds.get(q, [])])}
                  for q in tools.added}
        arrivals = {table.relation(q): frozenset(f for f in frames if f in starts.get(q, ()))
                    for q, frames in tools.arrivals.items()}  # tools that came into reach (the detector's)
        removed = dict(tools.removed)  # and, after a lift-off, two objects side by side (the detector's)
        kept = {q: union_spans([*held.get(q, []), *tools.added.get(q, [])]) for q in lifts}
        for q, beside in set_down_beside(lifts, found.closest, kept, recording.positions_m, table).items():
            removed[q] = union_spans([*removed.get(q, []), *beside])
        if settings.side_by_side:  # objects at the static distance, neither over the other (the detector's)
            static = [q for q, (a, b) in enumerate(table.instance_pairs.tolist())
                      if q not in learned and a not in agents and b not in agents]
            added = {q: union_spans([*tools.added.get(q, []), *holds.get(q, [])]) for q in tools.added}
            for q, beside in side_by_side(table, recording.positions_m, found.closest, static,
                                          settings.static_distance_m, added).items():
                removed[q] = union_spans([*removed.get(q, []), *beside])
        sources = ((spans, held), (spans, tools.added), (spans, holds), (vetoes, removed))
        for target, per_pair in sources:
            for q, intervals in per_pair.items():
                for a, b in intervals:  # as the detector reports them: clamped to the last decidable frame
                    on, off = min(a, n_frames - 1 - delay), min(b, n_frames - 1 - delay)
                    if b >= n_frames:
                        target.setdefault(q, []).append((on, n_frames))
                    elif off > on:
                        target.setdefault(q, []).append((on, off))
    pos = recording.positions_m.tolist()
    times = [float(t) for t in recording.times_s]
    touching = [[False] * n_frames for _ in range(table.n_instance_pairs)]
    for p in range(table.n_pairs):
        q = int(table.block[p])
        ma, mb = int(table.first[p]), int(table.second[p])
        dist = [math.dist(pos[i][ma], pos[i][mb]) for i in range(n_frames)]
        state, close_run, far_run, d = False, 0, 0, distance[q]
        changes: list[tuple[int, bool]] = []
        for i in range(n_frames - half):  # the last `half` frames have no full window
            if math.isnan(dist[i]):
                close = far = False
            elif dist[i] > d:  # far whatever the slope: no need to fit it
                close, far = False, True
            else:
                slope = _slope(dist, times, i, half)
                close = not math.isnan(slope) and dist[i] < d and abs(slope) < v
                far = not math.isnan(slope) and abs(slope) > v
            close_run = close_run + 1 if close else 0
            far_run = far_run + 1 if far else 0
            if not state and close_run >= n or state and far_run >= n:
                state = not state
                changes.append((i - n + 1, state))
        for k, (frame, value) in enumerate(changes):
            end = changes[k + 1][0] if k + 1 < len(changes) else n_frames
            if value:
                for i in range(frame, end):
                    touching[q][i] = True
    for q in range(table.n_instance_pairs):
        for a, b in spans.get(q, []):
            for i in range(a, b):
                touching[q][i] = True
        for a, b in vetoes.get(q, []):
            for i in range(a, b):
                touching[q][i] = False
    instances = frozenset(table.instances)
    keyframes: list[Keyframe] = []
    for i in range(n_frames):
        rels = frozenset(table.relation(q) for q in range(table.n_instance_pairs) if touching[q][i])
        state_i = WorldState(instances, rels)
        if not keyframes or state_i != keyframes[-1].state:
            keyframes.append(Keyframe(i, times[i], state_i))
    if params.mode == "adaptive" and settings is not None and settings.merge == "connected":
        agents = frozenset(table.instances[i] for i in agents_of(table.instances, settings.agent_pattern))
        merged = merge_keyframes(keyframes, params.merge_s, connected=True, agents=agents, arrivals=arrivals)
    else:
        merged = merge_keyframes(keyframes, params.merge_s)
    return Segmentation(
        recording.source,
        float(recording.rate_hz),
        n_frames,
        recording.instances,
        tuple(merged),
        params.to_dict(),
    )


def _slope(dist: list[float], times: list[float], i: int, half: int) -> float:
    """Least-squares slope (m/s) of the visible distances of frames ``i - half .. i + half``."""
    lo, hi = max(0, i - half), min(len(dist), i + half + 1)
    ts = [times[j] - times[i] for j in range(lo, hi) if not math.isnan(dist[j])]
    xs = [dist[j] for j in range(lo, hi) if not math.isnan(dist[j])]
    if len(xs) < half + 1:
        return math.nan
    t_mean, x_mean = sum(ts) / len(ts), sum(xs) / len(xs)
    var = sum((t - t_mean) ** 2 for t in ts)
    if var <= 0:
        return math.nan
    return sum((t - t_mean) * (x - x_mean) for t, x in zip(ts, xs, strict=True)) / var


def pair_frames(recording: Recording) -> int:
    """Marker-pair-frames of a recording: cross-instance marker pairs × frames."""
    sizes = np.array([len(g) for g in recording.groups.values()])
    pairs = (sizes.sum() ** 2 - (sizes**2).sum()) // 2
    return int(pairs) * recording.n_frames
