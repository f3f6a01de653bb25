"""The press regulated on the wrist's force (motion/press.py), on a model of an arm pressing a tool
on a rigid surface: the arm is a spring (``STIFF_N_PER_M``) between its goal and where the surface
stops the tool, and it floats off its goal by an amount that changes along the way (as a real
arm's lag does along a circle)."""

from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

from oacdsl.runtime.control import CONTROL_DT_S
from oacdsl.runtime.motion.press import ForcePress
from oacdsl.runtime.motion.tuning import TUNING

FREE_FZ_N = 17.8  # the wrist's vertical force with the tool free (its weight)
STIFF_N_PER_M = 10_000.0  # 10 N per mm the goal is below where the surface stops the tool
PERIOD_S = 1.2


class Arm:
    """Goal → contact force; ``float_m(t)``: how far above its goal the arm holds the tool."""

    def __init__(self, float_m, surface_m: float | None = 0.0) -> None:
        self.float_m, self.surface_m, self.t, self.goal_m = float_m, surface_m, 0.0, 0.0
        self.world = SimpleNamespace(wrist_force=self.wrist_force)

    def contact_n(self) -> float:
        if self.surface_m is None:
            return 0.0
        return STIFF_N_PER_M * max(0.0, self.surface_m - (self.goal_m + self.float_m(self.t)))

    def wrist_force(self, _side: str) -> np.ndarray:
        return np.array([0.0, 0.0, FREE_FZ_N - self.contact_n()])


def run(arm: Arm, press: ForcePress | None, seconds: float, fixed_depth_m: float = 0.0) -> list[float]:
    """The contact force at each tick of ``seconds`` of a path along the surface (its z 0)."""
    path = press.lowered(lambda _s: np.eye(4)) if press is not None else (lambda _s: np.eye(4))
    forces = []
    for k in range(round(seconds / CONTROL_DT_S)):
        arm.goal_m = float(path(k / 100)[2, 3]) - (fixed_depth_m if press is None else 0.0)
        arm.t += CONTROL_DT_S
        forces.append(arm.contact_n())
    return forces


def longest_loss_s(forces: list[float]) -> float:
    longest = run_ = 0
    for f in forces:
        run_ = run_ + 1 if f <= 0.0 else 0
        longest = max(longest, run_)
    return longest * CONTROL_DT_S


def wavy(t: float) -> float:
    """2 mm above the goal, ±1.5 mm along a circle (the mixer's arm on a bowl's floor)."""
    return 0.002 + 0.0015 * math.sin(2 * math.pi * t / PERIOD_S)


def test_the_press_settles_at_the_wanted_force_on_a_steady_arm():
    arm = Arm(lambda _t: 0.002)
    press = ForcePress(arm, "r", FREE_FZ_N)
    forces = run(arm, press, 3.0)
    assert np.mean(forces[-50:]) == pytest.approx(TUNING.press_force_n, rel=0.05)
    assert press.depth_m == pytest.approx(0.002 + TUNING.press_force_n / STIFF_N_PER_M, abs=2e-4)


def test_the_press_keeps_a_contact_that_a_fixed_depth_loses():
    fixed = run(Arm(wavy), None, 4 * PERIOD_S, fixed_depth_m=TUNING.press_m)
    assert longest_loss_s(fixed) >= 0.1  # the arm floats off the surface for part of each circle
    arm = Arm(wavy)
    press = ForcePress(arm, "r", FREE_FZ_N)
    press.depth_m = TUNING.press_m
    regulated = run(arm, press, 4 * PERIOD_S)
    assert longest_loss_s(regulated[round(PERIOD_S / CONTROL_DT_S):]) < 0.1
    assert max(regulated) < 4 * TUNING.press_force_n


def test_the_press_goes_no_deeper_nor_higher_than_its_bounds():
    arm = Arm(lambda _t: 0.0, surface_m=None)  # nothing under the tool
    press = ForcePress(arm, "r", FREE_FZ_N)
    run(arm, press, 3.0)
    assert press.depth_m == pytest.approx(TUNING.press_depth_max_m)
    arm = Arm(lambda _t: 0.0, surface_m=0.02)  # the surface far above the path: pressed hard
    press = ForcePress(arm, "r", FREE_FZ_N)
    run(arm, press, 30.0)
    assert press.depth_m == pytest.approx(-TUNING.press_rise_max_m)
