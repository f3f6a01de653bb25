"""A press regulated on the wrist's measured force: a held tool kept on a surface below it.

Pressed a fixed depth below where it touched, a tool moved along a surface has no force it
keeps: the arm lags its command by a few millimetres, by a different amount at each point of
a circle, so a fixed depth is sometimes no press at all (the tool floats on the surface and
its contact comes and goes, a mixer circling on a bowl's floor: 40-50 losses per run, a few
longer than 0.1 s) and sometimes a hard one (5 mm deeper: 25-40 N). :class:`ForcePress`
instead lowers or raises the hand's path, every control tick, by what the wrist feels: the
contact's force is the wrist's vertical force with the tool free (measured once, before it
touches) minus the vertical force now, low-pass filtered; the path goes down while it is
below the wanted force and up while it is above, at a rate proportional to the difference
(at most the tuning's seek speed), within the tuning's bounds below and above the path.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from oacdsl.runtime.control import CONTROL_DT_S
from oacdsl.runtime.motion.tuning import TUNING, Tuning
from oacdsl.runtime.transforms import make_T

if TYPE_CHECKING:
    from collections.abc import Callable

    from oacdsl.runtime.control import Controller

__all__ = ["ForcePress"]


class ForcePress:
    """Keeps hand ``side``'s tool pressed down with ``force_n`` (N; default the tuning's
    ``press_force_n``): see the module docstring. ``free_fz_n``: the wrist's vertical force
    (world z, N) with the tool held free of everything. State (how far the path is lowered)
    is kept from one motion to the next, so that one press may span many short motions."""

    def __init__(
        self,
        ctl: Controller,
        side: str,
        free_fz_n: float,
        force_n: float | None = None,
        tuning: Tuning = TUNING,
    ) -> None:
        self.ctl, self.side, self.tuning = ctl, side, tuning
        self.free_fz_n = free_fz_n
        self.force_n = tuning.press_force_n if force_n is None else force_n
        #: how far below its path the hand is aimed now, m (negative: above it)
        self.depth_m = 0.0
        #: the contact's force as last filtered, N
        self.felt_n = 0.0

    def contact_n(self) -> float:
        """The force the surface pushes the tool up with now (unfiltered), N."""
        return self.free_fz_n - float(self.ctl.world.wrist_force(self.side)[2])

    def update(self) -> float:
        """One control tick: filter the force, move the depth towards the wanted force; the
        depth now, m."""
        t = self.tuning
        self.felt_n += t.press_filter_share * (self.contact_n() - self.felt_n)
        lack = self.force_n - self.felt_n
        step = t.press_gain_m_per_n_s * lack * (1.0 if lack > 0 else t.press_ease_share)
        step = float(np.clip(step, -t.seek_speed_m_s, t.seek_speed_m_s)) * CONTROL_DT_S
        self.depth_m = float(np.clip(self.depth_m + step, -t.press_rise_max_m, t.press_depth_max_m))
        return self.depth_m

    def lowered(self, path: Callable[[float], np.ndarray]) -> Callable[[float], np.ndarray]:
        """``path`` (T_world_grasp for each phase) lowered by the regulated depth, updated at
        each call (the control loop calls a path once per tick)."""

        def pressed(s: float) -> np.ndarray:
            pose = path(s)
            return make_T(pose[:3, :3], pose[:3, 3] - np.array([0.0, 0.0, self.update()]))

        return pressed
