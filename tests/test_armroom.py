"""The room an arm posture leaves from the table and the objects (the IK sees neither)."""

import numpy as np
import pytest

pytest.importorskip("mujoco", reason="the robot runtime needs the 'robot' extra (mujoco)")
pytest.importorskip("placo", reason="the robot runtime needs the 'robot' extra (placo)")


@pytest.fixture(scope="module")
def run():  # type: ignore[no-untyped-def]
    from runtime_lib import task_library

    from oacdsl.runtime.executor import prepare

    return prepare(task_library(), "pick_and_place", scene="pouring")


def _table_top(run) -> float:  # type: ignore[no-untyped-def]
    from oacdsl.runtime.shapes import lowest_z

    name = next(p.name for p in run.world.layout.placements)
    return lowest_z(run.context.body(name), run.world.body_pose(name))


def test_reach_postures_follow_a_path_and_leave_the_ik_as_it_was(run):
    ik = run.controller.ik
    before = ik.snapshot()
    start = ik.frame("grasp_r")
    path = [start.copy() for _ in range(3)]
    for k, pose in enumerate(path):
        pose[2, 3] += 0.05 * (k + 1)
    out = ik.reach_postures("r", path)
    assert np.allclose(ik.snapshot(), before)
    assert [r.position_m < 0.01 for r, _ in out] == [True] * 3
    assert out[0][1]["shoulder_1_r"] != pytest.approx(out[2][1]["shoulder_1_r"], abs=1e-4)


def test_an_arm_reaching_below_the_table_top_has_no_room_and_one_above_it_has(run):
    from oacdsl.runtime.armroom import arm_room

    ik, world = run.controller.ik, run.world
    assert arm_room(world, "r", ik.joints()) > 0.02  # at home, over the table
    top = _table_top(run)
    low = ik.frame("grasp_r")
    low[:3, 3] = (0.65, -0.25, top - 0.06)  # the hand under the table top: the wrist goes in
    (res, posture), = ik.reach_postures("r", [low])
    assert res.position_m < 0.02
    assert arm_room(world, "r", posture) < 0.0
    high = low.copy()
    high[2, 3] = top + 0.3
    (_, posture), = ik.reach_postures("r", [high])
    assert arm_room(world, "r", posture) > 0.0
    assert arm_room(world, "l", posture) > 0.02  # the other arm, at home, is not in the table


def test_reach_postures_at_a_motions_pace_lag_a_far_target(run):
    """One solver step per target (a control tick) leaves a target 20 cm away further off than
    a static solve does: the IK's joint speed limits (how far it keeps up with a fast motion)."""
    ik = run.controller.ik
    far = ik.frame("grasp_r")
    far[2, 3] += 0.2
    (_, _), (paced, _) = ik.reach_postures("r", [ik.frame("grasp_r"), far], [150, 1])
    (_, _), (settled, _) = ik.reach_postures("r", [ik.frame("grasp_r"), far])
    assert paced.position_m > 0.1 > 0.01 > settled.position_m
