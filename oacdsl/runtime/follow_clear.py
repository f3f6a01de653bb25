"""How far ``follow``'s held object stays from the other hand along its path.

The demonstrator's other hand held its object where it suited them; the robot's holds it
where its grasp put it (a cup held from above by its rim). The turns the demonstration
shows in the core (a carton tipped towards the cup, a ladle swung over it) may then sweep
the robot's object into the fingers of that hand: a touch the demonstration never had,
and a safety stop when it pushes. :func:`clearance` measures, before the object moves, the
smallest distance (m) between the object's solids at the core's keyframes and the other
hand's collision boxes where that hand is now; :func:`turned_less` gives the variants with
the core's turns scaled down that ``follow`` tries, in order, until one keeps
:data:`~oacdsl.runtime.retarget.FOLLOW`'s ``hand_clearance_m``. Metres, world frame.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace

import numpy as np

from oacdsl.runtime.bodies import Body
from oacdsl.runtime.handgap import box_distance, box_surface
from oacdsl.runtime.hands import hand_boxes
from oacdsl.runtime.retarget import FOLLOW, Retargeted
from oacdsl.runtime.shapes import corners
from oacdsl.runtime.simworld import SimWorld
from oacdsl.runtime.transforms import make_T
from oacdsl.segmentation.followpath import from_rotvec, rotvec

__all__ = ["clear_of_hand", "clearance", "turned_less"]

#: Keyframes of the core checked (spread evenly, the first and last included).
_CHECKED = 9


def _solid_boxes(body: Body) -> list[tuple[np.ndarray, np.ndarray]]:
    """(centre, half sizes) of each solid's bounding box, object frame (m)."""
    c = corners(body)
    out = []
    for k in range(0, len(c), 8):
        lo, hi = c[k : k + 8].min(axis=0), c[k : k + 8].max(axis=0)
        out.append((0.5 * (lo + hi), 0.5 * (hi - lo)))
    return out


def clearance(world: SimWorld, other: str, body: Body, plan: Retargeted,
              pose_at: Callable[[Retargeted, int], np.ndarray]) -> float:
    """The smallest distance (m; 0 when they overlap) between ``body`` at ``pose_at(plan, k)``
    (T_world_obj) for the core's keyframes and the collision boxes of hand ``other`` as it is now."""
    hand = [(world.frame_pose(b.link) @ make_T(None, np.array(b.centre)), np.array(b.half))
            for b in hand_boxes(other)]
    hand_points = [(box_surface(h) @ t[:3, :3].T) + t[:3, 3] for t, h in hand]
    solids = [(make_T(None, c), h, box_surface(h)) for c, h in _solid_boxes(body)]
    n, c = len(plan.times_s), plan.core
    best = float("inf")
    for k in sorted({int(round(x)) for x in np.linspace(c, n - 1, _CHECKED)}):
        t_obj = pose_at(plan, k)
        for t_solid, half, surface in solids:
            t_box = t_obj @ t_solid
            pts = surface @ t_box[:3, :3].T + t_box[:3, 3]
            for (t_hand, h_half), h_pts in zip(hand, hand_points, strict=True):
                best = min(best, box_distance(pts, t_hand, h_half), box_distance(h_pts, t_box, half))
    return best


def turned_less(plan: Retargeted, factor: float) -> Retargeted:
    """``plan`` with its turns scaled by ``factor`` (its positions kept; a twist split by
    regrasps is kept whole: turned about its own axis, a round object sweeps no other room)."""
    rot = np.array([from_rotvec(factor * rotvec(m)) for m in plan.rotations])
    return replace(plan, rotations=rot, turn_scale=plan.turn_scale * factor)


def clear_of_hand(world: SimWorld, other: str, body_o: Body, plan: Retargeted,
                   at: Callable[[Retargeted, int], np.ndarray]) -> Retargeted:
    """``plan`` with its core's turns scaled down (:data:`FOLLOW`'s ``clear_turns``) until the
    object, its core started where it meets the target's top (``at``), keeps ``hand_clearance_m``
    from the other hand's boxes; the variant farthest from them when none does."""
    best: tuple[float, Retargeted] | None = None
    for factor in FOLLOW.clear_turns:
        r = plan if factor == 1.0 else turned_less(plan, factor)
        gap = clearance(world, other, body_o, r, at)
        if gap >= FOLLOW.hand_clearance_m:
            return r
        if best is None or gap > best[0]:
            best = (gap, r)
    return best[1] if best is not None else plan
