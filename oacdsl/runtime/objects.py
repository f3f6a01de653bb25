"""Object geometry per class: cups, bowls, balls (liquid), mixer, sponge, tray, table.

Every object is one MuJoCo body with a free joint (the table is fixed). Its frame, the
*object frame* in which grasp offsets are given, has its origin at the centre of the
object's base, z up and x pointing away from the robot at the nominal placement.
Containers are shells of boxes around a base disc, so that balls can lie inside and
be poured out. Sizes are metres, masses kilograms.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import mujoco
import numpy as np

__all__ = [
    "Shape3D",
    "SHAPES",
    "CLASS_SHAPES",
    "add_object",
    "add_table",
    "add_balls",
    "BALL_RADIUS",
    "TABLE_TOP",
    "TABLE_FRONT",
    "TABLE_DEPTH",
    "TABLE_WIDTH",
    "colour_for",
]

#: Height of the table top above the floor and its front edge (x), metres.
TABLE_TOP = 0.80
TABLE_FRONT = 0.40
TABLE_DEPTH = 1.00
TABLE_WIDTH = 1.60
#: Radius of a liquid ball, metres (the paper's robot runs used small balls).
BALL_RADIUS = 0.009
BALL_MASS = 0.003

#: Geom group of the balls (objects and the table are group 0).
BALL_GROUP = 1
#: Collision bits: robot geoms (2) touch objects (1) but not each other.
OBJECT_CONTYPE, OBJECT_CONAFFINITY = 1, 3


@dataclass(frozen=True)
class Shape3D:
    """The geometry of one object kind.

    ``radius``: footprint radius used for placement; ``inner_radius``/``height``: the
    inside of a container (0 when it is not one); ``grip_height``: where a hand holds it.
    ``markers``: a few points in the object frame, for recorded trajectories.
    """

    kind: str
    radius: float
    height: float
    mass: float
    inner_radius: float = 0.0
    markers: tuple[tuple[float, float, float], ...] = field(default=())


SHAPES: dict[str, Shape3D] = {
    "cup": Shape3D("cup", 0.04, 0.10, 0.15, 0.034, ((0.0, 0.0, 0.10), (0.04, 0.0, 0.05), (0.0, 0.04, 0.02))),
    "bowl": Shape3D(
        "bowl", 0.115, 0.055, 0.5, 0.108, ((0.0, 0.0, 0.0), (0.115, 0.0, 0.055), (0.0, 0.115, 0.055))
    ),
    "mixer": Shape3D("mixer", 0.036, 0.22, 0.62, 0.0, ((0.0, 0.0, 0.0), (0.0, 0.0, 0.12), (0.0, 0.0, 0.22))),
    "sponge": Shape3D(
        "sponge", 0.06, 0.05, 0.06, 0.0, ((0.05, 0.0, 0.05), (-0.05, 0.0, 0.05), (0.0, 0.035, 0.0))
    ),
    "tray": Shape3D(
        "tray", 0.17, 0.012, 0.6, 0.0, ((0.15, 0.0, 0.012), (-0.15, 0.0, 0.012), (0.0, 0.11, 0.012))
    ),
}

#: DSL class → object kind (the most specific class of an instance that is listed wins).
CLASS_SHAPES: dict[str, str] = {
    "Cup": "cup",
    "Bowl": "bowl",
    "Mixer": "mixer",
    "Sponge": "sponge",
    "Tray": "tray",
    "Surface": "tray",
    "Liquid": "liquid",
    "Hand": "hand",
    "Table": "table",
}

_COLOURS = {
    "red": (0.8, 0.15, 0.12, 1.0),
    "green": (0.15, 0.65, 0.2, 1.0),
    "blue": (0.15, 0.3, 0.8, 1.0),
    "orange": (0.95, 0.55, 0.1, 1.0),
    "yellow": (0.95, 0.85, 0.2, 1.0),
    "white": (0.9, 0.9, 0.9, 1.0),
}
_DEFAULT = {
    "cup": (0.6, 0.6, 0.65, 1.0),
    "bowl": (0.95, 0.55, 0.1, 1.0),
    "mixer": (0.9, 0.9, 0.92, 1.0),
    "sponge": (0.95, 0.85, 0.2, 1.0),
    "tray": (0.45, 0.3, 0.2, 1.0),
}


def colour_for(name: str, kind: str) -> tuple[float, float, float, float]:
    """A colour from a colour word in the instance name, else the kind's default."""
    for word, rgba in _COLOURS.items():
        if word in name:
            return rgba
    return _DEFAULT.get(kind, (0.6, 0.6, 0.6, 1.0))


def _geom(
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
) -> None:
    g = body.add_geom()
    g.name, g.type, g.pos, g.quat, g.rgba = name, gtype, pos, quat, rgba
    g.size = (*size, 0.0, 0.0)[:3] if len(size) < 3 else size
    g.contype, g.conaffinity, g.friction = OBJECT_CONTYPE, OBJECT_CONAFFINITY, friction
    g.condim = condim
    g.priority = 1 if condim == 1 else 0  # a frictionless ball decides its contacts' condim
    if mass is not None:
        g.mass = mass


def _shell(
    body: mujoco.MjsBody,
    name: str,
    inner: float,
    wall: float,
    height: float,
    bottom: float,
    n: int,
    rgba: tuple[float, float, float, float],
    mass: float,
) -> None:
    """A cylindrical container: a base disc and ``n`` wall boxes (mass split evenly)."""
    each = mass / (n + 1)
    _geom(
        body,
        f"{name}/base",
        mujoco.mjtGeom.mjGEOM_CYLINDER,
        (inner + wall, bottom / 2),
        (0.0, 0.0, bottom / 2),
        rgba,
        mass=each,
    )
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
            (r_mid * math.cos(a), r_mid * math.sin(a), 0.002 + (height - 0.002) / 2),
            rgba,
            quat=quat,
            mass=each,
        )


def add_object(
    spec: mujoco.MjSpec, name: str, kind: str, pos: tuple[float, float, float], yaw: float = 0.0
) -> mujoco.MjsBody:
    """Add a free object of ``kind`` called ``name`` with its base centre at ``pos``."""
    s = SHAPES[kind]
    rgba = colour_for(name, kind)
    body = spec.worldbody.add_body()
    body.name, body.pos = name, pos
    body.quat = (math.cos(yaw / 2), 0.0, 0.0, math.sin(yaw / 2))
    body.add_freejoint().name = f"{name}/free"
    if kind == "cup":
        _shell(body, name, s.inner_radius, s.radius - s.inner_radius, s.height, 0.006, 12, rgba, s.mass)
    elif kind == "bowl":
        _shell(body, name, s.inner_radius, s.radius - s.inner_radius, s.height, 0.008, 20, rgba, s.mass)
    elif kind == "mixer":
        cyl = mujoco.mjtGeom.mjGEOM_CYLINDER
        # a stick mixer: whisk head 0-6 cm, neck, grip 7-22 cm (the hand takes it around 12 cm)
        steel = (0.75, 0.75, 0.8, 1.0)
        _geom(body, f"{name}/head", cyl, (0.036, 0.03), (0.0, 0.0, 0.03), steel, mass=0.35)
        _geom(body, f"{name}/neck", cyl, (0.01, 0.006), (0.0, 0.0, 0.065), steel, mass=0.02)
        _geom(body, f"{name}/grip", cyl, (0.02, 0.075), (0.0, 0.0, 0.145), rgba, mass=0.25)
    elif kind == "sponge":  # a kitchen sponge block, taken from above
        _geom(
            body,
            f"{name}/body",
            mujoco.mjtGeom.mjGEOM_BOX,
            (0.05, 0.035, 0.025),
            (0.0, 0.0, 0.025),
            rgba,
            mass=s.mass,
            friction=(1.2, 0.005, 0.0001),
        )
    elif kind == "tray":
        _geom(
            body,
            f"{name}/plate",
            mujoco.mjtGeom.mjGEOM_BOX,
            (0.15, 0.11, 0.006),
            (0.0, 0.0, 0.006),
            rgba,
            mass=s.mass,
            friction=(0.4, 0.005, 0.0001),
        )
    else:
        raise ValueError(f"unknown object kind {kind!r}")
    return body


def add_balls(
    spec: mujoco.MjSpec,
    name: str,
    count: int,
    centre: np.ndarray,
    inner_radius: float,
    rgba: tuple[float, float, float, float],
    rng: np.random.Generator,
) -> list[str]:
    """``count`` free balls stacked in layers inside a container whose base centre is ``centre``."""
    r = BALL_RADIUS
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
            float(centre[2] + 0.008 + r + layer * 2.05 * r),
        )
        body.add_freejoint()
        # frictionless (condim 1): balls flow like a liquid and cost one constraint row per contact
        _geom(
            body,
            f"{name}/ball{i}",
            mujoco.mjtGeom.mjGEOM_SPHERE,
            (r,),
            (0.0, 0.0, 0.0),
            rgba,
            mass=BALL_MASS,
            condim=1,
        )
        body.first_geom().group = BALL_GROUP
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
