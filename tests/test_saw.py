"""``saw``'s stroke direction: along the tool's longest horizontal axis (a knife's blade)."""

from __future__ import annotations

import math

import numpy as np
import pytest

pytest.importorskip("mujoco", reason="the robot runtime needs the 'robot' extra (mujoco)")

from oacdsl.runtime.skills.saw import blade_direction  # noqa: E402
from oacdsl.runtime.transforms import make_T, rot_z  # noqa: E402


def _box(length_m: float, width_m: float, height_m: float) -> np.ndarray:
    return np.array([[sx * length_m / 2, sy * width_m / 2, z] for sx in (-1, 1) for sy in (-1, 1)
                     for z in (0.0, height_m)])


@pytest.mark.parametrize("yaw_deg", [0.0, 30.0, 90.0, 200.0])
def test_the_strokes_go_along_the_blade_however_the_knife_stands(yaw_deg: float) -> None:
    T = make_T(rot_z(math.radians(yaw_deg)), np.array([0.4, -0.1, 0.9]))
    corners = _box(0.12, 0.01, 0.03) @ T[:3, :3].T + T[:3, 3]
    u, half = blade_direction(corners, T)
    blade = T[:3, 0]
    assert abs(float(u @ blade)) == pytest.approx(1.0) and u[2] == 0.0
    assert half == pytest.approx(0.06)
    # a blade lying along the frame's y axis
    T2 = make_T(rot_z(math.radians(yaw_deg)), np.zeros(3))
    corners2 = _box(0.01, 0.12, 0.03) @ T2[:3, :3].T
    u2, half2 = blade_direction(corners2, T2)
    assert abs(float(u2 @ T2[:3, 1])) == pytest.approx(1.0) and half2 == pytest.approx(0.06)
