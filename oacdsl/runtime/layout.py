"""Where the scene's instances go on the table, and which liquid starts in which container.

A :class:`Layout` is computed from a DSL scene: every instance gets its
:class:`~oacdsl.runtime.bodies.Body` from the language's geometry (its own, else its
most specific class's), hands are mapped to the robot's right/left hand by their names,
``ignored`` instances are left out (not built). Each object's place comes, first match wins, from

1. the caller's ``places`` (``--place OBJECT=X,Y``),
2. the scene's ``OBJECT at (x, y)``, unless the caller gives a layout (``--layout``),
3. the demonstration's first frame mapped into reach (``layout demonstrated`` of the
   caller or the scene, when the caller gives the recording's positions;
   :mod:`oacdsl.runtime.demo_layout`); an object that starts on top of another there (a lid
   on its bottle: its centre within the other's footprint and above the other's centre,
   see :func:`stacked_on`) starts on top of it on the robot's table too,
4. the first free slot of a fixed list (``layout auto``), in the order of the objects' names.

Each object is turned about the vertical (its yaw, :mod:`~oacdsl.runtime.layout_yaw`) as the
demonstration's first frame shows it when it is laid out as demonstrated and its class declares
``markers`` that pose its shape there; else as the scene's ``OBJECT at (x, y) turned ANGLE``
says; else not at all.

A liquid starts in the container given by the caller's ``contents`` (``--fill``, or the
OAC's own preconditions), else by the scene's ``LIQUID in CONTAINER``; a liquid that has
neither is an error. With a seed, every object is moved by up to :data:`MAX_SHIFT_M` in a
random direction, keeping a gap between objects, so the same OAC is executed on a new
arrangement. The liquids' containers are found in :mod:`~oacdsl.runtime.layout_liquids`, the
free slots and a seed's shifts in :mod:`~oacdsl.runtime.layout_slots`.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

import numpy as np

from oacdsl.errors import RuntimeFailure, did_you_mean
from oacdsl.geometry import ROLE_HAND, ROLE_OBJECT, ROLE_TABLE
from oacdsl.library import Library
from oacdsl.model import Scene
from oacdsl.runtime.bodies import Body, bodies_for_scene
from oacdsl.runtime.demo_layout import map_into_reach
from oacdsl.runtime.demo_places import set_downs_on_table
from oacdsl.runtime.layout_liquids import starting_liquids
from oacdsl.runtime.layout_slots import (
    MAX_SHIFT_M,
    MIN_GAP_M,
    STAND_X_RANGE_M,
    STAND_Y_LIMIT_M,
    nominal_places,
    shuffled,
)
from oacdsl.runtime.layout_yaw import object_yaws
from oacdsl.runtime.objects import TABLE_DEPTH, TABLE_FRONT
from oacdsl.units import language_si

__all__ = [
    "Placement",
    "Layout",
    "plan_layout",
    "seed_note",
    "MAX_SHIFT_M",
    "MIN_GAP_M",
    "BALLS_PER_LIQUID",
    "hand_side",
    "STAND_X_RANGE_M",
    "STAND_Y_LIMIT_M",
]

#: How far outside an object's footprint another's centre may be and still count as on top
#: of it at the demonstration's first frame, metres (markers sit on stalks, off the axis).
STACK_SLACK_M = 0.02
#: Number of balls of one liquid when the scene does not say (``balls N``).
BALLS_PER_LIQUID = 10


@dataclass(frozen=True)
class Placement:
    """A free object built from ``body`` standing at (x, y) on the table, rotated by ``yaw`` (rad),
    or, with ``on``, standing on top of that object (at its x, y)."""

    name: str
    body: Body
    x: float
    y: float
    yaw: float = 0.0
    on: str | None = None


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
    #: Every instance's body (hands, liquids and the table included; not the ignored ones).
    bodies: Mapping[str, Body] = field(default_factory=dict)
    #: Balls of each liquid (``balls N`` of the scene or --fill); others have ``balls_per_liquid``.
    balls: Mapping[str, int] = field(default_factory=dict)
    #: Where each object's place came from: "given", "scene", "demonstrated" or "auto".
    sources: Mapping[str, str] = field(default_factory=dict)
    #: Objects the seed left where they were: placed by the caller, stacked on another, or
    #: with no free room within :data:`MAX_SHIFT_M` (sorted; empty without a seed).
    unmoved: tuple[str, ...] = ()
    #: Where the demonstration sets each object down, in order, as robot-table (x, y), m
    #: (:func:`oacdsl.runtime.demo_places.mapped_set_downs`; only with ``layout demonstrated``).
    set_downs: Mapping[str, tuple[tuple[float, float], ...]] = field(default_factory=dict)

    def ball_count(self, liquid: str) -> int:
        """How many balls ``liquid`` has."""
        return self.balls.get(liquid, self.balls_per_liquid)

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
    *,
    balls: Mapping[str, int] | None = None,
    layout: str | None = None,
    demonstrated: Mapping[str, np.ndarray] | None = None,
    set_downs: Mapping[str, Sequence[np.ndarray]] | None = None,
    headings: Mapping[str, np.ndarray] | None = None,
) -> Layout:
    """The layout of ``scene`` (see the module docstring).

    ``contents`` maps liquids to their starting containers over the scene's ``in``;
    ``places`` puts named objects at given (x, y) positions on the table (metres) over the
    scene's ``at``; ``balls`` sets liquids' ball counts; ``layout`` (``auto`` or
    ``demonstrated``) replaces the scene's layout and its ``at``s; ``demonstrated`` holds
    the first-frame position (m, motion capture frame) of each marker group, hands
    included, for ``demonstrated``; ``set_downs`` where the demonstration sets objects down
    (:func:`oacdsl.runtime.demo_places.set_down_places`), mapped as the layout is;
    ``headings`` the first-frame direction of each posed object's x axis
    (:func:`oacdsl.runtime.demo_layout.first_frame_poses`), which turns an object laid out as
    demonstrated (:func:`~oacdsl.runtime.layout_yaw.object_yaws`).
    """
    built = scene.model_copy(update={"instances": tuple(i for i in scene.instances if not i.ignored)})
    bodies = bodies_for_scene(library, built)
    table = None
    for inst in built.instances:
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
    liquids, counts = starting_liquids(scene, bodies, dict(contents or {}), dict(balls or {}))
    names = sorted(n for n, k in kinds.items() if k == ROLE_OBJECT)
    stacks: dict[str, str] = {}
    if (layout or scene.layout) == "demonstrated" and demonstrated:
        given = set(places or {}) | ({p.instance for p in scene.places} if layout is None else set())
        first = {n: demonstrated[n] for n in names if n in demonstrated and n not in given}
        stacks = stacked_on(first, bodies)
    free = [n for n in names if n not in stacks]
    wanted, sources = _wanted(scene, free, bodies, hands, places or {}, layout, demonstrated)
    nominal = nominal_places(free, bodies, wanted)
    placed = nominal if seed is None else shuffled(nominal, bodies, np.random.default_rng(seed))
    for name, source in sources.items():
        if source == "given":  # exactly where the caller said, even with a seed
            placed[name] = wanted[name]
    unmoved = () if seed is None else tuple(n for n in names if n in stacks or placed[n] == nominal[n])
    for name, support in stacks.items():
        placed[name], sources[name] = placed[support], "demonstrated"
    for name in names:
        sources.setdefault(name, "auto")
    mapped = {}
    if demonstrated and set_downs:  # relative to the objects laid out as demonstrated
        laid = [n for n in names if sources.get(n) == "demonstrated" and n in demonstrated]
        demo_hands = {side: demonstrated[h] for h, side in hands.items() if h in demonstrated}
        radii = {n: bodies[n].radius for n in laid}
        mapped = set_downs_on_table(set_downs, demonstrated, demo_hands, radii, placed, stacks)
    shown = [n for n in free if sources.get(n) == "demonstrated"]  # the objects map_into_reach laid out
    yaws = object_yaws(scene, names, sources, shown, demonstrated, headings, hands, bodies)
    placements = tuple(
        Placement(n, bodies[n], placed[n][0], placed[n][1], yaws[n], on=stacks.get(n)) for n in names
    )
    return Layout(
        scene.name,
        placements,
        liquids,
        hands,
        table or ROLE_TABLE,
        seed,
        bodies=bodies,
        balls=counts,
        sources=sources,
        unmoved=unmoved,
        set_downs=mapped,
    )


def seed_note(layout: Layout) -> str | None:
    """A warning when the layout's seed moved no object, or left some for want of room; else None.

    ``--seed N`` moves every object by up to :data:`MAX_SHIFT_M`; an object placed by
    ``--place`` or standing on another stays put by design (no warning for it alone), one
    without free room around it stays put too. When no object moved, every seed runs the
    same arrangement, and the user is told.
    """
    if layout.seed is None or not layout.unmoved:
        return None
    if len(layout.unmoved) == len(layout.placements):
        return (
            f"--seed {layout.seed} moves no object of scene {layout.scene} (each is placed by --place,"
            f" stands on another object, or has no free room within {MAX_SHIFT_M * 100:.0f} cm):"
            " every seed runs the same arrangement"
        )
    cramped = [n for n in layout.unmoved if layout.sources.get(n) != "given" and not layout.placement(n).on]
    if not cramped:
        return None
    return (
        f"--seed {layout.seed} leaves {', '.join(cramped)} where planned: no free room within"
        f" {MAX_SHIFT_M * 100:.0f} cm"
    )


def stacked_on(first: Mapping[str, np.ndarray], bodies: Mapping[str, Body]) -> dict[str, str]:
    """object → the object it stands on at the demonstration's first frame (``first``: each
    object's position, m, z up): its centre within the other's footprint (radius plus
    :data:`STACK_SLACK_M`) and higher than the other's centre by more than half the other's
    height. One level: what stands on a stacked object is not stacked again."""
    out: dict[str, str] = {}
    for name, p in sorted(first.items()):
        below = [
            (float(q[2]), other)
            for other, q in first.items()
            if other != name
            and math.dist(p[:2], q[:2]) < bodies[other].radius + STACK_SLACK_M
            and p[2] - q[2] > 0.5 * bodies[other].height
        ]
        if below:
            out[name] = max(below)[1]  # the highest one below it
    return {n: s for n, s in out.items() if s not in out}


def _wanted(
    scene: Scene,
    names: list[str],
    bodies: Mapping[str, Body],
    hands: Mapping[str, str],
    places: Mapping[str, tuple[float, float]],
    layout: str | None,
    demonstrated: Mapping[str, np.ndarray] | None,
) -> tuple[dict[str, tuple[float, float]], dict[str, str]]:
    """The place each object asks for, and where that came from (given, scene, demonstrated).

    ``layout`` is the caller's: it replaces the scene's ``layout`` and its ``at`` statements,
    but for ``demonstrated`` the ``at`` of an object the demonstration does not show (an
    untracked one: it has no first frame) stays. The objects laid out as demonstrated keep
    clear of those placed otherwise."""
    wanted: dict[str, tuple[float, float]] = {}
    sources: dict[str, str] = {}
    for name, xy in places.items():
        if name not in names:
            raise RuntimeFailure(
                f"cannot place {name!r}: not an object on the table{did_you_mean(name, names)}"
            )
        wanted[name], sources[name] = _on_table(name, bodies, xy), "given"
    shown = demonstrated if layout == "demonstrated" and demonstrated else None
    for place in scene.places:  # a layout given by the caller replaces them
        if layout is not None and (shown is None or place.instance in shown):
            continue
        if place.instance in names and place.instance not in wanted:
            xy = (language_si(place.x.value, place.x.unit)[0], language_si(place.y.value, place.y.unit)[0])
            wanted[place.instance] = _on_table(place.instance, bodies, xy)
            sources[place.instance] = "scene"
    if (layout or scene.layout) == "demonstrated" and demonstrated:
        free = {n: demonstrated[n] for n in names if n not in wanted and n in demonstrated}
        demo_hands = {side: demonstrated[h] for h, side in hands.items() if h in demonstrated}
        radii = {n: bodies[n].radius for n in free}
        fixed = {n: (xy, bodies[n].radius) for n, xy in wanted.items()}  # kept clear of
        for name, xy in map_into_reach(free, demo_hands, radii, MIN_GAP_M, fixed).items():
            wanted[name], sources[name] = xy, "demonstrated"
    return wanted, sources


def _on_table(name: str, bodies: Mapping[str, Body], xy: tuple[float, float]) -> tuple[float, float]:
    r = bodies[name].radius
    if not (TABLE_FRONT <= xy[0] - r and xy[0] + r <= TABLE_FRONT + TABLE_DEPTH and abs(xy[1]) + r <= 0.8):
        near, far = TABLE_FRONT + r, TABLE_FRONT + TABLE_DEPTH - r
        across = f"y within ±{0.8 - r:.2f} m" if r < 0.8 else "no y"
        raise RuntimeFailure(
            f"cannot place {name!r} at ({xy[0]:.2f}, {xy[1]:.2f}) m: off the table (x from {TABLE_FRONT:g} to"
            f" {TABLE_FRONT + TABLE_DEPTH:g} m, y within ±0.8 m; the circle of radius {r:.2f} m around its"
            f" origin that holds it must lie on it: x from {near:.2f} to {far:.2f} m, {across})"
        )
    return (float(xy[0]), float(xy[1]))


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
