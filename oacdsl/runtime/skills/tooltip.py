"""The working end of a held tool, and the tool turned so that this end points down.

A tool's *tip* is the end of its longest axis farther from the hand (a spoon's bowl, a
knife's point, a ladle's cup), read from the language's geometry
(:mod:`~oacdsl.runtime.shapes`). Skills that work with the tip (``stir``,
``scoop``, ``cut``) place the tip, not the hand: :class:`HeldTool` turns a wanted tip
position (and tool orientation) into the hand pose for it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from oacdsl.runtime.shapes import corners, tip_local
from oacdsl.runtime.skills.base import SkillContext
from oacdsl.runtime.transforms import make_T, rot_axis

__all__ = ["HeldTool", "held_tool", "pointing"]


@dataclass(frozen=True)
class HeldTool:
    """A tool in hand ``side``: its pose now (T_world_obj), its pose in the grasp frame
    (T_grasp_obj), its tip (object frame, m) and the unit direction from its middle to the
    tip (object frame)."""

    side: str
    t_world_obj: np.ndarray
    t_grasp_obj: np.ndarray
    tip: np.ndarray
    axis: np.ndarray
    #: half the tool's largest width across its axis at the tip's end (a spoon's bowl), m
    half_width: float

    def tip_world(self) -> np.ndarray:
        return self.t_world_obj[:3, :3] @ self.tip + self.t_world_obj[:3, 3]

    def hand_for(self, r_world_obj: np.ndarray, tip_world: np.ndarray) -> np.ndarray:
        """T_world_grasp that puts the tool, turned to ``r_world_obj``, with its tip at ``tip_world``."""
        t_obj = make_T(r_world_obj, tip_world - r_world_obj @ self.tip)
        return t_obj @ np.linalg.inv(self.t_grasp_obj)


def held_tool(ctx: SkillContext, side: str, tool: str) -> HeldTool:
    """The tool ``tool`` held by hand ``side``, with its tip (see the module docstring)."""
    t_obj, in_hand = ctx.held_pose(side, tool)
    c = corners(ctx.body(tool))
    span = c.max(axis=0) - c.min(axis=0)
    k = int(np.argmax(span))
    mid = 0.5 * (c.max(axis=0) + c.min(axis=0))
    grip = np.linalg.inv(in_hand)[:3, 3]  # the grasp centre in the object frame
    axis = np.zeros(3)
    axis[k] = 1.0 if grip[k] <= mid[k] else -1.0  # the end away from the hand
    tip = tip_local(ctx.body(tool), axis)
    near = c[np.abs((c - tip) @ axis) < 0.5 * span[k]]  # corners of the tip's half
    across = near - np.outer(near @ axis, axis)
    half_width = float(np.abs(across).max(initial=0.0))
    return HeldTool(side, t_obj, in_hand, tip, axis, half_width)


def pointing(tool: HeldTool, down: np.ndarray) -> np.ndarray:
    """R_world_obj: the tool turned by the smallest rotation so that its middle-to-tip axis
    points along ``down`` (a unit world direction)."""
    r = tool.t_world_obj[:3, :3]
    now = r @ tool.axis
    cross = np.cross(now, down)
    s, c = float(np.linalg.norm(cross)), float(now @ down)
    if s < 1e-9:
        if c > 0:
            return r.copy()
        perp = np.cross(now, (1.0, 0.0, 0.0) if abs(now[0]) < 0.9 else (0.0, 1.0, 0.0))
        return rot_axis(perp / np.linalg.norm(perp), np.pi) @ r
    return rot_axis(cross / s, float(np.arctan2(s, c))) @ r
