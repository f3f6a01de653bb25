"""Primitive shapes of the ARMAR-III body links, sized from the facts' collision hulls.

Shapes are written in world coordinates at q = 0 (millimetres, as in the facts'
"approximate link geometry" table) and converted by :mod:`oacdsl.runtime.urdf` into
each link's frame. Right-side links are listed; the left side mirrors y.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

__all__ = ["Shape", "body_shapes", "rotation_to_rpy", "segment"]


@dataclass(frozen=True)
class Shape:
    """A primitive in a link frame: ``kind`` box (size = full extents), cylinder
    (size = radius, length, along local z) or sphere (size = radius); metres, radians."""

    kind: str
    size: tuple[float, ...]
    xyz: tuple[float, float, float]
    rpy: tuple[float, float, float] = (0.0, 0.0, 0.0)
    rgba: tuple[float, float, float, float] = (0.7, 0.7, 0.75, 1.0)


def rotation_to_rpy(r: np.ndarray) -> tuple[float, float, float]:
    """URDF roll-pitch-yaw of a rotation matrix, R = Rz(yaw) Ry(pitch) Rx(roll)."""
    pitch = math.asin(max(-1.0, min(1.0, -float(r[2, 0]))))
    if abs(math.cos(pitch)) > 1e-9:
        roll = math.atan2(float(r[2, 1]), float(r[2, 2]))
        yaw = math.atan2(float(r[1, 0]), float(r[0, 0]))
    else:  # gimbal lock: put everything into yaw
        roll = 0.0
        yaw = math.atan2(-float(r[0, 1]), float(r[1, 1]))
    return (roll, pitch, yaw)


def segment(
    p0_mm: tuple[float, float, float],
    p1_mm: tuple[float, float, float],
    radius_mm: float,
    rgba: tuple[float, float, float, float] = (0.7, 0.7, 0.75, 1.0),
) -> Shape:
    """A cylinder from ``p0`` to ``p1`` (world, mm) — returned in world metres."""
    a, b = np.array(p0_mm) * 1e-3, np.array(p1_mm) * 1e-3
    d = b - a
    length = float(np.linalg.norm(d))
    z = d / length
    x = np.cross([0.0, 1.0, 0.0], z) if abs(z[1]) < 0.9 else np.cross([1.0, 0.0, 0.0], z)
    x /= np.linalg.norm(x)
    y = np.cross(z, x)
    mid = (a + b) / 2
    rpy = rotation_to_rpy(np.column_stack([x, y, z]))
    centre = (float(mid[0]), float(mid[1]), float(mid[2]))
    return Shape("cylinder", (radius_mm * 1e-3, length), centre, rpy, rgba)


def _box(
    lo: tuple[float, float, float],
    hi: tuple[float, float, float],
    rgba: tuple[float, float, float, float] = (0.7, 0.7, 0.75, 1.0),
) -> Shape:
    c = tuple((a + b) / 2e3 for a, b in zip(lo, hi, strict=True))
    s = tuple((b - a) / 1e3 for a, b in zip(lo, hi, strict=True))
    return Shape("box", s, (c[0], c[1], c[2]), rgba=rgba)


def _sphere(
    c: tuple[float, float, float], r: float, rgba: tuple[float, float, float, float] = (0.7, 0.7, 0.75, 1.0)
) -> Shape:
    return Shape("sphere", (r * 1e-3,), (c[0] * 1e-3, c[1] * 1e-3, c[2] * 1e-3), rgba=rgba)


_DARK = (0.25, 0.25, 0.3, 1.0)
_BLUE = (0.35, 0.45, 0.7, 1.0)
_SKIN = (0.8, 0.8, 0.82, 1.0)


def _arm_right() -> dict[str, list[Shape]]:
    return {
        # shoulder hull (35,-267,1313)..(210,-122,1458)
        "shoulder_1_r_link": [_sphere((123.0, -215.0, 1385.0), 62.0, _BLUE)],
        "shoulder_2_r_link": [_sphere((123.0, -240.0, 1352.0), 48.0, _BLUE)],
        # upper arm hull (82,-351,1060)..(165,-219,1363): shoulder → elbow
        "upperarm_r_link": [segment((123.0, -236.0, 1330.0), (141.0, -306.0, 1100.0), 42.0, _SKIN)],
        "elbow_r_link": [_sphere((145.0, -318.0, 1077.0), 38.0, _BLUE)],
        # forearm hull (190,-367,1031)..(393,-276,1122)
        "underarm_r_link": [segment((185.0, -319.5, 1077.5), (365.0, -319.5, 1077.5), 44.0, _SKIN)],
        "wrist_1_r_link": [_box((371.0, -348.0, 1046.0), (393.0, -291.0, 1108.0), _DARK)],
    }


def _mirror(shapes: dict[str, list[Shape]]) -> dict[str, list[Shape]]:
    out: dict[str, list[Shape]] = {}
    for link, items in shapes.items():
        mirrored = []
        for s in items:
            rpy = s.rpy
            if s.kind == "cylinder":  # reflect the axis direction through the xz plane
                r = _rpy_matrix(rpy)
                m = np.diag([1.0, -1.0, 1.0])
                rm = m @ r @ m
                rpy = rotation_to_rpy(rm)
            mirrored.append(Shape(s.kind, s.size, (s.xyz[0], -s.xyz[1], s.xyz[2]), rpy, s.rgba))
        out[link.replace("_r_link", "_l_link")] = mirrored
    return out


def _rpy_matrix(rpy: tuple[float, float, float]) -> np.ndarray:
    r, p, y = rpy
    cr, sr, cp, sp, cy, sy = math.cos(r), math.sin(r), math.cos(p), math.sin(p), math.cos(y), math.sin(y)
    rz = np.array([[cy, -sy, 0], [sy, cy, 0], [0, 0, 1]])
    ry = np.array([[cp, 0, sp], [0, 1, 0], [-sp, 0, cp]])
    rx = np.array([[1, 0, 0], [0, cr, -sr], [0, sr, cr]])
    return rz @ ry @ rx


def body_shapes() -> dict[str, list[Shape]]:
    """Link name → shapes in *world* coordinates at q = 0 (metres)."""
    platform = [
        # wheel base: the hull's 680 mm footprint as a cylinder (yaw-invariant clearance)
        Shape("cylinder", (0.33, 0.36), (0.0, 0.0, 0.18), rgba=_DARK),
        # lower-body column up to the hip
        _box((-180.0, -160.0, 360.0), (230.0, 160.0, 830.0), _SKIN),
    ]
    shapes: dict[str, list[Shape]] = {
        "base_yaw_link": platform,
        "hip_pitch_link": [_box((95.0, -150.0, 850.0), (215.0, 150.0, 930.0), _DARK)],
        "hip_roll_link": [_box((60.0, -110.0, 845.0), (225.0, 110.0, 960.0), _DARK)],
        # torso hull (-41,-181,911)..(254,181,1522), narrowed so that the arms stay clear
        "hip_yaw_link": [_box((-41.0, -150.0, 960.0), (250.0, 150.0, 1460.0), _SKIN)],
        "neck_1_pitch_link": [_box((98.0, -40.0, 1478.0), (148.0, 40.0, 1520.0), _DARK)],
        "neck_3_yaw_link": [_box((90.0, -16.0, 1520.0), (160.0, 16.0, 1600.0), _DARK)],
        # head hull (80,-118,1550)..(263,118,1787)
        "head_tilt_link": [_box((85.0, -100.0, 1560.0), (240.0, 100.0, 1780.0), _SKIN)],
        "eye_left_link": [_sphere((233.0, 46.5, 1667.5), 18.0, _DARK)],
        "eye_right_link": [_sphere((233.0, -46.5, 1667.5), 18.0, _DARK)],
    }
    arm = _arm_right()
    shapes.update(arm)
    shapes.update(_mirror(arm))
    return shapes
