"""Which turn back a hand taking a turned object again starts its next stroke from."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np

from oacdsl.runtime.motion import TUNING
from oacdsl.runtime.motion.rotate import _wound

STEP_RAD = 0.3


def _yaw(t: np.ndarray) -> float:
    return math.atan2(float(t[1, 0]), float(t[0, 0]))


def _wind(miss_m) -> float:
    """The share of the stroke the chosen start is turned back, the IK missing a pose turned
    ``yaw`` (rad) about the vertical by ``miss_m(yaw)``."""
    ik = SimpleNamespace(try_reach=lambda side, t: SimpleNamespace(position_m=miss_m(_yaw(t)), angle_rad=0.0))
    ctx = SimpleNamespace(ctl=SimpleNamespace(ik=ik))
    m = SimpleNamespace(side="l", tuning=TUNING)
    start = _wound(ctx, m, np.eye(4), np.array([0.0, 0.0, 1.0]), np.zeros(3), STEP_RAD)  # type: ignore[arg-type]
    return -_yaw(start) / STEP_RAD


def test_small_gains_of_each_quarter_add_up_to_a_full_wind_back() -> None:
    # each quarter turned back reaches the stroke's end 0.4 mm better, all of it 1.5 mm: less
    # than the tuning's gain per quarter, but the hand is wound back all the way
    assert TUNING.turn_wind_back_gain_m > 0.0015
    share = _wind(lambda yaw: 0.004 + 0.005 * yaw)
    assert math.isclose(share, 1.0, abs_tol=1e-6)


def test_no_wind_back_where_turning_back_reaches_worse() -> None:
    # the wrist cannot turn back: every pose turned back is missed by far more than the gain
    share = _wind(lambda yaw: 0.003 + (0.05 if yaw < -1e-6 else 0.0))
    assert math.isclose(share, 0.0, abs_tol=1e-6)


def test_the_furthest_turn_back_reaching_about_as_well_as_the_best() -> None:
    # the best is a quarter turned back; half is 1 mm worse (kept), three quarters 5 mm worse
    def miss(yaw: float) -> float:
        back = -yaw / STEP_RAD
        return 0.004 if back < 0.3 else 0.005 if back < 0.6 else 0.009
    share = _wind(lambda yaw: max(miss(yaw), 0.0))
    assert math.isclose(share, 0.5, abs_tol=1e-6)
