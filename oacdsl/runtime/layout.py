"""Where the scene's instances go on the table, and which liquid starts in which cup.

A :class:`Layout` is computed from a DSL scene: every instance gets its
:class:`~oacdsl.runtime.bodies.Body` from the language's geometry (its own, else its
most specific class's), hands are mapped to the robot's right/left hand by their names, liquids start inside a
container, and the other objects stand on the table at nominal places (the paper's
kitchen: cups left and right, the bowl in the middle, the mixer to the right). With a
seed, every object is moved by up to :data:`MAX_SHIFT_M` in a random direction, keeping
a gap between objects, so the same OAC is executed on a new arrangement.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np

from oacdsl.errors import RuntimeFailure, did_you_mean
from oacdsl.geometry import ROLE_HAND, ROLE_LIQUID, ROLE_OBJECT, ROLE_TABLE
from oacdsl.library import Library
from oacdsl.model import Scene
from oacdsl.runtime.bodies import Body, bodies_for_scene
from oacdsl.runtime.objects import TABLE_DEPTH, TABLE_FRONT

__all__ = ["Placement", "Layout", "plan_layout", "MAX_SHIFT_M", "NOMINAL", "hand_side"]

#: How far a seed may move an object from its nominal place, metres.
MAX_SHIFT_M = 0.10
#: Free space kept between two objects' footprints, metres (room for the fingers).
MIN_GAP_M = 0.05
#: Number of balls of one liquid.
BALLS_PER_LIQUID = 10

#: Nominal (x, y) of the paper's kitchen instances, metres, robot at the origin facing +x.
NOMINAL: dict[str, tuple[float, float]] = {
    "red_cup": (0.56, 0.28),
    "green_cup": (0.56, -0.28),
    "orange_bowl": (0.64, 0.0),
    "mixer": (0.72, -0.40),
    "sponge": (0.56, -0.28),
    "tray": (0.68, 0.02),
}
#: Where the paper's liquids start when nothing else says (red cup: liquid one).
NOMINAL_CONTENTS: dict[str, str] = {"liquid_one": "red_cup", "liquid_two": "green_cup"}
_SLOTS: tuple[tuple[float, float], ...] = (
    (0.64, 0.0),
    (0.56, 0.28),
    (0.56, -0.28),
    (0.72, -0.40),
    (0.72, 0.40),
    (0.82, 0.18),
    (0.82, -0.18),
)
#: Region of the table objects may stand in: footprint x range and |y| limit, metres.
_X_RANGE = (TABLE_FRONT + 0.04, TABLE_FRONT + 0.56)
_Y_LIMIT = 0.60


@dataclass(frozen=True)
class Placement:
    """A free object built from ``body`` standing at (x, y) on the table, rotated by ``yaw`` (rad)."""

    name: str
    body: Body
    x: float
    y: float
    yaw: float = 0.0


@dataclass(frozen=True)
class Layout:
    """The physical arrangement of a scene (see the module docstring)."""

    scene: str
    placements: tuple[Placement, ...]
    liquids: Mapping[str, str]
    hands: Mapping[str, str]
    table: str
    seed: int | None = None
    balls_per_liquid: int = BALLS_PER_LIQUID
    #: Every instance's body (hands, liquids and the table included).
    bodies: Mapping[str, Body] = field(default_factory=dict)

    def placement(self, name: str) -> Placement:
        for p in self.placements:
            if p.name == name:
                return p
        raise KeyError(name)


def hand_side(name: str) -> str | None:
    """ "r" or "l" from a hand instance's name (``right_hand``, ``hand_l`` …), None if unclear."""
    low = name.lower()
    right = "right" in low or low.endswith("_r") or low.startswith("r_")
    left = "left" in low or low.endswith("_l") or low.startswith("l_")
    if right == left:
        return None
    return "r" if right else "l"


def plan_layout(
    library: Library,
    scene: Scene,
    contents: Mapping[str, str] | None = None,
    seed: int | None = None,
    places: Mapping[str, tuple[float, float]] | None = None,
) -> Layout:
    """The layout of ``scene``; ``contents`` maps liquids to their starting containers;
    ``places`` puts named objects at given (x, y) positions on the table (metres)."""
    bodies = bodies_for_scene(library, scene)
    table = None
    for inst in scene.instances:
        role = bodies[inst.name].role
        if inst.environment and role != ROLE_TABLE:
            raise RuntimeFailure(
                f"environment instance {inst.name!r} (classes {', '.join(inst.classes)}) is not the table;"
                " the runtime builds only the table (`shape table`) as environment"
            )
        if role == ROLE_TABLE:
            table = inst.name
    kinds = {n: b.role for n, b in bodies.items() if n != table}
    hands = _hands(kinds)
    liquids = _liquids(bodies, dict(contents or {}))
    names = sorted(n for n, k in kinds.items() if k == ROLE_OBJECT)
    nominal = _nominal(names, bodies)
    placed = nominal if seed is None else _shuffle(nominal, bodies, np.random.default_rng(seed))
    for name, xy in (places or {}).items():
        if name not in placed:
            raise RuntimeFailure(
                f"cannot place {name!r}: not an object on the table{did_you_mean(name, placed)}"
            )
        r = bodies[name].radius
        if not (
            TABLE_FRONT <= xy[0] - r and xy[0] + r <= TABLE_FRONT + TABLE_DEPTH and abs(xy[1]) + r <= 0.8
        ):
            raise RuntimeFailure(f"cannot place {name!r} at ({xy[0]:.2f}, {xy[1]:.2f}) m: off the table")
        placed[name] = (float(xy[0]), float(xy[1]))
    placements = tuple(Placement(n, bodies[n], placed[n][0], placed[n][1]) for n in names)
    return Layout(scene.name, placements, liquids, hands, table or ROLE_TABLE, seed, bodies=bodies)


def _hands(kinds: Mapping[str, str]) -> dict[str, str]:
    hands: dict[str, str] = {}
    for name in sorted(n for n, k in kinds.items() if k == ROLE_HAND):
        side = hand_side(name)
        if side is None:
            raise RuntimeFailure(
                f"hand instance {name!r}: cannot tell the robot's left from right hand"
                " by its name (use a name with 'left' or 'right')"
            )
        if side in hands.values():
            raise RuntimeFailure(
                f"hand instance {name!r}: the robot has one {'right' if side == 'r' else 'left'}"
                " hand, already mapped"
            )
        hands[name] = side
    return hands


def _liquids(bodies: Mapping[str, Body], contents: dict[str, str]) -> dict[str, str]:
    containers = sorted(n for n, b in bodies.items() if b.container)
    liquid_names = sorted(n for n, b in bodies.items() if b.role == ROLE_LIQUID)
    for liquid, container in contents.items():
        if liquid not in liquid_names:
            valid = liquid_names
            raise RuntimeFailure(
                f"cannot fill {liquid!r}: not a liquid of the scene{did_you_mean(liquid, valid)}"
            )
        if container not in containers:
            raise RuntimeFailure(
                f"cannot put {liquid!r} into {container!r}: not a container of the scene"
                f"{did_you_mean(container, containers)}"
            )
    taken = set(contents.values())
    # a liquid starts in a container the robot can pour from: one it can grasp
    free_cups = [c for c in containers if bodies[c].graspable and c not in taken]
    for liquid in liquid_names:
        if liquid in contents:
            continue
        if NOMINAL_CONTENTS.get(liquid) in free_cups:
            contents[liquid] = NOMINAL_CONTENTS[liquid]
            free_cups.remove(contents[liquid])
            continue
        if not free_cups:
            raise RuntimeFailure(
                f"liquid {liquid!r} has no cup to start in (give one with --fill {liquid}=CUP)"
            )
        contents[liquid] = free_cups.pop(0)
    return contents


def _fits(
    name: str, xy: tuple[float, float], placed: Mapping[str, tuple[float, float]], bodies: Mapping[str, Body]
) -> bool:
    r = bodies[name].radius
    if not (_X_RANGE[0] <= xy[0] - r and xy[0] + r <= _X_RANGE[1]) or abs(xy[1]) + r > _Y_LIMIT:
        return False
    for other, oxy in placed.items():
        if other != name and math.dist(xy, oxy) < r + bodies[other].radius + MIN_GAP_M:
            return False
    return True


def _nominal(names: list[str], bodies: Mapping[str, Body]) -> dict[str, tuple[float, float]]:
    placed: dict[str, tuple[float, float]] = {}
    for name in sorted(names, key=lambda n: (n not in NOMINAL, n)):
        wanted = ([NOMINAL[name]] if name in NOMINAL else []) + list(_SLOTS)
        slot = next((s for s in wanted if _fits(name, s, placed, bodies)), None)
        if slot is None:
            raise RuntimeFailure(f"no room on the table for {name!r} ({len(names)} objects)")
        placed[name] = slot
    return placed


def _shuffle(
    nominal: dict[str, tuple[float, float]], bodies: Mapping[str, Body], rng: np.random.Generator
) -> dict[str, tuple[float, float]]:
    placed = dict(nominal)
    for name in sorted(nominal):
        for _ in range(200):
            r = MAX_SHIFT_M * math.sqrt(rng.uniform())
            a = rng.uniform(0, 2 * math.pi)
            xy = (nominal[name][0] + r * math.cos(a), nominal[name][1] + r * math.sin(a))
            if _fits(name, xy, placed, bodies):
                placed[name] = xy
                break
    return placed
