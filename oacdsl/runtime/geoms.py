"""The MuJoCo geoms of the scene's objects: their collision bits and groups, and how one is
added to a body (sizes in metres, masses in kilograms)."""

from __future__ import annotations

import mujoco

__all__ = [
    "BALL_CONAFFINITY",
    "BALL_CONTYPE",
    "BALL_GROUP",
    "CATCH_CONTYPE",
    "OBJECT_CONAFFINITY",
    "OBJECT_CONTYPE",
    "add_geom",
]

#: Geom group of the balls (objects and the table are group 0).
BALL_GROUP = 1
#: Collision bits: robot geoms (2) touch objects (1) but not each other; balls (8) touch
#: objects, the robot, each other and a container's catch (16), not its visible floor.
OBJECT_CONTYPE, BALL_CONTYPE, CATCH_CONTYPE = 1, 8, 16
OBJECT_CONAFFINITY = 3 | BALL_CONTYPE
BALL_CONAFFINITY = 2 | BALL_CONTYPE | CATCH_CONTYPE


def add_geom(
    body: mujoco.MjsBody,
    name: str,
    gtype: mujoco.mjtGeom,
    size: tuple[float, ...],
    pos: tuple[float, float, float],
    rgba: tuple[float, float, float, float],
    quat: tuple[float, float, float, float] = (1.0, 0.0, 0.0, 0.0),
    mass: float | None = None,
    friction: tuple[float, float, float] = (1.0, 0.005, 0.0001),
    condim: int = 3,
) -> mujoco.MjsGeom:
    """A geom of an object (collision bits :data:`OBJECT_CONTYPE`, :data:`OBJECT_CONAFFINITY`) on
    ``body``; ``size`` is MuJoCo's (half-sizes, radii), ``pos`` in the body's frame."""
    g = body.add_geom()
    g.name, g.type, g.pos, g.quat, g.rgba = name, gtype, pos, quat, rgba
    g.size = (*size, 0.0, 0.0)[:3] if len(size) < 3 else size
    g.contype, g.conaffinity, g.friction = OBJECT_CONTYPE, OBJECT_CONAFFINITY, friction
    g.condim = condim
    g.priority = 1 if condim == 1 else 0  # a frictionless ball decides its contacts' condim
    if mass is not None:
        g.mass = mass
    return g
