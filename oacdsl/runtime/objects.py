"""Build the scene's objects in MuJoCo from their :class:`~oacdsl.runtime.bodies.Body`.

Every object is one MuJoCo body with a free joint (the table is fixed). Its frame, the
*object frame* in which grasp offsets are given, has its origin at the centre of the
object's base, z up and x pointing away from the robot at the nominal placement. Each
solid of the language's geometry becomes geoms: a box, cylinder, sphere or capsule one
geom; an open container (``shell``) a base disc and a ring of wall boxes, so that balls
can lie inside and be poured out; a rack a base board and its walls (boxes,
:mod:`oacdsl.runtime.racks`); a mesh a mesh geom. Sizes are metres, masses kilograms.
"""

from __future__ import annotations

import math

import mujoco
import numpy as np

from oacdsl.runtime.bodies import Body, Solid
from oacdsl.runtime.geoms import (
    BALL_CONAFFINITY,
    BALL_CONTYPE,
    BALL_GROUP,
    OBJECT_CONAFFINITY,
    OBJECT_CONTYPE,
)
from oacdsl.runtime.geoms import add_geom as _geom
from oacdsl.runtime.racks import rack_boxes, rack_volume
from oacdsl.runtime.shells import add_shell as _shell
from oacdsl.runtime.shells import wall_count as _wall_count

__all__ = [
    "add_object",
    "add_table",
    "add_balls",
    "TABLE_TOP",
    "TABLE_FRONT",
    "TABLE_DEPTH",
    "TABLE_WIDTH",
]

#: Height of the table top above the floor and its front edge (x), metres.
TABLE_TOP = 0.80
TABLE_FRONT = 0.40
TABLE_DEPTH = 1.00
TABLE_WIDTH = 1.60

_FRICTION = (1.0, 0.005, 0.0001)


def _solid(
    body: mujoco.MjsBody,
    name: str,
    s: Solid,
    rgba: tuple[float, float, float, float],
    mass: float,
    friction: tuple[float, float, float],
    catch: bool = True,
) -> None:
    d, (x, y, z) = s.dims, s.at
    if s.kind == "shell":
        inner = d["radius"] - d["wall"]
        _shell(
            body,
            name,
            inner,
            d["wall"],
            d["height"],
            d.get("floor", d["wall"]),
            _wall_count(d["radius"]),
            rgba,
            mass,
            (x, y, z),
            catch,
        )
    elif s.kind == "box":
        size = (d["length"] / 2, d["width"] / 2, d["height"] / 2)
        _geom(
            body,
            name,
            mujoco.mjtGeom.mjGEOM_BOX,
            size,
            (x, y, z + size[2]),
            rgba,
            mass=mass,
            friction=friction,
        )
    elif s.kind == "rack":
        for k, (centre, half) in enumerate(rack_boxes(d, (x, y, z))):
            part = "base" if k == 0 else f"wall{k - 1}"
            _geom(body, f"{name}/{part}", mujoco.mjtGeom.mjGEOM_BOX, half, centre, rgba,
                  mass=mass * _box_share(half, d), friction=friction)
    elif s.kind == "cylinder":
        _geom(
            body,
            name,
            mujoco.mjtGeom.mjGEOM_CYLINDER,
            (d["radius"], d["height"] / 2),
            (x, y, z + d["height"] / 2),
            rgba,
            mass=mass,
            friction=friction,
        )
    elif s.kind == "capsule":
        _geom(
            body,
            name,
            mujoco.mjtGeom.mjGEOM_CAPSULE,
            (d["radius"], d["height"] / 2 - d["radius"]),
            (x, y, z + d["height"] / 2),
            rgba,
            mass=mass,
            friction=friction,
        )
    elif s.kind == "sphere":
        _geom(
            body,
            name,
            mujoco.mjtGeom.mjGEOM_SPHERE,
            (d["radius"],),
            (x, y, z + d["radius"]),
            rgba,
            mass=mass,
            friction=friction,
        )
    elif s.kind == "mesh":
        g = body.add_geom()
        g.name, g.type, g.meshname, g.pos, g.rgba = name, mujoco.mjtGeom.mjGEOM_MESH, name, (x, y, z), rgba
        g.contype, g.conaffinity, g.friction, g.mass = OBJECT_CONTYPE, OBJECT_CONAFFINITY, friction, mass
    else:
        raise ValueError(f"the runtime cannot build a {s.kind!r}")


def _box_share(half: tuple[float, float, float], d: dict[str, float]) -> float:
    """A box's share of a rack's volume (its mass splits by volume)."""
    return 8 * half[0] * half[1] * half[2] / rack_volume(d)


def _masses(body: Body) -> list[float]:
    """Each solid's mass: its own, else a share of the rest of the body's mass by volume."""
    given = sum(s.mass for s in body.solids if s.mass is not None)
    free = [s for s in body.solids if s.mass is None]
    volume = sum(s.volume for s in free)
    rest = max(body.mass - given, 1e-3 * len(free))
    return [s.mass if s.mass is not None else rest * s.volume / volume for s in body.solids]


def _add_meshes(spec: mujoco.MjSpec, name: str, body: Body) -> None:
    for i, s in enumerate(body.solids):
        if s.kind == "mesh":
            mesh = spec.add_mesh()
            mesh.name, mesh.file, mesh.scale = _part_name(name, body, i), str(s.file), (s.scale,) * 3
            mesh.inertia = mujoco.mjtMeshInertia.mjMESH_INERTIA_SHELL


def _part_name(name: str, body: Body, i: int) -> str:
    """Geom names: a single solid is ``name/body`` (a shell's base ``name/base``), else ``name/partI``."""
    return f"{name}/body" if len(body.solids) == 1 else f"{name}/part{i}"


def add_object(
    spec: mujoco.MjSpec, name: str, shape: Body, pos: tuple[float, float, float], yaw: float = 0.0
) -> mujoco.MjsBody:
    """Add a free object called ``name`` built from ``shape`` with its base centre at ``pos``."""
    if not shape.solids:
        raise ValueError(f"{name!r} has no solids to build")
    _add_meshes(spec, name, shape)
    body = spec.worldbody.add_body()
    body.name, body.pos = name, pos
    body.quat = (math.cos(yaw / 2), 0.0, 0.0, math.sin(yaw / 2))
    body.add_freejoint().name = f"{name}/free"
    friction = (shape.friction, 0.005, 0.0001) if shape.friction is not None else _FRICTION
    for i, (s, mass) in enumerate(zip(shape.solids, _masses(shape), strict=True)):
        part = name if s.kind == "shell" and len(shape.solids) == 1 else _part_name(name, shape, i)
        # a catch under the floor of a container that stays on the table (inside the table top)
        _solid(body, part, s, shape.rgba, mass, friction, catch=not shape.graspable)
    return body


def add_balls(
    spec: mujoco.MjSpec,
    name: str,
    count: int,
    centre: np.ndarray,
    container: Body,
    liquid: Body,
    rng: np.random.Generator,
) -> list[str]:
    """``count`` free balls of ``liquid`` stacked in layers inside ``container``, whose base
    centre is at ``centre`` (world, metres)."""
    r, inner_radius, rgba = liquid.ball_radius, container.inner_radius, liquid.rgba
    ring = max(inner_radius - r - 0.002, 0.0)
    slots: list[tuple[float, float]] = [(0.0, 0.0)]
    per_ring = max(int(2 * math.pi * ring / (2.2 * r)), 1)
    slots += [
        (ring * math.cos(2 * math.pi * k / per_ring), ring * math.sin(2 * math.pi * k / per_ring))
        for k in range(per_ring)
    ]
    names = []
    for i in range(count):
        layer, slot = divmod(i, len(slots))
        jitter = rng.uniform(-0.001, 0.001, size=2)
        x, y = slots[slot][0] + jitter[0], slots[slot][1] + jitter[1]
        body = spec.worldbody.add_body()
        body.name = f"{name}/ball{i}"
        body.pos = (
            float(centre[0] + x),
            float(centre[1] + y),
            float(centre[2] + container.floor + 0.002 + r + layer * 2.05 * r),
        )
        body.add_freejoint()
        # frictionless (condim 1): balls flow like a liquid and cost one constraint row per contact
        ball = _geom(
            body,
            f"{name}/ball{i}",
            mujoco.mjtGeom.mjGEOM_SPHERE,
            (r,),
            (0.0, 0.0, 0.0),
            rgba,
            mass=liquid.ball_mass,
            condim=1,
        )
        ball.group, ball.contype, ball.conaffinity = BALL_GROUP, BALL_CONTYPE, BALL_CONAFFINITY
        names.append(body.name)
    return names


def add_table(spec: mujoco.MjSpec, name: str) -> mujoco.MjsBody:
    """The fixed table: top surface at :data:`TABLE_TOP`, front edge at :data:`TABLE_FRONT`."""
    body = spec.worldbody.add_body()
    body.name = name
    cx = TABLE_FRONT + TABLE_DEPTH / 2
    body.pos = (cx, 0.0, 0.0)
    wood = (0.55, 0.42, 0.3, 1.0)
    _geom(
        body,
        f"{name}/top",
        mujoco.mjtGeom.mjGEOM_BOX,
        (TABLE_DEPTH / 2, TABLE_WIDTH / 2, 0.02),
        (0.0, 0.0, TABLE_TOP - 0.02),
        wood,
    )
    for i, (sx, sy) in enumerate(((1, 1), (1, -1), (-1, 1), (-1, -1))):
        _geom(
            body,
            f"{name}/leg{i}",
            mujoco.mjtGeom.mjGEOM_BOX,
            (0.03, 0.03, (TABLE_TOP - 0.04) / 2),
            (sx * (TABLE_DEPTH / 2 - 0.05), sy * (TABLE_WIDTH / 2 - 0.05), (TABLE_TOP - 0.04) / 2),
            wood,
        )
    return body
