"""Grasp planning per grasp type (no simulation): where the hand goes for a handle and
for a pinch of a flat object's edge, decided by the grasp's type and offset alone."""

import numpy as np
import pytest

from oacdsl.model import Grasp
from oacdsl.runtime.grasping import FINGERTIP_AHEAD_M, FINGERTIP_BEHIND_M, PINCH_TILT_RAD, plan_grasps
from oacdsl.runtime.transforms import make_T, rot_axis

UP = np.array([0.0, 0.0, 1.0])


def pose(x, y, yaw_deg=0.0, z=0.80):
    return make_T(rot_axis(UP, np.radians(yaw_deg)), (x, y, z))


def grasp(kind, approach, offset):
    return Grasp(cls="Thing", type=kind, approach=approach, offset=offset)


@pytest.mark.parametrize("yaw_deg", [0.0, 90.0, -135.0])
def test_a_handle_off_the_axis_is_taken_from_outside_whichever_way_the_object_turns(yaw_deg):
    # a handle 7 cm out along the object's x, 10 cm up: it turns with the object
    t = pose(0.6, -0.2, yaw_deg)
    plans = plan_grasps(grasp("handle", "side", (0.07, 0.0, 0.10)), False, t, "r", support_z=0.80)
    out = t[:3, :3] @ np.array([1.0, 0.0, 0.0])
    handle = t[:3, 3] + t[:3, :3] @ np.array([0.07, 0.0, 0.10])
    first = plans[0]
    assert np.allclose(first.grasp[:3, 3], handle)  # the grasp centre on the bar
    assert np.allclose(first.approach, -out)  # towards the object's axis
    palm_normal = -first.grasp[:3, 0]
    assert np.allclose(palm_normal, -out)
    fingers = first.grasp[:3, 2]
    assert abs(fingers @ UP) < 1e-9 and abs(fingers @ out) < 1e-9  # across the vertical bar
    assert fingers[0] >= 0.0  # away from the robot when they can
    # the pre-grasp pose is outside the handle, on the line of approach
    assert np.allclose(first.pre_grasp[:3, 3], handle + 0.20 * out)
    # every variant keeps the centre on the bar and the palm horizontal
    for p in plans:
        assert np.allclose(p.grasp[:3, 3], handle) and abs(p.approach @ UP) < 1e-9


def test_a_handle_on_the_axis_is_taken_from_the_hands_own_side():
    t = pose(0.7, -0.3)
    for side, direction in (("r", 1.0), ("l", -1.0)):
        first = plan_grasps(grasp("handle", "side", (0.0, 0.0, 0.14)), False, t, side)[0]
        assert np.allclose(first.approach, (0.0, direction, 0.0))  # right hand from the right
        assert np.allclose(first.grasp[:3, 2], (1.0, 0.0, 0.0))  # fingers forward


def test_a_pinch_puts_the_fingertips_beside_the_edge_and_the_palm_over_the_top():
    # a plate 1.2 cm thick on a table at 0.80 m; the edge point 11 cm to its right
    t = pose(0.68, 0.02)
    plans = plan_grasps(grasp("pinch", "top", (0.0, -0.11, 0.012)), False, t, "r", support_z=0.80)
    first = plans[0]
    out = np.array([0.0, -1.0, 0.0])  # the right hand takes the edge on its side first
    fingers, palm_normal = first.grasp[:3, 2], -first.grasp[:3, 0]
    assert np.isclose(np.degrees(np.arccos(-fingers @ UP)), np.degrees(PINCH_TILT_RAD))
    assert fingers @ out > 0 and palm_normal @ out < 0 and palm_normal @ UP < 0
    tip = first.grasp[:3, 3] - FINGERTIP_BEHIND_M * palm_normal + FINGERTIP_AHEAD_M * fingers
    across = first.grasp[:3, 1]
    tip_mid = tip + 0.0075 * across
    edge = t[:3, 3] + 0.11 * out
    assert 0.0 < (tip_mid - edge) @ out < 0.01  # just outside the edge …
    assert 0.80 < tip_mid[2] < 0.812  # … below the plate's top
    assert np.allclose(first.approach, -UP)
    # the left hand takes the opposite edge first
    left = plan_grasps(grasp("pinch", "top", (0.0, -0.11, 0.012)), False, t, "l", support_z=0.80)[0]
    assert left.grasp[1, 3] > t[1, 3]
