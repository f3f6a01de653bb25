"""``stir``: circles of a held tool's tip inside a container, which may be held by the other hand.

The tool is turned so that its tip (:mod:`~oacdsl.runtime.skills.tooltip`) points down,
leaning ``tilt`` from the vertical with the handle towards the hand, and carried so that
the tip is above the container's middle. The tip goes down to ``depth`` above the
container's floor (a wrist force above ``force``, or a contact with the container, stops it
earlier), and, unless it touches the container already (the floor), it is moved sideways
to the wall away from the hand until the simulation reports the contact. Only then does
it circle, ``turns`` circles in ``period`` seconds each, from where it touches and at that
height: along the wall, pressed a little beyond it, or, on the floor, pressed onto it with
``radius`` (clamped so that the tool's end stays clear of the wall). The tool touches the
container all the while (the OAC's effect ``s <-> c`` holds during the stir, as in a
demonstration) and is left there, touching it. The container is read where it is when
the skill starts.
"""

from __future__ import annotations

import math

import numpy as np

from oacdsl.errors import RuntimeFailure
from oacdsl.runtime.skills.base import SkillContext
from oacdsl.runtime.skills.place import MIN_JERK_PEAK
from oacdsl.runtime.skills.shapes import hand_reach_below
from oacdsl.runtime.skills.tooltip import HeldTool, held_tool, pointing

__all__ = ["stir", "dip_poses", "STIR_RADIUS_M", "STIR_PERIOD_S", "STIR_TURNS", "STIR_TILT_RAD"]

STIR_RADIUS_M = 0.015
STIR_PERIOD_S = 0.8
STIR_TURNS = 3
STIR_TILT_RAD = math.radians(15.0)
#: Height of the tip above the container's floor while it circles, m.
STIR_DEPTH_M = 0.015
#: Wrist force change that stops the descent into the container, N.
STIR_FORCE_N = 10.0
#: Room kept between the tool's side at the tip and the container's inner wall, m.
WALL_MARGIN_M = 0.004
#: Free space kept between the hand and the container's rim, m.
RIM_CLEARANCE_M = 0.015
#: How far beyond the wall the tool's side is aimed on its way to the wall (a contact stops it), m.
PRESS_WALL_M = 0.02
#: How far the circling tip is pressed beyond the wall or into the floor it touches, m.
PRESS_M = 0.005
#: How far below the rim the tip must reach for a stir, m.
MIN_INSIDE_M = 0.02
#: Height of the tip above the rim before it goes in, m.
ABOVE_RIM_M = 0.05
DIP_SPEED_M_S = 0.08


def dip_poses(
    ctx: SkillContext, side: str, tool: str, container: str, tilt: float
) -> tuple[HeldTool, np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(the held tool, R_world_obj while working, the container's floor centre, its axis
    (world unit), the horizontal unit direction from the container to the hand, the hand
    pose with the tip above the rim's middle)."""
    world = ctx.world
    held = held_tool(ctx, side, tool)
    t_c = world.body_pose(container)
    body = ctx.body(container)
    up = t_c[:3, 2]
    floor = t_c[:3, 3] + body.floor * up
    rim = t_c[:3, 3] + body.rim_height * up
    hand_xy = world.frame_pose(f"grasp_{side}")[:2, 3] - floor[:2]
    toward = np.array([hand_xy[0], hand_xy[1], 0.0])
    toward = toward / max(float(np.linalg.norm(toward)), 1e-9)
    down = -math.cos(tilt) * up - math.sin(tilt) * toward  # handle leaning towards the hand
    r_work = pointing(held, down / np.linalg.norm(down))
    above = held.hand_for(r_work, rim + ABOVE_RIM_M * up)
    return held, r_work, floor, up, toward, above


def stir(
    ctx: SkillContext,
    hand: str,
    tool: str,
    container: str,
    *,
    radius: float = STIR_RADIUS_M,
    period: float = STIR_PERIOD_S,
    turns: float = STIR_TURNS,
    tilt: float = STIR_TILT_RAD,
    depth: float = STIR_DEPTH_M,
    force: float = STIR_FORCE_N,
) -> None:
    """Stir ``container`` with the held ``tool``: the tip into it, onto its wall (or floor), then
    ``turns`` circles, ``period`` (s) each, in contact (of ``radius``, m, on the floor), the tip at
    most ``depth`` (m) above the floor, leaning ``tilt`` (rad)."""
    world, ctl = ctx.world, ctx.ctl
    side = ctx.require_held(hand, tool)
    body = ctx.body(container)
    if not body.container:
        raise RuntimeFailure(f"stir: {container!r} is no container (its shape has no shell)")
    held, r_work, floor, up, toward, above = dip_poses(ctx, side, tool, container, tilt)
    room = max(0.0, body.inner_radius - held.half_width - WALL_MARGIN_M)
    # two axes across the container's axis for the circles
    e1 = np.cross(up, (1.0, 0.0, 0.0) if abs(up[0]) < 0.9 else (0.0, 1.0, 0.0))
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(up, e1)
    rim = floor + (body.rim_height - body.floor) * up
    below = hand_reach_below(world, side, above[:3, :3])  # the hand as it will hold the tool

    def tip_level(above_floor: float) -> np.ndarray:
        """The tip's centre ``above_floor`` over the floor, raised as far as the hand needs
        to stay clear of the rim."""
        tip = floor + above_floor * up
        low = float(held.hand_for(r_work, tip)[2, 3])
        clear = float(rim[2]) + below + RIM_CLEARANCE_M
        return tip + max(0.0, clear - low) * np.array([0.0, 0.0, 1.0])

    level = tip_level(depth)
    inside = float((rim - level) @ up)
    if inside < MIN_INSIDE_M:
        raise RuntimeFailure(
            f"stir: {tool} is too short to reach into {container}: with {hand} clear of the rim its"
            f" tip gets {inside * 100:.0f} cm below the rim (needs {MIN_INSIDE_M * 100:.0f} cm)"
        )

    def at(angle: float, rr: float, height: np.ndarray = level) -> np.ndarray:
        return held.hand_for(r_work, height + rr * (math.cos(angle) * e1 + math.sin(angle) * e2))

    def touching() -> bool:
        return world.touching(tool, container)

    def felt() -> bool:
        return float(np.linalg.norm(ctl.force_change(side))) > force

    # the tip first touches the container at the wall away from the hand, where the circles start
    away = -toward - float(-toward @ up) * up
    start_angle = math.atan2(float(away @ e2), float(away @ e1))
    wall = body.inner_radius - held.half_width  # the tip's middle when its side is at the wall
    ctl.activity = f"bringing {tool} over {container}"
    ctx.check_reachable(side, above, f"the inside of {container}")
    for k in range(4):
        angle = start_angle + k * math.pi / 2
        ctx.check_reachable(side, at(angle, wall + PRESS_WALL_M), f"the stirring circle in {container}")
    ctx.carry(side, above, {tool, container}, 1.8)
    ctl.activity = f"dipping {tool} into {container}"
    start = at(start_angle, 0.0)
    travel = float(np.linalg.norm(above[:3, 3] - start[:3, 3]))
    ctl.move(side, start, MIN_JERK_PEAK * travel / DIP_SPEED_M_S, guard=lambda: touching() or felt())
    if not touching():
        # into contact: sideways to the wall (aimed a little beyond it), or down onto the floor
        ctl.activity = f"bringing {tool} against {container}"
        ctl.move(side, at(start_angle, wall + PRESS_WALL_M), 0.8, guard=lambda: touching() or felt())
    if not ctl.wait(0.3, until=touching) and not touching():
        raise RuntimeFailure(f"stir: {tool} is in {container} but does not touch it")
    # circle from where the tip touches, at its height, kept on the wall (pressed a little beyond
    # it) or, on the floor, pressed onto it: the tool touches the container all the while
    tip = held_tool(ctx, side, tool).tip_world()
    out = float(np.linalg.norm((tip - floor) - float((tip - floor) @ up) * up))
    on_wall = out > wall - WALL_MARGIN_M
    height = floor + float((tip - floor) @ up) * up - (0.0 if on_wall else PRESS_M) * up
    rr = out + PRESS_M if on_wall else max(min(radius, room), out)
    ctl.move(side, at(start_angle, rr, height), 0.2)  # pressed on where it touches
    ctl.activity = f"stirring {container} with {tool}"
    n = 16
    for k in range(1, max(1, round(turns)) * n + 1):
        ctl.move(side, at(start_angle + 2 * math.pi * k / n, rr, height), period / n)
    if not ctl.wait(0.3, until=touching) and not touching():
        raise RuntimeFailure(f"stir: {tool} lost contact with {container} while stirring")
