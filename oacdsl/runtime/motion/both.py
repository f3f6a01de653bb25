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

from oacdsl.runtime.control import CONTROL_DT_S, Controller
from oacdsl.runtime.transforms import interpolate, make_T, min_jerk, rot_axis

__all__ = ["Move", "aligned", "lockstep", "lockstep_miss", "move_both", "mover", "paced", "turn_both"]

#: A hand's way: (T_world_grasp, seconds) phases, driven in :func:`lockstep` with the other's.
Way = list[tuple[np.ndarray, float]]


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


def aligned(paths: Mapping[str, Way]) -> dict[str, Way]:
    """``paths`` with the shorter ways lengthened to the longest by waiting at their ends (the
    last pose again, 0 s): a carry's way has three or four phases, one more with a detour."""
    most = max((len(w) for w in paths.values()), default=0)
    return {s: [*w, *[(w[-1][0], 0.0)] * (most - len(w))] for s, w in paths.items()}


def lockstep(ctl: Controller, paths: Mapping[str, Way]) -> None:
    """Follow each side's list of (T_world_grasp, seconds) together, phase by phase (a shorter
    way's hand waits at its end: :func:`aligned`); a phase lasts as long as its slower hand
    needs, each hand the same fraction along its own phase at every instant."""
    paths = aligned({s: w for s, w in paths.items() if w})
    for phase in zip(*paths.values(), strict=True):
        seconds = max(t for _, t in phase)
        if seconds > 0:
            move_both(ctl, {s: pose for s, (pose, _) in zip(paths, phase, strict=True)}, seconds)


def lockstep_miss(ctl: Controller, paths: Mapping[str, Way], settle_s: float = 0.0) -> float:
    """How far (m) a hand of the IK model gets off its way while :func:`lockstep` drives
    ``paths``: the largest distance from a phase's straight line (a hand lagging along it is
    not off it), or from the last pose once ``settle_s`` more have passed, found by running the
    IK alone, tick by tick, in a trial (the IK runs open loop: its model is what the arms are
    commanded; nothing moves). Ways each reachable at their ends may not be together on the
    way: two hands reaching far across the table bent the torso to its limits, a hand sagged
    17 cm below its way onto a rack or stayed 12 cm above its grasp."""
    ik = ctl.ik
    worst = 0.0
    paths = aligned({s: w for s, w in paths.items() if w})
    with ik.trial():
        for phase in zip(*paths.values(), strict=True):
            seconds = max(t for _, t in phase)
            if seconds <= 0:
                continue
            starts = {s: ik.goal(s) for s in paths}
            goals = {s: goal for s, (goal, _) in zip(paths, phase, strict=True)}
            n = max(1, round(seconds / CONTROL_DT_S))
            for k in range(1, n + 1):
                for s in paths:
                    ik.set_hand_target(s, interpolate(starts[s], goals[s], min_jerk(k / n)))
                ik.step()
                worst = max(worst, *(_off_segment(ik.frame(f"grasp_{s}")[:3, 3], starts[s][:3, 3],
                                                  goals[s][:3, 3]) for s in paths))
        for _ in range(round(settle_s / CONTROL_DT_S)):
            ik.step()
        return max(worst, *(ik.residual(s).position_m for s in paths))


def paced(ctl: Controller, paths: Mapping[str, Way], tolerance_m: float, slower: tuple[float, ...],
          settle_s: float = 0.0) -> float | None:
    """The first factor of ``slower`` by which the phases of ``paths`` are slowed so that the IK
    keeps each hand within ``tolerance_m`` of its way (:func:`lockstep_miss`); None when none
    does (the ways are not for these hands together)."""
    for f in slower:
        if lockstep_miss(ctl, {s: [(pose, t * f) for pose, t in way] for s, way in paths.items()},
                         settle_s) <= tolerance_m:
            return f
    return None


def _off_segment(p: np.ndarray, a: np.ndarray, b: np.ndarray) -> float:
    """The distance (m) of point ``p`` from the segment ``a``-``b``."""
    ab = b - a
    u = float(np.clip((p - a) @ ab / max(float(ab @ ab), 1e-12), 0.0, 1.0))
    return float(np.linalg.norm(p - (a + u * ab)))
