"""One hand's motion, composed of primitives; the other hand follows a policy chosen once.

A skill makes a :class:`Motion` for the hand it moves, with the policy of the other hand
(:class:`OtherHand`), and composes it of primitives: :meth:`Motion.carry` (along a way
over the objects near it), :meth:`Motion.approach` (guarded: until a contact or a force),
:meth:`Motion.press`, :meth:`Motion.stay`, :meth:`Motion.slide` (and :meth:`Motion.slide_back`, a stroke's way
back on the surface), :meth:`Motion.rise`, :meth:`Motion.hold_still`, :meth:`Motion.release`
and :meth:`Motion.withdraw` (letting go: :mod:`~oacdsl.runtime.motion.letgo`). Every one of them
runs through the controller's one control loop (:meth:`~oacdsl.runtime.control.Controller.drive`);
their defaults come from one :class:`~oacdsl.runtime.motion.tuning.Tuning`.
"""

from __future__ import annotations

from collections.abc import Callable
from enum import Enum
from typing import TYPE_CHECKING

import numpy as np

from oacdsl.errors import RuntimeFailure
from oacdsl.runtime.control import CONTROL_DT_S, IDLE_HOLD_WEIGHT
from oacdsl.runtime.motion.letgo import LettingGo
from oacdsl.runtime.motion.paths import carry_path
from oacdsl.runtime.motion.press import ForcePress
from oacdsl.runtime.motion.tuning import TUNING, Tuning
from oacdsl.runtime.transforms import MIN_JERK_PEAK, down, interpolate, make_T, raised

if TYPE_CHECKING:
    from oacdsl.runtime.motion.context import MotionContext

__all__ = ["Motion", "OtherHand", "Guard", "Path", "other_side", "felt_nothing"]

#: A condition that ends a motion early (checked every control tick).
Guard = Callable[[], bool]
#: A hand pose (T_world_grasp) for each phase s in [0, 1] of a motion.
Path = Callable[[float], np.ndarray]


class OtherHand(Enum):
    """What the other hand does while a skill moves one hand: chosen once, for the skill."""

    #: the controller's idle hold: re-anchored where it is at each motion (it yields a little
    #: to the torso; a cup held up while the other hand works in it)
    IDLE = "idle"
    #: its goal fixed where it was when the skill began, as strong a task as the moving
    #: hand's: what it holds stays put however the torso moves (a cucumber held on a board)
    STEADY = "steady"
    #: moves rigidly with the moving hand (one object held by both)
    FOLLOW = "follow"


def other_side(side: str) -> str:
    return "l" if side == "r" else "r"


class Motion(LettingGo):
    """The primitives for hand ``side`` in a skill (see the module docstring)."""

    def __init__(
        self,
        ctx: MotionContext,
        side: str,
        other: OtherHand = OtherHand.IDLE,
        tuning: Tuning = TUNING,
        keep: np.ndarray | None = None,
    ) -> None:
        """``keep``: where a steady other hand is kept (T_world_grasp; default: its goal now)."""
        self.ctx, self.side, self.tuning = ctx, side, tuning
        self.other = other_side(side)
        self.policy = other
        ik = ctx.ctl.ik
        #: the other hand's goal when the skill began, and its pose relative to this hand's
        self._keep = ik.goal(self.other) if keep is None else keep
        self._rel = np.linalg.inv(ik.goal(side)) @ self._keep
        #: how far a slide on a surface has been lowered to keep its contact, m (kept from one
        #: slide to the next of the same skill)
        self._seek = 0.0
        #: the open shape a hand that let go opened only part of the way to (:meth:`release`)
        self._reopen: dict[str, float] | None = None

    # --- the loop -----------------------------------------------------------------------------
    def along(
        self,
        path: Path,
        seconds: float,
        until: Guard | None = None,
        orientation_weight: float | None = None,
        keep_contact: Guard | None = None,
        press: ForcePress | None = None,
    ) -> bool:
        """Drive the hand along ``path`` in ``seconds``, the other hand by the policy; True when
        ``until`` stopped it (where it then is). ``orientation_weight``: how much the hand's
        orientation counts (a hand's position counts 1 per metre; 0.3 otherwise).
        ``keep_contact``: sliding on a surface, the path is lowered (at the tuning's seek speed,
        at most its seek depth) while this is false, so that the tool stays on the surface.
        ``press``: the path lowered by a press regulated on the wrist's force instead."""
        ctl, side = self.ctx.ctl, self.side
        guards = {side: until} if until is not None else None
        weights = {side: orientation_weight} if orientation_weight is not None else None
        if keep_contact is not None:
            path = self._pressed(path, keep_contact)
        if press is not None:
            path = press.lowered(path)
        if self.policy is OtherHand.IDLE:
            if ctl.ik.active[self.other]:
                ctl.ik.hold_hand(self.other, weight=IDLE_HOLD_WEIGHT)
            return ctl.drive({side: path}, seconds, guards, weights=weights, stop_at_model=True)[side]
        keep, rel = self._keep, self._rel
        if self.policy is OtherHand.STEADY:
            return ctl.drive({side: path, self.other: lambda _s: keep}, seconds, guards, weights=weights)[
                side
            ]
        return ctl.drive({side: path, self.other: lambda s: path(s) @ rel}, seconds, guards, weights=weights)[
            side
        ]

    def _pressed(self, path: Path, touching: Guard) -> Path:
        """``path`` lowered by a depth that grows, tick by tick, while ``touching`` is false."""
        t = self.tuning
        step = t.seek_speed_m_s * CONTROL_DT_S
        depth = [self._seek]

        def lowered(s: float) -> np.ndarray:
            if not touching():
                depth[0] = min(t.seek_max_m, depth[0] + step)
            self._seek = depth[0]
            return down(path(s), depth[0])

        return lowered

    def go(
        self, goal: np.ndarray, seconds: float, until: Guard | None = None, press: ForcePress | None = None
    ) -> bool:
        """Move the hand from its goal now to ``goal`` (T_world_grasp) in ``seconds``; with
        ``press``, ``goal`` is where the path goes unpressed (:meth:`along`)."""
        start = self.ctx.ctl.ik.goal(self.side) if press is None else down(self.here(), -press.depth_m)
        return self.along(lambda s: interpolate(start, goal, s), seconds, until, press=press)

    def pressing(self, force_n: float | None = None) -> ForcePress:
        """A press regulated on this hand's wrist force (:class:`ForcePress`, ``force_n``
        default the tuning's), its tool's free weight read now, as the hand holds still for
        the tuning's pause: call it before the tool touches anything."""
        ctl, side, readings = self.ctx.ctl, self.side, []

        def read() -> bool:
            readings.append(float(ctl.world.wrist_force(side)[2]))
            return False

        ctl.wait(self.tuning.pause_s, read)
        return ForcePress(ctl, side, float(np.mean(readings)), force_n, self.tuning)

    def here(self) -> np.ndarray:
        """The hand's commanded pose now (T_world_grasp)."""
        return self.ctx.ctl.ik.goal(self.side)

    # --- guards ---------------------------------------------------------------------------------
    def felt(self, force_n: float) -> Guard:
        """True once this hand's wrist force changed by more than ``force_n`` since its motion began."""
        ctl, side = self.ctx.ctl, self.side
        return lambda: float(np.linalg.norm(ctl.force_change(side))) > force_n

    def force_n(self) -> float:
        return float(np.linalg.norm(self.ctx.ctl.force_change(self.side)))

    def touching(self, a: str, b: str) -> Guard:
        world = self.ctx.world
        return lambda: world.touching(a, b)

    def contact_or_force(self, a: str, b: str, force_n: float | None = None) -> Guard:
        """``a`` touches ``b``, or the wrist felt more than ``force_n`` (default: the tuning's
        obstacle force) first."""
        touch, felt = self.touching(a, b), self.felt(force_n or self.tuning.obstacle_force_n)
        return lambda: touch() or felt()

    # --- primitives -----------------------------------------------------------------------------
    def carry(self, goal: np.ndarray, exclude: set[str], seconds: float | None = None) -> None:
        """Carry the hand (and what it holds) to ``goal`` over the objects near the way
        (``exclude`` left out), in ``seconds`` (default: the tuning's carry time, longer for a
        long way at its carry speed). A carry to what the other hand holds (it is in
        ``exclude``: the way ends at it) flies over that hand too: its fingers reach around
        and past what it holds."""
        now = self.here()
        if seconds is None:
            far = float(np.linalg.norm(goal[:3, 3] - now[:3, 3]))
            seconds = max(self.tuning.carry_s, far / self.tuning.carry_speed_m_s)
        world = self.ctx.world
        to_other = world.held.get(self.other) in exclude
        for pose, s in carry_path(world, self.side, now, goal, exclude, seconds, self.tuning,
                                  over_other_hand=to_other):
            if s > 0:
                self.go(pose, s)

    def approach(
        self, goal: np.ndarray, until: Guard, speed_m_s: float | None = None, wait_for: Guard | None = None
    ) -> bool:
        """Guarded approach to ``goal`` at a peak speed (default: the tuning's approach speed)
        until ``until``; then, with ``wait_for``, wait up to the tuning's contact wait for it.
        True when it ended on ``until`` (or ``wait_for`` holds)."""
        dist = float(np.linalg.norm(goal[:3, 3] - self.here()[:3, 3]))
        speed = speed_m_s or self.tuning.approach_speed_m_s
        stopped = self.go(goal, MIN_JERK_PEAK * dist / speed, until)
        if wait_for is None:
            return stopped
        return self.hold_still(self.tuning.contact_wait_s, wait_for) or wait_for()

    def lower_onto_support(
        self, start: np.ndarray, depth_m: float, what: str, force_n: float | None = None
    ) -> None:
        """Lower the held object from ``start`` by up to ``depth_m`` until the wrist feels the
        support (a force change above ``force_n``, default the tuning's support force)."""
        if not self.felt_support(start, depth_m, force_n):
            raise felt_nothing(what, depth_m)

    def felt_support(self, start: np.ndarray, depth_m: float, force_n: float | None = None) -> bool:
        """:meth:`lower_onto_support` that says whether the wrist felt the support instead of
        raising."""
        return self.approach(
            down(start, depth_m),
            self.felt(force_n or self.tuning.support_force_n),
            self.tuning.set_down_speed_m_s,
        )

    def press(self, depth_m: float | None = None, seconds: float | None = None) -> None:
        """Press on: the hand's goal ``depth_m`` further down (default: the tuning's press)."""
        t = self.tuning
        self.go(down(self.here(), t.press_m if depth_m is None else depth_m), seconds or t.press_s)

    def slide(self, offset_m: np.ndarray, seconds: float, keep_contact: Guard | None = None) -> None:
        """Slide the hand (a tool on a surface) by ``offset_m`` (world), keeping its orientation;
        with ``keep_contact``, lowered while that is false (:meth:`along`'s seek)."""
        now = self.here()
        goal = make_T(now[:3, :3], now[:3, 3] + offset_m)
        self.along(lambda s: interpolate(now, goal, s), seconds, keep_contact=keep_contact)

    def slide_back(self, offset_m: np.ndarray, seconds: float, touching: Guard, pressed_m: float) -> None:
        """The way back of a stroke that goes one way (a peeler along a cucumber), on the surface:
        the press ``pressed_m`` (how far the hand's goal is below where the tool touches, m)
        eased by the tuning's ``slide_back_ease_share`` of what it has over the light slide
        press, slid by ``offset_m`` (world) keeping the contact (``touching``; :meth:`along`'s
        seek), then pressed as before. Lifted back through the air, the tool left the object
        between strokes: a contact lost and made again each time, which the demonstrated
        stroke does not have."""
        t = self.tuning
        ease = t.slide_back_ease_share * max(pressed_m - t.slide_press_m, 0.0)
        self.go(raised(self.here(), ease), t.press_s)
        self.slide(offset_m, seconds, keep_contact=touching)
        self.press(ease)

    def stay(self) -> None:
        """Command the hand so that the whole-body IK keeps it where its model is now. At the
        edge of its reach the soft IK settles short of its command (its posture pulls back);
        stopped where its model had come, an arm reaching 1.3 cm short rose 1 cm, relieved,
        and lifted a plate it had just set into a slot off the floor. The command is set
        beyond that pose by what a static solve towards it misses (nothing where the arm
        reaches)."""
        ik, name = self.ctx.ctl.ik, f"grasp_{self.side}"
        here = ik.frame(name)
        with ik.trial():
            ik.set_hand_target(self.side, here)
            for _ in range(self.tuning.stay_solve_tries):
                ik.step()
            settled = ik.frame(name)[:3, 3]
        ik.set_hand_target(self.side, make_T(here[:3, :3], 2.0 * here[:3, 3] - settled))

    def rise(self, height_m: float | None = None, seconds: float | None = None) -> None:
        """Straight up by ``height_m`` (default: the tuning's lift)."""
        t = self.tuning
        self.go(raised(self.here(), t.lift_m if height_m is None else height_m), seconds or t.lift_s)

    def hold_still(self, seconds: float | None = None, until: Guard | None = None) -> bool:
        """Keep still for ``seconds`` (default: the tuning's settle time); True when ``until``
        became true first."""
        return self.ctx.ctl.wait(self.tuning.settle_s if seconds is None else seconds, until)

def felt_nothing(what: str, depth_m: float) -> RuntimeFailure:
    """The failure of a set-down (``what``) whose wrist felt no support after ``depth_m`` (m)."""
    return RuntimeFailure(f"{what}: the wrist felt no contact after lowering {depth_m * 100:.0f} cm")
