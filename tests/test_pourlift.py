"""A pour's lip is lifted without jerking the liquid (`runtime/pourlift.py`, no simulator)."""

from __future__ import annotations

import numpy as np

from oacdsl.runtime.motion import TUNING
from oacdsl.runtime.pourlift import follow_lift, ramped_lift

DT_S = 0.02  # the tilt's steps at the demonstrated pace (125 deg in 0.8 s, 40 steps)


def test_a_lift_needed_within_one_step_is_ramped_up_before_it_and_down_after_it() -> None:
    # the dough's seed 3: the pouring hand's boxes reached the bowl's rim and asked for 2.3 cm at once
    at_s = np.arange(41) * DT_S
    asked = np.where((at_s > 0.29) & (at_s < 0.41), 0.023, 0.0)
    lift = ramped_lift(asked, at_s, 0.1)
    assert np.all(lift >= asked - 1e-12)  # never lower than needed
    assert np.abs(np.diff(lift)).max() <= 0.1 * DT_S + 1e-12  # 2 mm a step, not 23
    first = int(np.argmax(asked > 0))
    assert lift[first - 5] > 0.0  # begun before the step that needs it
    assert lift[-1] == 0.0 and lift[0] == 0.0  # the lip comes back down where nothing is in the way


def test_a_smooth_lift_is_left_as_it_is() -> None:
    at_s = np.arange(41) * DT_S
    asked = 0.01 + 0.05 * at_s  # rising at 5 cm/s
    assert np.allclose(ramped_lift(asked, at_s, 0.1), asked)


def test_the_lags_lift_no_longer_feeds_itself() -> None:
    # the lag is measured against the lifted goal: an arm that follows its goal a tick late and
    # 15 % of the way each tick (a time constant of about 0.12 s) lags by nearly as much as the
    # goal just rose, and that lag asks for as much more lift
    def highest_lift(speed_m_s: float) -> float:
        goals, hand, lift, highest = [0.0, 0.0], 0.0, 0.0, 0.0
        for k in range(40):
            lag = hand - goals[-1]
            want = max(0.0, 0.015 - lag) if k >= 10 else 0.0  # the rim needs 1.5 cm once tilted
            lift = follow_lift(lift, want, DT_S, speed_m_s)
            goals.append(lift)
            hand += 0.15 * (goals[-2] - hand)
            highest = max(highest, lift)
        return highest

    assert highest_lift(np.inf) > 0.05  # unbounded, 3.6 times what the rim needs
    assert highest_lift(TUNING.pour_lift_speed_m_s) < 0.03


def test_follow_lift_moves_at_most_its_speed() -> None:
    assert follow_lift(0.0, 0.05, DT_S, 0.1) == 0.1 * DT_S
    assert follow_lift(0.05, 0.0, DT_S, 0.1) == 0.05 - 0.1 * DT_S
    assert follow_lift(0.01, 0.011, DT_S, 0.1) == 0.011
