"""``place``: set the held object down where the step's predicted effect says, feeling for
the support; or, in a hand-over, let go of what the other hand holds too.

Where it goes is read from the world state the step is predicted to leave
(``SkillContext.expected``): when the object is to touch another free object (the
sponge stays on the tray it wiped), it is set down on that object — where it is, when it
touches it already, else above its middle; otherwise (or when it was picked up from that
very object) it goes back to where it was picked up. The hand carries it above that spot,
lowers it slowly and stops when the wrist force/torque sensor feels the support (a change
of more than :data:`CONTACT_FORCE_N` since the descent began), keeps still for
:data:`SETTLE_S` while the arm, which lags its command, comes to rest, releases the weld, opens
the hand (a power grasp from above with its thumb still folded) and withdraws along the
grasp's approach direction. When the other hand holds the
object as well, nothing is carried: the hand only opens and withdraws.
"""

from __future__ import annotations

import numpy as np

from oacdsl.errors import RuntimeFailure
from oacdsl.runtime.hands import TOP_PRESHAPE
from oacdsl.runtime.skills.base import Pick, SkillContext
from oacdsl.runtime.transforms import make_T

__all__ = [
    "place",
    "CONTACT_FORCE_N",
    "lower_until_contact",
    "target_support",
    "set_down_pose",
    "withdrawal",
]

#: Force change (N) at the wrist that counts as "the object touches the support".
CONTACT_FORCE_N = 3.0
HOVER_M = 0.04
DESCENT_SPEED_M_S = 0.05
#: Time the hand keeps still on the support before it lets go, s: at the contact the arm is
#: still pressing down (9 N instead of 3 N), and a tall narrow object let go then tips over
#: (the KIT knife, standing on its blade, fell on its side next to the board it cut on).
SETTLE_S = 0.3
#: Time to carry the object above where it goes, s, and the mean speed (m/s) a longer way
#: is carried at: a sponge carried 56 cm back to its place in 1.6 s swung the arm so that
#: the descent felt 3 N at once and let go of it 4 cm above the table.
CARRY_S = 1.6
CARRY_SPEED_M_S = 0.25
#: Peak over mean speed of a min-jerk motion: the descent is timed so that its *peak* speed
#: is :data:`DESCENT_SPEED_M_S` (a heavy object meeting the support at twice that speed made
#: the arm's tracking lag a 66 N spike at the wrist within one control tick).
MIN_JERK_PEAK = 1.875


def lower_until_contact(
    ctx: SkillContext,
    side: str,
    t_hand: np.ndarray,
    depth_m: float,
    what: str,
    force_n: float = CONTACT_FORCE_N,
) -> np.ndarray:
    """Lower hand ``side`` from ``t_hand`` by up to ``depth_m`` until the wrist's force changed
    by more than ``force_n`` (N). Returns the hand pose where contact was felt; raises when
    nothing was felt.
    """
    ctl = ctx.ctl
    goal = make_T(t_hand[:3, :3], t_hand[:3, 3] - np.array([0.0, 0.0, depth_m]))
    felt = ctl.move(
        side,
        goal,
        MIN_JERK_PEAK * depth_m / DESCENT_SPEED_M_S,
        guard=lambda: float(np.linalg.norm(ctl.force_change(side))) > force_n,
    )
    if not felt:
        raise RuntimeFailure(f"{what}: the wrist felt no contact after lowering {depth_m * 100:.0f} cm")
    return ctl.ik.frame(f"grasp_{side}")


def place(ctx: SkillContext, hand: str, obj: str, *, force: float = CONTACT_FORCE_N) -> None:
    """Set the held ``obj`` down; the descent stops when the wrist feels ``force`` (N)."""
    world, ctl = ctx.world, ctx.ctl
    side = ctx.require_held(hand, obj)
    pick = ctx.picked.get(side)
    approach = pick.approach if pick is not None else np.array([0.0, 0.0, -1.0])
    if ctx.other_holder(side, obj) is None:
        _set_down(ctx, side, obj, pick, force)
        ctl.wait(SETTLE_S)
    ctl.activity = f"releasing {obj}"
    world.release(side)
    grasp = ctx.library.grasp_for(ctx.classes[obj])
    if grasp is not None and grasp.approach == "top" and grasp.type == "power":
        # the thumb stays folded: opened, it reaches 12 cm below the palm, into the support and
        # the flat object just set down on it (a sponge pressed into the table: 60-72 N)
        ctl.set_fingers(side, TOP_PRESHAPE)
        ctl.wait(0.4)
    else:
        ctl.open_hand(side, 0.4)
    ctx.picked.pop(side, None)
    ctl.activity = "withdrawing"
    for pose, seconds in withdrawal(ctl.ik.frame(f"grasp_{side}"), approach):
        ctl.move(side, pose, seconds)


def withdrawal(now: np.ndarray, approach: np.ndarray) -> list[tuple[np.ndarray, float]]:
    """The two (T_world_grasp, seconds) of an open hand backing off along the grasp's
    ``approach`` and rising, from hand pose ``now``."""
    back = make_T(now[:3, :3], now[:3, 3] - 0.12 * approach + np.array([0.0, 0.0, 0.03]))
    up = make_T(now[:3, :3], back[:3, 3] + np.array([0.0, 0.0, 0.08]))
    return [(back, 0.8), (up, 0.6)]


def target_support(ctx: SkillContext, obj: str) -> str | None:
    """The object ``obj`` is predicted to stand on after the step (another free object it
    touches in the step's predicted world state), or None for "back where it was"."""
    if ctx.expected is None:
        return None
    partners = sorted(ctx.expected.partners(obj) & ctx.objects())
    return partners[0] if partners else None


def set_down_pose(
    ctx: SkillContext, side: str, obj: str, pick: Pick | None
) -> tuple[np.ndarray, str, str | None]:
    """(T_world_grasp above where ``obj`` goes, a name for that place, the object it goes
    is predicted to touch or None, left out of the obstacles): back where it was picked up,
    or onto the support the step predicts."""
    world = ctx.world
    t_obj, t_obj_in_hand = ctx.held_pose(side, obj)
    origin = pick.origin if pick is not None else t_obj
    support = target_support(ctx, obj)
    if support is None or (pick is not None and support in pick.supports):
        xy, where = origin[:2, 3], "its place"  # back where it was picked up (it stood there)
    elif world.touching(obj, support):  # on the support already (a wipe, a ladle in a bowl): set it down here
        ctl = ctx.ctl
        here = ctl.ik.goal(side)
        return here, support, support
    else:
        xy, where = world.body_pose(support)[:2, 3], support
    height = ctx.support_height(xy, exclude=obj)
    target_obj = make_T(origin[:3, :3], (xy[0], xy[1], height + HOVER_M))
    return target_obj @ np.linalg.inv(t_obj_in_hand), where, support


def _set_down(
    ctx: SkillContext, side: str, obj: str, pick: Pick | None, force: float = CONTACT_FORCE_N
) -> None:
    """Carry ``obj`` above where it goes and lower it until the wrist feels the support."""
    ctl = ctx.ctl
    hover, where, support = set_down_pose(ctx, side, obj, pick)
    if support is not None and ctx.world.touching(obj, support):  # no hover: that would break the contact
        ctl.activity = f"setting {obj} down on {support}"
        lower_until_contact(ctx, side, hover, 0.03, f"placing {obj}", force)
        return
    ctl.activity = f"carrying {obj} to {where}"
    ctx.check_reachable(side, hover, f"the place of {obj} on {where}")
    now = ctl.ik.goal(side)
    far = float(np.linalg.norm(hover[:3, 3] - now[:3, 3]))
    ctx.carry(side, hover, {obj} if support is None else {obj, support}, max(CARRY_S, far / CARRY_SPEED_M_S))
    ctl.wait(0.2)
    ctl.activity = f"setting {obj} down"
    lower_until_contact(ctx, side, hover, HOVER_M + 0.03, f"placing {obj}", force)
