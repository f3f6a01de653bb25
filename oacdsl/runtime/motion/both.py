"""Both hands at once, each along its own way (a bimanual grasp, place or mix).

Each hand's goal is interpolated (min-jerk) from where it is commanded now; both go through
the controller's one loop together. A hand whose guard becomes true stops where it really
is (the arm lags its command: a hand waiting for the other one would otherwise keep
pressing on what it touched), so two contacts may happen at different instants.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from functools import partial

import numpy as np

from oacdsl.runtime.control import Controller
from oacdsl.runtime.transforms import interpolate

__all__ = ["move_both", "lockstep"]


def move_both(
    ctl: Controller,
    goals: Mapping[str, np.ndarray],
    duration_s: float,
    guards: Mapping[str, Callable[[], bool]] | None = None,
) -> dict[str, bool]:
    """Move each hand of ``goals`` (side → T_world_grasp) there in ``duration_s``, together;
    the motion ends when it is over or every guarded hand stopped. Returns, per side, whether
    its guard stopped it."""
    paths = {s: partial(interpolate, ctl.ik.goal(s), goal) for s, goal in goals.items()}
    return ctl.drive(paths, duration_s, guards)


def lockstep(ctl: Controller, paths: Mapping[str, list[tuple[np.ndarray, float]]]) -> None:
    """Follow each side's list of (T_world_grasp, seconds) together, phase by phase (equal
    lengths); a phase lasts as long as its slower hand needs."""
    for phase in zip(*paths.values(), strict=True):
        seconds = max(t for _, t in phase)
        if seconds > 0:
            move_both(ctl, {s: pose for s, (pose, _) in zip(paths, phase, strict=True)}, seconds)
