"""What a skill gets: the controller, the library's knowledge, and the bound instances.

A skill is a function ``skill(ctx, *instances, **params)`` whose instances are the
arguments of the OAC's ``execute`` line in the order of the skill's signature
(:data:`oacdsl.skills.SIGNATURES`; for ``pour(h, c, l, b)``: hand, source container,
liquid, target container) and whose keyword parameters are the named skill
parameters in SI units (``tilt=1.92``), the signature's defaults filling the rest.
It reads object poses from the simulation when it runs, moves the robot through
:class:`~oacdsl.runtime.control.Controller`, and raises
:class:`~oacdsl.errors.RuntimeFailure` with a reason when it cannot do its job.
"""

from __future__ import annotations

from collections.abc import Callable, Collection, Mapping
from dataclasses import dataclass, field
from typing import TypeVar

import mujoco
import numpy as np

from oacdsl.errors import RuntimeFailure
from oacdsl.library import Library
from oacdsl.model import Grasp
from oacdsl.runtime.bodies import Body
from oacdsl.runtime.control import Controller
from oacdsl.runtime.motion import paths
from oacdsl.runtime.motion.tuning import TUNING
from oacdsl.runtime.simworld import SimWorld
from oacdsl.world import WorldState

__all__ = ["SkillContext", "Skill", "Pick", "cm", "fmt_xyz"]


T = TypeVar("T")


def cm(length_m: float) -> str:
    """A length for a message: 0.123 → ``12 cm``."""
    return f"{length_m * 100:.0f} cm"


def fmt_xyz(p: np.ndarray) -> str:
    return f"({p[0]:.2f}, {p[1]:.2f}, {p[2]:.2f}) m"


#: Largest hand-to-target distance (m) and angle (rad) the IK may leave for a target to count as reachable.
REACH_TOLERANCE_M = 0.02
REACH_TOLERANCE_RAD = 0.25


@dataclass(frozen=True)
class Pick:
    """How a hand took what it holds: the object's pose when it was picked up
    (T_world_object), the grasp's approach direction (world, unit), the objects it
    stood on or touched then (its supports), and whether it was taken from the other hand
    (a hand-over: its pose then is no place to set it down again)."""

    obj: str
    origin: np.ndarray
    approach: np.ndarray
    supports: frozenset[str]
    from_hand: bool = False


@dataclass
class SkillContext:
    """Everything a skill may use. ``picked`` remembers, per hand side, how it took what
    it holds; ``expected`` is the world state the running step is predicted to leave
    (set by the executor around each skill; None outside a run); ``coming``, the (hand,
    object) takes the run's later steps are predicted to make, in order
    (:func:`~oacdsl.runtime.intent.coming_takes`; set likewise, empty outside a run)."""

    ctl: Controller
    library: Library
    classes: Mapping[str, frozenset[str]]
    picked: dict[str, Pick] = field(default_factory=dict)
    expected: WorldState | None = None
    coming: tuple[tuple[str, str], ...] = ()
    #: how many times each object has been set down on the table so far (``place``)
    set_downs: dict[str, int] = field(default_factory=dict)

    @property
    def world(self) -> SimWorld:
        return self.ctl.world

    def side(self, hand: str) -> str:
        sides = self.world.layout.hands
        if hand not in sides:
            raise RuntimeFailure(f"{hand!r} is not a hand of the scene (hands: {', '.join(sorted(sides))})")
        return sides[hand]

    def body(self, instance: str) -> Body:
        """The geometry of ``instance`` (from the language)."""
        return self.world.layout.bodies[instance]

    def grasp_for(self, obj: str) -> Grasp:
        grasp = self.library.grasp_for(self.classes[obj])
        if grasp is None:
            raise RuntimeFailure(
                f"no grasp is declared for {obj!r} (classes {', '.join(sorted(self.classes[obj]))});"
                " declare one, e.g. `grasp Cup { type power approach side offset (0, 0, 0.05) }`"
            )
        return grasp

    def other_holder(self, side: str, obj: str) -> str | None:
        """The other hand's side when it holds ``obj`` too, else None."""
        other = "l" if side == "r" else "r"
        return other if self.world.held.get(other) == obj else None

    def objects(self) -> frozenset[str]:
        """The free objects of the scene (what stands on the table; no hands, no liquids)."""
        return frozenset(p.name for p in self.world.layout.placements)

    def require_held(self, hand: str, obj: str) -> str:
        side = self.side(hand)
        held = self.world.held[side]
        if held != obj:
            raise RuntimeFailure(f"{hand} does not hold {obj} (it holds {held or 'nothing'})")
        return side

    def held_pose(self, side: str, obj: str) -> tuple[np.ndarray, np.ndarray]:
        """``(T_world_obj, T_grasp_obj)``: a held object's pose in the world and in the grasp
        frame of hand ``side`` (metres)."""
        t_world_grasp = self.world.frame_pose(f"grasp_{side}")
        t_world_obj = self.world.body_pose(obj)
        return t_world_obj, np.linalg.inv(t_world_grasp) @ t_world_obj

    def check_reachable(self, side: str, target: np.ndarray, what: str) -> None:
        """Raise when the whole-body IK cannot bring hand ``side`` to ``target``."""
        res = self.ctl.ik.try_reach(side, target)
        if res.position_m > REACH_TOLERANCE_M or res.angle_rad > REACH_TOLERANCE_RAD:
            hand = next(h for h, s in self.world.layout.hands.items() if s == side)
            raise RuntimeFailure(
                f"{what} at {fmt_xyz(target[:3, 3])} is out of reach of {hand}: the best whole-body IK"
                f" solution leaves the hand {cm(res.position_m)} and"
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
            f" solution leaves the hand {cm(best[0])} and {np.degrees(best[1]):.0f}° from the target"
        )

    def obstacles(self, exclude: set[str]) -> list[tuple[np.ndarray, float, float]]:
        """(xy, footprint radius, top height) of the objects standing on the table
        (:func:`~oacdsl.runtime.motion.paths.obstacles`)."""
        return paths.obstacles(self.world, exclude)

    def clearance(self, a: np.ndarray, b: np.ndarray, exclude: set[str]) -> float:
        """Smallest horizontal gap (m) between the way a → b (xy) and an obstacle's footprint."""
        return paths.clearance(self.world, a, b, exclude)

    def via_height(self, a: np.ndarray, b: np.ndarray, exclude: set[str], hanging_m: float) -> float:
        """Height for a hand frame moving over a → b (xy) with ``hanging_m`` below it
        (:func:`~oacdsl.runtime.motion.paths.via_height`)."""
        return paths.via_height(self.world, a, b, exclude, hanging_m)

    def carry_path(
        self, side: str, goal: np.ndarray, exclude: set[str], duration_s: float = TUNING.carry_s
    ) -> list[tuple[np.ndarray, float]]:
        """The three (T_world_grasp, seconds) of a carry from hand ``side``'s goal now to ``goal``
        (:func:`~oacdsl.runtime.motion.paths.carry_path`)."""
        return paths.carry_path(self.world, side, self.ctl.ik.goal(side), goal, exclude, duration_s)

    def reach_error(self, side: str, target: np.ndarray) -> float:
        """A score of how well ``target`` can be reached (m, angle weighted 0.1 m/rad)."""
        return self.ctl.ik.try_reach(side, target).miss_m

    def support_height(self, xy: np.ndarray, exclude: str, below: float = 2.0,
                       passing: Collection[str] = ()) -> float:
        """Height (m) of the first surface under ``xy`` below height ``below`` (a ray cast down),
        ignoring ``exclude``: from an object's base, what it stands on, not a lid on top of it;
        and seen through the objects ``passing`` (held up by a hand that carries them elsewhere
        at the same time: a milk carton held over the cup's place, set down together with the
        cup, put the cup's hover 28 cm up, and the cup, lifted there, met the carton: 62 N)."""
        m, d = self.world.model, self.world.data
        geomid = np.array([-1], dtype=np.int32)
        groups = np.array([1, 0, 0, 0, 0, 0], dtype=np.uint8)  # group 0: table and objects only
        skip, down = {m.body(name).id for name in passing}, np.array([0.0, 0.0, -1.0])
        top = below
        while True:
            start = np.array([xy[0], xy[1], top])
            dist = mujoco.mj_ray(m, d, start, down, groups, 1, m.body(exclude).id, geomid)
            if dist < 0:
                return 0.0
            if int(m.geom_bodyid[geomid[0]]) not in skip:
                return float(start[2] - dist)
            top = float(start[2] - dist) - 1e-4  # through that object: on from just below it


Skill = Callable[..., None]
