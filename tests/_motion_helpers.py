"""A synthetic stirring demonstration for the motion tests (metres, seconds)."""

from __future__ import annotations

import numpy as np

from oacdsl.segmentation.recording import Recording
from oacdsl.segmentation.result import Keyframe, Segmentation
from oacdsl.world import WorldState

RATE = 20.0
BODY = np.array([[0.03, 0, 0], [-0.02, 0.02, 0], [0, -0.03, 0.01], [0.0, 0.0, -0.02]])


def synthetic_stir():
    """left_hand holds a cup that slides slowly; right_hand takes a spoon, stirs in the cup, leaves it there
    and moves away (hand-made keyframes as a segmentation would find them)."""
    n = int(6 * RATE)
    t = np.arange(n) / RATE
    cup = np.stack([0.01 * t, 0 * t, 0 * t], axis=1)
    spoon = np.tile([0.3, 0.0, 0.05], (n, 1))
    stir = (t >= 2) & (t < 5)
    w = 2 * np.pi * (t - 2) / 0.6
    spoon[t >= 1.5] = cup[t >= 1.5] + [0.0, 0.0, 0.1]
    spoon[stir] = cup[stir] + np.stack([0.02 * np.cos(w), 0.02 * np.sin(w), 0.1 + 0 * t], axis=1)[stir]
    r_hand = spoon + [0, 0, 0.05]
    r_hand[t < 1] = [0.5, 0.0, 0.2]
    late = t >= 5.2  # the hand lets go and moves away
    r_hand[late] += (t[late, None] - 5.2) * np.array([0.4, 0.0, 0.3])
    l_hand = cup + [-0.05, 0, 0]
    groups, positions = {}, []
    for name, centre in (("cup", cup), ("spoon", spoon), ("right_hand", r_hand), ("left_hand", l_hand)):
        groups[name] = tuple(range(4 * len(groups), 4 * len(groups) + 4))
        positions.append(centre[:, None, :] + BODY[None])
    pos = np.concatenate(positions, axis=1)
    pos[70:73, 4] = np.nan  # a spoon marker lost during the stir: three remain, still posed
    names = tuple(f"{g}{i}" for g in groups for i in range(4))
    rec = Recording("synthetic-stir", RATE, t, names, pos, groups)
    inst = rec.instances

    def kf(frame, *pairs):
        return Keyframe(frame, frame / RATE, WorldState.of(inst, [("cup", "left_hand"), *pairs]))

    keyframes = (kf(0), kf(20, ("right_hand", "spoon")), kf(40, ("right_hand", "spoon"), ("cup", "spoon")),
                 kf(100, ("cup", "spoon")))
    return rec, Segmentation("synthetic-stir", RATE, n, inst, keyframes)
