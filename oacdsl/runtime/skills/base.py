"""What a skill gets: the controller, the library's knowledge, and the bound instances.

A skill is a function ``skill(ctx, *instances)`` whose instances are the OAC's
arguments in parameter order (for ``pour(h, c, l, b)``: hand, source container,
liquid, target container). It reads object poses from the simulation when it runs,
moves the robot through :class:`~oacdsl.runtime.control.Controller`, and raises
:class:`~oacdsl.errors.RuntimeFailure` with a reason when it cannot do its job.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import TypeVar

import mujoco
import numpy as np

from oacdsl.errors import RuntimeFailure
from oacdsl.library import Library
from oacdsl.model import Grasp
from oacdsl.runtime.control import Controller
from oacdsl.runtime.simworld import SimWorld

__all__ = ["SkillContext", "Skill", "fmt_xyz"]


T = TypeVar("T")


def fmt_xyz(p: np.ndarray) -> str:
    return f"({p[0]:.2f}, {p[1]:.2f}, {p[2]:.2f}) m"


#: Largest hand-to-target distance (m) and angle (rad) the IK may leave for a target to count as reachable.
REACH_TOLERANCE_M = 0.02
REACH_TOLERANCE_RAD = 0.25


@dataclass
class SkillContext:
    """Everything a skill may use. ``picked`` remembers, per held object, where it was
    picked up (T_world_object) and the approach direction of its grasp."""

    ctl: Controller
    library: Library
    classes: Mapping[str, frozenset[str]]
    picked: dict[str, tuple[np.ndarray, np.ndarray]] = field(default_factory=dict)

    @property
    def world(self) -> SimWorld:
        return self.ctl.world

    def side(self, hand: str) -> str:
        sides = self.world.layout.hands
        if hand not in sides:
            raise RuntimeFailure(f"{hand!r} is not a hand of the scene (hands: {', '.join(sorted(sides))})")
        return sides[hand]

    def kind(self, instance: str) -> str:
        return self.world.layout.kinds[instance]

    def grasp_for(self, obj: str) -> Grasp:
        grasp = self.library.grasp_for(self.classes[obj])
        if grasp is None:
            raise RuntimeFailure(
                f"no grasp is declared for {obj!r} (classes {', '.join(sorted(self.classes[obj]))});"
                " declare one, e.g. `grasp Cup { type power approach side offset (0, 0, 0.05) }`"
            )
        return grasp

    def require_held(self, hand: str, obj: str) -> str:
        side = self.side(hand)
        held = self.world.held[side]
        if held != obj:
            raise RuntimeFailure(f"{hand} does not hold {obj} (it holds {held or 'nothing'})")
        return side

    def check_reachable(self, side: str, target: np.ndarray, what: str) -> None:
        """Raise when the whole-body IK cannot bring hand ``side`` to ``target``."""
        res = self.ctl.ik.try_reach(side, target)
        if res.position_m > REACH_TOLERANCE_M or res.angle_rad > REACH_TOLERANCE_RAD:
            hand = next(h for h, s in self.world.layout.hands.items() if s == side)
            raise RuntimeFailure(
                f"{what} at {fmt_xyz(target[:3, 3])} is out of reach of {hand}: the best whole-body IK"
                f" solution leaves the hand {res.position_m * 100:.0f} cm and"
                f" {np.degrees(res.angle_rad):.0f}° from the target"
            )

    def first_reachable(self, side: str, options: list[tuple[np.ndarray, T]], what: str) -> T:
        """The payload of the first option whose target pose hand ``side`` can reach; when
        none can, a failure naming the closest miss."""
        best: tuple[float, float, np.ndarray] | None = None
        for target, payload in options:
            res = self.ctl.ik.try_reach(side, target)
            if res.position_m <= REACH_TOLERANCE_M and res.angle_rad <= REACH_TOLERANCE_RAD:
                return payload
            if best is None or res.position_m < best[0]:
                best = (res.position_m, res.angle_rad, target)
        if best is None:
            raise RuntimeFailure(f"{what}: nothing to reach")
        hand = next(h for h, s in self.world.layout.hands.items() if s == side)
        raise RuntimeFailure(
            f"{what} at {fmt_xyz(best[2][:3, 3])} is out of reach of {hand}: the best whole-body IK"
            f" solution leaves the hand {best[0] * 100:.0f} cm and {np.degrees(best[1]):.0f}° from the target"
        )

    def reach_error(self, side: str, target: np.ndarray) -> float:
        """A score of how well ``target`` can be reached (m, angle weighted 0.1 m/rad)."""
        res = self.ctl.ik.try_reach(side, target)
        return res.position_m + 0.1 * res.angle_rad

    def support_height(self, xy: np.ndarray, exclude: str) -> float:
        """Height (m) of the first surface below ``xy`` (a ray cast down), ignoring ``exclude``."""
        m, d = self.world.model, self.world.data
        geomid = np.array([-1], dtype=np.int32)
        start = np.array([xy[0], xy[1], 2.0])
        groups = np.array([1, 0, 0, 0, 0, 0], dtype=np.uint8)  # group 0: table and objects only
        dist = mujoco.mj_ray(m, d, start, np.array([0.0, 0.0, -1.0]), groups, 1, m.body(exclude).id, geomid)
        if dist < 0:
            return 0.0
        return float(start[2] - dist)


Skill = Callable[..., None]
