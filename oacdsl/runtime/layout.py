"""Where the scene's instances go on the table, and which liquid starts in which cup.

A :class:`Layout` is computed from a DSL scene: every instance gets an object kind
from its most specific class that has geometry (:data:`~oacdsl.runtime.objects.CLASS_SHAPES`),
hands are mapped to the robot's right/left hand by their names, liquids start inside a
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
from oacdsl.library import Library
from oacdsl.model import Scene
from oacdsl.runtime.objects import CLASS_SHAPES, SHAPES, TABLE_DEPTH, TABLE_FRONT

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
    """A free object of kind ``kind`` standing at (x, y) on the table, rotated by ``yaw`` (rad)."""

    name: str
    kind: str
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
    kinds: Mapping[str, str] = field(default_factory=dict)

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


def _kind(library: Library, cls_names: frozenset[str]) -> str | None:
    known = [c for c in cls_names if c in CLASS_SHAPES]
    if not known:
        return None
    best = max(sorted(known), key=lambda c: len(library.ancestors(c)))
    return CLASS_SHAPES[best]


def plan_layout(
    library: Library,
    scene: Scene,
    contents: Mapping[str, str] | None = None,
    seed: int | None = None,
    places: Mapping[str, tuple[float, float]] | None = None,
) -> Layout:
    """The layout of ``scene``; ``contents`` maps liquids to their starting containers;
    ``places`` puts named objects at given (x, y) positions on the table (metres)."""
    classes = library.instance_classes(scene)
    kinds: dict[str, str] = {}
    table = "table"
    for inst in scene.instances:
        kind = _kind(library, classes[inst.name])
        if kind == "table" or (inst.environment and kind is None):
            if kind is None:
                raise RuntimeFailure(
                    f"environment instance {inst.name!r} (classes {', '.join(inst.classes)}) has no geometry;"
                    " the runtime builds only a Table as environment"
                )
            table = inst.name
            continue
        if kind is None:
            have = ", ".join(sorted(classes[inst.name]))
            raise RuntimeFailure(
                f"instance {inst.name!r} of scene {scene.name!r} (classes {have})"
                f" has no geometry in the runtime; classes with geometry: {', '.join(sorted(CLASS_SHAPES))}"
            )
        kinds[inst.name] = kind
    hands = _hands(kinds)
    liquids = _liquids(kinds, dict(contents or {}))
    names = sorted(n for n, k in kinds.items() if k in SHAPES)
    nominal = _nominal(names, kinds)
    placed = nominal if seed is None else _shuffle(nominal, kinds, np.random.default_rng(seed))
    for name, xy in (places or {}).items():
        if name not in placed:
            raise RuntimeFailure(
                f"cannot place {name!r}: not an object on the table{did_you_mean(name, placed)}"
            )
        r = SHAPES[kinds[name]].radius
        if not (
            TABLE_FRONT <= xy[0] - r and xy[0] + r <= TABLE_FRONT + TABLE_DEPTH and abs(xy[1]) + r <= 0.8
        ):
            raise RuntimeFailure(f"cannot place {name!r} at ({xy[0]:.2f}, {xy[1]:.2f}) m: off the table")
        placed[name] = (float(xy[0]), float(xy[1]))
    placements = tuple(Placement(n, kinds[n], placed[n][0], placed[n][1]) for n in names)
    return Layout(scene.name, placements, liquids, hands, table, seed, kinds=kinds)


def _hands(kinds: Mapping[str, str]) -> dict[str, str]:
    hands: dict[str, str] = {}
    for name in sorted(n for n, k in kinds.items() if k == "hand"):
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


def _liquids(kinds: Mapping[str, str], contents: dict[str, str]) -> dict[str, str]:
    containers = sorted(n for n, k in kinds.items() if k in ("cup", "bowl"))
    for liquid, container in contents.items():
        if kinds.get(liquid) != "liquid":
            valid = [n for n, k in kinds.items() if k == "liquid"]
            raise RuntimeFailure(
                f"cannot fill {liquid!r}: not a liquid of the scene{did_you_mean(liquid, valid)}"
            )
        if container not in containers:
            raise RuntimeFailure(
                f"cannot put {liquid!r} into {container!r}: not a container of the scene"
                f"{did_you_mean(container, containers)}"
            )
    taken = set(contents.values())
    free_cups = [c for c in containers if kinds[c] == "cup" and c not in taken]
    for liquid in sorted(n for n, k in kinds.items() if k == "liquid"):
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
    name: str, xy: tuple[float, float], placed: Mapping[str, tuple[float, float]], kinds: Mapping[str, str]
) -> bool:
    r = SHAPES[kinds[name]].radius
    if not (_X_RANGE[0] <= xy[0] - r and xy[0] + r <= _X_RANGE[1]) or abs(xy[1]) + r > _Y_LIMIT:
        return False
    for other, oxy in placed.items():
        if other != name and math.dist(xy, oxy) < r + SHAPES[kinds[other]].radius + MIN_GAP_M:
            return False
    return True


def _nominal(names: list[str], kinds: Mapping[str, str]) -> dict[str, tuple[float, float]]:
    placed: dict[str, tuple[float, float]] = {}
    for name in sorted(names, key=lambda n: (n not in NOMINAL, n)):
        wanted = ([NOMINAL[name]] if name in NOMINAL else []) + list(_SLOTS)
        slot = next((s for s in wanted if _fits(name, s, placed, kinds)), None)
        if slot is None:
            raise RuntimeFailure(f"no room on the table for {name!r} ({len(names)} objects)")
        placed[name] = slot
    return placed


def _shuffle(
    nominal: dict[str, tuple[float, float]], kinds: Mapping[str, str], rng: np.random.Generator
) -> dict[str, tuple[float, float]]:
    placed = dict(nominal)
    for name in sorted(nominal):
        for _ in range(200):
            r = MAX_SHIFT_M * math.sqrt(rng.uniform())
            a = rng.uniform(0, 2 * math.pi)
            xy = (nominal[name][0] + r * math.cos(a), nominal[name][1] + r * math.sin(a))
            if _fits(name, xy, placed, kinds):
                placed[name] = xy
                break
    return placed
