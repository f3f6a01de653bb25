"""Which way the demonstrator faced, and how a drafted object lies turned from it.

Forward is as ``layout demonstrated`` takes it (``oacdsl/runtime/demo_layout.py``): left is
from the right hand to the left hand at the first frame both are seen, forward is left
turned a quarter clockwise seen from above (left × up). A drafted box's x axis is the
principal horizontal axis of its markers with the larger spread (its length); how far that
axis is turned from forward towards the left (:func:`drafted_turn`: a rolling pin held across
the body, 90deg) is the ``turned`` of the object's scene: ``layout demonstrated`` turns it so
by the drafted markers, and a scene that places it with ``at`` says ``turned`` (docs/language.md).
"""

from __future__ import annotations

from collections.abc import Iterable

import numpy as np

from oacdsl.segmentation.recording import Recording

__all__ = ["MIN_TURN_DEG", "demonstrator_forward", "drafted_turn"]

#: A drafted object turned less than this from the demonstrator's forward is not said to be, degrees.
MIN_TURN_DEG = 10.0


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


def drafted_turn(x_axis_xy: tuple[float, float], forward_xy: np.ndarray) -> float:
    """How far (degrees, whole) the object's x axis ``x_axis_xy`` is turned from ``forward_xy``
    towards the left, counter-clockwise seen from above, as the one of the two turns that stand
    a box alike (half a turn apart) nearer 0: in (-90, 90]."""
    x, f = np.asarray(x_axis_xy, float), np.asarray(forward_xy, float)
    left = np.array([-f[1], f[0]])  # up × forward
    deg = float(np.degrees(np.arctan2(float(x @ left), float(x @ f))))
    deg = (deg + 90.0) % 180.0 - 90.0  # in [-90, 90)
    return 90.0 if round(deg) == -90 else float(round(deg))
