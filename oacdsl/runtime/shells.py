"""An open container (the language's ``shell``) in MuJoCo: a base disc and a ring of wall boxes,
so that balls can lie inside and be poured out, and under the base of one no hand carries a
*catch* that only the balls touch (sizes in metres, masses in kilograms)."""

from __future__ import annotations

import math

import mujoco

from oacdsl.runtime.geoms import BALL_CONTYPE, BALL_GROUP, CATCH_CONTYPE, OBJECT_CONAFFINITY
from oacdsl.runtime.geoms import add_geom as _geom

__all__ = ["CATCH_DEPTH_M", "WALL_SEGMENT_M", "add_shell", "wall_count"]

#: How far below the top of a container's floor (m) its catch reaches (see :func:`add_shell`): a
#: ball that hits a floor at speed sinks into it for a few time steps before the contact stops
#: it, and one whose centre passes the middle of the geom it touches is pushed out below it
#: (a ball dropped from 25 cm into the 8 mm floor of a bowl fell through it); a ball dropped
#: from 60 cm (3.4 m/s, 17 mm per time step) stops with its centre 13 mm below the floor's top,
#: above the middle of a 3 cm catch.
CATCH_DEPTH_M = 0.03
#: Width of one wall box of a shell along its circumference, metres (at least 12 boxes).
WALL_SEGMENT_M = 0.036


def add_shell(
    body: mujoco.MjsBody,
    name: str,
    inner: float,
    wall: float,
    height: float,
    bottom: float,
    n: int,
    rgba: tuple[float, float, float, float],
    mass: float,
    at: tuple[float, float, float] = (0.0, 0.0, 0.0),
    catch: bool = True,
) -> None:
    """A cylindrical container with its base centre at ``at``: a base disc and ``n`` wall
    boxes (mass split evenly), and the base's *catch*: to the balls alone, the base is a disc
    as wide whose top is the floor's and which reaches :data:`CATCH_DEPTH_M` down (under the
    floor, where the table or nothing is), so that a falling ball cannot pass through the
    floor; the visible base touches everything but the balls, the catch (invisible, no mass,
    in the balls' geom group: rays and the arm's room leave it out) only the balls. Without
    ``catch`` (a container a hand may carry: with a catch under every container, KIT Pour's
    carton, tilted over a cup's near wall, sent a ball past the cup on 4 of 6 seeds) the base
    is the floor to the balls too."""
    each = mass / (n + 1)
    x0, y0, z0 = at
    base = _geom(
        body,
        f"{name}/base",
        mujoco.mjtGeom.mjGEOM_CYLINDER,
        (inner + wall, bottom / 2),
        (x0, y0, z0 + bottom / 2),
        rgba,
        mass=each,
    )
    if not catch:
        return _walls(body, name, inner, wall, height, n, rgba, each, at)
    base.conaffinity = OBJECT_CONAFFINITY & ~BALL_CONTYPE
    depth = max(CATCH_DEPTH_M, bottom)
    slab = body.add_geom()
    slab.name, slab.type, slab.group = f"{name}/catch", mujoco.mjtGeom.mjGEOM_CYLINDER, BALL_GROUP
    slab.size = (inner + wall, depth / 2, 0.0)
    slab.pos = (x0, y0, z0 + bottom - depth / 2)
    slab.rgba, slab.contype, slab.conaffinity, slab.mass = (0.0, 0.0, 0.0, 0.0), CATCH_CONTYPE, 0, 0.0
    _walls(body, name, inner, wall, height, n, rgba, each, at)


def _walls(
    body: mujoco.MjsBody,
    name: str,
    inner: float,
    wall: float,
    height: float,
    n: int,
    rgba: tuple[float, float, float, float],
    each: float,
    at: tuple[float, float, float],
) -> None:
    """The ``n`` wall boxes of a shell (see :func:`add_shell`), ``each`` kg."""
    x0, y0, z0 = at
    r_mid = inner + wall / 2
    half_width = (inner + wall) * math.tan(math.pi / n) + 0.001
    for i in range(n):
        a = 2 * math.pi * i / n
        quat = (math.cos(a / 2), 0.0, 0.0, math.sin(a / 2))
        # walls stand on the base disc, 2 mm above the support, so only the disc touches it
        _geom(
            body,
            f"{name}/wall{i}",
            mujoco.mjtGeom.mjGEOM_BOX,
            (wall / 2, half_width, (height - 0.002) / 2),
            (x0 + r_mid * math.cos(a), y0 + r_mid * math.sin(a), z0 + 0.002 + (height - 0.002) / 2),
            rgba,
            quat=quat,
            mass=each,
        )


def wall_count(radius: float) -> int:
    """How many wall boxes a shell of outer ``radius`` (m) has: one per :data:`WALL_SEGMENT_M`, at
    least 12."""
    return max(12, round(2 * math.pi * radius / WALL_SEGMENT_M))
