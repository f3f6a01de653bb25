"""Whole-body IK with placo: reaching, soft tasks, self-collision avoidance, clean errors."""

import numpy as np
import pytest

placo = pytest.importorskip("placo", reason="the robot runtime needs the 'robot' extra (placo)")
pytest.importorskip("mujoco", reason="the robot runtime needs the 'robot' extra (mujoco)")

from oacdsl.errors import RuntimeFailure  # noqa: E402
from oacdsl.runtime.ik import BASE_LIMITS, IKError, WholeBodyIK  # noqa: E402
from oacdsl.runtime.transforms import make_T  # noqa: E402

SIDE_GRASP_R = np.column_stack([[0, -1, 0], [0, 0, -1], [1, 0, 0]])  # palm facing +y, fingers forward


def test_reaches_a_cup_on_the_table_with_base_torso_and_arm():
    ik = WholeBodyIK()
    target = make_T(SIDE_GRASP_R, (0.56, -0.28, 0.88))
    ik.set_hand_target("r", target)
    res = ik.converge(300)
    assert res.position_m < 0.005 and res.angle_rad < 0.02
    q = ik.joints()
    for name, (lo, hi) in BASE_LIMITS.items():
        assert lo - 1e-6 <= q[name] <= hi + 1e-6


def test_an_unreachable_target_is_approached_softly_and_try_reach_restores_the_state():
    ik = WholeBodyIK()
    before = ik.snapshot()
    res = ik.try_reach("r", make_T(SIDE_GRASP_R, (1.6, -0.3, 0.9)))
    assert res.position_m > 0.2  # as close as possible, no exception
    assert np.allclose(ik.snapshot(), before)


def test_self_collision_keeps_the_hand_out_of_the_torso():
    # a hand pose just in front of the chest: without avoidance the hand's pinky edge goes
    # into the torso, with it the hand keeps the 1 cm margin
    target = make_T(np.eye(3), (0.28, 0.0, 1.1))

    def closest(self_collision):
        ik = WholeBodyIK(self_collision=self_collision)
        ik.set_hand_target("r", target)
        ik.converge(400)
        if not self_collision:  # measure with the same pairs as the avoiding solver
            probe = WholeBodyIK()
            probe.set_state(ik.joints())
            ik = probe
        return min(d.min_distance for d in ik.robot.distances())

    assert closest(True) > 0.005
    assert closest(False) < 0.0


def test_an_infeasible_problem_raises_a_runtime_failure_naming_the_frame():
    ik = WholeBodyIK(self_collision=False)
    hard = ik.solver.add_frame_task("tcp_r", make_T(np.eye(3), (3.0, 0.0, 1.0)))
    hard.configure("impossible", "hard", 1.0, 1.0)
    with pytest.raises(IKError) as info:
        ik.step()
    assert isinstance(info.value, RuntimeFailure) and "whole-body IK failed" in str(info.value)
    assert info.value.frame.startswith("grasp_")


def test_travel_s_is_the_slowest_joints_time_at_its_speed_limit_summed_over_the_legs():
    """The least time through postures: per leg, the joint that needs longest at its speed limit
    (the forearm's roll 1.5 rad/s, the torso 0.8 rad/s); the legs one after the other."""
    from oacdsl.runtime.ik import VELOCITY_LIMITS

    limit = {n: v for names, v in VELOCITY_LIMITS for n in names}
    ik = WholeBodyIK()
    start = ik.joints()
    arm = next(n for n in start if n.startswith("underarm"))
    hip = next(n for n in start if n.startswith("hip"))
    turned = {**start, arm: start[arm] + 2.8}
    bent = {**turned, hip: start[hip] + 0.4}
    assert ik.travel_s([start]) == 0.0
    assert ik.travel_s([start, turned]) == pytest.approx(2.8 / limit[arm])
    assert ik.travel_s([start, turned, bent]) == pytest.approx(2.8 / limit[arm] + 0.4 / limit[hip])
    assert ik.travel_s([start, bent]) == pytest.approx(max(2.8 / limit[arm], 0.4 / limit[hip]))
