"""``stir`` and ``mix`` cut a circle into waypoints the arm can follow: each waypoint is one
min-jerk move of at least two control ticks (``Tuning.waypoint_min_s``), so a fast circle is cut
into fewer waypoints (24 waypoints of a 0.5 s circle would be single-tick jumps). Fast: the skills
are run against a recording stand-in of the motion layer, no simulator."""

from __future__ import annotations

import importlib
from types import SimpleNamespace
from typing import Any

import numpy as np
import pytest

from oacdsl.runtime.control import CONTROL_DT_S
from oacdsl.runtime.motion import TUNING


class _Recorder:
    """Stands in for :class:`~oacdsl.runtime.motion.Motion`: every ``go`` is recorded, every
    guard is met at once (the tool touches the container)."""

    def __init__(self, ctx: Any, side: str, *_: Any) -> None:
        self.ctx, self.side, self.moves = ctx, side, []
        ctx.moves = self.moves

    def go(self, goal: np.ndarray, seconds: float, *_: Any, **__: Any) -> bool:
        self.moves.append((goal[:3, 3].copy(), float(seconds)))
        return True

    def pressing(self, *_: Any) -> SimpleNamespace:
        return SimpleNamespace(depth_m=0.0)

    def here(self) -> np.ndarray:
        return np.eye(4)

    def carry(self, *_: Any, **__: Any) -> None:
        pass

    def approach(self, *_: Any, **__: Any) -> bool:
        return True

    def hold_still(self, *_: Any, **__: Any) -> bool:
        return True

    def touching(self, *_: Any) -> object:
        return object()

    contact_or_force = touching


def _ctx(container: SimpleNamespace) -> SimpleNamespace:
    world = SimpleNamespace(body_pose=lambda name: np.eye(4), touching=lambda a, b: True,
                            frame_pose=lambda name: np.eye(4), built=SimpleNamespace(balls={}))
    return SimpleNamespace(world=world, ctl=SimpleNamespace(activity=""), require_held=lambda h, o: "r",
                           held_pose=lambda side, obj: (np.eye(4), np.eye(4)), body=lambda name: container,
                           check_reachable=lambda *a: None)


def _circling(moves: list[tuple[np.ndarray, float]], period: float, turns: int) -> list[float]:
    """The durations of the moves that make the circles: the last ``turns`` periods' worth."""
    durations = [d for _, d in moves]
    total, out = 0.0, []
    for d in reversed(durations):
        if total >= turns * period - 1e-9:
            break
        out.append(d)
        total += d
    return out


@pytest.mark.parametrize("period", [0.3, 0.5, 0.7, 1.2])
def test_mix_cuts_a_fast_circle_into_waypoints_of_two_ticks_at_least(monkeypatch, period: float) -> None:
    mix = importlib.import_module("oacdsl.runtime.skills.mix")

    monkeypatch.setattr(mix, "Motion", _Recorder)
    bowl = SimpleNamespace(height=0.1, floor=0.01, radius=0.04, inner_radius=0.11)
    ctx = _ctx(bowl)
    mix.mix(ctx, "right_hand", "mixer", "bowl", radius=0.03, turns=2, period=period, force=10.0)
    circling = _circling(ctx.moves[:-1], period, 2)  # the last move goes back to the middle
    assert sum(circling) == pytest.approx(2 * period)
    assert min(circling) >= TUNING.waypoint_min_s - 1e-12 >= 2 * CONTROL_DT_S - 1e-12, (period, circling)
    if period >= mix.CIRCLE_POINTS * TUNING.waypoint_min_s:
        assert len(circling) == 2 * mix.CIRCLE_POINTS  # a slow circle as before


@pytest.mark.parametrize("period", [0.3, 0.5, 1.2])
def test_stir_cuts_a_fast_circle_into_waypoints_of_two_ticks_at_least(monkeypatch, period: float) -> None:
    stir = importlib.import_module("oacdsl.runtime.skills.stir")

    from oacdsl.runtime.transforms import make_T

    tool = SimpleNamespace(half_width=0.01, hand_for=make_T, tip_world=lambda: np.array([0.0, 0.0, 0.02]))
    monkeypatch.setattr(stir, "Motion", _Recorder)
    monkeypatch.setattr(stir, "held_tool", lambda *a: tool)
    monkeypatch.setattr(stir, "hand_reach_below", lambda *a: -1.0)  # the hand never near the rim
    up, toward = np.array([0.0, 0.0, 1.0]), np.array([1.0, 0.0, 0.0])
    monkeypatch.setattr(stir, "dip_poses", lambda *a: (tool, np.eye(3), np.zeros(3), up, toward, np.eye(4)))
    cup = SimpleNamespace(container=True, inner_radius=0.04, rim_height=0.1, floor=0.0)
    ctx = _ctx(cup)
    stir.stir(ctx, "right_hand", "spoon", "cup", radius=0.02, period=period, turns=3, tilt=0.2, depth=0.02,
              force=10.0)
    circling = _circling(ctx.moves, period, 3)
    assert sum(circling) == pytest.approx(3 * period)
    assert min(circling) >= TUNING.waypoint_min_s - 1e-12, (period, circling)
    if period >= stir.CIRCLE_POINTS * TUNING.waypoint_min_s:
        assert len(circling) == 3 * stir.CIRCLE_POINTS
