"""From instance-pair changes to keyframes, and the paper's keyframe merging.

Conventions (see ``docs/segmentation.md``): frame 0 is always the first keyframe
and carries the initial world state; every later keyframe is a frame where at
least one relation changed, with the world state from that frame on.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from collections.abc import Set as AbstractSet
from dataclasses import dataclass, field

import numpy as np

from oacdsl.segmentation.result import Keyframe
from oacdsl.world import Relation, WorldState

__all__ = ["TIME_EPS_S", "keyframes_from_changes", "merge_keyframes"]

#: Seconds: frame times read from files are not exact (0.1 + 0.2 != 0.3), so two
#: keyframes count as "closer than the window" only when closer by more than this.
TIME_EPS_S = 1e-6


def keyframes_from_changes(
    instances: Sequence[str],
    relations: Sequence[Relation],
    frames: np.ndarray,
    which: np.ndarray,
    values: np.ndarray,
    times_s: np.ndarray,
    change_times_s: np.ndarray | None = None,
) -> list[Keyframe]:
    """Keyframes from a list of relation changes.

    ``frames`` (K,) are the frames the changes belong to (≤ 0 folds into the initial
    state), ``which`` (K,) indices into ``relations``, ``values`` (K,) the new state
    (True = touching from that frame on). Changes of one relation must be in time order.
    ``change_times_s`` (K,): when each change happened, seconds (below the frame,
    :mod:`oacdsl.segmentation.subframe`); a keyframe's ``change_s`` is the earliest of its own.
    """
    order = np.argsort(frames, kind="stable")
    when = None if change_times_s is None else np.asarray(change_times_s, dtype=np.float64)[order].tolist()
    # Python lists: the loop below reads every change, numpy scalars would cost more than the work
    frame_of = np.asarray(frames)[order].tolist()
    rel_of = [relations[i] for i in np.asarray(which)[order].tolist()]
    value_of = np.asarray(values, dtype=bool)[order].tolist()
    touching: set[Relation] = set()
    inst = frozenset(instances)
    keyframes: list[Keyframe] = []
    k = 0
    n_changes = len(frame_of)
    while k < n_changes and frame_of[k] <= 0:
        _apply(touching, rel_of[k], value_of[k])
        k += 1
    last = frozenset(touching)
    keyframes.append(Keyframe(0, float(times_s[0]), WorldState(inst, last)))
    while k < n_changes:
        frame = frame_of[k]
        first = k
        while k < n_changes and frame_of[k] == frame:
            _apply(touching, rel_of[k], value_of[k])
            k += 1
        now = frozenset(touching)
        if now != last:  # the state changed (the instances are the same throughout)
            change = None if when is None else min(when[first:k])
            keyframes.append(Keyframe(frame, float(times_s[frame]), WorldState(inst, now), change))
            last = now
    return keyframes


def _apply(touching: set[Relation], rel: Relation, value: bool) -> None:
    if value:
        touching.add(rel)
    else:
        touching.discard(rel)


def merge_keyframes(keyframes: Sequence[Keyframe], window_s: float, at_onset: bool = False,
                    connected: bool = False, agents: frozenset[str] | None = None,
                    arrivals: Mapping[Relation, AbstractSet[int]] | None = None) -> list[Keyframe]:
    """The paper's merging: keyframes closer than ``window_s`` seconds form a group.

    A keyframe joins a group when it is less than ``window_s`` after the group's
    latest member (so a group is a chain: each member is within the window of
    another). A group is replaced by its last keyframe with that keyframe's world
    state; a merged keyframe whose state equals the previous kept one is dropped
    (a touch that began and ended within the window leaves no trace). The group
    that contains frame 0 stays at frame 0 and takes the group's last state: the
    first keyframe is always the initial state. ``window_s = 0`` merges nothing;
    a gap equal to the window (within :data:`TIME_EPS_S`) does not merge.

    ``at_onset`` (the adaptive detector's): a group stands at its *first* keyframe's frame,
    with its last state. The paper's last frame moves an event by up to the window when
    another, unrelated change follows it closely (Pour: the carton's grasp at 2.0 s, the
    carton reaching the cup at 2.1 s); the first frame is where the group's change began.

    ``connected`` (the adaptive detector's): a keyframe joins a group only when its change
    shares an instance with the group's changes (the carton grasped and the carton reaching
    the cup; not the left hand's grasp and the right hand's): independent changes keep their
    own frames, however close in time.

    ``agents`` (with ``connected``; the adaptive detector's hands): a group stands at the first of
    its changes that begins or ends an agent's contact (where the group's action began: the carton
    grasped, then reaching the cup), and a group of changes between objects only (a liquid leaving
    the cup, then reaching the bowl) at its last frame, as the paper places it.

    ``arrivals`` (with ``connected`` and ``agents``; the adaptive detector's): relation → frames where
    it began because a held tool came into its target's reach. Such an arrival and an agent's change
    never share a group: the tool had to be carried there after the hand acted (a spoon grasped
    20 cm from the cup, then brought into it), so the group's anchor at the hand's change would date
    the contact to the grasp (KIT Stir done 1.4-1.8 times as fast, where the window, in the pace,
    reaches from a grasp to the spoon's arrival).
    """
    if not keyframes:
        return []
    if connected:
        return _merge_connected(keyframes, window_s, at_onset, agents, arrivals)
    groups: list[list[Keyframe]] = [[keyframes[0]]]
    for kf in keyframes[1:]:
        if kf.time_s - groups[-1][-1].time_s < window_s - TIME_EPS_S:
            groups[-1].append(kf)
        else:
            groups.append([kf])
    first = groups[0]
    kept = [Keyframe(first[0].frame, first[0].time_s, first[-1].state)]
    for group in groups[1:]:
        last = group[-1]
        if last.state != kept[-1].state:
            kept.append(Keyframe(group[0].frame, group[0].time_s, last.state, group[0].change_s)
                        if at_onset else last)
    return kept



def _compatible(kinds: set[str], group: set[str]) -> bool:
    """May a change of these kinds join a group of those? Not an arrival with a hand's change."""
    return not (("arrival" in kinds and "agent" in group) or ("agent" in kinds and "arrival" in group))


def _touched(before: WorldState, after: WorldState) -> set[str]:
    """The instances whose relations differ between two states."""
    return {name for rel in before.relations ^ after.relations for name in rel}


@dataclass
class _Group:
    members: list[int]  # keyframe indices
    names: set[str]  # instances their changes touch
    last_s: float  # time of the latest member
    kinds: set[str] = field(default_factory=set)  # "agent" (a hand's change), "arrival" (a tool's)


def _kinds(before: WorldState, kf: Keyframe, agents: frozenset[str] | None,
           arrivals: Mapping[Relation, AbstractSet[int]] | None) -> set[str]:
    """Whether the change into ``kf`` changes an agent's relation and whether it holds an arrival."""
    out = set()
    if agents is not None and _touched(before, kf.state) & agents:
        out.add("agent")
    if arrivals and any(kf.frame in arrivals.get(rel, ()) for rel in kf.state.relations - before.relations):
        out.add("arrival")
    return out


def _merge_connected(keyframes: Sequence[Keyframe], window_s: float, at_onset: bool,
                     agents: frozenset[str] | None = None,
                     arrivals: Mapping[Relation, AbstractSet[int]] | None = None) -> list[Keyframe]:
    """:func:`merge_keyframes` with ``connected``: groups are chains in time *and* in instances.

    Each change (keyframe ``i`` against ``i - 1``) joins the open groups whose latest member is
    within the window and that share an instance with it (joining them); else it opens a group.
    A group's relations take their last values at its anchor (its first or last member's frame,
    or with ``agents`` its first member that changes an agent's relation, else its last; frame 0
    for a group within the window of the start); the states are rebuilt from them.
    """
    states = [kf.state for kf in keyframes]
    groups: list[_Group] = []
    active: list[_Group] = []  # groups whose latest member may still be within the window (in order)
    for i in range(1, len(keyframes)):
        names, t = _touched(states[i - 1], states[i]), keyframes[i].time_s
        kinds = _kinds(states[i - 1], keyframes[i], agents, arrivals) if arrivals else set()
        active = [g for g in active if t - g.last_s < window_s - TIME_EPS_S]  # times only grow
        near = []
        for g in active:  # the groups it shares an instance with, as long as their kinds agree
            if g.names & names and _compatible(kinds, g.kinds):
                near.append(g)
                kinds = kinds | g.kinds
        group = near[0] if near else _Group([], set(), t)
        if not near:
            groups.append(group)
            active.append(group)
        for other in near[1:]:
            group.members += other.members
            group.names |= other.names
            other.members = []  # joined: left out below
            active.remove(other)
        group.members.append(i)
        group.names |= names
        group.kinds |= kinds
        group.last_s = t
    start = keyframes[0]
    anchored: list[tuple[int, float, dict[Relation, bool], float | None]] = []
    for g in groups:
        if not g.members:
            continue
        members = sorted(g.members)
        final: dict[Relation, bool] = {}
        for i in members:
            for rel in states[i - 1].relations ^ states[i].relations:
                final[rel] = rel in states[i].relations
        anchor = keyframes[members[0]] if at_onset else keyframes[members[-1]]
        if agents is not None:
            by_agent = [i for i in members if _touched(states[i - 1], states[i]) & agents]
            anchor = keyframes[by_agent[0]] if by_agent else keyframes[members[-1]]
        if keyframes[members[0]].time_s - start.time_s < window_s - TIME_EPS_S:
            anchor = start  # early flicker folds into the initial state
        anchored.append((anchor.frame, anchor.time_s, final, anchor.change_s))
    anchored.sort(key=lambda c: c[0])
    touching = set(states[0].relations)
    out: list[Keyframe] = []
    for frame, time_s, final, change in [(start.frame, start.time_s, {}, start.change_s), *anchored]:
        for rel, value in final.items():
            _apply(touching, rel, value)
        state = WorldState(states[0].instances, frozenset(touching))
        if out and out[-1].frame == frame:
            both = [c for c in (out[-1].change_s, change) if c is not None]
            out[-1] = Keyframe(frame, time_s, state, min(both) if both else None)
            if len(out) > 1 and out[-2].state == state:
                out.pop()
        elif not out or state != out[-1].state:
            out.append(Keyframe(frame, time_s, state, change))
    return out
