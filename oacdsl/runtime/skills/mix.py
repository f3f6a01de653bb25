"""``mix``: put the held mixer into a container and stir, ending with it in the container.

The mixer is carried upright above the container, lowered until it touches the
container (pushing the balls aside; the wrist force stops the descent at 15 N), and
moved in circles pressed lightly onto the bottom; it stays in the container at the end,
as the OAC's effect ``m <-> b`` says.
"""

from __future__ import annotations

import math

import numpy as np

from oacdsl.errors import RuntimeFailure
from oacdsl.runtime.skills.base import SkillContext
from oacdsl.runtime.skills.place import DESCENT_SPEED_M_S
from oacdsl.runtime.transforms import make_T

__all__ = ["mix", "STIR_RADIUS_M", "STIR_TURNS"]

STIR_RADIUS_M = 0.03
STIR_TURNS = 2
STIR_PERIOD_S = 1.2
#: Thickness of a container's bottom (objects.py), how far below it the tool is pressed,
#: and the wrist force that stops the descent if the container is never touched.
BOTTOM_M = 0.008
PRESS_M = 0.003
PUSH_LIMIT_N = 15.0
#: While stirring the tool is held this far below the bottom: a light press (about 10 N through the arm).
STIR_PRESS_M = 0.002


def mix(
    ctx: SkillContext,
    hand: str,
    tool: str,
    container: str,
    *,
    radius: float = STIR_RADIUS_M,
    turns: float = STIR_TURNS,
    period: float = STIR_PERIOD_S,
    force: float = PUSH_LIMIT_N,
) -> None:
    """Stir ``container`` with the held ``tool``: ``turns`` circles of ``radius`` (m), ``period``
    (s) each; the descent stops when it touches the container or the wrist feels ``force`` (N)."""
    world, ctl = ctx.world, ctx.ctl
    side = ctx.require_held(hand, tool)
    t_tool, tool_in_hand = ctx.held_pose(side, tool)
    t_bowl = world.body_pose(container)
    bowl = ctx.body(container)
    centre = t_bowl[:3, 3]
    upright = make_T(t_tool[:3, :3], (0.0, 0.0, 0.0))
    upright[:3, :3] = _upright(t_tool[:3, :3])

    def hand_for(p: np.ndarray) -> np.ndarray:
        return make_T(upright[:3, :3], p) @ np.linalg.inv(tool_in_hand)

    above = np.array([centre[0], centre[1], centre[2] + bowl.height + 0.04])
    ctl.activity = f"bringing {tool} over {container}"
    ctx.check_reachable(side, hand_for(above), f"the inside of {container}")
    ctx.carry(side, hand_for(above), {tool, container}, 1.8)
    ctl.activity = f"lowering {tool} into {container}"
    # the container's inner bottom; the tool is pressed a little below it, pushing the
    # (frictionless) balls aside, until it touches the container itself
    floor = centre[2] + BOTTOM_M
    bottom = np.array([centre[0], centre[1], floor - PRESS_M])
    depth = float(above[2] - bottom[2])
    touched = ctl.move(
        side,
        hand_for(bottom),
        depth / DESCENT_SPEED_M_S,
        guard=lambda: (
            world.touching(tool, container) or float(np.linalg.norm(ctl.force_change(side))) > force
        ),
    )
    if not touched and not ctl.wait(0.5, until=lambda: world.touching(tool, container)):
        raise RuntimeFailure(f"mix: {tool} went down into {container} without touching it")
    level = min(float(world.body_pose(tool)[2, 3]), floor) - STIR_PRESS_M
    ctl.activity = f"stirring {container} with {tool}"
    n = 24
    for k in range(1, int(round(turns)) * n + 1):
        a = 2 * math.pi * k / n
        r = radius * min(1.0, k / n)
        p = np.array([centre[0] + r * math.sin(a), centre[1] + r * (1 - math.cos(a)) * 0.5, level])
        ctl.move(side, hand_for(p), period / n)
    ctl.move(side, hand_for(np.array([centre[0], centre[1], level])), 0.4)
    ctl.wait(0.6, until=lambda: world.touching(tool, container))


def _upright(r: np.ndarray) -> np.ndarray:
    """The rotation with the same heading as ``r`` and its z axis vertical."""
    yaw = math.atan2(r[1, 0], r[0, 0])
    c, s = math.cos(yaw), math.sin(yaw)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
