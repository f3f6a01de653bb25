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


def _hand_lowest_z(side, t_world_grasp):
    """World height (m) of the lowest corner of the open hand's collision boxes."""
    from oacdsl.runtime.handgap import hand_box_poses
    from oacdsl.runtime.hands import OPEN

    signs = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], dtype=float)
    return min(
        float((t[:3, 3] + (signs * half) @ t[:3, :3].T)[:, 2].min())
        for t, half in hand_box_poses(side, t_world_grasp, OPEN)
    )


@pytest.mark.parametrize("height_m", [0.045, 0.08, 0.12])
@pytest.mark.parametrize("symmetric", [False, True])
def test_a_side_grasp_keeps_the_hand_out_of_the_closed_loops_reach_of_the_support(height_m, symmetric):
    """An object held sideways on a board (KIT Cut, Peel: the other hand works on it) is seen
    touching the board when the hand's lowest point is within the closed loop's 15 mm of it.
    The grasp point a new user writes (mid-height, or low on a cup) must not bring it there:
    before issue 11's fix the hand was kept 12 mm above the support."""
    from oacdsl.pipeline.markers import ROBOT_DISTANCE_M

    board_z = 0.815  # a 1.5 cm board on a table 0.80 m up
    t = pose(0.6, 0.15, 20.0, z=board_z)
    offset = (0.0, 0.0, height_m / 2) if symmetric else (-0.06, 0.0, height_m / 2)
    for side in ("r", "l"):
        plans = plan_grasps(
            grasp("power", "side", offset), symmetric, t, side, support_z=board_z, top_z=board_z + height_m
        )
        for p in plans:
            lowest = _hand_lowest_z(side, p.grasp)
            assert lowest - board_z > ROBOT_DISTANCE_M + 0.004  # 4 mm margin (the arm's tracking)
            assert board_z + height_m - lowest >= 0.025 - 1e-9  # the hand still grips 2.5 cm of it


def test_a_low_object_is_still_gripped_with_less_room_under_the_hand():
    """A 3 cm object: keeping 2 cm under the hand would leave it 1 cm to hold; the hand goes
    lower (never below the 12 mm kept before), and a grasp point high on an object is kept."""
    from oacdsl.runtime.grasping import CLEARANCE_M, MIN_CLEARANCE_M, side_clearance

    assert side_clearance(0.03) == pytest.approx(MIN_CLEARANCE_M)
    assert side_clearance(0.04) == pytest.approx(0.015)
    assert side_clearance(0.2) == side_clearance(None) == CLEARANCE_M
    t = pose(0.6, -0.2, z=0.80)
    low = plan_grasps(grasp("power", "side", (0.0, 0.0, 0.015)), False, t, "r", support_z=0.80, top_z=0.83)[0]
    assert _hand_lowest_z("r", low.grasp) - 0.80 == pytest.approx(MIN_CLEARANCE_M, abs=2e-3)
    high = plan_grasps(grasp("power", "side", (0.0, 0.0, 0.14)), False, t, "r", support_z=0.80, top_z=0.99)[0]
    assert high.grasp[2, 3] == pytest.approx(0.94)
