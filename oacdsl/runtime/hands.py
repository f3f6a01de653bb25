"""The simplified ARMAR-III hands: a palm, one four-finger plate and a thumb.

The real hand has five pneumatic fingers (11 joints, 8 actuators). The model keeps
what grasping a cup, a mixer's handle and a sponge needs:

* ``hand_<s>``: the palm, fixed to ``wrist_2_<s>`` with the orientation of the facts'
  *Hand Base* frame H: x_H = back of the hand, y_H = across the fingers (index → pinky
  for the right hand is +y_H), z_H = along the fingers. The palm surface faces -x_H.
* ``fingers_<s>_j0`` / ``_j1``: index to pinky as one plate of two phalanges, at the
  facts' *Index J0/J1* positions and axes (40.2 mm phalanges); the plate is as wide as
  the four fingers (index at 0 mm, pinky at 73 mm across the hand).
* ``thumb_<s>_j0`` / ``_j1``: at the facts' *Thumb J0/J1* positions and axes.

Closing the fingers (positive angles) curls the plate toward the palm side (-x_H);
closing the thumb swings it toward the fingertips (+z_H): the two meet around an
object held in front of the palm. Deviation from the facts, documented in
``docs/runtime.md``: the thumb base may open to -0.5 rad (facts: 0) so that the hand
can come at an object sideways, and finger joints stop at 1.6 rad (facts: π).

All positions are metres in H (right hand); the left hand mirrors y_H.
"""

from __future__ import annotations

from dataclasses import dataclass

__all__ = [
    "HandJoint",
    "HandBox",
    "hand_joints",
    "hand_boxes",
    "GRASP_CENTRE_H",
    "OPEN",
    "CLOSED",
    "TOP_PRESHAPE",
    "PINCH_CLOSED",
    "finger_joint_names",
    "SQUEEZE_RAD",
]

#: How much further than where they touched the object the fingers are told to close, rad.
SQUEEZE_RAD = 0.08


@dataclass(frozen=True)
class HandJoint:
    """A finger joint: its parent link, origin and axis in the parent's frame."""

    name: str
    parent: str
    origin: tuple[float, float, float]
    axis: tuple[float, float, float]
    limits: tuple[float, float]
    mass_kg: float


@dataclass(frozen=True)
class HandBox:
    """A box of a hand link: centre and half sizes in the link frame, metres."""

    link: str
    centre: tuple[float, float, float]
    half: tuple[float, float, float]


#: The grasp centre (the facts' *TCP Power* point) in H, right hand, metres.
GRASP_CENTRE_H: tuple[float, float, float] = (-0.0501, 0.0160, 0.115)

#: Joint targets of an open and a closed hand (rad), per joint suffix.
OPEN: dict[str, float] = {"fingers_j0": 0.0, "fingers_j1": 0.0, "thumb_j0": -0.4, "thumb_j1": 0.0}
CLOSED: dict[str, float] = {"fingers_j0": 1.5, "fingers_j1": 1.5, "thumb_j0": 1.5, "thumb_j1": 1.2}
#: Hand shape before a grasp from above: the thumb folded along the palm, so that it does
#: not reach down past the object (an open thumb sticks 12 cm out of the palm).
TOP_PRESHAPE: dict[str, float] = {"fingers_j0": 0.0, "fingers_j1": 0.0, "thumb_j0": 1.3, "thumb_j1": 0.0}
#: Closing a pinch: the finger plate stays straight beside the edge, the folded thumb turns
#: down onto the top (its lowest reach is at 1.57 rad).
PINCH_CLOSED: dict[str, float] = {"fingers_j0": 0.0, "fingers_j1": 0.0, "thumb_j0": 1.57, "thumb_j1": 0.0}


def _m(v: tuple[float, float, float], side: str) -> tuple[float, float, float]:
    return v if side == "r" else (v[0], -v[1], v[2])


def finger_joint_names(side: str) -> dict[str, str]:
    """Suffix (``fingers_j0`` …) → joint name (``fingers_r_j0`` …) for one hand."""
    return {
        "fingers_j0": f"fingers_{side}_j0",
        "fingers_j1": f"fingers_{side}_j1",
        "thumb_j0": f"thumb_{side}_j0",
        "thumb_j1": f"thumb_{side}_j1",
    }


def hand_joints(side: str) -> list[HandJoint]:
    """The four finger joints of the hand on ``side`` ("r" or "l"), parents first.

    Origins from the facts, expressed in H: Index J0 at (105.4, ∓13.5, -8.7 palm-normal)
    mm; Thumb J0 48.9 mm along the palm normal and 65.2 mm forward; J1s 40.2 mm further.
    The masses (0.1 kg per segment) replace the file's 0.5 kg placeholders.
    """
    n = finger_joint_names(side)
    hand = f"hand_{side}"
    return [
        HandJoint(
            n["fingers_j0"], hand, _m((-0.0087, -0.0135, 0.1054), side), (0.0, -1.0, 0.0), (0.0, 1.6), 0.1
        ),
        HandJoint(
            n["fingers_j1"], f"{n['fingers_j0']}_link", (0.0, 0.0, 0.0402), (0.0, -1.0, 0.0), (0.0, 1.6), 0.1
        ),
        HandJoint(n["thumb_j0"], hand, _m((-0.0489, 0.0, 0.0652), side), (0.0, 1.0, 0.0), (-0.5, 1.6), 0.1),
        HandJoint(
            n["thumb_j1"], f"{n['thumb_j0']}_link", (-0.0402, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 1.6), 0.1
        ),
    ]


def hand_boxes(side: str) -> list[HandBox]:
    """The collision boxes of one hand (palm, thumb root, finger plate, thumb)."""
    n = finger_joint_names(side)
    hand = f"hand_{side}"
    return [
        # palm: 30 mm thick, 110 mm across, from 31 to 105 mm in front of the wrist
        HandBox(hand, _m((0.003, 0.025, 0.068), side), (0.015, 0.055, 0.037)),
        # thumb root between the palm and the thumb base
        HandBox(hand, _m((-0.030, 0.0, 0.0652), side), (0.018, 0.011, 0.009)),
        HandBox(f"{n['fingers_j0']}_link", _m((0.004, 0.037, 0.020), side), (0.009, 0.0465, 0.020)),
        HandBox(f"{n['fingers_j1']}_link", _m((0.004, 0.037, 0.024), side), (0.008, 0.0465, 0.024)),
        HandBox(f"{n['thumb_j0']}_link", (-0.020, 0.0, 0.0), (0.020, 0.011, 0.009)),
        HandBox(f"{n['thumb_j1']}_link", (-0.028, 0.0, 0.0), (0.028, 0.010, 0.008)),
    ]
