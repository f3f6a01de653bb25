"""``mix``: put the held mixer into a container and stir, ending with it in the container.

The mixer is carried upright above the container, lowered until it touches the
container (beside the balls lying on its floor where it fits, :func:`floor_spot`, else pushing
them aside; the wrist force stops the descent at 15 N), slid to the middle, and moved in
circles pressed onto the bottom with a force regulated on the wrist's
(:class:`~oacdsl.runtime.motion.press.ForcePress`); it stays in the container at the end,
as the OAC's effect ``m <-> b`` says.
"""

from __future__ import annotations

import math

import numpy as np

from oacdsl.errors import RuntimeFailure
from oacdsl.runtime.motion import TUNING, Motion, raised, waypoints_per_cycle
from oacdsl.runtime.skills.base import SkillContext
from oacdsl.runtime.transforms import make_T
from oacdsl.skills import SIGNATURES

__all__ = ["mix", "floor_spot", "SIGNATURE"]

SIGNATURE = SIGNATURES["mix"]
D = SIGNATURE.defaults()

#: Points per circle of the stirring path (fewer for a fast one:
#: :func:`~oacdsl.runtime.motion.waypoints_per_cycle`, each at least two control ticks).
CIRCLE_POINTS = 24
#: Time back to the middle after the circles, s.
CENTRE_S = 0.4
#: How long a tool that went down without touching the container may still find it, s.
FIND_S = 0.5


def mix(
    ctx: SkillContext,
    hand: str,
    tool: str,
    container: str,
    *,
    radius: float = D["radius"],
    turns: float = D["turns"],
    period: float = D["period"],
    force: float = D["force"],
) -> None:
    """Stir ``container`` with the held ``tool``: ``turns`` circles of ``radius`` (m), ``period``
    (s) each; the descent stops when it touches the container or the wrist feels ``force`` (N).
    Composition: carry upright over the container, approach its floor (guarded), circles pressed
    on the floor (slides, the press regulated on the wrist's force), back to the middle, hold still."""
    world, ctl, t = ctx.world, ctx.ctl, TUNING
    side = ctx.require_held(hand, tool)
    m = Motion(ctx, side)
    t_tool, tool_in_hand = ctx.held_pose(side, tool)
    t_bowl = world.body_pose(container)
    bowl = ctx.body(container)
    centre = t_bowl[:3, 3]
    upright = _upright(t_tool[:3, :3])

    def hand_for(p: np.ndarray) -> np.ndarray:
        return make_T(upright, p) @ np.linalg.inv(tool_in_hand)

    above = np.array([centre[0], centre[1], centre[2] + bowl.height + t.hover_m])
    ctl.activity = f"bringing {tool} over {container}"
    ctx.check_reachable(side, hand_for(above), f"the inside of {container}")
    m.carry(hand_for(above), {tool, container}, t.work_carry_s)
    press = m.pressing()  # the tool's free weight, read before it goes in
    ctl.activity = f"lowering {tool} into {container}"
    # the container's inner floor; the tool is aimed a little below it, beside the balls lying
    # there if it fits (else pushing them aside), until it touches the container itself
    floor = centre[2] + bowl.floor
    spot = floor_spot(ctx, container, ctx.body(tool).radius)
    bottom = raised(hand_for(np.array([spot[0], spot[1], floor])), -t.press_m)
    depth = float(m.here()[2, 3] - bottom[2, 3])
    touched = m.go(bottom, depth / t.set_down_speed_m_s, m.contact_or_force(tool, container, force))
    if not touched and not m.hold_still(FIND_S, m.touching(tool, container)):
        raise RuntimeFailure(f"mix: {tool} went down into {container} without touching it")
    # the circles' level where the tool touched; the press starts as deep as a press on a touch
    level = min(float(world.body_pose(tool)[2, 3]), floor)
    press.depth_m = t.press_m
    ctl.activity = f"stirring {container} with {tool}"
    off = float(np.hypot(*(spot - centre[:2])))
    if off:  # gone down beside the balls: slid to the middle first, where the circles begin
        m.go(hand_for(np.array([centre[0], centre[1], level])), off / t.slide_speed_m_s, press=press)
    n = waypoints_per_cycle(period, CIRCLE_POINTS)  # fewer for fast circles: none a jump
    for k in range(1, int(round(turns)) * n + 1):
        a = 2 * math.pi * k / n
        r = radius * min(1.0, k / n)
        p = np.array([centre[0] + r * math.sin(a), centre[1] + r * (1 - math.cos(a)) / 2, level])
        m.go(hand_for(p), period / n, press=press)
    m.go(hand_for(np.array([centre[0], centre[1], level])), CENTRE_S, press=press)
    m.hold_still(2 * t.settle_s, m.touching(tool, container))


def floor_spot(ctx: SkillContext, container: str, tool_radius_m: float) -> np.ndarray:
    """Where (world xy, m) a tool of footprint radius ``tool_radius_m`` goes down to the floor of
    ``container``: its middle, else the nearest point to it (rings 1 cm apart, 30° apart round
    each: ``Tuning.free_spot_*``) whose footprint keeps :data:`TUNING.wall_margin_m` from the
    container's inner wall and from every ball lying there, else the middle (the tool pushes the
    balls aside). A mixer
    lowered onto a ball lying in the middle of the bowl touched it 0.3 s before the floor (the
    dough, seeds 2 and 9): a change the task does not make."""
    world = ctx.world
    t_box = world.body_pose(container)
    centre, inner = t_box[:2, 3], ctx.body(container).inner_radius
    margin = TUNING.wall_margin_m
    balls = [(world.ball_positions(liq)[:, :2], world.layout.bodies[liq].ball_radius)
             for liq in world.built.balls]
    step, turn = TUNING.free_spot_step_m, TUNING.free_spot_turn_rad
    rings = np.arange(1, int((inner - tool_radius_m - margin) / step) + 1) * step
    spots = [centre] + [centre + r * np.array([math.cos(a), math.sin(a)])
                        for r in rings for a in np.arange(round(math.tau / turn)) * turn]
    for xy in spots:
        if all((np.hypot(*(pts - xy).T) >= tool_radius_m + r + margin).all() for pts, r in balls):
            return xy
    return centre


def _upright(r: np.ndarray) -> np.ndarray:
    """The rotation with the same heading as ``r`` and its z axis vertical."""
    yaw = math.atan2(r[1, 0], r[0, 0])
    c, s = math.cos(yaw), math.sin(yaw)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
