"""Two hands carrying at once (``place_both``): each way is planned as if the other's object
were gone (it leaves), so nothing but :func:`~oacdsl.runtime.motion.detour.lockstep_gap`
checks how the two pass each other. Boxes only, no simulation."""

from __future__ import annotations

import numpy as np
import pytest

from oacdsl.runtime.motion import TUNING
from oacdsl.runtime.motion.both import aligned
from oacdsl.runtime.motion.detour import Box, first_to_carry, gap, lockstep_gap, way_gap


def _pose(x: float, y: float, z: float) -> np.ndarray:
    t = np.eye(4)
    t[:3, 3] = (x, y, z)
    return t


def _carried(x: float, y: float, z: float) -> list[Box]:
    """A hand at (x, y, z) (its boxes 10 cm across) and a carton 7 cm across hanging below it."""
    return [(np.array([x - 0.05, y - 0.05, z - 0.05]), np.array([x + 0.05, y + 0.05, z + 0.05])),
            (np.array([x - 0.035, y - 0.035, z - 0.20]), np.array([x + 0.035, y + 0.035, z - 0.04]))]


def _way(now: np.ndarray, goal: np.ndarray, over_z: float) -> list[tuple[np.ndarray, float]]:
    """A carry's way as ``paths.direct_path`` makes it: a climb, over the middle, down to the goal."""
    up, via = now.copy(), now.copy()
    up[2, 3] = via[2, 3] = over_z
    via[:2, 3] = 0.5 * (now[:2, 3] + goal[:2, 3])
    return [(up, 0.3), (via, 1.0), (goal, 1.0)]


#: The two hands side by side in front of the robot after a pour (right hand: y < 0), each
#: object going to a place on the other's side (a rotated take's set-down places).
RIGHT, LEFT = _pose(0.55, -0.09, 1.00), _pose(0.55, 0.09, 1.00)


def test_two_ways_each_clear_alone_cross_when_carried_at_once() -> None:
    moving = [_carried(0.55, -0.09, 1.00), _carried(0.55, 0.09, 1.00)]
    ways = [_way(RIGHT, _pose(0.45, 0.25, 0.98), 1.05), _way(LEFT, _pose(0.65, -0.25, 0.98), 1.05)]
    start = gap(moving[0], moving[1], np.zeros(3))
    assert start == pytest.approx(0.08)
    # at the same instant each hand is the same fraction along its phase: half way, both hands
    # and cartons are in the same place
    assert lockstep_gap(moving, [RIGHT, LEFT], ways) < -0.05
    # ... which no check of one way at a time sees: against the other where it is now, the
    # right hand's way goes right through the left hand (that is why each leaves the other out)
    pts = [RIGHT[:3, 3]] + [p[:3, 3] for p, _ in ways[0]]
    assert way_gap(moving[0], moving[1], RIGHT[:3, 3], pts) < 0
    assert first_to_carry(moving, [RIGHT, LEFT], ways) is not None


def test_ways_that_part_are_carried_together() -> None:
    moving = [_carried(0.55, -0.09, 1.00), _carried(0.55, 0.09, 1.00)]
    ways = [_way(RIGHT, _pose(0.50, -0.30, 0.98), 1.05), _way(LEFT, _pose(0.50, 0.30, 0.98), 1.05)]
    assert lockstep_gap(moving, [RIGHT, LEFT], ways) == pytest.approx(0.08)  # the start's gap
    assert first_to_carry(moving, [RIGHT, LEFT], ways) is None


def test_the_hand_whose_way_clears_the_other_standing_still_goes_first() -> None:
    # the left object goes far out to the right, in front of the right hand; the right one goes
    # just behind where it is: carried at once they meet; the right hand, moving alone, keeps clear
    moving = [_carried(0.55, -0.09, 1.00), _carried(0.55, 0.09, 1.00)]
    ways = [_way(RIGHT, _pose(0.40, -0.09, 0.98), 1.05), _way(LEFT, _pose(0.75, -0.20, 0.98), 1.05)]
    assert lockstep_gap(moving, [RIGHT, LEFT], ways) < TUNING.over_m
    assert first_to_carry(moving, [RIGHT, LEFT], ways) == 0
    assert first_to_carry(moving[::-1], [LEFT, RIGHT], ways[::-1]) == 1


def test_a_shorter_way_waits_at_its_end() -> None:
    a = [(_pose(0, 0, 1), 0.3), (_pose(0.1, 0, 1), 1.0), (_pose(0.2, 0, 1), 1.0)]
    b = [*a, (_pose(0.3, 0, 1), 0.5)]
    out = aligned({"r": a, "l": b})
    assert len(out["r"]) == len(out["l"]) == 4
    assert out["r"][-1][1] == 0.0 and np.allclose(out["r"][-1][0], a[-1][0])
    assert out["l"] == b
    # the gap of ways of unequal length: the first hand waits at its end while the second goes on
    moving = [_carried(0.0, 0.0, 1.0), _carried(0.0, 0.5, 1.0)]
    far = [(_pose(0, 0.5, 1), 1.0), (_pose(0, 0.25, 1), 1.0)]  # the second comes to the first's end
    near = [(_pose(0, 0.12, 1), 1.0)]
    assert lockstep_gap(moving, [_pose(0, 0, 1), _pose(0, 0.5, 1)], [near, far]) == pytest.approx(0.03)
