"""``wipe``: press the held tool onto a surface and move it to and fro.

The tool is carried above the middle of the surface, lowered until the wrist feels the
contact, and moved in strokes across the surface while commanded slightly into it
(a light press, limited by the arm's stiffness); it stays on the surface at the end,
as the OAC's effect ``s <-> t`` says.

A surface the other hand holds up (a plate held by its edge, KIT Wipe) is wiped where it
is held, on its half away from that hand (:data:`FAR_M` off its middle), the strokes going
across: that hand's goal stays fixed, as strong a task as the wiping hand's (the
controller's usual hold of an idle hand re-anchors it at every motion, and the plate
would sink under the press), and every goal of the wiping hand is read from where the
surface is at that tick. ARMAR-III cannot hold a tool flat from above close to a plate
its other hand pinches from above (the whole-body IK leaves both hands 10–17 cm off),
so the wiping hand's orientation counts little (:data:`HELD_ORIENTATION_WEIGHT`): the
tool tilts onto the plate, touching it with its edge. The tool is lowered until the
simulation reports it touching the surface, and the skill fails when it does not, or
no longer touches it after the strokes.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from functools import partial

import numpy as np

from oacdsl.errors import RuntimeFailure
from oacdsl.runtime.motion import TUNING, Motion, OtherHand, other_side
from oacdsl.runtime.shapes import half_width
from oacdsl.runtime.skills.base import SkillContext
from oacdsl.runtime.transforms import MIN_JERK_PEAK, interpolate, make_T
from oacdsl.skills import SIGNATURES

__all__ = ["wipe", "FAR_M", "HELD_ORIENTATION_WEIGHT", "SIGNATURE"]

SIGNATURE = SIGNATURES["wipe"]
D = SIGNATURE.defaults()

#: How far below the surface's top the descent may go before it counts as a miss, m.
DESCENT_M = 0.08
#: Time back to the middle after the last stroke, s.
RETURN_S = 0.4
#: How far from the held surface's middle, away from the holding hand, the tool wipes, m.
FAR_M = 0.05
#: Weight of the wiping hand's orientation while it wipes a held surface (a hand's position
#: counts 1 per metre; 0.3 elsewhere): the tool may tilt on the surface rather than stay
#: out of reach.
HELD_ORIENTATION_WEIGHT = 0.02
#: Time to carry the tool over a held surface, s.
CARRY_S = 2.0


def wipe(
    ctx: SkillContext,
    hand: str,
    tool: str,
    surface: str,
    *,
    strokes: float = D["strokes"],
    length: float = D["length"],
    press: float = D["press"],
) -> None:
    """Wipe ``surface`` with the held ``tool``: ``strokes`` times ``length`` (m) to either side of
    its middle, pressed ``press`` (m) into it. Composition: carry over the middle, lower onto
    it (guarded by the wrist), press, slide to and fro, hold still."""
    side = ctx.require_held(hand, tool)
    other = other_side(side)
    if ctx.world.held.get(other) == surface:
        _wipe_held(ctx, side, other, tool, surface, round(strokes), length, press)
        return
    world, t = ctx.world, TUNING
    m = Motion(ctx, side)
    t_tool, tool_in_hand = ctx.held_pose(side, tool)
    t_surface = world.body_pose(surface)
    top = t_surface[2, 3] + ctx.body(surface).height
    above = make_T(t_tool[:3, :3], (t_surface[0, 3], t_surface[1, 3], top + t.hover_m)) @ np.linalg.inv(
        tool_in_hand
    )
    ctx.ctl.activity = f"bringing {tool} over {surface}"
    ctx.check_reachable(side, above, f"the middle of {surface}")
    m.carry(above, {tool, surface}, t.work_carry_s)
    ctx.ctl.activity = f"pressing {tool} onto {surface}"
    m.lower_onto_support(above, DESCENT_M, f"wiping {surface}")
    m.press(press, t.settle_s)
    pressed = m.here()
    ctx.ctl.activity = f"wiping {surface} with {tool}"
    sideways = t_surface[:3, 1] * length
    seconds = max(t.slide_min_s, length / t.slide_speed_m_s)
    for sign in (1.0, -1.0) * int(round(strokes)):
        m.go(make_T(pressed[:3, :3], pressed[:3, 3] + sign * sideways), seconds)
    m.go(pressed, RETURN_S)
    m.hold_still()


def _wipe_held(
    ctx: SkillContext,
    side: str,
    other: str,
    tool: str,
    surface: str,
    strokes: int,
    length: float,
    press: float,
) -> None:
    """Wipe ``surface`` held by hand ``other`` (see the module docstring)."""
    world, ctl = ctx.world, ctx.ctl
    ik = ctl.ik
    _, tool_in_hand = ctx.held_pose(side, tool)
    r_tool = world.body_pose(tool)[:3, :3].copy()
    t_surface = world.body_pose(surface)
    # the spot: on the half of the surface away from the holding hand, FAR_M off its middle
    away = t_surface[:2, 3] - world.frame_pose(f"grasp_{other}")[:2, 3]
    away = away / max(float(np.linalg.norm(away)), 1e-6)
    along = np.array([-away[1], away[0]])  # the strokes go across that direction
    height = ctx.body(surface).height
    # the strokes keep the tool's middle on the surface, its narrow half width in from the edge:
    # from the spot FAR_M off the middle, as far to either side as that leaves (a stroke of 8 cm
    # on a plate 12 cm in radius lifted the sponge off at one end for 0.6 s, stroke after stroke)
    room = ctx.body(surface).radius - half_width(ctx.body(tool))
    length = min(length, math.sqrt(max(room * room - FAR_M * FAR_M, 0.0)))

    def spot(shift: float, drop: float) -> np.ndarray:
        """T_world_grasp with the tool's base ``drop`` below HOVER_M above the spot, moved
        ``shift`` (m) along the strokes; read from where the surface is now."""
        t = world.body_pose(surface)
        xy = t[:2, 3] + FAR_M * away + shift * along
        p = np.array([xy[0], xy[1], t[2, 3] + height + TUNING.hover_m - drop])
        return make_T(r_tool, p) @ np.linalg.inv(tool_in_hand)

    def touching() -> bool:
        return world.touching(tool, surface)

    m = Motion(ctx, side, OtherHand.STEADY)

    def go(
        goal: Callable[[float], np.ndarray], seconds: float, guard: Callable[[], bool] | None = None
    ) -> bool:
        """Follow ``goal(s)``, s from 0 to 1 (min-jerk), the other hand's goal fixed; True when
        ``guard`` stopped it (where the hand really is). The tool may tilt on the surface."""
        return m.along(goal, seconds, guard, HELD_ORIENTATION_WEIGHT)

    def stroke_s(distance: float) -> float:
        return max(TUNING.slide_min_s, abs(distance) / TUNING.slide_speed_m_s)

    start = ik.goal(side)
    ctl.activity = f"bringing {tool} over {surface}"
    ctx.check_reachable(side, spot(0.0, 0.0), f"the middle of {surface}")
    go(lambda s: interpolate(start, spot(0.0, -TUNING.hover_m * (1.0 - s)), s), CARRY_S)
    ctl.activity = f"pressing {tool} onto {surface}"
    depth = TUNING.hover_m + DESCENT_M
    if not go(lambda s: spot(0.0, depth * s), MIN_JERK_PEAK * depth / TUNING.set_down_speed_m_s, touching):
        felt = float(np.linalg.norm(ctl.force_change(side)))
        raise RuntimeFailure(
            f"wipe: {tool} did not reach {surface} held by the other hand (the wrist felt {felt:.0f} N)"
        )
    # how far below the hover point it touched, then pressed on
    reached = float(spot(0.0, 0.0)[2, 3] - world.frame_pose(f"grasp_{side}")[2, 3])
    pressed = reached + press
    go(lambda s: spot(0.0, reached + press * s), TUNING.settle_s)
    ctl.activity = f"wiping {surface} with {tool}"
    last = 0.0
    for sign in (1.0, -1.0) * strokes:
        a, b = last, sign * length
        go(partial(_between, spot, a, b, pressed), stroke_s(b - a))
        last = b
    go(lambda s: spot(last * (1.0 - s), pressed), stroke_s(last))
    if not touching():  # the strokes lifted it: down again until it touches
        again = MIN_JERK_PEAK * DESCENT_M / TUNING.set_down_speed_m_s
        go(lambda s: spot(0.0, pressed + DESCENT_M * s), again, touching)
    m.hold_still()
    if not touching():
        raise RuntimeFailure(f"wipe: {tool} no longer touches {surface} after the strokes")
    # the next skill starts from the hand as it is, tool tilted and all (from the upright goal,
    # a lift turned the hand so fast that the wrist felt 68 N)
    ik.set_hand_target(side, ik.frame(f"grasp_{side}"))


def _between(
    spot: Callable[[float, float], np.ndarray], a: float, b: float, drop: float, s: float
) -> np.ndarray:
    """``spot`` moved from ``a`` to ``b`` along the strokes at phase ``s`` (0 … 1), ``drop`` down."""
    return spot(a + (b - a) * s, drop)
