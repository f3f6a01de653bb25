"""Both hands at once, each along its own way (a bimanual grasp, place or mix).

Each hand's goal is interpolated (min-jerk) from where it is commanded now; both go through
the controller's one loop together. A hand whose guard becomes true stops where it really
is (the arm lags its command: a hand waiting for the other one would otherwise keep
pressing on what it touched), so two contacts may happen at different instants. A turn
about a line (:func:`turn_both`) follows its arc instead.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from functools import partial
from typing import Protocol

import numpy as np

from oacdsl.runtime.control import Controller
from oacdsl.runtime.transforms import interpolate, make_T, rot_axis

__all__ = ["Move", "lockstep", "move_both", "mover", "turn_both"]


def move_both(
    ctl: Controller,
    goals: Mapping[str, np.ndarray],
    duration_s: float,
    guards: Mapping[str, Callable[[], bool]] | None = None,
    weights: Mapping[str, float] | None = None,
    stop_at_model: bool = False,
) -> dict[str, bool]:
    """Move each hand of ``goals`` (side → T_world_grasp) there in ``duration_s``, together;
    the motion ends when it is over or every guarded hand stopped. Returns, per side, whether
    its guard stopped it. ``weights``: a hand's orientation weight (the IK's default otherwise).
    ``stop_at_model``: a stopped hand keeps its commanded pose (the IK model's), pressing on by
    the arm's lag, instead of stopping where it really is (``Controller.drive``)."""
    paths = {s: partial(interpolate, ctl.ik.goal(s), goal) for s, goal in goals.items()}
    return ctl.drive(paths, duration_s, guards, weights=weights, stop_at_model=stop_at_model)


def turn_both(
    ctl: Controller,
    starts: Mapping[str, np.ndarray],
    axis: np.ndarray,
    pivots: Mapping[str, np.ndarray],
    angle_rad: float,
    duration_s: float,
) -> None:
    """Turn each hand of ``starts`` (side → T_world_grasp), with what it holds, by ``angle_rad``
    about the line along ``axis`` (world) through its pivot (side → world point, m), along the
    arc, both together (min-jerk timed). A straight move between the two ends would cut the
    chord: a hand 22 cm up a tool's handle, the tool leaned 40° about its head's edge on a
    floor, passes 1.3 cm inside the arc, pushing the head into the floor and the fingers down
    onto what is near (KIT Mix: the far rim of the bowl)."""

    def along(s: str, u: float) -> np.ndarray:
        r = rot_axis(axis, angle_rad * u)
        pose, pivot = starts[s], pivots[s]
        return make_T(r @ pose[:3, :3], pivot + r @ (pose[:3, 3] - pivot))

    ctl.drive({s: partial(along, s) for s in starts}, duration_s)


class Move(Protocol):
    """Move a hand to T_world_grasp in ``seconds``; a true ``guard`` stops it."""

    def __call__(self, pose: np.ndarray, seconds: float, guard: Callable[[], bool] | None = None) -> None: ...


def mover(
    ctl: Controller, side: str, keep: np.ndarray | None, orientation_weight: float | None = None
) -> Move:
    """A move of hand ``side`` (``go(T_world_grasp, seconds, guard=None)``): alone when ``keep``
    is None, else with the other hand's goal fixed at ``keep`` (T_world_grasp) throughout.
    ``orientation_weight``: of the moving hand's orientation task (None: the IK's default)."""
    other = "l" if side == "r" else "r"
    weights = {side: orientation_weight} if orientation_weight is not None else None

    def go(pose: np.ndarray, seconds: float, guard: Callable[[], bool] | None = None) -> None:
        if keep is None:
            ctl.move(side, pose, seconds, guard=guard, orientation_weight=orientation_weight)
        else:
            move_both(ctl, {side: pose, other: keep}, seconds, {side: guard} if guard else None, weights)

    return go


def lockstep(ctl: Controller, paths: Mapping[str, list[tuple[np.ndarray, float]]]) -> None:
    """Follow each side's list of (T_world_grasp, seconds) together, phase by phase (equal
    lengths); a phase lasts as long as its slower hand needs."""
    for phase in zip(*paths.values(), strict=True):
        seconds = max(t for _, t in phase)
        if seconds > 0:
            move_both(ctl, {s: pose for s, (pose, _) in zip(paths, phase, strict=True)}, seconds)
