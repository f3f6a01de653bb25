"""Letting go of what one hand holds: the press on what bears it eased, the fingers opened (only
part of the way beside a neighbour: :mod:`~oacdsl.runtime.motion.opening`), the pick forgotten;
then the open hand backed off along its grasp's approach and up. :class:`LettingGo` gives
:class:`~oacdsl.runtime.motion.hand.Motion` these primitives (:meth:`LettingGo.release`,
:meth:`LettingGo.withdraw`), driven through its :meth:`~oacdsl.runtime.motion.hand.Motion.go`.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING

import numpy as np

from oacdsl.runtime.hands import OPEN, TOP_PRESHAPE
from oacdsl.runtime.motion.opening import clear_opening
from oacdsl.runtime.motion.tuning import TUNING, Tuning
from oacdsl.runtime.transforms import make_T, raised

if TYPE_CHECKING:
    from oacdsl.runtime.motion.context import MotionContext

__all__ = ["LettingGo", "withdrawal"]


class LettingGo:
    """The primitives of a :class:`~oacdsl.runtime.motion.hand.Motion` that let go of what its
    hand holds; they use its context, hand, tuning and motions."""

    ctx: MotionContext
    side: str
    tuning: Tuning
    _reopen: dict[str, float] | None

    if TYPE_CHECKING:

        def go(self, goal: np.ndarray, seconds: float, until: Callable[[], bool] | None = None) -> bool: ...

        def here(self) -> np.ndarray: ...

    def release(self, obj: str) -> None:
        """Let go of ``obj``: weld off, the fingers open (a power grasp from above keeps its thumb
        folded: opened, it reaches 12 cm below the palm, into the support; a pinch opens its thumb
        only as far as the top preshape's: opened wide, it swings across the edge it pinched and
        pushed a lid let go on a pot 9 cm off it; beside a neighbour they open only part of the way,
        :mod:`~oacdsl.runtime.motion.opening`, and fully once withdrawn), the pick forgotten."""
        ctx = self.ctx
        ctx.ctl.activity = f"releasing {obj}"
        if ctx.world.supported(obj):
            self.ease(obj)
        ctx.ctl.tare(self.side)  # letting go is a motion of its own: its force change counts from here
        ctx.world.release(self.side)
        grasp = ctx.library.grasp_for(ctx.classes[obj])
        top_power = grasp is not None and grasp.approach == "top" and grasp.type == "power"
        pinch = grasp is not None and grasp.type == "pinch"
        shape = TOP_PRESHAPE if top_power else self._open_shape(pinch)
        part = clear_opening(ctx.world, self.side, obj, shape, self.tuning, ctx.ctl.fingers[self.side])
        ctx.ctl.set_fingers(self.side, shape if part is None else part)
        self._reopen = None if part is None else shape
        ctx.ctl.wait(self.tuning.open_s)
        ctx.picked.pop(self.side, None)

    def ease(self, obj: str) -> None:
        """Ease the press of the held ``obj`` on what bears it before letting go: while the wrist
        is pushed up by more than the tuning's obstacle force, the hand's goal is raised to where
        the hand really is (pressed on, the arm stays below its goal), at most the tuning's
        ``ease_tries`` times (each about halves the press), stopping when it is pushed up by no
        more than the support force or ``obj`` loses its support. Each guarded motion counts its
        force from its own start: a lid brought onto a pot by ``touch`` and pressed, then lowered
        by ``place`` until the wrist felt the pot, was pressed on with 72-79 N, all of it off the
        wrist at once when the hand let go (a 61 N safety stop); eased, 16-28 N."""
        world, ctl, t = self.ctx.world, self.ctx.ctl, self.tuning

        def eased() -> bool:
            return ctl.pushed_up_n(self.side) <= t.support_force_n or not world.supported(obj)

        if ctl.pushed_up_n(self.side) <= t.obstacle_force_n:
            return
        for _ in range(t.ease_tries):
            now = self.here()
            up = float(world.frame_pose(f"grasp_{self.side}")[2, 3] - now[2, 3])
            if up <= 0 or self.go(raised(now, up), t.press_s, eased):
                return

    def _open_shape(self, pinch: bool = False) -> dict[str, float]:
        """The open hand (:data:`OPEN`), or, when opening it so would bring its boxes more than the
        tuning's ``open_drop_m`` lower than they are now, only the fingers opened and the thumb kept
        where it is (a pinch on the rim of a plate set on edge in a rack: the opening thumb swung
        down onto a wall, 60 N); else, for a ``pinch``, the thumb opened only to the top
        preshape's (:data:`TOP_PRESHAPE`)."""
        from oacdsl.runtime.handgap import hand_box_poses
        from oacdsl.runtime.hands import finger_joint_names

        world, side = self.ctx.world, self.side
        grasp = world.frame_pose(f"grasp_{side}")
        q = world.joint_positions()
        now = {j: float(q[name]) for j, name in finger_joint_names(side).items()}

        def lowest(fingers: dict[str, float]) -> float:
            boxes = hand_box_poses(side, grasp, fingers)
            return min(float(t[2, 3] - np.abs(t[2, :3]) @ h) for t, h in boxes)

        if lowest(now) - lowest(OPEN) <= self.tuning.open_drop_m:
            return {j: TOP_PRESHAPE[j] if pinch and j.startswith("thumb") else v for j, v in OPEN.items()}
        # the thumb kept at its command, not where it is measured: pressed on the object it may be
        # past its limit, and the IK, given that, finds no solution
        held = self.ctx.ctl.fingers[side]
        return {j: OPEN[j] if j.startswith("fingers") else held.get(j, now[j]) for j in OPEN}

    def withdraw(self, approach: np.ndarray | None) -> None:
        """Back an open hand off along its grasp's ``approach`` (world unit; default: from
        above) and up."""
        self.ctx.ctl.activity = "withdrawing"
        for pose, seconds in withdrawal(self.ctx.ctl.ik.frame(f"grasp_{self.side}"), approach, self.tuning):
            self.go(pose, seconds)
        if self._reopen is not None:  # opened only part of the way beside a neighbour: now fully
            self.ctx.ctl.set_fingers(self.side, self._reopen)
            self._reopen = None


def withdrawal(
    now: np.ndarray, approach: np.ndarray | None, tuning: Tuning = TUNING
) -> list[tuple[np.ndarray, float]]:
    """The two (T_world_grasp, seconds) of an open hand at ``now`` backing off along its grasp's
    ``approach`` (world unit; None: it came from above) and rising."""
    t = tuning
    a = np.array([0.0, 0.0, -1.0]) if approach is None else approach
    back = make_T(now[:3, :3], now[:3, 3] - t.withdraw_back_m * a + np.array([0.0, 0.0, t.withdraw_rise_m]))
    return [(back, t.withdraw_back_s), (raised(back, t.withdraw_up_m), t.withdraw_up_s)]
