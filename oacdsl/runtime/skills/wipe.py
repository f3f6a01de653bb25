"""``wipe``: press the held tool onto a surface and move it to and fro.

The tool is carried above the middle of the surface, lowered until the wrist feels the
contact, and moved in strokes across the surface while commanded slightly into it
(a light press, limited by the arm's stiffness); it stays on the surface at the end,
as the OAC's effect ``s <-> t`` says.
"""

from __future__ import annotations

import numpy as np

from oacdsl.runtime.skills.base import SkillContext
from oacdsl.runtime.skills.place import lower_until_contact
from oacdsl.runtime.transforms import make_T

__all__ = ["wipe", "STROKE_M", "STROKES"]

STROKE_M = 0.06
STROKES = 3
PRESS_M = 0.004


def wipe(
    ctx: SkillContext,
    hand: str,
    tool: str,
    surface: str,
    *,
    strokes: float = STROKES,
    length: float = STROKE_M,
    press: float = PRESS_M,
) -> None:
    """Wipe ``surface`` with the held ``tool``: ``strokes`` times ``length`` (m) to either side of
    its middle, pressed ``press`` (m) into it."""
    world, ctl = ctx.world, ctx.ctl
    side = ctx.require_held(hand, tool)
    t_tool, tool_in_hand = ctx.held_pose(side, tool)
    t_surface = world.body_pose(surface)
    top = t_surface[2, 3] + ctx.body(surface).height

    def hand_for(p: np.ndarray) -> np.ndarray:
        return make_T(t_tool[:3, :3], p) @ np.linalg.inv(tool_in_hand)

    above = np.array([t_surface[0, 3], t_surface[1, 3], top + 0.04])
    ctl.activity = f"bringing {tool} over {surface}"
    ctx.check_reachable(side, hand_for(above), f"the middle of {surface}")
    ctx.carry(side, hand_for(above), {tool, surface}, 1.8)
    ctl.activity = f"pressing {tool} onto {surface}"
    contact = lower_until_contact(ctx, side, hand_for(above), 0.08, f"wiping {surface}")
    pressed = contact.copy()
    pressed[2, 3] -= press
    ctl.move(side, pressed, 0.3)
    ctl.activity = f"wiping {surface} with {tool}"
    sideways = t_surface[:3, 1] * length
    for sign in (1.0, -1.0) * int(round(strokes)):
        goal = pressed.copy()
        goal[:3, 3] += sign * sideways
        ctl.move(side, goal, 0.7 * max(1.0, length / STROKE_M))
    ctl.move(side, pressed, 0.4)
    ctl.wait(0.3)
