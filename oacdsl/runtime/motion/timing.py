"""How a repeated path (circles) is cut into waypoints the control loop can follow.

Each waypoint is one min-jerk move of the control loop (:meth:`Controller.drive`), whose
duration is rounded to whole control ticks (``CONTROL_DT_S``); a waypoint shorter than
:attr:`Tuning.waypoint_min_s` becomes a jump of one tick that the arms do not follow, and the
rounding makes the cycle faster than asked.
"""

from __future__ import annotations

import math

from oacdsl.runtime.motion.tuning import TUNING, Tuning

__all__ = ["waypoints_per_cycle"]


def waypoints_per_cycle(period_s: float, most: int, tuning: Tuning = TUNING) -> int:
    """How many waypoints one cycle of ``period_s`` (s) is cut into: ``most``, or fewer so that
    each lasts at least ``tuning.waypoint_min_s``; at least one."""
    return max(1, min(most, math.floor(period_s / tuning.waypoint_min_s + 1e-9)))
