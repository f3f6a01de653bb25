"""`mix` lowers its tool beside the balls lying in the container, not onto one (no simulator)."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np

from oacdsl.runtime.motion import TUNING
from oacdsl.runtime.skills.mix import floor_spot

BOWL_INNER_M, WHISK_M, BALL_M = 0.108, 0.036, 0.009


def ctx_with(balls_xy: list[tuple[float, float]]) -> SimpleNamespace:
    pose = np.eye(4)
    pose[:3, 3] = (0.6, 0.0, 0.8)
    pts = np.array([[x, y, 0.817] for x, y in balls_xy]).reshape(-1, 3)
    world = SimpleNamespace(
        body_pose=lambda _name: pose,
        ball_positions=lambda _liq: pts,
        layout=SimpleNamespace(bodies={"liquid": SimpleNamespace(ball_radius=BALL_M)}),
        built=SimpleNamespace(balls={"liquid": ("liquid/ball0",)}),
    )
    return SimpleNamespace(world=world, body=lambda _name: SimpleNamespace(inner_radius=BOWL_INNER_M))


def test_the_middle_when_it_is_free() -> None:
    ring = [(0.6 + 0.095 * np.cos(a), 0.095 * np.sin(a)) for a in np.linspace(0, 6, 12)]
    assert np.allclose(floor_spot(ctx_with(ring), "bowl", WHISK_M), (0.6, 0.0))


def test_beside_a_ball_lying_in_the_middle() -> None:
    # the dough, seed 2: a ball slid from the wall to 2.9 cm from the middle; the mixer came
    # down on it and touched it 0.3 s before the bowl
    balls = [(0.6 + 0.01, 0.029)]
    xy = floor_spot(ctx_with(balls), "bowl", WHISK_M)
    assert np.hypot(xy[0] - 0.61, xy[1] - 0.029) >= WHISK_M + BALL_M + TUNING.wall_margin_m
    assert np.hypot(xy[0] - 0.6, xy[1]) <= BOWL_INNER_M - WHISK_M - TUNING.wall_margin_m + 1e-9


def test_the_middle_when_no_spot_is_free() -> None:
    full = [(0.6 + x, y) for x in np.arange(-0.1, 0.11, 0.02) for y in np.arange(-0.1, 0.11, 0.02)]
    assert np.allclose(floor_spot(ctx_with(full), "bowl", WHISK_M), (0.6, 0.0))
