"""``mix_both``: both hands' tools in one container at once, mixing side by side (a salad
mixed with a fork and a spoon).

Each tool works on its hand's half of the container: its tip
(:mod:`~oacdsl.runtime.skills.tooltip`) goes to a *spot* :data:`MIX_SPREAD` × the inner radius from
the middle, on the line from the right hand to the left hand, the tool turned tip down and
leaning ``tilt`` from the vertical with its handle towards its hand (so the hands stay
apart and above the rim). Both arms move together (the lockstep of
:mod:`~oacdsl.runtime.skills.bimanual`): over the rim, down onto the floor until each tool
touches the container (``depth`` 0, the default) or to ``depth`` above the floor,
``turns`` circles of ``radius`` (m) in ``period`` (s) each, both tips in phase, so that
the distance between them never changes (the radius is clamped so that each tool stays
clear of the wall). On the floor the tips circle pressed lightly on it: each tool touches
the container while it mixes, as the demonstrated servers touch the bowl. Then both are
set on the floor (the OAC's effect: both tools touch it) and pressed on a moment. The container is read
where it is when the skill starts.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from functools import partial

import numpy as np

from oacdsl.errors import RuntimeFailure
from oacdsl.runtime.motion import TUNING, waypoints_per_cycle
from oacdsl.runtime.motion.both import move_both, turn_both
from oacdsl.runtime.simworld import SimWorld
from oacdsl.runtime.skills.base import REACH_TOLERANCE_M, SkillContext, cm
from oacdsl.runtime.skills.bimanual import reach_both
from oacdsl.runtime.skills.tooltip import HeldTool, held_tool, pointing
from oacdsl.runtime.transforms import MIN_JERK_PEAK, make_T, rot_axis
from oacdsl.skills import SIGNATURES

__all__ = ["mix_both", "MIX_SPREAD", "SIGNATURE"]

SIGNATURE = SIGNATURES["mix_both"]
D = SIGNATURE.defaults()
#: Each tip's spot: this fraction of the inner radius from the middle.
MIX_SPREAD = 0.5
#: Points per circle (fewer for a fast one: :func:`~oacdsl.runtime.motion.waypoints_per_cycle`).
CIRCLE_POINTS = 16
#: How far below the floor the tips are aimed at the end (a contact stops them), m.
AIM_BELOW_FLOOR_M = 2 * TUNING.aim_beyond_m
#: How far below where it touched each hand holds its tool while it rests, m (without it a
#: tool could spring back off the floor; from 3 mm on, the tool shifts in the hand's weld
#: and the fingers of a hand holding a 2 cm handle lose their contact with it: KIT Mix).
REST_PRESS_M = 0.002


def _hand_points(world: SimWorld, side: str, t_hand: np.ndarray, grid: np.ndarray) -> list[np.ndarray]:
    """Per geom of hand ``side`` (the fingers as they are now), the points ``grid`` (n, 3: -1
    to 1 along each half-size) of its bounding box, moved with the hand to ``t_hand``
    (T_world_grasp), world, m."""
    m, d = world.model, world.data
    move = t_hand @ np.linalg.inv(world.frame_pose(f"grasp_{side}"))
    bodies = np.array(sorted(world.hand_bodies[side]))
    out = []
    for g in np.flatnonzero(np.isin(m.geom_bodyid, bodies)):
        centre, half = m.geom_aabb[g, :3], m.geom_aabb[g, 3:]
        pts = (centre + grid * half) @ d.geom_xmat[g].reshape(3, 3).T + d.geom_xpos[g]
        out.append(pts @ move[:3, :3].T + move[:3, 3])
    return out


def _below_rim(
    world: SimWorld, side: str, t_hand: np.ndarray, rim: np.ndarray, inner: float, outer: float
) -> float:
    """How far (m) hand ``side`` (its geoms' bounding boxes, the fingers as they are now),
    moved to ``t_hand`` (T_world_grasp), reaches below :data:`TUNING.rim_clearance_m` over the
    rim (``rim``: the rim's centre, world, m; ``inner``, ``outer``: its radii, m) where it is
    within that clearance of the rim across (negative: clear of it). An upright container."""
    corners = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)], dtype=float)
    worst = -np.inf
    for pts in _hand_points(world, side, t_hand, corners):
        across = np.linalg.norm(pts[:, :2] - rim[:2], axis=1)
        if across.max() < inner - TUNING.rim_clearance_m or across.min() > outer + TUNING.rim_clearance_m:
            continue  # wholly inside the rim or wholly outside it
        worst = max(worst, float(rim[2]) + TUNING.rim_clearance_m - float(pts[:, 2].min()))
    return worst


def _over_rim(
    world: SimWorld, side: str, t_hand: np.ndarray, rim: np.ndarray, inner: float, outer: float
) -> float:
    """How high (m) the lowest point of hand ``side`` moved to ``t_hand`` is above the rim
    where it is over the rim (``rim``: its centre; ``inner``, ``outer``: its radii, m), its
    geoms' bounding boxes sampled at corners and edges' and faces' middles; +inf when nothing
    is over it. Finer than :func:`_below_rim`, which takes a whole box straddling the rim: a
    hand crossing the far rim to lean a tool in has its fingers beside the wall, outside."""
    ticks = (-1, 0, 1)
    grid = np.array([[sx, sy, sz] for sx in ticks for sy in ticks for sz in ticks], dtype=float)
    low = np.inf
    for pts in _hand_points(world, side, t_hand, grid):
        across = np.linalg.norm(pts[:, :2] - rim[:2], axis=1)
        over = (across >= inner) & (across <= outer)
        if over.any():
            low = min(low, float(pts[over, 2].min()) - float(rim[2]))
    return low


def _lean_room(world: SimWorld, starts: Mapping[str, np.ndarray], axis: np.ndarray,
               pivots: Mapping[str, np.ndarray], lean: float, rim: np.ndarray, inner: float,
               outer: float) -> float:
    """The largest turn (rad, at most ``lean``) of each hand from ``starts`` (side →
    T_world_grasp) about ``axis`` through its pivot along which no hand comes down onto the
    rim (:func:`_over_rim`), in steps of :data:`TUNING.lean_step_rad`. (Kept the rim's
    clearance above it, the KIT Mix servers, leaned 29° instead of 40°, ended 32-35° from
    the vertical, one standing on its head, and the mixing circles were no longer found in
    the span that holds them and the rest.)"""
    steps = max(1, math.ceil(lean / TUNING.lean_step_rad))
    room = 0.0
    for k in range(1, steps + 1):
        a = lean * k / steps
        r = rot_axis(axis, a)
        for s, pose in starts.items():
            turned = make_T(r @ pose[:3, :3], pivots[s] + r @ (pose[:3, 3] - pivots[s]))
            if _over_rim(world, s, turned, rim, inner, outer) < 0:
                return room
        room = a
    return room


def _felt(ctx: SkillContext, side: str, force: float) -> bool:
    """The wrist of ``side`` felt more than ``force`` (N) since its motion began."""
    return float(np.linalg.norm(ctx.ctl.force_change(side))) > force


def _landed(ctx: SkillContext, side: str, tool: str, container: str, force: float) -> bool:
    """``tool`` touches ``container``, or the wrist of ``side`` felt more than ``force`` (N)."""
    return ctx.world.touching(tool, container) or _felt(ctx, side, force)


def _land(ctx: SkillContext, down: Mapping[str, np.ndarray], tools: Mapping[str, str], container: str,
          travel: float, force: float) -> None:
    """Both hands towards ``down`` (T_world_grasp each) over ``travel`` (m), each stopping
    when its tool touches ``container`` or its wrist feels ``force`` (N)."""
    move_both(
        ctx.ctl,
        down,
        MIN_JERK_PEAK * travel / TUNING.approach_speed_m_s,
        {s: partial(_landed, ctx, s, tools[s], container, force) for s in down},
    )


def _path(ctx: SkillContext, phases: Sequence[Mapping[str, np.ndarray]], seconds: Sequence[float]) -> None:
    for goals, s in zip(phases, seconds, strict=True):
        if s > 0:
            move_both(ctx.ctl, goals, s)


def mix_both(
    ctx: SkillContext,
    h1: str,
    t1: str,
    h2: str,
    t2: str,
    container: str,
    *,
    radius: float = D["radius"],
    period: float = D["period"],
    turns: float = D["turns"],
    tilt: float = D["tilt"],
    depth: float = D["depth"],
    force: float = D["force"],
    lean: float = D["lean"],
) -> None:
    """Mix in ``container`` with ``t1`` held by ``h1`` and ``t2`` held by ``h2`` at once:
    ``turns`` circles of ``radius`` (m), ``period`` (s) each, the tips ``depth`` (m) above the
    floor, each on its hand's half of it, leaning ``tilt`` (rad); both
    end on the floor, touching the container."""
    world, ctl = ctx.world, ctx.ctl
    if t1 == t2:
        raise RuntimeFailure(f"mix_both needs two tools ({t1} given twice)")
    sides = (ctx.require_held(h1, t1), ctx.require_held(h2, t2))
    if sides[0] == sides[1]:
        raise RuntimeFailure(f"mix_both needs two different hands ({h1} given twice)")
    body = ctx.body(container)
    if not body.container:
        raise RuntimeFailure(f"mix_both: {container!r} is no container (its shape has no shell)")
    tools = dict(zip(sides, (t1, t2), strict=True))
    t_c = world.body_pose(container)
    up = t_c[:3, 2]
    floor = t_c[:3, 3] + body.floor * up
    rim = t_c[:3, 3] + body.rim_height * up
    # across: the horizontal unit direction from the right hand to the left hand
    hand_xy = {s: world.frame_pose(f"grasp_{s}")[:3, 3] for s in sides}
    across = hand_xy["l"] - hand_xy["r"]
    across[2] = 0.0
    across /= max(float(np.linalg.norm(across)), 1e-9)
    held: dict[str, HeldTool] = {s: held_tool(ctx, s, tools[s]) for s in sides}
    half = max(h.half_width for h in held.values())
    inner = body.inner_radius
    offset = max(MIX_SPREAD * inner, half + TUNING.wall_margin_m)
    room = inner - offset - half - TUNING.wall_margin_m
    if room < 0:
        raise RuntimeFailure(
            f"mix_both: {container} is too narrow for {t1} and {t2} side by side"
            f" ({inner * 200:.0f} cm inside, the tools {half * 200:.0f} cm wide)"
        )
    r = min(radius, room)
    spot = {s: floor + (offset if s == "l" else -offset) * across for s in sides}
    r_work: dict[str, np.ndarray] = {}
    for s in sides:
        out = spot[s] - floor
        out /= float(np.linalg.norm(out))
        down = -math.cos(tilt) * up - math.sin(tilt) * out  # the handle leaning out, towards the hand
        r_work[s] = pointing(held[s], down / np.linalg.norm(down))
    e1 = np.cross(up, across)
    e1 /= np.linalg.norm(e1)

    def hand(s: str, tip: np.ndarray) -> np.ndarray:
        return held[s].hand_for(r_work[s], tip)

    def short(s: str, above_floor: float) -> float:
        """How far (m) hand ``s`` comes below the rim's clearance with its tip ``above_floor``."""
        return _below_rim(
            world, s, hand(s, spot[s] + above_floor * up), rim, body.inner_radius, body.rim_radius
        )

    # the tools end on the floor: the hands must stay clear of the rim there
    worst = max(sides, key=lambda s: short(s, 0.0))
    if short(worst, 0.0) > 0:
        raise RuntimeFailure(
            f"mix_both: {tools[worst]} is too short to reach the floor of {container} with the hand"
            f" clear of its rim (its tip stays {cm(short(worst, 0.0))} above the floor);"
            f" a grasp farther up its handle (a larger grasp offset) reaches deeper"
        )
    # the tips' height while circling: raised as far as both hands need to stay clear of the rim
    lift = max(0.0, *(short(s, depth) for s in sides))
    on_floor = depth + lift <= 0
    # on the floor: dipped to a hover above it, then down until each tool touches it
    level = {s: spot[s] + (TUNING.hover_m if on_floor else depth + lift) * up for s in sides}

    def at(angle: float, rr: float) -> dict[str, np.ndarray]:
        d = rr * (math.cos(angle) * e1 + math.sin(angle) * across)
        return {s: hand(s, level[s] + d) for s in sides}

    above = {s: hand(s, spot[s] + (float((rim - spot[s]) @ up) + TUNING.above_rim_m) * up) for s in sides}
    ctl.activity = f"bringing {t1} and {t2} over {container}"
    for goals, what in ((above, "over"), (at(0.0, r), "the circles in"), (at(math.pi, r), "the circles in")):
        err = reach_both(ctx, goals)
        if err > REACH_TOLERANCE_M:
            raise RuntimeFailure(
                f"mix_both: {what} {container} is out of reach of {h1} and {h2} together: the best"
                f" whole-body IK solution leaves a hand off by {cm(err)}"
            )
    paths = {s: ctx.carry_path(s, above[s], {t1, t2, container}, TUNING.work_carry_s) for s in sides}
    _path(
        ctx,
        [{s: paths[s][k][0] for s in sides} for k in range(3)],
        [max(paths[s][k][1] for s in sides) for k in range(3)],
    )
    ctl.activity = f"dipping {t1} and {t2} into {container}"
    start = at(0.0, 0.0)
    travel = max(float(np.linalg.norm(above[s][:3, 3] - start[s][:3, 3])) for s in sides)
    guards = {s: partial(_felt, ctx, s, force) for s in sides}
    move_both(ctl, start, MIN_JERK_PEAK * travel / TUNING.approach_speed_m_s, guards)
    if on_floor:
        _land(ctx, {s: hand(s, spot[s] - AIM_BELOW_FLOOR_M * up) for s in sides}, tools, container,
              TUNING.hover_m + AIM_BELOW_FLOOR_M, force)
        for s in sides:  # circling lightly pressed on where each touched
            tip = held_tool(ctx, s, tools[s]).tip_world()
            level[s] = spot[s] + float((tip - spot[s]) @ up - TUNING.slide_press_m) * up
    ctl.activity = f"mixing in {container} with {t1} and {t2}"
    n = waypoints_per_cycle(period, CIRCLE_POINTS)  # fewer for fast circles: none a jump
    for k in range(1, max(1, round(turns)) * n + 1):
        move_both(ctl, at(2 * math.pi * k / n, r * min(1.0, k / n)), period / n)
    ctl.activity = f"resting {t1} and {t2} in {container}"
    if lean > 0:
        # to the near side of each spot, then leaning away from the robot about the head's far
        # edge (each tool in its own plane: the two never cross), on the floor
        e1 = -e1  # away from the robot (leaning towards it, the arms reach 15° at most)
        reach = inner - half - TUNING.wall_margin_m
        back = math.sqrt(max(reach * reach - offset * offset, 0.0))
        near = {s: hand(s, level[s] - back * e1) for s in sides}
        move_both(ctl, near, MIN_JERK_PEAK * back / TUNING.approach_speed_m_s)
        edges = {s: level[s] - back * e1 + half * e1 for s in sides}
        # no farther than the hands, crossing the far rim, stay above it (leaned farther, a
        # hand presses the rim and lifts its tool off the floor: a shallow bowl)
        lean = _lean_room(world, near, np.cross(up, e1), edges, lean, rim, inner, body.rim_radius)
        r_lean = rot_axis(np.cross(up, e1), lean)
        for s in sides:
            r_work[s] = r_lean @ r_work[s]
            level[s] = edges[s] + r_lean @ (level[s] - back * e1 - edges[s])
            spot[s] = spot[s] + float((level[s] - spot[s]) @ e1) * e1
        # along the arc about each head's far edge (a straight move cuts the chord, pushing the
        # heads into the floor and the fingers down onto the far rim)
        turn_both(ctl, near, np.cross(up, e1), edges, lean, TUNING.lift_s)
        _land(ctx, {s: hand(s, level[s] - TUNING.hover_m * up) for s in sides}, tools, container,
              TUNING.hover_m, force)
    else:
        move_both(ctl, at(0.0, 0.0), TUNING.settle_s)
        _land(ctx, {s: hand(s, spot[s] - AIM_BELOW_FLOOR_M * up) for s in sides}, tools, container,
              depth + lift + AIM_BELOW_FLOOR_M, force)
        # each hand holds its tool pressed lightly on (stopped where it was, an arm lags its
        # command and springs back: the tool rose off the floor)
        pressed = {s: world.frame_pose(f"grasp_{s}") for s in sides}
        for t in pressed.values():
            t[2, 3] -= REST_PRESS_M
        move_both(ctl, pressed, TUNING.settle_s)
        ctl.wait(TUNING.settle_s)
    missing = [tools[s] for s in sides if not world.touching(tools[s], container)]
    if missing:
        raise RuntimeFailure(f"mix_both: {' and '.join(missing)} in {container} but not touching it")
