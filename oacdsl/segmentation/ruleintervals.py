"""The adaptive detector's interval rules, found on the whole recording before its chunks.

Steps 1–3a and 5 of the adaptive touch detector (:mod:`oacdsl.segmentation.adaptive`) and its
holding-still and geometry options each give, per instance pair, frame intervals ``[a, b)``: what
touches by co-motion or a rest on top (with the pair's learned distance), what a tool or a hand
held still adds, and what the cross-hand and tool-role rules veto. :func:`rule_intervals` runs them
in their order on the co-motion scan's result; :func:`causal_events` turns the intervals into the
on/off events the chunks read (:class:`~oacdsl.segmentation.combine.StateCombiner`).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np

from oacdsl.segmentation.beside import side_by_side
from oacdsl.segmentation.comotion import AdaptiveSettings, CoMotion
from oacdsl.segmentation.episodes import union_spans
from oacdsl.segmentation.geomcontact import decided_by_geometry, geometric_contacts
from oacdsl.segmentation.holding import resting_holds
from oacdsl.segmentation.liftoff import LiftOff, lift_offs, set_down_beside
from oacdsl.segmentation.pairs import PairTable
from oacdsl.segmentation.params import AasParams
from oacdsl.segmentation.recording import Recording
from oacdsl.segmentation.shapes import ShapeModel
from oacdsl.segmentation.stacking import resting_on_top, with_rests
from oacdsl.segmentation.tooluse import LiftOut, tool_contacts

__all__ = ["EPISODE", "TOOL", "VETO", "RuleIntervals", "causal_events", "event_rows", "rule_intervals"]

Spans = list[tuple[int, int]]

#: Kinds of event (the flags of :class:`~oacdsl.segmentation.combine.StateCombiner`).
EPISODE, TOOL, VETO = 1, 2, 3


@dataclass(frozen=True)
class RuleIntervals:
    """Per instance pair, frame intervals ``[a, b)``.

    Attributes:
        learned: touching by co-motion or a rest on top, and the pair's learned distance, metres.
        added: touching by a tool or a hand held still.
        removed: vetoed (cross-hand, tool roles, geometry).
        geometry_report: instance → how its contacts were measured (contacts from geometry only).
        arrivals: the first frames of tool contacts that began by the held tool coming into its
            target's reach (:class:`~oacdsl.segmentation.tooluse.ToolContacts`): events of their own,
            which keyframe merging keeps apart from a hand's change.
    """

    learned: dict[int, tuple[Spans, float]]
    added: dict[int, Spans]
    removed: dict[int, Spans]
    geometry_report: dict[str, str] | None = None
    arrivals: dict[int, list[int]] = field(default_factory=dict)


def rule_intervals(
    recording: Recording,
    table: PairTable,
    found: CoMotion,
    params: AasParams,
    run: AdaptiveSettings,
    agents: Sequence[int],
    tool_reach_m: float,
    shapes: Mapping[str, ShapeModel] | None = None,
) -> RuleIntervals:
    """The interval rules on ``found`` (the co-motion scan of ``recording``), with ``params`` and
    ``run`` (the detector's settings in force, rescaled), ``agents`` (the hands' instance indices),
    ``tool_reach_m`` (the tool rule's reach between two objects) and, for contacts from geometry,
    ``shapes``."""
    learned = dict(found.learned)
    n_frames, rate = recording.n_frames, recording.rate_hz
    lifts: dict[int, list[LiftOff]] = {}
    if run.stacked:  # an object at rest on top of another (stacking.py), until lifted off (liftoff.py)
        rests = resting_on_top(
            recording, table, found.closest, {q: s for q, (s, _) in learned.items()}, agents,
            params.distance_m, run.move_speed_m_s, run.lag_s, run.tool_dwell_s, run.tool_bridge_s, run.margin)
        learned = with_rests(learned, rests)
        lifts = lift_offs(recording, table, rests, run.frames(run.tool_dwell_s, rate), run.margin)
    held = {q: spans for q, (spans, _) in learned.items()}
    tools = tool_contacts(
        table, n_frames, rate, held, found.closest, agents, tool_reach_m, run.tool_dwell_s,
        run.tool_bridge_s, run.rest_m, tool_reach_m * (1 + run.margin), recording.positions_m,
        run.frames(run.lag_s, rate), lifts, LiftOut(run.frames(run.lag_s, rate), run.move_speed_m_s),
    )
    added = dict(tools.added)
    if run.hold_still:  # a hand at rest on or around a still object (holding.py)
        holds = resting_holds(recording, table, found.closest, agents, params.distance_m,
                              run.move_speed_m_s, run.lag_s, run.tool_dwell_s,
                              speeds=found.speeds,  # the hands' speeds: measured by the scan
                              held=held)
        for q, spans in holds.items():
            added[q] = union_spans([*added.get(q, []), *spans])  # one flag per kind and pair
    removed = dict(tools.removed)
    if lifts:  # after a lift-off, the rest's distance does not make two objects side by side touch
        kept = {q: union_spans([*held.get(q, []), *added.get(q, [])]) for q in lifts}
        for q, spans in set_down_beside(lifts, found.closest, kept, recording.positions_m, table).items():
            removed[q] = union_spans([*removed.get(q, []), *spans])
    if run.side_by_side:  # two objects at the static distance touch only where one is over the other
        static = [q for q, (a, b) in enumerate(table.instance_pairs.tolist())
                  if q not in learned and a not in agents and b not in agents]
        for q, spans in side_by_side(table, recording.positions_m, found.closest, static,
                                     run.static_distance_m, added).items():
            removed[q] = union_spans([*removed.get(q, []), *spans])
    report = None
    if shapes is not None:  # pairs measured by geometry: decided by it alone
        geo = geometric_contacts(recording, table, dict(shapes), agents, params.n, run.tool_bridge_s)
        report = geo.report
        with_hand = np.isin(table.instance_pairs, agents).sum(axis=1) == 1
        carried = {q: spans for q, spans in held.items() if with_hand[q]}
        added, removed = decided_by_geometry(geo, added, removed, n_frames, carried)
    starts = {q: {a for a, _ in spans} for q, spans in added.items()}
    arrivals = {q: came for q, frames in tools.arrivals.items()
                if (came := [f for f in frames if f in starts.get(q, ())])}
    return RuleIntervals(learned, added, removed, report, arrivals)


def causal_events(rules: RuleIntervals, delay_frames: int, n_frames: int) -> dict[int, np.ndarray]:
    """Per instance pair, (E, 3) events [causal frame, kind, on?] of ``rules``' intervals, sorted: true
    frames ``[a, b)`` → causal frames (+ ``delay_frames``), clamped to the recording's last frame
    (an interval to the end has no off event)."""
    last = n_frames - 1
    collected: dict[int, list[tuple[int, int, int]]] = {}
    sources = [(EPISODE, {q: spans for q, (spans, _) in rules.learned.items()}), (TOOL, rules.added),
               (VETO, rules.removed)]
    for kind, per_pair in sources:
        for q, spans in per_pair.items():
            events = []
            for a, b in spans:
                on, off = min(a + delay_frames, last), min(b + delay_frames, last)
                if b >= n_frames:
                    events.append((on, kind, 1))
                elif off > on:
                    events += [(on, kind, 1), (off, kind, 0)]
            collected.setdefault(q, []).extend(events)
    return {q: np.asarray(sorted(e), dtype=np.intp).reshape(-1, 3) for q, e in collected.items() if e}


def event_rows(events: Mapping[int, np.ndarray]) -> np.ndarray:
    """All ``events`` as (E, 4) [causal frame, kind, on?, block], sorted by frame (stable): a chunk
    slices its own."""
    rows = [np.column_stack([e, np.full(len(e), q, dtype=np.intp)]) for q, e in events.items()]
    merged = np.concatenate(rows) if rows else np.zeros((0, 4), dtype=np.intp)
    return merged[np.argsort(merged[:, 0], kind="stable")]
