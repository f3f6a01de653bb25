"""ARMAR-III kinematic facts: the one table the robot model is generated from.

Every number here comes from ``shared/reference/armar3-kinematics.md`` (extracted
from the Simox description of ARMAR-III, KIT H2T, LGPL-2.1+), converted to the ROS
convention (x forward, y left, z up; origin: platform centre on the floor) and to
metres and radians. Link frames are parallel to the world at q = 0, so a joint's
origin is its offset from the previous *moving* joint and its axis is the world
axis at q = 0 ("URDF recipe" of the facts file).

Joint names are the Simox names in snake case (``Shoulder 1 R`` → ``shoulder_1_r``);
the same names are used by the URDF, placo and MuJoCo. The simplified hands are
in :mod:`oacdsl.runtime.hands`; the platform joints ``base_x``, ``base_y`` (prismatic)
and ``base_yaw`` stand for the holonomic base.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

__all__ = [
    "JointFact",
    "FrameFact",
    "JOINTS",
    "FRAMES",
    "S15",
    "C15",
    "MM",
    "ARM_JOINTS",
    "TORSO_JOINTS",
    "BASE_JOINTS",
    "HEAD_JOINTS",
    "joint",
    "simox_name",
]

#: sin 15° and cos 15°: the facts' axis components 0.259 / 0.966, exact.
S15 = math.sin(math.radians(15.0))
C15 = math.cos(math.radians(15.0))
#: one millimetre in metres.
MM = 1e-3


@dataclass(frozen=True)
class JointFact:
    """One joint of the facts table.

    ``origin_m``: offset from the parent joint's frame (world-aligned at q = 0), metres.
    ``axis``: unit axis, world frame at q = 0. ``limits``: (lower, upper), rad or m.
    ``mass_kg``: mass of the link the joint moves (Simox value, or a documented guess).
    """

    name: str
    simox: str
    parent: str | None
    kind: str
    origin_m: tuple[float, float, float]
    axis: tuple[float, float, float]
    limits: tuple[float, float]
    mass_kg: float


Vec3 = tuple[float, float, float]
Axes = tuple[Vec3, Vec3, Vec3]


@dataclass(frozen=True)
class FrameFact:
    """A fixed frame (TCP, GCP, …) on a moving joint's link: offset in metres (world-aligned
    at q = 0) and the frame's x, y, z axes in world coordinates at q = 0."""

    name: str
    simox: str
    parent: str
    offset_m: tuple[float, float, float]
    axes: Axes


def _mm(x: float, y: float, z: float) -> tuple[float, float, float]:
    return (x * MM, y * MM, z * MM)


def _j(
    name: str,
    simox: str,
    parent: str | None,
    origin_mm: tuple[float, float, float],
    axis: tuple[float, float, float],
    limits: tuple[float, float],
    mass: float,
    kind: str = "revolute",
) -> JointFact:
    return JointFact(name, simox, parent, kind, _mm(*origin_mm), axis, limits, mass)


# Platform: the facts give Yaw_Platform only (plus x/y slides in the *_withPlatformJoints
# file, 0..5 m / 0..10 m); the runtime restricts the planar base in the IK, not here.
# The slide "links" carry a nominal 1 kg so that MuJoCo accepts them as moving bodies.
_BASE = [
    _j("base_x", "Y_Platform", None, (0, 0, 0), (1, 0, 0), (-1.0, 1.0), 1.0, "prismatic"),
    _j("base_y", "X_Platform", "base_x", (0, 0, 0), (0, 1, 0), (-1.0, 1.0), 1.0, "prismatic"),
    _j("base_yaw", "Yaw_Platform", "base_y", (0, 0, 0), (0, 0, 1), (-6.2832, 6.2832), 100.0),
]

_TORSO = [
    _j("hip_pitch", "Hip Pitch", "base_yaw", (158.0, 0.0, 890.0), (0, -1, 0), (-0.7854, 0.7854), 10.0),
    _j("hip_roll", "Hip Roll", "hip_pitch", (0, 0, 0), (1, 0, 0), (-0.7854, 0.7854), 10.0),
    _j("hip_yaw", "Hip Yaw", "hip_roll", (0, 0, 0), (0, 0, 1), (-0.7854, 0.7854), 15.415),
]

_HEAD = [
    _j("neck_1_pitch", "Neck_1_Pitch", "hip_yaw", (-35.0, 0.0, 603.0), (0, -1, 0), (-0.7854, 0.7854), 4.0),
    _j("neck_2_roll", "Neck_2_Roll", "neck_1_pitch", (0, 0, 0), (1, 0, 0), (-0.7854, 0.7854), 2.0),
    _j("neck_3_yaw", "Neck_3_Yaw", "neck_2_roll", (0, 0, 0), (0, 0, 1), (-0.7854, 0.7854), 2.0),
    _j("head_tilt", "Head_Tilt", "neck_3_yaw", (0, 0, 120.0), (0, -1, 0), (-0.7854, 0.7854), 6.79877),
    # The cameras and eyes carry no mass in the file; 0.1 kg each is a guess.
    _j("cameras", "Cameras", "head_tilt", (100.0, 0.0, 54.5), (0, 1, 0), (-0.5236, 0.7854), 0.1),
    _j("eye_left", "Eye_Left", "cameras", (0.0, 46.5, 0.0), (0, 0, -1), (-0.5236, 0.5236), 0.1),
    _j("eye_right", "Eye_Right", "cameras", (0.0, -46.5, 0.0), (0, 0, -1), (-0.5236, 0.5236), 0.1),
]

_ARM_R = [
    _j("shoulder_1_r", "Shoulder 1 R", "hip_yaw", (-35.0, -232.0, 485.0), (0, 1, 0), (-1.8665, 1.3963), 3.65),
    _j("shoulder_2_r", "Shoulder 2 R", "shoulder_1_r", (0, 0, 0), (-1, 0, 0), (-0.2417, 1.6514), 2.5),
    _j("upperarm_r", "Upperarm R", "shoulder_2_r", (0, 0, 0), (0, S15, C15), (-1.8869, 1.2905), 1.55685),
    _j("elbow_r", "Elbow R", "upperarm_r", (20.0, -80.2, -299.4), (0, -C15, S15), (-1.9998, 0.9599), 1.15744),
    _j("underarm_r", "Underarm R", "elbow_r", (0.0, -7.2, 1.9), (-1, 0, 0), (-1.2156, 1.8893), 2.26566087),
    _j(
        "wrist_1_r",
        "Wrist 1 R",
        "underarm_r",
        (240.0, 0.0, 0.0),
        (0, -S15, -C15),
        (-0.5093, 0.5215),
        1.29945309,
    ),
    # Wrist 2 mass is "just guessed" (0.2 kg) in the file.
    _j("wrist_2_r", "Wrist 2 R", "wrist_1_r", (0, 0, 0), (0, C15, -S15), (-0.5393, 0.8878), 0.2),
]

_ARM_L = [
    _j("shoulder_1_l", "Shoulder 1 L", "hip_yaw", (-35.0, 232.0, 485.0), (0, 1, 0), (-1.8659, 1.3963), 3.65),
    _j("shoulder_2_l", "Shoulder 2 L", "shoulder_1_l", (0, 0, 0), (-1, 0, 0), (-1.6514, 0.2417), 2.5),
    _j("upperarm_l", "Upperarm L", "shoulder_2_l", (0, 0, 0), (0, -S15, C15), (-1.2156, 1.8893), 1.55685),
    _j("elbow_l", "Elbow L", "upperarm_l", (20.0, 80.2, -299.4), (0, -C15, -S15), (-2.1461, 0.9599), 1.15744),
    _j("underarm_l", "Underarm L", "elbow_l", (0.0, 7.2, 1.9), (-1, 0, 0), (-1.8893, 1.2156), 2.26566087),
    _j(
        "wrist_1_l",
        "Wrist 1 L",
        "underarm_l",
        (240.0, 0.0, 0.0),
        (0, S15, -C15),
        (-0.5124, 0.4208),
        1.29945309,
    ),
    _j("wrist_2_l", "Wrist 2 L", "wrist_1_l", (0, 0, 0), (0, C15, S15), (-0.6702, 0.7735), 0.2),
]

#: Every moving joint of the body (hands excluded), parents before children.
JOINTS: tuple[JointFact, ...] = (*_BASE, *_TORSO, *_HEAD, *_ARM_R, *_ARM_L)

BASE_JOINTS: tuple[str, ...] = tuple(j.name for j in _BASE)
TORSO_JOINTS: tuple[str, ...] = tuple(j.name for j in _TORSO)
HEAD_JOINTS: tuple[str, ...] = tuple(j.name for j in _HEAD)
#: side ("r" / "l") → the 7 arm joints, shoulder to wrist.
ARM_JOINTS: dict[str, tuple[str, ...]] = {
    "r": tuple(j.name for j in _ARM_R),
    "l": tuple(j.name for j in _ARM_L),
}


def _hand_axes(side: str) -> Axes:
    """Axes of Hand Base / TCP at q = 0: x = back of the hand, y = across the fingers,
    z = along the fingers (forward)."""
    if side == "r":
        return ((0.0, -S15, -C15), (0.0, C15, -S15), (1.0, 0.0, 0.0))
    return ((0.0, S15, -C15), (0.0, C15, S15), (1.0, 0.0, 0.0))


def _grasp_axes(side: str) -> Axes:
    """Axes of GCP / TCP Power / TCP Precision: the hand frame pitched by -45°."""
    h = 1.0 / math.sqrt(2.0)
    sign = -1.0 if side == "r" else 1.0
    return ((h, sign * h * S15, -h * C15), (0.0, C15, sign * S15), (h, -sign * h * S15, h * C15))


def _frames(side: str) -> list[FrameFact]:
    up = side.upper()
    s = -1.0 if side == "r" else 1.0
    w = f"wrist_2_{side}"
    return [
        FrameFact(f"hand_base_{side}", f"Hand {up} Base", w, (0.0, 0.0, 0.0), _hand_axes(side)),
        FrameFact(f"tcp_{side}", f"TCP {up}", w, _mm(130.0, 0.0, 0.0), _hand_axes(side)),
        FrameFact(f"gcp_{side}", f"GCP {up}", w, _mm(90.0, -s * 29.7, 33.5), _grasp_axes(side)),
        FrameFact(
            f"tcp_{side}_precision", f"TCP {up} Precision", w, _mm(144.0, -s * 21.7, 81.1), _grasp_axes(side)
        ),
        FrameFact(f"tcp_{side}_power", f"TCP {up} Power", w, _mm(115.0, -s * 28.4, 44.2), _grasp_axes(side)),
    ]


#: The fixed frames of the facts table that the model carries (per hand).
FRAMES: tuple[FrameFact, ...] = (*_frames("r"), *_frames("l"))

_BY_NAME = {j.name: j for j in JOINTS}


def joint(name: str) -> JointFact:
    """The fact row of joint ``name`` (KeyError when unknown)."""
    return _BY_NAME[name]


def simox_name(name: str) -> str:
    """The Simox name of a joint or frame of this model."""
    if name in _BY_NAME:
        return _BY_NAME[name].simox
    for f in FRAMES:
        if f.name == name:
            return f.simox
    raise KeyError(name)
