"""Which way the demonstrator faced: the horizontal direction a drafted object's x axis takes.

The robot stands every object with its x axis pointing away from it, whatever the recording
(a scene's ``at`` and ``layout demonstrated`` place objects, they do not turn them;
docs/language.md). So that an object drafted from a recording lies on the robot's table as
it lay in front of the demonstrator, a drafted box's x axis is the principal horizontal axis
of its markers that lies nearer the demonstrator's forward direction, pointing forward (a
rolling pin held across the body: its x across its length, its length the shorter size).
Forward is as ``layout demonstrated`` takes it (``oacdsl/runtime/demo_layout.py``): left is
from the right hand to the left hand at the first frame both are seen, forward is left
turned a quarter clockwise seen from above (left × up).
"""

from __future__ import annotations

from collections.abc import Iterable

import numpy as np

from oacdsl.segmentation.recording import Recording

__all__ = ["demonstrator_forward"]


def _side(name: str) -> str | None:
    """``"l"`` or ``"r"`` from a hand's name (``left_hand``, ``hand_r`` …), None when unclear."""
    low = name.lower()
    right = "right" in low or low.endswith("_r") or low.startswith("r_")
    left = "left" in low or low.endswith("_l") or low.startswith("l_")
    return None if right == left else ("r" if right else "l")


def demonstrator_forward(recording: Recording, hands: Iterable[str]) -> np.ndarray | None:
    """The demonstrator's forward direction, a horizontal unit vector (x, y), from the left and
    right hands' markers at the first frame both are seen; None without a left and a right
    hand, or with the two hands at one place."""
    sides = {s: h for h in hands if (s := _side(h)) is not None}
    if set(sides) != {"l", "r"}:
        return None
    left_m, right_m = (recording.group_positions(sides[s]) for s in ("l", "r"))  # (F, k, 3)
    both = np.isfinite(left_m).all(axis=2).any(axis=1) & np.isfinite(right_m).all(axis=2).any(axis=1)
    if not both.any():
        return None
    f = int(np.argmax(both))
    left = np.nanmean(left_m[f], axis=0)[:2] - np.nanmean(right_m[f], axis=0)[:2]
    norm = float(np.linalg.norm(left))
    if norm < 1e-3:
        return None
    left /= norm
    return np.array([left[1], -left[0]])  # left × up
