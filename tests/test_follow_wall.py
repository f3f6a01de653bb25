"""``follow`` in a container it is to touch (``runtime/skills/follow_wall.py``, ``retarget(inside=…)``):
the core's turns shrink with its positions, and a core that does not touch the container is
pushed out, circle by circle, to the wall, never through it. Fast: numpy and stand-ins, no
simulator (the robot runs: ``tests/test_kit_follow.py``, Stir)."""

from __future__ import annotations

import importlib
import math
from types import SimpleNamespace

import numpy as np
import pytest

from oacdsl.runtime.motion import TUNING
from oacdsl.runtime.retarget import retarget
from oacdsl.runtime.transforms import make_T
from oacdsl.segmentation.followpath import from_rotvec, rotvec

wall_module = importlib.import_module("oacdsl.runtime.skills.follow_wall")


def _stir_path(radius_m: float = 0.016, rock_deg: float = 8.0, cycles: int = 4,
               period_s: float = 0.5) -> np.ndarray:
    """A spoon's reference point circling ``radius_m`` round a point 3 cm off the axis, rocking
    ``rock_deg`` about a horizontal axis in phase with the circles (10 Hz keyframes)."""
    t = np.arange(0.0, cycles * period_s + 1e-9, 0.1)
    a = 2 * math.pi * t / period_s
    rows = []
    for tk, ak in zip(t, a, strict=True):
        rot = from_rotvec(math.radians(20.0 + rock_deg * math.sin(ak)) * np.array([0.0, 1.0, 0.0]))
        rows.append([tk, 0.03 + radius_m * math.cos(ak), radius_m * math.sin(ak), 0.15, *rotvec(rot)])
    return np.array(rows)


def test_in_a_container_the_cores_turns_shrink_with_its_positions() -> None:
    path = _stir_path()
    free = retarget(path, room_m=0.01, speed_m_s=0.25, turn_rad=math.radians(30), stay=True)
    inside = retarget(path, room_m=0.01, speed_m_s=0.25, turn_rad=math.radians(30), stay=True, inside=True)
    assert free.scale == pytest.approx(inside.scale) and inside.scale < 0.7  # 16 mm circles, 1 cm room
    assert free.turn_scale == 1.0  # the positions alone were scaled: the rocking kept whole
    assert inside.turn_scale == pytest.approx(inside.scale)

    def rock(r) -> float:  # type: ignore[no-untyped-def]
        return max(float(np.linalg.norm(rotvec(m))) for m in r.rotations[r.core:])

    assert rock(inside) == pytest.approx(inside.scale * rock(free), rel=1e-6)
    # without ``inside`` (a solid target, a twist): as before
    assert np.allclose(free.positions_m, inside.positions_m)


def _seek(monkeypatch: pytest.MonkeyPatch, touching: bool, core: list[np.ndarray]):  # type: ignore[no-untyped-def]
    """A :class:`WallSeek` in a cup 4 cm inside (its axis the world's z through the origin) for
    an object 2.5 cm wide whose lowest end is its origin; the hand at +x."""
    monkeypatch.setattr(wall_module, "lowest_end", lambda body, t: t[:3, 3].copy())
    world = SimpleNamespace(body_pose=lambda name: np.eye(4), touching=lambda a, b: touching,
                            frame_pose=lambda name: make_T(np.eye(3), np.array([0.2, 0.0, 0.3])))
    bodies = {"spoon": SimpleNamespace(radius=0.025), "cup": SimpleNamespace(radius=0.045, inner_radius=0.04)}
    ctx = SimpleNamespace(world=world, body=lambda name: bodies[name])
    return wall_module.WallSeek(ctx, "r", "spoon", "cup", core)


def _circle(centre_xy: tuple[float, float], radius_m: float, n: int = 12) -> list[np.ndarray]:
    x, y = centre_xy
    return [make_T(np.eye(3), np.array([x + radius_m * math.cos(a), y + radius_m * math.sin(a), 0.05]))
            for a in np.linspace(0, 2 * math.pi, n, endpoint=False)]


def test_a_core_that_does_not_touch_the_container_is_pushed_to_the_wall_and_no_further(monkeypatch) -> None:
    core = _circle((0.006, 0.0), 0.005)  # a small circle off the middle, touching nothing
    seek = _seek(monkeypatch, touching=False, core=core)
    reach = 0.04 - 0.025 + TUNING.aim_beyond_m
    assert seek.reach_m == pytest.approx(reach)
    assert all(np.allclose(seek.offset(p), 0.0) for p in core)  # nothing found yet: as planned
    for _ in range(100):  # 2 s at the seek speed: far more than the wall is away
        seek.grow(0.02)
    assert seek.out_m == pytest.approx(reach)  # never more than the wall allows
    pushed = [p[:3, 3] + seek.offset(p) for p in core]
    radii = [float(np.hypot(q[0], q[1])) for q in pushed]
    assert max(radii) <= reach + 1e-9  # at the wall, never through it
    assert min(radii) >= 0.8 * reach  # the whole circle along the wall, not an arc on one side
    angles = np.unwrap([math.atan2(q[1], q[0]) for q in pushed])
    assert abs(angles[-1] - angles[0]) > 1.5 * math.pi  # it still goes round the axis
    assert all(abs(q[2] - 0.05) < 1e-12 for q in pushed)  # across the axis only


def test_a_core_that_touches_the_container_is_not_pushed(monkeypatch) -> None:
    core = _circle((0.0, 0.0), 0.005)
    seek = _seek(monkeypatch, touching=True, core=core)
    for _ in range(50):
        seek.grow(0.02)
    assert seek.out_m == 0.0 and all(np.allclose(seek.offset(p), 0.0) for p in core)
