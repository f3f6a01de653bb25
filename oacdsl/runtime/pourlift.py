"""How fast a pour's lip may be lifted over its planned path: the liquid must not be jerked.

The lip of a pour is raised where the pouring hand's boxes would meet the target's rim (a
lift planned step by step along the tilt) and where the arm's measured lag would bring the cup
down on the rim (a lift decided each control tick). Both used to change within one step: the
hand's boxes reaching the bowl's rim asked for 2.3 cm at once, and the lag, measured against the
raised goal, fed its own lift (a step up made the arm lag as much more, which asked for more):
on the dough (seed 3, and the hand-over story's seed 3) the lip's goal rose 9 cm and fell again
within 0.12 s. The cup's jerk threw the balls up in it, they fell back onto each other, and one
left the lip at 1.1 m/s, 5 cm above the rim, and flew over the bowl's far rim.

Here both lifts change no faster than a speed (``Tuning.pour_lift_speed_m_s``): a planned lift
is begun before the step that needs it and ended after it (the least such profile that is never
lower than the one asked for), and the lag's lift follows what it asks for at that speed.
Metres and seconds throughout.
"""

from __future__ import annotations

import numpy as np

__all__ = ["ramped_lift", "follow_lift"]


def ramped_lift(lift_m: np.ndarray, at_s: np.ndarray, speed_m_s: float) -> np.ndarray:
    """The least lift, never below ``lift_m`` at the times ``at_s`` (s, rising), that changes by
    no more than ``speed_m_s`` times the time between any two of them: each lift asked for is
    reached ramping up before its time and left ramping down after it."""
    lift, t = np.asarray(lift_m, dtype=float), np.asarray(at_s, dtype=float)
    return (lift[None, :] - speed_m_s * np.abs(t[:, None] - t[None, :])).max(axis=1)


def follow_lift(now_m: float, want_m: float, seconds: float, speed_m_s: float) -> float:
    """The lift after ``seconds`` that moves from ``now_m`` towards ``want_m`` at no more than
    ``speed_m_s``."""
    most = speed_m_s * seconds
    return min(max(want_m, now_m - most), now_m + most)
