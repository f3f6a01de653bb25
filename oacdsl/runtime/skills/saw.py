"""``saw(h, k, t)``: a held tool (a knife) brought down onto an object and drawn to and fro
along its own length, pressed on (cutting a cucumber the other hand holds on a board).

Composition: ``touch``'s way onto the target (carried over it, a guarded approach down until
the two touch; a solid target the other hand holds is worked at its far end from that hand),
pressed ``press`` on; then ``strokes`` strokes there and back along the tool's longest
horizontal axis (a knife's blade), each ``length`` to either side of where it touched, one
stroke in ``period`` seconds but no faster than the tuning's slide speed. The strokes keep the
contact: while the tool does not touch the target, the path is lowered (the slide primitive's
seek). It stays on the target at the end (the OAC's effect ``k <-> t``).

Strokes, length and period come from the demonstration (the composer writes them on the step
from the sub-action's oscillation, :mod:`oacdsl.matching.demoparams`): a stroke goes along
the blade, which passes over the target, so its length is not bounded by the target's width,
only by the tool's own (``length`` at most its half length less the tuning's end margin).
The other hand keeps its goal fixed while it holds something (as ``touch``).
"""

from __future__ import annotations

from functools import partial

import numpy as np

from oacdsl.errors import RuntimeFailure
from oacdsl.runtime.motion import TUNING, Motion, OtherHand, other_side
from oacdsl.runtime.shapes import world_corners
from oacdsl.runtime.skills.base import SkillContext
from oacdsl.runtime.skills.touch import bring_onto
from oacdsl.runtime.transforms import interpolate, make_T
from oacdsl.skills import SIGNATURES

__all__ = ["saw", "blade_direction", "SIGNATURE"]

SIGNATURE = SIGNATURES["saw"]
D = SIGNATURE.defaults()


def blade_direction(corners: np.ndarray, T_world_tool: np.ndarray) -> tuple[np.ndarray, float]:
    """(horizontal unit direction, half extent along it, m) of the tool's longest horizontal
    axis (its frame's x or y), from its box ``corners`` (world)."""
    best: tuple[np.ndarray, float] | None = None
    for axis in (T_world_tool[:3, 0], T_world_tool[:3, 1]):
        u = np.array([axis[0], axis[1], 0.0])
        norm = float(np.linalg.norm(u))
        if norm == 0.0:  # a vertical axis
            continue
        u /= norm
        d = corners @ u
        half = float(d.max() - d.mean())  # a box's corners lie symmetric about its middle
        if best is None or half > best[1]:
            best = (u, half)
    if best is None:
        raise RuntimeFailure("saw: the tool has no horizontal axis to stroke along")
    return best


def saw(
    ctx: SkillContext,
    hand: str,
    tool: str,
    target: str,
    *,
    strokes: float = D["strokes"],
    length: float = D["length"],
    period: float = D["period"],
    press: float = D["press"],
    hover: float = D["hover"],
    force: float = D["force"],
) -> None:
    """``strokes`` strokes of the held ``tool`` on ``target``, ``length`` (m) to either side, one
    in ``period`` (s), pressed ``press`` (m) on after a guarded approach from ``hover`` (m) above;
    fail when the wrist feels ``force`` (N) first or the tool ends off the target."""
    world, t = ctx.world, TUNING
    side = ctx.require_held(hand, tool)
    if target not in world.layout.bodies or not ctx.body(target).solids:
        raise RuntimeFailure(f"saw: {target!r} is no object of the scene")
    other = other_side(side)
    held_target = world.held.get(other) == target
    keep = world.held.get(other) is not None and not (held_target and ctx.body(target).container)
    m = Motion(ctx, side, OtherHand.STEADY if keep else OtherHand.IDLE)
    away = world.frame_pose(f"grasp_{other}")[:3, 3] if keep and held_target else None
    if not world.touching(tool, target):
        if not bring_onto(ctx, m, tool, target, hover, force, away):
            raise RuntimeFailure(
                f"saw: {tool} did not reach {target} (the wrist felt {m.force_n():.0f} N)"
            )
        m.press(press)
    t_tool = world.body_pose(tool)
    u, half = blade_direction(world_corners(ctx.body(tool), t_tool), t_tool)
    reach = min(length, max(half - t.end_margin_m, 0.0))
    n = max(1, round(strokes))
    ends = [sign * reach for _ in range(n) for sign in (1.0, -1.0)] + [0.0]
    way = float(np.sum(np.abs(np.diff([0.0, *ends]))))
    speed = min(way / max(n * period, t.slide_min_s), t.slide_speed_m_s)
    middle = m.here()
    on = m.touching(tool, target)
    ctx.ctl.activity = f"sawing {target} with {tool}"
    last = 0.0
    for end in ends:
        a = make_T(middle[:3, :3], middle[:3, 3] + last * u)
        b = make_T(middle[:3, :3], middle[:3, 3] + end * u)
        m.along(partial(interpolate, a, b), abs(end - last) / speed, keep_contact=on)
        last = end
    if not (m.hold_still(t.contact_wait_s, on) or on()):
        raise RuntimeFailure(f"saw: {tool} left {target} during its strokes")
