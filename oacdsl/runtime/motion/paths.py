"""Collision-free ways for a hand and what it carries: over the objects near the way.

The objects standing on the table are read from the simulation now (footprint radius and
top, from the language's geometry); a way from a hand pose to a goal climbs first when it
must, crosses over the middle high enough for what hangs below the hand to clear every
object near the way, and comes down to the goal.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

from oacdsl.runtime.grasping import HAND_BELOW_CENTRE_M
from oacdsl.runtime.motion.detour import detour
from oacdsl.runtime.motion.tuning import TUNING, Tuning
from oacdsl.runtime.shapes import hand_corners, highest_z

if TYPE_CHECKING:
    from oacdsl.runtime.simworld import SimWorld

__all__ = ["Obstacle", "obstacles", "clearance", "via_height", "carry_path", "direct_path",
           "segment_distance", "other_hand_obstacle", "held_by_other"]

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


def other_hand_obstacle(world: SimWorld, side: str) -> Obstacle | None:
    """The other hand than ``side`` as an obstacle while it holds something (it is then out
    among the objects; its thumb reaches some 9 cm past what it holds): the footprint and top
    of its collision boxes now. None while it holds nothing."""
    other = "l" if side == "r" else "r"
    if world.held.get(other) is None:
        return None
    t = world.frame_pose(f"grasp_{other}")
    pts = hand_corners(world, other) @ t[:3, :3].T + t[:3, 3]
    xy = 0.5 * (pts[:, :2].min(axis=0) + pts[:, :2].max(axis=0))
    return xy, float(np.linalg.norm(pts[:, :2] - xy, axis=1).max()), float(pts[:, 2].max())


def held_by_other(world: SimWorld, side: str, exclude: set[str]) -> list[Obstacle]:
    """What the other hand than ``side`` holds (unless in ``exclude``) as an obstacle: its
    footprint and highest point now. Held up beside the way (a bottle whose lid this hand
    has just taken off), it is as much in the way as an object standing on the table."""
    other = "l" if side == "r" else "r"
    held = world.held.get(other)
    if held is None or held in exclude:
        return []
    t = world.body_pose(held)
    body = world.layout.bodies[held]
    return [(t[:2, 3].copy(), body.radius, highest_z(body, t))]


def carry_path(
    world: SimWorld,
    side: str,
    now: np.ndarray,
    goal: np.ndarray,
    exclude: set[str],
    duration_s: float,
    tuning: Tuning = TUNING,
    over_other_hand: bool = False,
) -> list[tuple[np.ndarray, float]]:
    """The way of :func:`direct_path`, first out from under what the other hand holds up when it
    would pass under it (:func:`~oacdsl.runtime.motion.detour.detour`)."""
    def way(start: np.ndarray) -> list[tuple[np.ndarray, float]]:
        return direct_path(world, side, start, goal, exclude, duration_s, tuning, over_other_hand)

    return detour(world, side, now, way(now), way, exclude, tuning)


def direct_path(
    world: SimWorld,
    side: str,
    now: np.ndarray,
    goal: np.ndarray,
    exclude: set[str],
    duration_s: float,
    tuning: Tuning = TUNING,
    over_other_hand: bool = False,
) -> list[tuple[np.ndarray, float]]:
    """Three (T_world_grasp, seconds) from hand pose ``now`` to ``goal``: a climb (0 s when none
    is needed), a point over the middle of the way, the goal; four when the slanting way down
    from the middle would pass too low over an object beside the goal (a cup set down next to
    another): then the hand crosses at the way's height to over the goal and comes straight
    down. The other hand, while it holds something, is flown over too
    (:func:`other_hand_obstacle`) with ``over_other_hand``, and whenever the way enters its
    footprint from outside it: the red cup brought to pour beside the hand holding the mixer
    in the bowl, crossing at the way's height to above the goal, met that hand's thumb (65 N).
    The slanting way down also keeps clear of what the other
    hand holds (:func:`held_by_other`), but the way's height does not fly over it: that hand is
    above what it holds (a knife held up by its handle; the cucumber carried over the knife
    met the hand, 70 N)."""
    hanging = HAND_BELOW_CENTRE_M
    held = world.held[side]
    if held is not None:
        hanging = max(hanging, float(world.frame_pose(f"grasp_{side}")[2, 3] - world.body_pose(held)[2, 3]))
    also, leave = held_by_other(world, side, exclude), exclude | ({held} if held else set())
    over = via_height(world, now[:3, 3], goal[:3, 3], leave, hanging, tuning)
    hand = other_hand_obstacle(world, side)
    if hand is not None and not (over_other_hand or _enters(hand, now[:2, 3], goal[:2, 3])):
        hand = None
    if hand is not None and segment_distance(hand[0], now[:2, 3], goal[:2, 3]) - hand[1] < tuning.near_path_m:
        over = max(over, hand[2] + hanging + tuning.over_m)
    via = now.copy()
    via[:2, 3] = 0.5 * (now[:2, 3] + goal[:2, 3])
    via[2, 3] = max(now[2, 3], goal[2, 3], over)
    up = now.copy()
    up[2, 3] = max(over, now[2, 3])  # climb first, then cross
    climb = tuning.climb_share * duration_s if over > now[2, 3] else 0.0
    half = 0.5 * duration_s
    reach = world.layout.bodies[held].radius if held is not None else 0.0
    if _slant_clear(world, via[:3, 3], goal[:3, 3], leave, hanging, tuning, also, reach):
        return [(up, climb), (via, half), (goal, half)]
    above = goal.copy()
    above[2, 3] = via[2, 3]
    return [(up, climb), (via, half), (above, 0.5 * half), (goal, 0.5 * half)]


def _enters(hand: Obstacle, a: np.ndarray, b: np.ndarray) -> bool:
    """Whether the way a → b (xy, m) comes from outside the footprint of ``hand`` to within it."""
    return bool(np.linalg.norm(a - hand[0]) >= hand[1] > np.linalg.norm(b - hand[0]))


def _slant_clear(
    world: SimWorld, a: np.ndarray, b: np.ndarray, exclude: set[str], hanging_m: float, tuning: Tuning,
    also: Sequence[Obstacle] = (), reach_m: float = 0.0,
) -> bool:
    """Whether what hangs ``hanging_m`` below a hand going straight from a to b (m), reaching
    ``reach_m`` out from the hand's line (a held object's footprint), passes ``tuning.over_m``
    above every object (and those of ``also``) whose footprint comes within
    ``tuning.near_path_m`` of the way: at the way's height where it passes nearest, and
    wherever along it their footprints overlap (a lid carried off the bottle the other hand
    holds, its way down starting beside the bottle)."""
    ab = b[:2] - a[:2]
    span = float(ab @ ab)
    along = np.linspace(0.0, 1.0, 21)
    for xy, r, top in [*obstacles(world, exclude), *also]:
        if segment_distance(xy, a[:2], b[:2]) - r >= tuning.near_path_m:
            continue
        s = 0.0 if span < 1e-12 else float(np.clip((xy - a[:2]) @ ab / span, 0.0, 1.0))
        if a[2] + s * (b[2] - a[2]) - hanging_m < top + tuning.over_m:
            return False
        pts = a[None, :] + along[:, None] * (b - a)[None, :]
        over = np.linalg.norm(pts[:, :2] - xy, axis=1) < r + reach_m
        if (pts[over, 2] - hanging_m < top + tuning.over_m).any():
            return False
    return True
