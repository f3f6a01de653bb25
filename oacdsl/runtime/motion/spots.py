"""Where to set a held object down on the table when it may not go back where it came from.

A lid taken off a bottle may not go back onto the bottle: it goes to a *free spot* of the
table, a point where objects may stand (the layout's region) whose footprint keeps ``gap_m`` from every
object's footprint now (those on the table, and what the other hand holds above it),
nearest to where the object is now (the hand's way is short), on the hand's own side
first. Candidates are a grid over the working area; the caller checks reach.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from oacdsl.runtime.layout import STAND_X_RANGE_M, STAND_Y_LIMIT_M
from oacdsl.runtime.motion.paths import obstacles, segment_distance
from oacdsl.runtime.motion.tuning import TUNING, Tuning

if TYPE_CHECKING:
    from oacdsl.runtime.simworld import SimWorld

__all__ = ["free_spots"]


def free_spots(
    world: SimWorld,
    side: str,
    obj: str,
    radius_m: float,
    tuning: Tuning = TUNING,
    limit: int = 8,
    hand_xy_m: tuple[np.ndarray, ...] = (),
    near_xy_m: np.ndarray | None = None,
) -> list[np.ndarray]:
    """Up to ``limit`` free (x, y) spots of the table (m) for ``obj`` (footprint radius
    ``radius_m``) held by hand ``side``, best first (module docstring).

    ``hand_xy_m``: where the hand is relative to the spot (m) while it sets ``obj`` down and
    as it backs off; each keeps half of ``tuning.near_path_m`` clear of every footprint too,
    so that letting go does not knock over a neighbour; and the forearm, seen from above as
    the last ``tuning.forearm_m`` of the segment from the elbow (where it is now) to the
    hand, passes over no footprint (a cup set down beyond another knocks it over).

    ``near_xy_m``: a wanted place (x, y, m; where the demonstration set the object down): the
    grid is laid through it, only spots within ``tuning.demo_spot_within_m`` of it count, and
    the nearest to it come first, on whichever side."""
    blocked = [(xy, r) for xy, r, _ in obstacles(world, {obj})]
    for s, held in world.held.items():
        if held is not None and held != obj:
            blocked.append((world.body_pose(held)[:2, 3].copy(), world.layout.bodies[held].radius))
        if s != side:  # the other hand's own footprint, wherever it is
            blocked.append((world.frame_pose(f"grasp_{s}")[:2, 3].copy(), tuning.near_path_m / 2))
    elbow = world.body_pose(f"elbow_{side}_link")[:2, 3].copy()
    step = tuning.spot_step_m
    x0, x1 = STAND_X_RANGE_M[0] + radius_m, STAND_X_RANGE_M[1] - radius_m
    y1 = STAND_Y_LIMIT_M - radius_m
    xs = np.arange(x0, x1 + 1e-9, step)
    ys = np.arange(-y1, y1 + 1e-9, step)
    here = world.body_pose(obj)[:2, 3]
    own = 1.0 if side == "l" else -1.0  # the left hand's side is +y
    if near_xy_m is not None:
        here, own = np.asarray(near_xy_m, float), 0.0
        n = int(np.ceil(tuning.demo_spot_within_m / step))
        xs, ys = (c + step * np.arange(-n, n + 1) for c in here)
        xs = xs[(xs >= x0 - 1e-9) & (xs <= x1 + 1e-9)]
        ys = ys[np.abs(ys) <= y1 + 1e-9]
    spots = []
    for x in xs:
        for y in ys:
            p = np.array([x, y])
            room = radius_m + tuning.spot_gap_m
            clear = all(float(np.linalg.norm(p - xy)) >= room + r for xy, r in blocked)
            hand_clear = all(
                float(np.linalg.norm(p + d - xy)) >= r + tuning.near_path_m / 2
                for d in hand_xy_m
                for xy, r in blocked
            )
            hand = p + (hand_xy_m[0] if hand_xy_m else np.zeros(2))
            arm_clear = all(
                _to_forearm(xy, elbow, hand, tuning.forearm_m) >= r + tuning.near_path_m / 2
                for xy, r in blocked
            )
            near = near_xy_m is None or float(np.linalg.norm(p - here)) <= tuning.demo_spot_within_m
            if near and clear and hand_clear and arm_clear:
                wrong_side = float(y) * own < 0
                spots.append((wrong_side, float(np.linalg.norm(p - here)), p))
    spots.sort(key=lambda s: (s[0], s[1]))
    return [p for _, _, p in spots[:limit]]


def _to_forearm(xy: np.ndarray, elbow: np.ndarray, hand: np.ndarray, length_m: float) -> float:
    """Distance (m) from ``xy`` to the last ``length_m`` of the segment elbow → hand (xy, m)."""
    d = hand - elbow
    n = float(np.linalg.norm(d))
    start = hand - d * min(1.0, length_m / n) if n > 1e-9 else hand
    return segment_distance(xy, start, hand)
