"""From instance-pair changes to keyframes, and the paper's keyframe merging.

Conventions (see ``docs/segmentation.md``): frame 0 is always the first keyframe
and carries the initial world state; every later keyframe is a frame where at
least one relation changed, with the world state from that frame on.
"""

from __future__ import annotations

from collections.abc import Sequence

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
) -> list[Keyframe]:
    """Keyframes from a list of relation changes.

    ``frames`` (K,) are the frames the changes belong to (≤ 0 folds into the initial
    state), ``which`` (K,) indices into ``relations``, ``values`` (K,) the new state
    (True = touching from that frame on). Changes of one relation must be in time order.
    """
    order = np.argsort(frames, kind="stable")
    frames, which, values = frames[order], which[order], values[order]
    touching: set[Relation] = set()
    inst = frozenset(instances)
    keyframes: list[Keyframe] = []
    k = 0
    n_changes = len(frames)
    while k < n_changes and frames[k] <= 0:
        _apply(touching, relations[int(which[k])], bool(values[k]))
        k += 1
    keyframes.append(Keyframe(0, float(times_s[0]), WorldState(inst, frozenset(touching))))
    while k < n_changes:
        frame = int(frames[k])
        while k < n_changes and frames[k] == frame:
            _apply(touching, relations[int(which[k])], bool(values[k]))
            k += 1
        state = WorldState(inst, frozenset(touching))
        if state != keyframes[-1].state:
            keyframes.append(Keyframe(frame, float(times_s[frame]), state))
    return keyframes


def _apply(touching: set[Relation], rel: Relation, value: bool) -> None:
    if value:
        touching.add(rel)
    else:
        touching.discard(rel)


def merge_keyframes(keyframes: Sequence[Keyframe], window_s: float) -> list[Keyframe]:
    """The paper's merging: keyframes closer than ``window_s`` seconds form a group.

    A keyframe joins a group when it is less than ``window_s`` after the group's
    latest member (so a group is a chain: each member is within the window of
    another). A group is replaced by its last keyframe with that keyframe's world
    state; a merged keyframe whose state equals the previous kept one is dropped
    (a touch that began and ended within the window leaves no trace). The group
    that contains frame 0 stays at frame 0 and takes the group's last state: the
    first keyframe is always the initial state. ``window_s = 0`` merges nothing;
    a gap equal to the window (within :data:`TIME_EPS_S`) does not merge.
    """
    if not keyframes:
        return []
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
            kept.append(last)
    return kept
