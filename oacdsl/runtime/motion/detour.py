"""A carry keeps clear of what the other hand holds up: a detour where the way passes under it.

The carry's way (:func:`~oacdsl.runtime.motion.paths.carry_path`) flies over what stands on
the table; what the other hand holds up is not standing there. When it is held above the
carried object's lowest point and the way comes nearer to it, or to the hand that holds it,
than ``tuning.over_m`` (and nearer than at the start), the carry first moves, at its height,
to a nearby point out from under it, the rest of the way planned from there: KIT Cut with
``follow``, the cucumber, lifted off the board under the knife the right hand holds up, was
carried to its place under the knife, the left hand's back against the blade for 0.6 s.

Both are seen as axis-aligned boxes in the world, as they are now: the carrying hand and what
it holds, translated with the hand along the way; the other hand and what it holds. Metres.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING

import numpy as np

from oacdsl.runtime.motion.tuning import TUNING, Tuning
from oacdsl.runtime.shapes import hand_corners, world_corners

if TYPE_CHECKING:
    from oacdsl.runtime.simworld import SimWorld

__all__ = ["Box", "Way", "boxes", "gap", "way_gap", "lockstep_gap", "first_to_carry", "detour",
           "out_from_under"]

#: (lowest corner, highest corner) of an axis-aligned box in the world, m
Box = tuple[np.ndarray, np.ndarray]
#: Directions tried for the detour's point (evenly round); points checked on each straight piece.
_DIRECTIONS = 16
_SAMPLES = 21


def _box(points: np.ndarray) -> Box:
    return points.min(axis=0), points.max(axis=0)


def boxes(world: SimWorld, side: str) -> list[Box]:
    """The boxes of hand ``side``'s parts (palm, fingers, thumb) and of the solids of what it
    holds, now (world)."""
    t = world.frame_pose(f"grasp_{side}")
    corners = [hand_corners(world, side) @ t[:3, :3].T + t[:3, 3]]
    held = world.held.get(side)
    if held is not None:
        corners.append(world_corners(world.layout.bodies[held], world.body_pose(held)))
    return [_box(c[k : k + 8]) for c in corners for k in range(0, len(c), 8)]


def gap(moving: Sequence[Box], still: Sequence[Box], offset_m: np.ndarray) -> float:
    """The smallest distance (m) between the ``moving`` boxes shifted by ``offset_m`` and the
    ``still`` ones; negative: how deep the least overlapping pair overlaps."""
    best = math.inf
    for lo, hi in moving:
        for s_lo, s_hi in still:
            g = np.maximum(s_lo - (hi + offset_m), (lo + offset_m) - s_hi)
            best = min(best, float(np.linalg.norm(np.maximum(g, 0.0))) if (g > 0).any() else float(g.max()))
    return best


def way_gap(moving: Sequence[Box], still: Sequence[Box], start: np.ndarray,
             points: Sequence[np.ndarray]) -> float:
    """The smallest gap along the straight pieces through ``points`` (hand positions, world),
    the boxes ``moving`` being where they are with the hand at ``start``."""
    s = np.linspace(0.0, 1.0, _SAMPLES)
    return min(gap(moving, still, a + u * (b - a) - start) for a, b in zip(points, points[1:], strict=False)
               for u in s)


Way = list[tuple[np.ndarray, float]]


def lockstep_gap(moving: Sequence[Sequence[Box]], starts: Sequence[np.ndarray],
                 ways: Sequence[Way]) -> float:
    """The smallest gap (m; negative: overlap) between two hands' boxes ``moving`` (each where it
    is with its hand at its ``starts`` pose, T_world_grasp) while both follow their ``ways``
    together as :func:`~oacdsl.runtime.motion.both.lockstep` drives them: phase by phase, each
    hand the same fraction along its own phase at every instant, a shorter way's hand waiting
    at its end. Each way alone may keep clear of the other hand where it stands now (two
    objects set down at once, each carried round the other's place, met half way)."""
    (a_boxes, b_boxes), (a0, b0) = moving, (starts[0][:3, 3], starts[1][:3, 3])
    most = max(len(w) for w in ways)
    pts = [[start] + [p[:3, 3] for p, _ in w] + [w[-1][0][:3, 3] if w else start] * (most - len(w))
           for w, start in zip(ways, (a0, b0), strict=True)]
    s = np.linspace(0.0, 1.0, _SAMPLES)
    best = gap(a_boxes, b_boxes, np.zeros(3))
    for k in range(most):
        (pa, qa), (pb, qb) = (pts[0][k], pts[0][k + 1]), (pts[1][k], pts[1][k + 1])
        for u in s:  # both translated: b's boxes kept still, a's shifted by the difference
            shift = (pa + u * (qa - pa) - a0) - (pb + u * (qb - pb) - b0)
            best = min(best, gap(a_boxes, b_boxes, shift))
    return best


def first_to_carry(moving: Sequence[Sequence[Box]], starts: Sequence[np.ndarray], ways: Sequence[Way],
                   tuning: Tuning = TUNING) -> int | None:
    """Whether two hands carry at once along ``ways`` (from their ``starts``, their boxes
    ``moving`` as in :func:`lockstep_gap`): None, together, when they keep ``tuning.over_m``
    from each other, or at least as much as at the start, all the way; else which hand (0, 1)
    carries first, the other then: the first whose way keeps that from the other's boxes where
    they are now (0 when neither does)."""
    need = min(tuning.over_m, gap(moving[0], moving[1], np.zeros(3)))
    if lockstep_gap(moving, starts, ways) >= need:
        return None
    for k in (0, 1):
        points = [starts[k][:3, 3]] + [p[:3, 3] for p, _ in ways[k]]
        if way_gap(moving[k], moving[1 - k], points[0], points) >= need:
            return k
    return 0


def detour(world: SimWorld, side: str, now: np.ndarray, way: Way, rest: Callable[[np.ndarray], Way],
           exclude: set[str], tuning: Tuning = TUNING) -> Way:
    """``way`` ((T_world_grasp, s) from hand pose ``now``), or, when hand ``side`` carries
    something and the other hand holds something up above it (its lowest point higher than the
    carried one's; not in ``exclude``: a way that ends at it is another matter), the way of
    :func:`out_from_under` (module doc)."""
    other = "l" if side == "r" else "r"
    held, mine = world.held.get(other), world.held.get(side)
    if held is None or mine is None or held in exclude:
        return way
    low = world_corners(world.layout.bodies[held], world.body_pose(held))[:, 2].min()
    if low <= world_corners(world.layout.bodies[mine], world.body_pose(mine))[:, 2].min():
        return way  # not held up above what this hand carries
    return out_from_under(boxes(world, side), boxes(world, other), now, way, rest, tuning)


def out_from_under(moving: Sequence[Box], still: Sequence[Box], now: np.ndarray, way: Way,
                   rest: Callable[[np.ndarray], Way], tuning: Tuning = TUNING) -> Way:
    """``way`` from hand pose ``now`` (T_world_grasp) when along it the ``moving`` boxes (where
    they are with the hand at ``now``) keep ``tuning.over_m`` from the ``still`` ones, or at
    least as much as at the start; else first to the nearest point at the hand's height (of
    :data:`_DIRECTIONS` directions, ``tuning.detour_steps_m`` away) from which ``rest(pose)``
    (the way from there on) keeps that, the shortest in all; ``way`` when none does."""
    start = now[:3, 3]
    need = min(tuning.over_m, gap(moving, still, np.zeros(3)))
    if way_gap(moving, still, start, [start] + [p[:3, 3] for p, _ in way]) >= need:
        return way
    best: tuple[float, Way] | None = None
    for k in range(_DIRECTIONS):
        a = 2.0 * math.pi * k / _DIRECTIONS
        for d in tuning.detour_steps_m:
            out = now.copy()
            out[:2, 3] += d * np.array([math.cos(a), math.sin(a)])
            then = rest(out)
            points = [start, out[:3, 3]] + [p[:3, 3] for p, _ in then]
            if way_gap(moving, still, start, points) < need:
                continue
            length = sum(float(np.linalg.norm(q - p)) for p, q in zip(points, points[1:], strict=False))
            if best is None or length < best[0]:
                best = (length, [(out, max(tuning.settle_s, d / tuning.carry_speed_m_s)), *then])
            break  # the nearest that does in this direction
    return way if best is None else best[1]
