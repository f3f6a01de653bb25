"""Tool–target contacts and cross-hand contacts: what a held object touches, and what a hand does not.

Step 5 of the adaptive touch detector (:mod:`oacdsl.segmentation.adaptive`), on the
instance level, after co-motion (:mod:`oacdsl.segmentation.comotion`) has found which
agent (hand) *holds* which object at each frame. Agents are the instances whose name
matches ``AdaptiveSettings.agent_pattern`` (``*hand*``: ``left_hand``, ``right_hand``,
as the KIT preset and the dough scene name them); without agents this step does nothing.

**A hand and what it holds are one body.** Markers sit on object corners, handles and
attachments, so a spoon stirring in a cup, a sponge sliding over a plate or a knife
cutting a cucumber held at its end have markers 30–210 mm from their target's, and
their distance changes fast: the paper's rule (Eq. 1 needs ``|Δdist| < v``) misses
them. Two rules on the closest-marker distances, per frame:

- **Tool contact.** An object X *wielded* by agent H (H holds X) touches an object A
  that H does not hold when X stays within ``d`` (``reach_m``: the adaptive detector passes
  ``AasParams.distance_m`` in the scene's length, :func:`~oacdsl.segmentation.scales.tool_reach_m`)
  of A — or of the agent holding A, since a knife cutting next to the hand that holds the
  cucumber cuts the cucumber — for at least ``tool_dwell_s``, with
  excursions beyond ``d`` of at most ``tool_bridge_s`` bridged. Carrying a tool past an
  object lasts a fraction of that; stirring, mixing, wiping, scooping and cutting last
  seconds, sliding and oscillating inside that reach.
- **No cross-hand contact.** A hand that holds an object does not touch an object that
  the *other* hand holds, unless the two co-move (a hand-over): when one hand pours or
  stirs into the cup the other hand holds, both objects come within 100 mm of both hands
  (13–19 frames of cross-hand "touching" on the KIT Pour and Stir clips); the contact
  between them is the tool contact.

What a tool contact then means for the objects and hands around it (a grasped tool that
was lying beside its target, an object let go of where it works, a support, two tools in
one bowl, the hand behind a tool): :mod:`oacdsl.segmentation.toolroles`.

Memory O(frames) per instance pair within reach, as the co-motion scan.
"""

from __future__ import annotations

import fnmatch
import warnings
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np

from oacdsl.segmentation.comotion import frames_within
from oacdsl.segmentation.episodes import true_runs
from oacdsl.segmentation.liftoff import LiftOff, cut_at_lift_offs
from oacdsl.segmentation.liftout import cut_at_lift_outs, size_m
from oacdsl.segmentation.pairs import PairTable
from oacdsl.segmentation.toolroles import refine

__all__ = ["STRAIGHT_RATIO", "LiftOut", "ToolContacts", "agents_of", "passes_through", "tool_contacts"]

Spans = list[tuple[int, int]]


@dataclass(frozen=True)
class LiftOut:
    """The settings of the lifted-out rule (:mod:`oacdsl.segmentation.liftout`): ``lag`` frames
    over which the tool's speed is measured, and the speed below which it is held still, m/s."""

    lag: int
    move_speed_m_s: float


@dataclass(frozen=True)
class ToolContacts:
    """Per instance pair, frame intervals ``[a, b)``: contacts added (tool) and removed (cross-hand),
    and the first frames of the added contacts that are *arrivals* (:func:`arrivals`)."""

    added: dict[int, Spans]
    removed: dict[int, Spans]
    arrivals: dict[int, list[int]] = field(default_factory=dict)


def agents_of(instances: Sequence[str], pattern: str) -> tuple[int, ...]:
    """Indices of the instances whose name matches the glob ``pattern`` (case-insensitive)."""
    return tuple(i for i, name in enumerate(instances) if fnmatch.fnmatch(name.lower(), pattern.lower()))


def tool_contacts(
    table: PairTable,
    n_frames: int,
    rate_hz: float,
    held: Mapping[int, Spans],
    closest: Mapping[int, np.ndarray],
    agents: Sequence[int],
    reach_m: float,
    dwell_s: float,
    bridge_s: float,
    rest_m: float = 0.005,
    hold_m: float | None = None,
    positions_m: np.ndarray | None = None,
    step: int = 1,
    lifts: Mapping[int, list[LiftOff]] | None = None,
    lift_out: LiftOut | None = None,
) -> ToolContacts:
    """Tool contacts and cross-hand vetoes (see the module docstring).

    ``held``: instance pair → intervals in which it touches by co-motion (steps 1–3);
    ``closest``: instance pair → (F,) closest marker distance, metres (inf beyond
    reach, NaN in a gap: a gap inside a tool contact does not end it); ``reach_m``: ``d``;
    ``dwell_s``, ``bridge_s``: seconds; ``rest_m``: metres a distance at rest varies
    (:mod:`oacdsl.segmentation.toolroles`); ``hold_m``: metres, an excursion between two
    contacts that stays within it is bridged (None: ``reach_m``, only ``bridge_s``);
    ``positions_m``: the recording's (F, M, 3) marker positions, with which a tool that goes
    straight through the target's reach is passing by, however long it takes
    (:func:`passes_through`, sampled every ``step`` frames); None: the dwell alone decides;
    ``lifts``: object pair → each lift-off from a rest on top, where its tool contact ends (with
    ``positions_m``) (:func:`~oacdsl.segmentation.liftoff.cut_at_lift_offs`); ``lift_out``: a tool
    lifted out of its target and held above it stops touching it (with ``positions_m``,
    :func:`~oacdsl.segmentation.liftout.cut_at_lift_outs`; None: it does not).
    """
    agent_set = set(agents)
    if not agent_set:
        return ToolContacts({}, {})
    index = {(int(a), int(b)): q for q, (a, b) in enumerate(table.instance_pairs)}
    index_of = {q: ab for ab, q in index.items()}
    objects = [i for i in range(len(table.instances)) if i not in agent_set]

    def pair(i: int, j: int) -> int | None:
        return index.get((min(i, j), max(i, j)))

    def dist(i: int, j: int) -> np.ndarray:
        q = pair(i, j)
        if q is None or q not in closest:
            return np.full(n_frames, np.inf)
        return np.asarray(closest[q], dtype=np.float64)  # NaN: a gap, unknown

    def dist_at(i: int, j: int, at: np.ndarray) -> np.ndarray:
        """``dist(i, j)[at]``, reading only those frames."""
        q = pair(i, j)
        if q is None or q not in closest:
            return np.full(at.size, np.inf)
        return closest[q][at].astype(np.float64)

    holds: dict[tuple[int, int], np.ndarray] = {}  # (agent, object) → (F,) bool
    for h in agent_set:
        for x in objects:
            q = pair(h, x)
            mask = np.zeros(n_frames, dtype=bool)
            for a, b in held.get(q, []) if q is not None else []:
                mask[a:b] = True
            holds[(h, x)] = mask
    dwell = max(1, round(dwell_s * rate_hz))
    bridge = frames_within(bridge_s, rate_hz)
    added: dict[int, Spans] = {}
    sizes: dict[int, float] = {}  # instance → its size, metres (lifted out)
    for i, x in enumerate(objects):
        for a in objects[i + 1 :]:
            q = pair(x, a)
            if q is None:
                continue
            near = np.zeros(n_frames, dtype=bool)
            unknown = np.zeros(n_frames, dtype=bool)
            kept = np.zeros(n_frames, dtype=bool)  # within hold_m: does not end a contact
            for tool, target in ((x, a), (a, x)):
                for h in agent_set:
                    # the frames where h wields the tool: the only ones the rest looks at
                    at = (holds[(h, tool)] & ~holds[(h, target)]).nonzero()[0]
                    if at.size == 0:
                        continue
                    reach = dist_at(tool, target, at)
                    gap = np.isnan(reach)
                    for other in agent_set - {h}:  # the hand holding the target is part of it
                        to_other = np.where(holds[(other, target)][at], dist_at(tool, other, at), np.inf)
                        gap |= np.isnan(to_other)
                        reach = np.fmin(reach, to_other)
                    with np.errstate(invalid="ignore"):
                        close = reach < reach_m
                        if hold_m is not None:
                            kept[at] |= reach < hold_m
                    near[at] |= close
                    unknown[at] |= gap & ~close
            near = _bridge(near, bridge, (unknown | kept) & ~near)
            spans = [(s, e) for s, e in true_runs(near) if e - s >= dwell
                     and not (positions_m is not None
                              and passes_through(_centre(positions_m, table, x, s, e),
                                                 _centre(positions_m, table, a, s, e), step, reach_m))]
            if lifts and q in lifts and positions_m is not None:  # lifted off a rest: not carried on
                spans = cut_at_lift_offs(spans, lifts[q], dist(x, a), dwell, positions_m, table)
            if lift_out is not None and positions_m is not None and spans:  # held above its target
                for tool, target in ((x, a), (a, x)):
                    wielded = np.zeros(n_frames, dtype=bool)
                    for h in agent_set:
                        wielded |= holds[(h, tool)]
                    if target not in sizes:
                        sizes[target] = size_m(positions_m, table, target, max(1, n_frames // 200))
                    spans = cut_at_lift_outs(spans, tool, target, wielded, positions_m, table, sizes[target],
                                             dwell, lift_out.lag, lift_out.move_speed_m_s, rate_hz)
            if spans:
                added[q] = spans
    removed: dict[int, Spans] = {}
    for h in agent_set:
        busy = np.zeros(n_frames, dtype=bool)
        for x in objects:
            busy |= holds[(h, x)]
        for x in objects:
            q = pair(h, x)
            if q is None:
                continue
            by_other = np.zeros(n_frames, dtype=bool)
            for other in agent_set - {h}:
                by_other |= holds[(other, x)]
            veto = busy & by_other & ~holds[(h, x)]
            if veto.any():
                removed[q] = true_runs(veto)
    added, removed = refine(added, removed, n_frames, holds, objects, agent_set, pair, dist, reach_m, dwell,
                            rest_m)
    came = {q: found for q, spans in added.items()
            if (found := [a for a, _ in spans
                          if _arrived(a, index_of[q], holds, agent_set, dist_at, reach_m)])}
    return ToolContacts(added, removed, came)


def _arrived(start: int, ends: tuple[int, int], holds: Mapping[tuple[int, int], np.ndarray], agents: set[int],
             dist_at: Callable[[int, int, np.ndarray], np.ndarray], reach_m: float) -> bool:
    """Did the tool contact of the objects ``ends`` that begins at frame ``start`` begin by a held tool
    coming into its target's reach (at ``start - 1`` a hand wielded one of them beyond ``reach_m``
    of the other, and of the other hand holding it)? Not when it began as the hand took hold of a tool
    already within reach (a ladle lying in its bowl, a fork beside it)."""
    if start <= 0:
        return False
    at = np.array([start - 1])
    for tool, target in (ends, ends[::-1]):
        for h in agents:
            if not holds[(h, tool)][start - 1] or holds[(h, target)][start - 1]:
                continue
            gap = float(dist_at(tool, target, at)[0])
            for other in agents - {h}:
                if holds[(other, target)][start - 1]:
                    gap = float(np.fmin(gap, dist_at(tool, other, at)[0]))
            if gap > reach_m:  # NaN (a gap): not known to be beyond
                return True
    return False


#: A tool whose path relative to the target within reach is at least this straight (net
#: displacement over path length) goes through, not to, the target: carrying a spoon past a cup
#: is straight (≈ 1), stirring, wiping, cutting and dipping go back and forth or stay (≪ 1).
STRAIGHT_RATIO = 0.8


def passes_through(tool_m: np.ndarray, target_m: np.ndarray, step: int = 1, reach_m: float = 0.0) -> bool:
    """Does a tool at ``tool_m`` ((F, 3) m, its centre over a stay within reach) go straight through
    the reach of a target at ``target_m`` ((F, 3))? Its path relative to the target, sampled every
    ``step`` frames (marker jitter adds no length), is at least :data:`STRAIGHT_RATIO` straight and
    crosses ``reach_m`` at least (a chord of the reach through its inner part: in at one side, out
    at the other; an object brought straight *to* the target and let go there moves less:
    KIT Wipe's plate into the rack, 70 mm), and it ends at least half as far from the target as it
    began, within a fifth (a lid brought 205 mm straight onto its bottle ends at half its
    distance: it stays there).

    Scale, pace and frame rate do not change the ratio, unlike the dwell: a spoon carried past a
    cup at the demonstration's fastest pace stays within reach as long, in its own time, as a short
    stir (docs/segmentation-adaptive.md, step 5)."""
    rel = tool_m - target_m
    rows = np.flatnonzero(np.isfinite(rel).all(axis=1))
    if rows.size < 3:
        return False
    step = max(1, step)
    rows = np.append(rows[::step], rows[-1]) if (rows.size - 1) % step else rows[::step]
    path = rel[rows]
    length = float(np.linalg.norm(np.diff(path, axis=0), axis=1).sum())
    net = float(np.linalg.norm(path[-1] - path[0]))
    ends = sorted(float(np.linalg.norm(path[i])) for i in (0, -1))
    leaves = ends[0] >= 0.8 * ends[1]  # out as far as in: not brought *to* the target and left there
    return length > 0 and net >= STRAIGHT_RATIO * length and net >= reach_m and leaves


def _centre(positions_m: np.ndarray, table: PairTable, instance: int, s: int, e: int) -> np.ndarray:
    """(e - s, 3) mean of ``instance``'s visible markers in frames ``s:e`` (NaN where none is)."""
    idx = table.marker_order[table.marker_offsets[instance] : table.marker_offsets[instance + 1]]
    with np.errstate(invalid="ignore"), warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # a frame without any marker: NaN
        return np.asarray(np.nanmean(positions_m[s:e, idx], axis=1), dtype=np.float64)


def _bridge(mask: np.ndarray, frames: int, unknown: np.ndarray) -> np.ndarray:
    """``mask`` with each run of False between two True runs set True when it is at most
    ``frames`` long or ``unknown`` throughout (a gap, or within the hold distance: neither ends
    nor starts a contact)."""
    out = mask.copy()
    for a, b in true_runs(~mask):
        if a > 0 and b < mask.size and (b - a <= frames or unknown[a:b].all()):
            out[a:b] = True
    return out


