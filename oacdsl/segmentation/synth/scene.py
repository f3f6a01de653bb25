"""Geometry of the synthetic dough scene: the table, the objects and where their markers sit.

World frame: x to the demonstrator's right, y away from the demonstrator across
the table, z up; metres. The table top is at :data:`TABLE_Z_M`; the table is
environment (geometry only, no markers), as in the paper's scene.

Every body has a local frame and its markers in it (metres):

* hands: origin at the grasp point (palm centre), x out of the back of the hand,
  y along the fingers, z towards the thumb for the right hand (the left hand is
  the mirror image: its thumb is on −z). Five markers as in the KIT marker set
  (``?HTS ?HPS ?IFD ?WTS ?WPS``): back of the hand, index finger, wrist — 3 to
  11 cm from the grasp point, so hand–object marker distances are never zero.
* cups: origin at the centre of the base, z up, the pouring lip at +x, a handle
  at −x (a jug); markers asymmetric on the rim and on top of the handle. The
  liquid is one big marker sitting in the cup (the paper's demonstration
  symbolises the liquid by a big marker).
* the bowl: origin at the centre of the base; two markers on the rim, two low on
  the outside wall (near where each liquid lands).
* the mixer: origin between the beater tips, z up along the beaters; markers on
  the body, the handle on top.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = [
    "BODIES",
    "BOWL_RIM_RADIUS_M",
    "CUP_HANDLE_GRASP_M",
    "CUP_LIP_M",
    "HAND_IFD_CLOSE_M",
    "LIQUID_IN_CUP_M",
    "MIXER_HANDLE_GRASP_M",
    "TABLE_Z_M",
    "Body",
    "hand_markers",
]

#: Height of the table top above the floor, metres (environment, no markers).
TABLE_Z_M = 0.75


@dataclass(frozen=True)
class Body:
    """One tracked rigid body: its instance name, marker labels and body-frame marker positions (m)."""

    name: str
    labels: tuple[str, ...]
    local_m: np.ndarray


def _polar(radius_m: float, azimuth_deg: float, z_m: float) -> list[float]:
    a = np.deg2rad(azimuth_deg)
    return [radius_m * np.cos(a), radius_m * np.sin(a), z_m]


# -- hands -------------------------------------------------------------------------------
_HAND_RIGHT_M = np.array(
    [
        [0.035, -0.020, 0.030],  # HTS back of hand, thumb side
        [0.035, -0.020, -0.035],  # HPS back of hand, pinky side
        [0.030, 0.060, 0.025],  # IFD index finger (moves when the hand closes)
        [0.015, -0.085, 0.028],  # WTS wrist, thumb side
        [0.015, -0.085, -0.030],  # WPS wrist, pinky side
    ]
)
_HAND_SUFFIXES = ("HTS", "HPS", "IFD", "WTS", "WPS")
#: How far the index-finger marker moves in the hand frame when the hand closes, metres.
HAND_IFD_CLOSE_M = np.array([-0.015, -0.015, 0.0])


def hand_markers(side: str) -> np.ndarray:
    """(5, 3) hand-frame marker positions of the ``"left"`` or ``"right"`` hand, metres."""
    m = _HAND_RIGHT_M.copy()
    if side == "left":
        m[:, 2] *= -1.0
    return m


# -- cups, liquids -----------------------------------------------------------------------
_CUP_HEIGHT_M = 0.12
_CUP_RIM_MARKER_RADIUS_M = 0.048
#: The pouring lip, cup frame, metres.
CUP_LIP_M = np.array([0.048, 0.0, _CUP_HEIGHT_M])
#: Grasp point on the handle (the hand frame's origin when holding the cup), cup frame, metres.
CUP_HANDLE_GRASP_M = np.array([-0.11, 0.0, 0.065])
#: Where the liquid's big marker sits in the cup (towards the lip, near the bottom), cup frame, metres.
LIQUID_IN_CUP_M = np.array([0.025, 0.0, 0.03])

_RED_CUP_M = np.array(
    [
        _polar(_CUP_RIM_MARKER_RADIUS_M, 40.0, _CUP_HEIGHT_M + 0.004),
        _polar(_CUP_RIM_MARKER_RADIUS_M, 150.0, _CUP_HEIGHT_M + 0.004),
        _polar(_CUP_RIM_MARKER_RADIUS_M, 265.0, _CUP_HEIGHT_M + 0.004),
        [-0.095, 0.0, 0.108],  # top of the handle
    ]
)
_GREEN_CUP_M = np.array(
    [
        _polar(_CUP_RIM_MARKER_RADIUS_M, 75.0, _CUP_HEIGHT_M + 0.004),
        _polar(_CUP_RIM_MARKER_RADIUS_M, 215.0, _CUP_HEIGHT_M + 0.004),
        [-0.095, 0.0, 0.108],
    ]
)

# -- bowl ----------------------------------------------------------------------------------
_BOWL_HEIGHT_M = 0.12
#: Outer radius of the bowl's rim, metres (bottom: flat, inner radius 0.11 m).
BOWL_RIM_RADIUS_M = 0.165
_BOWL_M = np.array(
    [
        _polar(BOWL_RIM_RADIUS_M + 0.003, 82.0, _BOWL_HEIGHT_M + 0.004),  # rim, back
        _polar(BOWL_RIM_RADIUS_M + 0.003, 257.0, _BOWL_HEIGHT_M + 0.004),  # rim, front
        _polar(0.121, 172.0, 0.018),  # low on the outside wall, left
        _polar(0.121, 328.0, 0.018),  # low on the outside wall, right
    ]
)

# -- mixer -----------------------------------------------------------------------------------
#: Grasp point on the mixer's handle, mixer frame, metres.
MIXER_HANDLE_GRASP_M = np.array([0.0, -0.05, 0.235])
_MIXER_M = np.array(
    [
        [-0.030, -0.120, 0.160],  # body, rear
        [-0.020, 0.050, 0.210],  # body, front top
        [-0.045, -0.030, 0.185],  # body, left side (the hand holds it from the right)
    ]
)

#: Every tracked body of the dough scene, by instance name.
BODIES: dict[str, Body] = {
    "left_hand": Body("left_hand", tuple("L" + s for s in _HAND_SUFFIXES), hand_markers("left")),
    "right_hand": Body("right_hand", tuple("R" + s for s in _HAND_SUFFIXES), hand_markers("right")),
    "red_cup": Body("red_cup", ("RC1", "RC2", "RC3", "RC4"), _RED_CUP_M),
    "green_cup": Body("green_cup", ("GC1", "GC2", "GC3"), _GREEN_CUP_M),
    "liquid_one": Body("liquid_one", ("LQ1",), np.zeros((1, 3))),
    "liquid_two": Body("liquid_two", ("LQ2",), np.zeros((1, 3))),
    "orange_bowl": Body("orange_bowl", ("OB1", "OB2", "OB3", "OB4"), _BOWL_M),
    "mixer": Body("mixer", ("MX1", "MX2", "MX3"), _MIXER_M),
}
