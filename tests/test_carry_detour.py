"""A carry keeps clear of what the other hand holds up above its way (``runtime/motion/detour.py``):
boxes only, no simulation. KIT Cut with ``follow``, seed 1: the cucumber carried to its place
from under the knife the right hand holds up (docs/runtime.md, "follow")."""

from __future__ import annotations

import numpy as np
import pytest

from oacdsl.runtime.motion import TUNING
from oacdsl.runtime.motion.detour import gap, out_from_under, way_gap


def _box(lo: tuple[float, float, float], hi: tuple[float, float, float]) -> tuple[np.ndarray, np.ndarray]:
    return np.array(lo), np.array(hi)


#: The carrying hand at (0, 0, 0.95) and the cucumber below it, reaching 14 cm along x.
MOVING = [_box((-0.05, -0.05, 0.90), (0.05, 0.05, 1.00)), _box((-0.02, -0.03, 0.86), (0.14, 0.03, 0.91))]
#: A knife held up by its handle 2 cm beyond the hand's reach along x, its blade's lowest edge
#: below the hand's top, and the hand holding it above.
KNIFE = [_box((0.07, -0.02, 0.97), (0.19, 0.02, 1.14)), _box((0.05, -0.08, 1.01), (0.21, 0.08, 1.12))]


def _pose(x: float, y: float, z: float) -> np.ndarray:
    t = np.eye(4)
    t[:3, 3] = (x, y, z)
    return t


def _straight(goal: np.ndarray):  # type: ignore[no-untyped-def]
    return lambda start: [(goal, 1.0)]


def test_gap_is_the_distance_between_boxes_or_how_deep_they_overlap() -> None:
    a, b = [_box((0, 0, 0), (1, 1, 1))], [_box((1.5, 0, 0), (2, 1, 1))]
    assert gap(a, b, np.zeros(3)) == pytest.approx(0.5)
    assert gap(a, b, np.array([0.3, 0.0, 0.0])) == pytest.approx(0.2)
    assert gap(a, b, np.array([0.6, 0.0, 2.0])) == pytest.approx(1.0)  # above: only z counts
    assert gap(a, b, np.array([0.7, 0.0, 0.0])) == pytest.approx(-0.2)


def test_a_carry_that_would_pass_under_what_the_other_hand_holds_goes_round_it_first() -> None:
    now, goal = _pose(0.0, 0.0, 0.95), _pose(0.30, 0.15, 0.93)
    straight = [(goal, 1.0)]
    start_gap = gap(MOVING, KNIFE, np.zeros(3))
    assert 0 < start_gap < TUNING.over_m
    assert way_gap(MOVING, KNIFE, now[:3, 3], [now[:3, 3], goal[:3, 3]]) < 0  # under the knife
    way = out_from_under(MOVING, KNIFE, now, straight, _straight(goal))
    assert len(way) == 2 and np.allclose(way[-1][0], goal)
    out = way[0][0][:3, 3]
    assert out[2] == pytest.approx(0.95)  # at the hand's height: no climb into the blade
    assert min(abs(float(np.linalg.norm(out[:2])) - d) for d in TUNING.detour_steps_m) < 1e-9
    assert out[1] > 0  # round the knife's side towards the goal, not back under the other hand
    points = [now[:3, 3], out, goal[:3, 3]]
    assert way_gap(MOVING, KNIFE, now[:3, 3], points) >= start_gap - 1e-9
    assert way[0][1] >= TUNING.settle_s


def test_a_way_clear_of_it_or_with_no_way_round_is_kept() -> None:
    now = _pose(0.0, 0.0, 0.95)
    away = [(_pose(-0.3, -0.1, 0.95), 1.0)]  # away from the knife
    assert out_from_under(MOVING, KNIFE, now, away, _straight(away[0][0])) is away
    walled = [_box((-1.0, -1.0, 0.97), (1.0, 1.0, 1.2))]  # a ceiling everywhere just above the hand
    goal = _pose(0.3, 0.15, 1.1)
    way = [(goal, 1.0)]
    assert out_from_under(MOVING, walled, now, way, _straight(goal)) is way
