"""``pour``: tilt the held container over a target container until its balls have left.

The cup's rim point facing the target (the *lip*) is brought above the target, a few
centimetres off its centre, and the cup is turned about a horizontal axis through the
lip until it is upside down enough for every ball to fall out; then it is turned back.
The direction the cup comes from is chosen among a few azimuths around the target, by
asking the whole-body IK which fully tilted pose it can reach best. The pour succeeds
when at least :data:`SUCCESS_FRACTION` of the liquid's balls end inside the target,
counted by the simulation.
"""

from __future__ import annotations

import math

import numpy as np

from oacdsl.errors import RuntimeFailure
from oacdsl.runtime.skills.base import REACH_TOLERANCE_M, SkillContext
from oacdsl.runtime.transforms import make_T, rot_axis

__all__ = ["pour", "SUCCESS_FRACTION", "TILT_RAD", "TILT_DURATION_S", "LIP_ABOVE_RIM_M"]

#: Share of the balls that must land in the target container.
SUCCESS_FRACTION = 0.9
#: Default final tilt of the cup (rad): 125°, past upside-down enough to empty it.
TILT_RAD = math.radians(125.0)
#: Lip height above the target's rim (m) while tilted, and its extra height before tilting.
LIP_ABOVE_RIM_M = 0.045
LIP_START_EXTRA_M = 0.07
#: Where the lip is over the target: this far from its centre towards the cup, m.
LIP_FROM_CENTRE_M = 0.03


def _cup_pose(
    base_r: np.ndarray, lip_local: np.ndarray, lip_world: np.ndarray, axis: np.ndarray, angle: float
) -> np.ndarray:
    r = rot_axis(axis, angle) @ base_r
    return make_T(r, lip_world - r @ lip_local)


#: Time to tilt the container to its final tilt, seconds.
TILT_DURATION_S = 1.8


def pour(
    ctx: SkillContext,
    hand: str,
    source: str,
    liquid: str,
    target: str,
    *,
    tilt: float = TILT_RAD,
    duration: float = TILT_DURATION_S,
    height: float = LIP_ABOVE_RIM_M,
) -> None:
    """Pour ``liquid`` from the held ``source`` into ``target``: the lip ``height`` (m) above the
    target's rim, turned to ``tilt`` (rad) over ``duration`` (s)."""
    world, ctl = ctx.world, ctx.ctl
    side = ctx.require_held(hand, source)
    if liquid not in world.built.balls:
        raise RuntimeFailure(f"pour: {liquid!r} is not a liquid of the scene")
    total = len(world.built.balls[liquid])
    t_cup, cup_in_hand = ctx.held_pose(side, source)
    cup, bowl = ctx.body(source), ctx.body(target)
    if not cup.container:
        raise RuntimeFailure(f"pour: {source!r} is no container (its shape has no shell)")
    t_bowl = world.body_pose(target)
    centre, rim_z = t_bowl[:3, 3], t_bowl[2, 3] + bowl.rim_height
    # the cup kept upright with its current heading
    yaw = math.atan2(t_cup[1, 0], t_cup[0, 0])
    base_r = rot_axis((0.0, 0.0, 1.0), yaw)

    def plan(u: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        lip_local = base_r.T @ (-u * cup.rim_radius) + np.array([0.0, 0.0, cup.rim_height])
        lip = np.array([*(centre[:2] + u[:2] * LIP_FROM_CENTRE_M), rim_z + height])
        return lip_local, lip, np.cross(u, (0.0, 0.0, 1.0))

    def hand_at(u: np.ndarray, angle: float, lift: float) -> np.ndarray:
        lip_local, lip, axis = plan(u)
        return _cup_pose(base_r, lip_local, lip + np.array([0.0, 0.0, lift]), axis, angle) @ np.linalg.inv(
            cup_in_hand
        )

    ctl.activity = f"planning to pour {liquid} into {target}"
    to_cup = t_cup[:2, 3] - centre[:2]
    home = math.atan2(to_cup[1], to_cup[0])
    candidates = sorted((home + k * math.pi / 4 for k in range(-3, 5)), key=lambda a: abs(a - home))
    best: tuple[float, np.ndarray] | None = None
    for a in candidates:
        u = np.array([math.cos(a), math.sin(a), 0.0])
        err = max(ctx.reach_error(side, hand_at(u, tilt, 0.0)), ctx.reach_error(side, hand_at(u, 0.0, 0.07)))
        if best is None or err < best[0]:
            best = (err, u)
        if err < REACH_TOLERANCE_M:
            break
    if best is None or best[0] > 3 * REACH_TOLERANCE_M:
        raise RuntimeFailure(
            f"cannot pour from {source} into {target}: no tilted pose over {target} is in reach"
            f" of {hand} (best leaves the hand {best[0] * 100 if best else float('nan'):.0f} cm off)"
        )
    u = best[1]
    ctl.activity = f"bringing {source} over {target}"
    start = hand_at(u, 0.0, LIP_START_EXTRA_M)
    ctx.carry(side, start, {source, target}, 1.8)
    ctl.activity = f"pouring {liquid} into {target}"
    steps = 40
    for k in range(1, steps + 1):
        s = k / steps
        ctl.move(side, hand_at(u, tilt * s, LIP_START_EXTRA_M * max(0.0, 1.0 - 2.0 * s)), duration / steps)
    ctl.wait(2.0, until=lambda: world.balls_inside(source, liquid) == 0)
    ctl.wait(0.6)
    for k in range(1, steps // 2 + 1):
        s = 1.0 - k / (steps // 2)
        ctl.move(side, hand_at(u, tilt * s, LIP_START_EXTRA_M * (1.0 - s)), 1.0 / (steps // 2))
    inside = world.balls_inside(target, liquid)
    if inside < SUCCESS_FRACTION * total:
        left = world.balls_inside(source, liquid)
        raise RuntimeFailure(
            f"pour: only {inside} of {total} balls of {liquid} ended in {target}"
            f" ({left} still in {source}; needed {math.ceil(SUCCESS_FRACTION * total)})"
        )
