"""``place(h, o)``: set the held object down where the step's predicted effect says, feeling
for the support; or, in a hand-over, let go of what the other hand holds too.

Where it goes is read from the world state the step is predicted to leave
(``SkillContext.expected``): when the object is to touch another free object (the sponge
stays on the tray it wiped), it is set down on that object — where it is, when it touches
it already, else above its middle; otherwise (or when it was picked up from that very
object) it goes back to where it was picked up, unless something stands there now, what it
stood on is held, or it was taken from the other hand (a hand-over: that pose is in the
air): then on the first free spot of the table. With ``layout demonstrated``, an object the
demonstration set down on the table elsewhere goes to a free spot near that place
(``Layout.set_downs``, :mod:`oacdsl.runtime.demo_places`; none passing the free-spot tests:
as without it). An object let go on an open container's rim is slid onto its middle first
(:func:`~oacdsl.runtime.motion.rotate.centre_over`). Composition: carry over the spot, lower
onto the support (guarded by the wrist force), hold still, release, withdraw.
"""

from __future__ import annotations

import math
from collections.abc import Collection
from dataclasses import replace

import numpy as np

from oacdsl.errors import RuntimeFailure
from oacdsl.runtime.motion import TUNING, Motion
from oacdsl.runtime.motion.hand import felt_nothing
from oacdsl.runtime.motion.rotate import centre_over
from oacdsl.runtime.motion.spots import free_spots
from oacdsl.runtime.shapes import lowest_z
from oacdsl.runtime.skills.base import Pick, SkillContext
from oacdsl.runtime.skills.free_spot import free_spot, hand_offsets, spot_near
from oacdsl.runtime.transforms import make_T, rot_z
from oacdsl.skills import SIGNATURES

__all__ = ["place", "resting", "target_support", "set_down_pose", "SIGNATURE"]

SIGNATURE = SIGNATURES["place"]
D = SIGNATURE.defaults()


def place(ctx: SkillContext, hand: str, obj: str, *, force: float = D["force"]) -> None:
    """Set the held ``obj`` down; the descent stops when the wrist feels ``force`` (N)."""
    side = ctx.require_held(hand, obj)
    m = Motion(ctx, side)
    pick = ctx.picked.get(side)
    if ctx.other_holder(side, obj) is None:
        _set_down(ctx, m, obj, pick, force)
        m.hold_still()  # the arm, which lags its command, comes to rest before it lets go
    pick = ctx.picked.get(side, pick)  # its approach turned with a round object set down turned
    m.release(obj)
    m.withdraw(pick.approach if pick is not None else None)


def target_support(ctx: SkillContext, obj: str) -> str | None:
    """The object ``obj`` is predicted to stand on after the step (another free object it
    touches in the step's predicted world state), or None for "back where it was"."""
    if ctx.expected is None:
        return None
    partners = sorted(ctx.expected.partners(obj) & ctx.objects())
    return partners[0] if partners else None


def set_down_pose(
    ctx: SkillContext, side: str, obj: str, pick: Pick | None, passing: Collection[str] = ()
) -> tuple[np.ndarray, str, str | None]:
    """(T_world_grasp above where ``obj`` goes, a name for that place, the object it goes
    is predicted to touch or None, left out of the obstacles): back where it was picked up,
    or onto the support the step predicts. ``passing``: objects the other hand carries away
    meanwhile, no support however they hang over that place now."""
    world = ctx.world
    t_obj, t_obj_in_hand = ctx.held_pose(side, obj)
    origin = pick.origin if pick is not None else t_obj
    support = target_support(ctx, obj)
    r_obj = origin[:3, :3]  # standing as it stood when it was picked up
    approach = pick.approach if pick is not None else None
    demo = _demonstrated_place(ctx, obj, pick) if support is None else None
    spot = None
    if demo is not None:  # where the person set it down, on a spot free and roomy enough
        r_obj = rot_z(math.atan2(t_obj[1, 0], t_obj[0, 0]))  # upright, turned as it is held now
        spot = spot_near(ctx, side, obj, t_obj_in_hand, r_obj, approach, demo)
        if spot is None:
            r_obj = origin[:3, :3]
    if spot is not None:
        xy, turn = spot
        where, r_obj = "its demonstrated place", rot_z(turn) @ r_obj
        if pick is not None and turn:  # the hand turned about the object: it withdraws turned too
            ctx.picked[side] = replace(pick, approach=rot_z(turn) @ pick.approach)
    elif support is None and not _origin_free(ctx, obj, pick):
        r_obj = rot_z(math.atan2(t_obj[1, 0], t_obj[0, 0]))  # upright, turned as it is held now
        xy, turn = free_spot(ctx, side, obj, t_obj_in_hand, r_obj, approach)
        where, r_obj = "a free spot of the table", rot_z(turn) @ r_obj
        if pick is not None and turn:  # the hand turned about the object: it withdraws turned too
            ctx.picked[side] = replace(pick, approach=rot_z(turn) @ pick.approach)
    elif support is None or (pick is not None and support in pick.supports):
        xy, where = origin[:2, 3], "its place"  # back where it was picked up (it stood there)
    elif world.touching(obj, support):  # on the support already (a wipe, a ladle in a bowl): set it down here
        return ctx.ctl.ik.goal(side), support, support
    else:
        xy, where = world.body_pose(support)[:2, 3], support
    height = ctx.support_height(xy, exclude=obj, passing=passing)
    target_obj = make_T(r_obj, (xy[0], xy[1], height + TUNING.hover_m))
    return target_obj @ np.linalg.inv(t_obj_in_hand), where, support


def _demonstrated_place(ctx: SkillContext, obj: str, pick: Pick | None) -> np.ndarray | None:
    """(x, y) (m) of the table where the demonstration sets ``obj`` down this time (the k-th
    of its set-down places for its k-th set-down on the table, the last one after that;
    :mod:`oacdsl.runtime.demo_places`), or None: none known, or nearer than the tuning's
    ``demo_spot_back_m`` to where it was picked up while that is free (it goes back there)."""
    places = ctx.world.layout.set_downs.get(obj)
    count = ctx.set_downs.get(obj, 0)
    ctx.set_downs[obj] = count + 1
    if not places:
        return None
    xy = np.asarray(places[min(count, len(places) - 1)], float)
    back = pick is not None and float(np.linalg.norm(xy - pick.origin[:2, 3])) < TUNING.demo_spot_back_m
    return None if back and _origin_free(ctx, obj, pick) else xy


def _origin_free(ctx: SkillContext, obj: str, pick: Pick | None) -> bool:
    """Whether ``obj`` may go back where it was picked up: not when it was taken from the
    other hand, when what it stood on there is now held by a hand (a lid taken off the bottle
    the other hand holds up), nor when another object's footprint now overlaps that spot."""
    if pick is None:
        return True
    if pick.from_hand:  # taken from the other hand: where that was is in the air, not a place
        return False
    held = {o for o in ctx.world.held.values() if o is not None}
    if pick.supports & held:
        return False
    room = ctx.body(obj).radius  # footprints that overlap it: something else stands there now
    here = pick.origin[:2, 3]
    return all(
        float(np.linalg.norm(xy - here)) >= room + r for xy, r, _ in ctx.obstacles({obj} | set(pick.supports))
    )


def resting(ctx: SkillContext, obj: str, support: str | None) -> bool:
    """Whether the held ``obj`` rests on what it is set down on: it touches something that
    bears it (``support``, when given), its lowest point no more than the tuning's
    ``rest_gap_m`` above the surface under its middle (not hanging on a neighbour's rim)."""
    world = ctx.world
    if not world.supported(obj) or (support is not None and not world.touching(obj, support)):
        return False
    t_obj = world.body_pose(obj)
    under = ctx.support_height(t_obj[:2, 3], exclude=obj)
    return lowest_z(ctx.body(obj), t_obj) - under <= TUNING.rest_gap_m


def _best_reached_spot(ctx: SkillContext, side: str, obj: str, pick: Pick | None) -> np.ndarray:
    """T_world_grasp above the free spot of the table where the whole-body IK brings the hand
    nearest to where the guarded descent ends, ``obj`` upright, turned as it is held now."""
    t_obj, t_obj_in_hand = ctx.held_pose(side, obj)
    r_obj = rot_z(math.atan2(t_obj[1, 0], t_obj[0, 0]))
    hand_in_obj = np.linalg.inv(t_obj_in_hand)

    def at(xy: np.ndarray, dz_m: float) -> np.ndarray:
        return make_T(r_obj, (xy[0], xy[1], ctx.support_height(xy, exclude=obj) + dz_m)) @ hand_in_obj

    back = np.array([0.0, 0.0, -1.0]) if pick is None else pick.approach
    offsets = hand_offsets(hand_in_obj, r_obj, back)
    spots = free_spots(ctx.world, side, obj, ctx.body(obj).radius, hand_xy_m=offsets)
    if not spots:
        raise RuntimeFailure(f"place: no free spot on the table for {obj}")
    best = min(spots, key=lambda xy: ctx.ctl.ik.try_reach(side, at(xy, -TUNING.support_search_m)).position_m)
    return at(best, TUNING.hover_m)


def _set_down(ctx: SkillContext, m: Motion, obj: str, pick: Pick | None, force: float) -> None:
    """Carry ``obj`` above where it goes and lower it until the wrist feels the support."""
    ctl, t = ctx.ctl, m.tuning
    hover, where, support = set_down_pose(ctx, m.side, obj, pick)
    if support is not None and ctx.world.touching(obj, support):  # no hover: that would break the contact
        if centre_over(ctx, m, obj, support):  # let go off a pot's middle, a lid stays 2-3 cm off it
            hover = ctl.ik.goal(m.side)
        ctl.activity = f"setting {obj} down on {support}"
        m.lower_onto_support(hover, t.support_search_m, f"placing {obj}", force)
        return
    ctl.activity = f"carrying {obj} to {where}"
    ctx.check_reachable(m.side, hover, f"the place of {obj} on {where}")
    m.carry(hover, {obj} if support is None else {obj, support})
    m.hold_still(t.carry_pause_s)
    ctl.activity = f"setting {obj} down"
    depth = t.hover_m + t.support_search_m
    if m.felt_support(hover, depth, force):
        if support is not None and ctx.world.touching(obj, support):
            centre_over(ctx, m, obj, support)  # the arm lags: it may have come down off the middle
        return
    if resting(ctx, obj, support):
        # the arm stalled with the object already resting on its support, too lightly for the
        # wrist to feel it (a 3 cm stall at the edge of the left arm's reach, a sponge on the
        # table: KIT Wipe, mirrored random takes, seed 1)
        return
    if where != "its place" or ctx.world.supported(obj):
        raise felt_nothing(f"placing {obj}", depth)
    # the arm stalled above its place, nothing felt, the object resting on nothing: at the
    # edge of its reach (a sponge that shifted in the hand as it wiped, set down on the
    # robot's far side); raised again, it goes to the free spot whose descent the hand
    # reaches best
    m.go(hover, t.lift_s)
    hover = _best_reached_spot(ctx, m.side, obj, pick)
    ctl.activity = f"carrying {obj} to a free spot of the table"
    m.carry(hover, {obj})
    m.hold_still(t.carry_pause_s)
    ctl.activity = f"setting {obj} down"
    m.lower_onto_support(hover, depth, f"placing {obj}", force)
