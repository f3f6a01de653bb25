"""The frames on which a demonstrated sub-action's motion is read, in the demonstration and in
the execution (``oacc verify``'s motion check, docs/verify.md).

A sub-action runs from one keyframe to the next, and its motion is that of the moved object
relative to its target (:mod:`oacdsl.segmentation.motion`). Two things make the keyframes a
poor frame for that motion when the pair's own relation is one of several changes:

- **Merged keyframes.** The demonstration's segmentation merges changes closer than its merge
  window (0.3 s) into one keyframe, at the last of them. At twice the speed, KIT Wipe's sponge
  leaving the plate (the end of the wiping) and the plate reaching the rack 0.15 s later are
  one keyframe; a robot makes them as two changes, seconds apart (it lifts the sponge, then
  carries the plate to the rack), which the relations check accepts as a *split*. Read from
  keyframe to keyframe, the wiping's span then runs over the plate's whole way to the rack in
  the execution, and over the plate's first turn toward it in the demonstration. Here each
  pair's span ends where the pair's own relation changes: in the execution at the robot change
  of the split that breaks it (and starts at the one that makes it), in the demonstration at
  the pair's own change in that recording's segmentation without merging (the simulation's
  contacts, too, are merged within 0.3 s).
- **While the relation holds.** A keyframe is the first frame of the new state, so a span that
  ends by breaking the pair's relation holds one frame in which the objects are apart: at
  10 Hz and twice the speed that frame is 0.2 s of the person's motion (Wipe: the sponge
  33 cm above the plate, which has turned 37° toward the rack meanwhile; its 61° "tilt" of
  the sponge against the plate is gained there, 20° while the sponge is on it, 40° in the
  original whose last frame is 0.1 s). A span that breaks the relation is read up to the last
  frame in which it holds, in both recordings.

A demonstrated keyframe that merges several changes therefore no longer decides the
execution's span for a pair whose change is among them: how the robot orders them does not
matter, and motion made after the pair's relation ended (or before it began) is not the
pair's.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any, NamedTuple

import numpy as np

from oacdsl.segmentation.recording import Recording
from oacdsl.segmentation.result import Keyframe, SubAction
from oacdsl.verify import Verification
from oacdsl.verify_changes import Change
from oacdsl.world import Relation, relation

__all__ = ["AlignedSpan", "Unmerged", "aligned_spans", "demonstration_frames", "execution_frames", "frame_of",
           "pair_frames"]


class AlignedSpan(NamedTuple):
    """The execution's frames ``(start, end)`` aligned with a demonstrated sub-action, and the
    execution's changes aligned with the demonstrated changes it starts and ends at (several
    when the robot split one); ``since``: the frame of the execution's keyframe before the
    first of the opening ones."""

    start: int
    end: int
    since: int = 0
    opening: tuple[Change, ...] = ()
    closing: tuple[Change, ...] = ()


def aligned_spans(v: Verification, dk: Any, rk: Any, rec: Recording) -> dict[int, AlignedSpan]:
    """Demonstration sub-action → the execution's recording frames aligned with it (from the
    keyframe before its first aligned change to its last aligned change's)."""
    frame = frame_of(rec)
    parts: dict[int, tuple[int, tuple[Change, ...]]] = {}  # demonstrated keyframe → robot changes
    bounds: dict[int, tuple[int, int]] = {}
    for s in v.alignment:
        if s.demonstration is None or s.robot is None:
            continue
        made = tuple(v.robot[s.robot:(s.robot_last if s.robot_last is not None else s.robot) + 1])
        first, end = made[0].index, made[-1].index
        dl = s.demonstration_last if s.demonstration_last is not None else s.demonstration
        for k in range(s.demonstration, dl + 1):
            a, b = frame(rk[first - 1].time_s), frame(rk[end].time_s)
            parts.setdefault(v.demonstration[k].index, (a, made))
            bounds.setdefault(v.demonstration[k].index - 1, (a, b))
    out = {}
    for k, (a, b) in bounds.items():
        since, opening = parts.get(k, (a, ()))
        out[k] = AlignedSpan(a, b, since, opening, parts.get(k + 1, (b, ()))[1])
    return out


def frame_of(rec: Recording) -> Callable[[float], int]:
    """Time since the recording's start (s) → its frame at or after it."""
    times = np.asarray(rec.times_s, dtype=np.float64) - float(rec.times_s[0])
    last = rec.n_frames - 1
    return lambda t: min(last, int(np.searchsorted(times, t - 1e-9)))


def _several(changes: Sequence[Change], pair: Relation) -> bool:
    """The changes change ``pair`` and something else."""
    changed = [r for c in changes for r in (*c.added, *c.removed)]
    return pair in changed and len(changed) > 1


def _own_change(keyframes: Sequence[tuple[int, frozenset[Relation]]], pair: Relation, after: int,
                upto: int, made: bool) -> int | None:
    """The frame of the last keyframe in ``(after, upto]`` at which ``pair`` starts (``made``)
    or stops touching; None when there is none."""
    found = None
    for (_, before), (f, now) in zip(keyframes, keyframes[1:], strict=False):
        if after < f <= upto and (pair in now) == made and (pair in before) != made:
            found = f
    return found


Unmerged = Callable[[], Sequence[tuple[int, frozenset[Relation]]]]


def _moves_on(keyframes: Sequence[tuple[int, frozenset[Relation]]], moved: str, target: str, after: int,
              upto: int, agents: frozenset[str]) -> bool:
    """Whether, in ``(after, upto]``, the target makes or breaks a relation with a third object
    (neither the moved object nor a hand): it has gone on to other work (a plate into the rack)."""
    for (_, before), (f, now) in zip(keyframes, keyframes[1:], strict=False):
        if after < f <= upto and any(target in r and not set(r) & ({moved} | agents) for r in before ^ now):
            return True
    return False


def pair_frames(a: int, b: int, since: int, moved: str, target: str, relation_: str | None,
                merged: tuple[bool, bool], unmerged: Unmerged,
                agents: frozenset[str] = frozenset()) -> tuple[int, int]:
    """The frames ``(a, b)`` of a recording on which ``moved`` → ``target`` is read over a
    sub-action that spans ``a``…``b`` and follows a keyframe at ``since`` (module doc), with
    ``unmerged()`` the recording's keyframes without merging (``(frame, relations)``):

    - where the keyframe at ``a`` holds the pair's making and other changes (``merged[0]``),
      from the pair's own making;
    - where the sub-action breaks the pair (``relation_``) and the keyframe at ``b`` holds other
      changes too (``merged[1]``), to the pair's own breaking when that is the last of them or
      the target goes on to other work after it (:func:`_moves_on`); else to ``b``: a robot may
      lose touch first and still work over its target (a carton lifted off the cup's rim pours
      into it; a ladle lifted out of a cup tips out over it), as the demonstration's AAS, which
      sees touch at some centimetres, reads it;
    - a span that ends at the pair's breaking, up to the last frame in which it holds."""
    pair = relation(moved, target)
    if merged[0]:
        own = _own_change(unmerged(), pair, since, a, made=True)
        a = a if own is None else own
    if relation_ == "broken":
        end: int | None = b
        if merged[1]:
            found = _own_change(unmerged(), pair, a, b, made=False)
            end = found if found is not None and (
                found == b or _moves_on(unmerged(), moved, target, found, b, agents)) else None
        if end is not None:
            b = max(a + 1, end - 1)
    return a, b


def execution_frames(span: AlignedSpan, moved: str, target: str, relation_: str | None,
                     unmerged: Unmerged, agents: frozenset[str] = frozenset()) -> tuple[int, int]:
    """The execution's frames on which the pair ``moved`` → ``target`` is read (module doc);
    ``unmerged()``: the execution's keyframes without merging, in its recording's frames."""
    pair = relation(moved, target)
    merged = (_several(span.opening, pair), _several(span.closing, pair))
    return pair_frames(span.start, span.end, span.since, moved, target, relation_, merged, unmerged, agents)


def demonstration_frames(sub: SubAction, previous: Keyframe | None, moved: str, target: str,
                         relation_: str | None, unmerged: Unmerged,
                         agents: frozenset[str] = frozenset()) -> tuple[int, int]:
    """The demonstration's frames on which the sub-action's pair is read (module doc), after
    the keyframe ``previous``; ``unmerged()``: the demonstration's keyframes without merging."""
    pair = relation(moved, target)
    opening = (previous.state if previous is not None else sub.start.state).relations ^ sub.before.relations
    closing = sub.before.relations ^ sub.after.relations
    merged = (pair in opening and len(opening) > 1, pair in closing and len(closing) > 1)
    since = previous.frame if previous is not None else sub.start.frame
    return pair_frames(sub.start.frame, sub.end.frame, since, moved, target, relation_, merged, unmerged,
                       agents)
