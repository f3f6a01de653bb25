"""Where on the table objects may stand (:func:`fits`), the free slots an object without a place
takes (:func:`nominal_places`), and a seed's shift of every object (:func:`shuffled`), for
:func:`oacdsl.runtime.layout.plan_layout`."""

from __future__ import annotations

import math
from collections.abc import Mapping

import numpy as np

from oacdsl.errors import RuntimeFailure
from oacdsl.runtime.bodies import Body
from oacdsl.runtime.objects import TABLE_FRONT

__all__ = [
    "MAX_SHIFT_M",
    "MIN_GAP_M",
    "SLOTS",
    "STAND_X_RANGE_M",
    "STAND_Y_LIMIT_M",
    "fits",
    "nominal_places",
    "shuffled",
]

#: How far a seed may move an object from its planned place, metres.
MAX_SHIFT_M = 0.10
#: Free space kept between two objects' footprints, metres (room for the fingers).
MIN_GAP_M = 0.05

#: Places tried, in order, for objects the scene does not place (x, y metres, robot at the
#: origin facing +x): the middle, then left and right, then further out.
SLOTS: tuple[tuple[float, float], ...] = (
    (0.64, 0.0),
    (0.56, 0.28),
    (0.56, -0.28),
    (0.72, -0.40),
    (0.72, 0.40),
    (0.82, 0.18),
    (0.82, -0.18),
)
#: Region of the table objects may stand in: footprint x range and |y| limit, metres.
STAND_X_RANGE_M = (TABLE_FRONT + 0.04, TABLE_FRONT + 0.56)
STAND_Y_LIMIT_M = 0.60


def fits(
    name: str, xy: tuple[float, float], placed: Mapping[str, tuple[float, float]], bodies: Mapping[str, Body]
) -> bool:
    """``name`` at ``xy`` (m) stands inside the region of :data:`STAND_X_RANGE_M` and
    :data:`STAND_Y_LIMIT_M`, :data:`MIN_GAP_M` clear of every object ``placed``."""
    r = bodies[name].radius
    (x0, x1), y1 = STAND_X_RANGE_M, STAND_Y_LIMIT_M
    if not (x0 <= xy[0] - r and xy[0] + r <= x1) or abs(xy[1]) + r > y1:
        return False
    for other, oxy in placed.items():
        if other != name and math.dist(xy, oxy) < r + bodies[other].radius + MIN_GAP_M:
            return False
    return True


def nominal_places(
    names: list[str], bodies: Mapping[str, Body], wanted: Mapping[str, tuple[float, float]]
) -> dict[str, tuple[float, float]]:
    """Objects that ask for a place get it; the others take the first free slot."""
    placed: dict[str, tuple[float, float]] = {n: wanted[n] for n in names if n in wanted}
    for name in names:
        if name in placed:
            continue
        slot = next((s for s in SLOTS if fits(name, s, placed, bodies)), None)
        if slot is None:
            raise RuntimeFailure(
                f"no room on the table for {name!r} ({len(names)} objects);"
                f" give it a place: '{name} at (x, y)'"
            )
        placed[name] = slot
    return placed


def shuffled(
    nominal: dict[str, tuple[float, float]], bodies: Mapping[str, Body], rng: np.random.Generator
) -> dict[str, tuple[float, float]]:
    """Every object moved from its ``nominal`` place by up to :data:`MAX_SHIFT_M` in a random
    direction where it :func:`fits` (in name order; left where it is after 200 tries)."""
    placed = dict(nominal)
    for name in sorted(nominal):
        for _ in range(200):
            r = MAX_SHIFT_M * math.sqrt(rng.uniform())
            a = rng.uniform(0, 2 * math.pi)
            xy = (nominal[name][0] + r * math.cos(a), nominal[name][1] + r * math.sin(a))
            if fits(name, xy, placed, bodies):
                placed[name] = xy
                break
    return placed
