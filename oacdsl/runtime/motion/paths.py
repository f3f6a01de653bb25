"""Collision-free ways for a hand and what it carries: over the objects near the way.

The objects standing on the table are read from the simulation now (footprint radius and
top, from the language's geometry); a way from a hand pose to a goal climbs first when it
must, crosses over the middle high enough for what hangs below the hand to clear every
object near the way, and comes down to the goal.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from oacdsl.runtime.grasping import HAND_BELOW_CENTRE_M
from oacdsl.runtime.motion.tuning import TUNING, Tuning

if TYPE_CHECKING:
    from oacdsl.runtime.simworld import SimWorld

__all__ = ["Obstacle", "obstacles", "clearance", "via_height", "carry_path", "segment_distance"]

#: (xy, footprint radius, top height) of an object on the table, m
Obstacle = tuple[np.ndarray, float, float]


def segment_distance(p: np.ndarray, a: np.ndarray, b: np.ndarray) -> float:
    """Distance from point p to the segment a–b (2-D)."""
    ab = b - a
    s = 0.0 if float(ab @ ab) < 1e-12 else float(np.clip((p - a) @ ab / (ab @ ab), 0.0, 1.0))
    return float(np.linalg.norm(p - (a + s * ab)))


def obstacles(world: SimWorld, exclude: set[str]) -> list[Obstacle]:
    """The objects standing on the table, read from the simulation now; ``exclude`` and
    held objects left out."""
    held = {o for o in world.held.values() if o is not None}
    out = []
    for p in world.layout.placements:
        if p.name in exclude or p.name in held:
            continue
        t = world.body_pose(p.name)
        out.append((t[:2, 3].copy(), p.body.radius, float(t[2, 3] + p.body.height)))
    return out


def clearance(world: SimWorld, a: np.ndarray, b: np.ndarray, exclude: set[str]) -> float:
    """Smallest horizontal gap (m) between the way a → b (xy) and an obstacle's footprint."""
    return min(
        (segment_distance(xy, a[:2], b[:2]) - r for xy, r, _ in obstacles(world, exclude)),
        default=float("inf"),
    )


def via_height(
    world: SimWorld,
    a: np.ndarray,
    b: np.ndarray,
    exclude: set[str],
    hanging_m: float,
    tuning: Tuning = TUNING,
) -> float:
    """Height for a hand frame moving over a → b (xy) so that what hangs ``hanging_m`` below it
    clears every obstacle within ``tuning.near_path_m`` of the way by ``tuning.over_m``."""
    tops = [
        top
        for xy, r, top in obstacles(world, exclude)
        if segment_distance(xy, a[:2], b[:2]) - r < tuning.near_path_m
    ]
    return max(tops, default=-np.inf) + hanging_m + tuning.over_m


def carry_path(
    world: SimWorld,
    side: str,
    now: np.ndarray,
    goal: np.ndarray,
    exclude: set[str],
    duration_s: float,
    tuning: Tuning = TUNING,
) -> list[tuple[np.ndarray, float]]:
    """Three (T_world_grasp, seconds) from hand pose ``now`` to ``goal``: a climb (0 s when none
    is needed), a point over the middle of the way, the goal; four when the slanting way down
    from the middle would pass too low over an object beside the goal (a cup set down next to
    another): then the hand crosses at the way's height to over the goal and comes straight
    down."""
    hanging = HAND_BELOW_CENTRE_M
    held = world.held[side]
    if held is not None:
        hanging = max(hanging, float(world.frame_pose(f"grasp_{side}")[2, 3] - world.body_pose(held)[2, 3]))
    over = via_height(world, now[:3, 3], goal[:3, 3], exclude | ({held} if held else set()), hanging, tuning)
    via = now.copy()
    via[:2, 3] = 0.5 * (now[:2, 3] + goal[:2, 3])
    via[2, 3] = max(now[2, 3], goal[2, 3], over)
    up = now.copy()
    up[2, 3] = max(over, now[2, 3])  # climb first, then cross
    climb = tuning.climb_share * duration_s if over > now[2, 3] else 0.0
    half = 0.5 * duration_s
    if _slant_clear(world, via[:3, 3], goal[:3, 3], exclude | ({held} if held else set()), hanging, tuning):
        return [(up, climb), (via, half), (goal, half)]
    above = goal.copy()
    above[2, 3] = via[2, 3]
    return [(up, climb), (via, half), (above, 0.5 * half), (goal, 0.5 * half)]


def _slant_clear(
    world: SimWorld, a: np.ndarray, b: np.ndarray, exclude: set[str], hanging_m: float, tuning: Tuning
) -> bool:
    """Whether what hangs ``hanging_m`` below a hand going straight from a to b (m) passes
    ``tuning.over_m`` above every object whose footprint comes within ``tuning.near_path_m``
    of the way, at the way's height where it passes nearest."""
    ab = b[:2] - a[:2]
    span = float(ab @ ab)
    for xy, r, top in obstacles(world, exclude):
        if segment_distance(xy, a[:2], b[:2]) - r >= tuning.near_path_m:
            continue
        s = 0.0 if span < 1e-12 else float(np.clip((xy - a[:2]) @ ab / span, 0.0, 1.0))
        if a[2] + s * (b[2] - a[2]) - hanging_m < top + tuning.over_m:
            return False
    return True
