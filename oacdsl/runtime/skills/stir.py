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
from oacdsl.runtime.motion import TUNING, Motion, waypoints_per_cycle
from oacdsl.runtime.shapes import hand_reach_below
from oacdsl.runtime.skills.base import SkillContext, cm
from oacdsl.runtime.skills.tooltip import HeldTool, held_tool, pointing
from oacdsl.skills import SIGNATURES
from oacdsl.units import format_mm

__all__ = ["stir", "dip_poses", "SIGNATURE"]

SIGNATURE = SIGNATURES["stir"]
D = SIGNATURE.defaults()
#: Points per circle (fewer for a fast one: :func:`~oacdsl.runtime.motion.waypoints_per_cycle`,
#: each at least two control ticks).
CIRCLE_POINTS = 16
#: Time of the move sideways to the wall (a contact stops it), s.
TO_WALL_S = 0.8
#: Room kept between the tool's side at the tip and the container's inner wall, m.
WALL_MARGIN_M = 0.004


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
    above = held.hand_for(r_work, rim + TUNING.above_rim_m * up)
    return held, r_work, floor, up, toward, above


def stir(
    ctx: SkillContext,
    hand: str,
    tool: str,
    container: str,
    *,
    radius: float = D["radius"],
    period: float = D["period"],
    turns: float = D["turns"],
    tilt: float = D["tilt"],
    depth: float = D["depth"],
    force: float = D["force"],
) -> None:
    """Stir ``container`` with the held ``tool``: the tip into it, onto its wall (or floor), then
    ``turns`` circles, ``period`` (s) each, in contact (of ``radius``, m, on the floor), the tip at
    most ``depth`` (m) above the floor, leaning ``tilt`` (rad). Composition: carry over the rim,
    approach the floor (guarded), approach the far wall (guarded) unless it touches already,
    press, slide in circles, hold still."""
    world, ctl, t = ctx.world, ctx.ctl, TUNING
    side = ctx.require_held(hand, tool)
    body = ctx.body(container)
    if not body.container:
        raise RuntimeFailure(f"stir: {container!r} is no container (its shape has no shell)")
    m = Motion(ctx, side)
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
        clear = float(rim[2]) + below + t.rim_clearance_m
        return tip + max(0.0, clear - low) * np.array([0.0, 0.0, 1.0])

    level = tip_level(depth)
    inside = float((rim - level) @ up)
    if inside < t.min_inside_m:
        raise RuntimeFailure(
            f"stir: {tool} is too short to reach into {container}: with {hand} clear of the rim its"
            f" tip gets {cm(inside)} below the rim (needs {cm(t.min_inside_m)})"
        )

    def at(angle: float, rr: float, height: np.ndarray = level) -> np.ndarray:
        return held.hand_for(r_work, height + rr * (math.cos(angle) * e1 + math.sin(angle) * e2))

    guard = m.contact_or_force(tool, container, force)
    # the tip first touches the container at the wall away from the hand, where the circles start
    away = -toward - float(-toward @ up) * up
    start_angle = math.atan2(float(away @ e2), float(away @ e1))
    wall = body.inner_radius - held.half_width  # the tip's middle when its side is at the wall
    beyond = wall + 4 * t.aim_beyond_m  # aimed beyond the wall on the way there (a contact stops it)
    ctl.activity = f"bringing {tool} over {container}"
    ctx.check_reachable(side, above, f"the inside of {container}")
    for k in range(4):
        ctx.check_reachable(
            side, at(start_angle + k * math.pi / 2, beyond), f"the stirring circle in {container}"
        )
    m.carry(above, {tool, container}, t.work_carry_s)
    start_pose = world.body_pose(container).copy()
    ctl.activity = f"dipping {tool} into {container}"
    m.approach(at(start_angle, 0.0), guard)
    if not world.touching(tool, container):
        # into contact: sideways to the wall (aimed a little beyond it), or down onto the floor
        ctl.activity = f"bringing {tool} against {container}"
        m.go(at(start_angle, beyond), TO_WALL_S, guard)
    if not m.hold_still(t.contact_wait_s, m.touching(tool, container)) and not world.touching(
        tool, container
    ):
        raise RuntimeFailure(f"stir: {tool} is in {container} but does not touch it")
    # circle from where the tip touches, at its height, kept on the wall (pressed a little beyond
    # it) or, on the floor, pressed onto it: the tool touches the container all the while
    tip = held_tool(ctx, side, tool).tip_world()
    out = float(np.linalg.norm((tip - floor) - float((tip - floor) @ up) * up))
    on_wall = out > wall - WALL_MARGIN_M
    height = floor + float((tip - floor) @ up) * up - (0.0 if on_wall else t.aim_beyond_m) * up
    rr = out + t.aim_beyond_m if on_wall else max(min(radius, room), out)
    m.go(at(start_angle, rr, height), t.press_s)  # pressed on where it touches
    ctl.activity = f"stirring {container} with {tool}"
    n = waypoints_per_cycle(period, CIRCLE_POINTS)  # fewer for fast circles: none a jump
    for k in range(1, max(1, round(turns)) * n + 1):
        m.go(at(start_angle + 2 * math.pi * k / n, rr, height), period / n)
    if not m.hold_still(t.contact_wait_s, m.touching(tool, container)) and not world.touching(
        tool, container
    ):
        raise RuntimeFailure(f"stir: {tool} lost contact with {container} while stirring"
                             + _lost_where(ctx, side, tool, container, start_pose))


def _lost_where(ctx: SkillContext, side: str, tool: str, container: str, start: np.ndarray) -> str:
    """Where the tool's tip ended in ``container`` (off its wall, above its floor) and how far the
    container moved since the tool went in (``start``: its pose then): what a user can change
    (the tool's or the container's size, how the other hand holds it)."""
    body = ctx.body(container)
    pose = ctx.world.body_pose(container)
    held = held_tool(ctx, side, tool)
    tip = pose[:3, :3].T @ (held.tip_world() - pose[:3, 3])  # in the container's frame
    off_wall = body.inner_radius - held.half_width - float(np.linalg.norm(tip[:2]))
    moved = float(np.linalg.norm(pose[:3, 3] - start[:3, 3]))
    return (f" (its tip ended {format_mm(off_wall)} off the wall, {format_mm(tip[2] - body.floor)}"
            f" above the floor; {container} moved {format_mm(moved)} while the tool was in it)")
