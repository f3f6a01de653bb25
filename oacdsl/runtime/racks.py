"""A rack (``shape rack(…)``, docs/language.md): its base board, its walls and the slots
between them, in the object frame (metres; origin at the centre of the base, z up).

The walls run along the rack's length (x), as high as the rack, and divide its width (y)
into ``slots`` equal slots; a slot's *normal* is y: something set into a slot stands on
edge with its thin side across it (a plate in a dish rack). Light: no MuJoCo.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

from oacdsl.geometry import RACK_FLOOR_M, RACK_WALL_M

__all__ = ["Slot", "rack_boxes", "rack_slots", "rack_volume"]

Vec = tuple[float, float, float]


@dataclass(frozen=True)
class Slot:
    """One slot of a rack, object frame: the middle of its floor (m), its normal (unit: the
    direction across it), its free width between the walls, its length and its depth (from
    its floor to the walls' top), m."""

    floor_m: Vec
    normal: Vec
    width_m: float
    length_m: float
    depth_m: float


def _sizes(d: Mapping[str, float]) -> tuple[float, float, float, int, float, float]:
    return (d["length"], d["width"], d["height"], round(d["slots"]), d.get("wall", RACK_WALL_M),
            d.get("floor", RACK_FLOOR_M))


def rack_boxes(d: Mapping[str, float], at: Vec = (0.0, 0.0, 0.0)) -> list[tuple[Vec, Vec]]:
    """(centre, half sizes) of the rack's boxes, object frame (m): the base board, then the
    ``slots + 1`` walls from −y to +y (standing on the board)."""
    length, width, height, n, wall, floor = _sizes(d)
    x, y, z = at
    out = [((x, y, z + floor / 2), (length / 2, width / 2, floor / 2))]
    pitch = (width - wall) / n
    for k in range(n + 1):
        wy = y - width / 2 + wall / 2 + k * pitch
        out.append(((x, wy, z + floor + (height - floor) / 2), (length / 2, wall / 2, (height - floor) / 2)))
    return out


def rack_volume(d: Mapping[str, float]) -> float:
    """The volume of a rack's board and walls, m³."""
    length, width, height, n, wall, floor = _sizes(d)
    return length * width * floor + (n + 1) * length * wall * (height - floor)


def rack_slots(d: Mapping[str, float], at: Vec = (0.0, 0.0, 0.0)) -> list[Slot]:
    """The slots of a rack with sizes ``d`` whose base's middle is at ``at`` (object frame, m)."""
    length, width, height, n, wall, floor = _sizes(d)
    x, y, z = at
    pitch = (width - wall) / n
    first = y - width / 2 + wall / 2 + pitch / 2  # the middle of the first slot
    return [Slot((x, first + k * pitch, z + floor), (0.0, 1.0, 0.0), pitch - wall, length, height - floor)
            for k in range(n)]
