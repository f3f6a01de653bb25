"""The runtime's view of an object's geometry, from the language (:mod:`oacdsl.geometry`).

A :class:`Body` is what the runtime knows about one instance: its role (an object
the robot may touch, one of the robot's hands, the table, a liquid), its solids in SI
units, mass, friction, colour, marker points, whether a grasp is declared for it,
and the properties the skills and the layout ask about (footprint radius, height,
the inside of a container, rotational symmetry). No class name decides anything
here: :func:`bodies_for_scene` resolves each instance's geometry in the library.
Lengths are metres, masses kilograms, in the object frame (origin at the centre of
the object's base, z up).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

from oacdsl.errors import RuntimeFailure
from oacdsl.geometry import (
    COLOURS,
    PRIMITIVES,
    ROLE_LIQUID,
    ROLE_OBJECT,
    ResolvedGeometry,
    point_si,
    resolve,
    si,
)
from oacdsl.library import Library
from oacdsl.model import Scene
from oacdsl.runtime.racks import Slot, rack_slots, rack_volume

__all__ = ["Solid", "Body", "body_from", "bodies_for_scene", "DEFAULT_DENSITY", "colour_for", "mesh_extent"]

#: Density of a solid whose mass nothing gives, kg/m³ (light plastic or wood).
DEFAULT_DENSITY = 600.0
_GREY = (0.6, 0.6, 0.6, 1.0)


@dataclass(frozen=True)
class Solid:
    """One primitive: ``kind`` (box, cylinder, sphere, capsule, shell, rack, mesh), its sizes
    (``dims``, SI), the centre of its base in the object frame (``at``), an explicit mass
    (kg) or None, and for a mesh its file and scale."""

    kind: str
    dims: dict[str, float] = field(hash=False)
    at: tuple[float, float, float] = (0.0, 0.0, 0.0)
    mass: float | None = None
    file: Path | None = None
    scale: float = 1.0

    @property
    def radius(self) -> float:
        """Horizontal extent around the object's z axis, m (0 for a mesh: see its bounds)."""
        d, off = self.dims, math.hypot(self.at[0], self.at[1])
        if self.kind in ("box", "rack"):
            return off + math.hypot(d["length"] / 2, d["width"] / 2)
        return off + d.get("radius", 0.0)

    @property
    def top(self) -> float:
        """Height of the solid's top above the object frame's origin, m."""
        d = self.dims
        return self.at[2] + (2 * d["radius"] if self.kind == "sphere" else d.get("height", 0.0))

    @property
    def volume(self) -> float:
        d = self.dims
        if self.kind == "box":
            return d["length"] * d["width"] * d["height"]
        if self.kind == "cylinder":
            return math.pi * d["radius"] ** 2 * d["height"]
        if self.kind == "sphere":
            return 4 / 3 * math.pi * d["radius"] ** 3
        if self.kind == "capsule":
            r = d["radius"]
            return math.pi * r**2 * (d["height"] - 2 * r) + 4 / 3 * math.pi * r**3
        if self.kind == "rack":
            return rack_volume(d)
        if self.kind == "shell":
            r, inner = d["radius"], d["radius"] - d["wall"]
            floor = d.get("floor", d["wall"])
            return math.pi * (r**2 - inner**2) * (d["height"] - floor) + math.pi * r**2 * floor
        return 1e-4  # a mesh: its mass should be given

    @property
    def centred(self) -> bool:
        """Round and on the object's z axis."""
        return self.kind in ("cylinder", "sphere", "capsule", "shell") and self.at[:2] == (0.0, 0.0)


@dataclass(frozen=True)
class Body:
    """An instance's geometry as the runtime uses it (see the module docstring)."""

    role: str
    solids: tuple[Solid, ...] = ()
    mass: float = 0.0
    friction: float | None = None
    rgba: tuple[float, float, float, float] = _GREY
    points: tuple[tuple[float, float, float], ...] = ()
    graspable: bool = False
    ball_radius: float = 0.0
    ball_mass: float = 0.0
    #: Horizontal extent of meshes (computed when the model is built), m.
    mesh_extent: tuple[float, float] = field(default=(0.0, 0.0))

    @property
    def radius(self) -> float:
        """Footprint radius around the object's z axis, m."""
        return max([s.radius for s in self.solids] + [self.mesh_extent[0]], default=0.0)

    @property
    def height(self) -> float:
        """Height of the object's top above its base, m."""
        return max([s.top for s in self.solids] + [self.mesh_extent[1]], default=0.0)

    @property
    def shell(self) -> Solid | None:
        """The open container solid, if the object is (or has) one."""
        return next((s for s in self.solids if s.kind == "shell"), None)

    @property
    def container(self) -> bool:
        return self.shell is not None

    @property
    def inner_radius(self) -> float:
        """Inner radius of the container, m (0 when it is none)."""
        s = self.shell
        return 0.0 if s is None else s.dims["radius"] - s.dims["wall"]

    @property
    def rim_radius(self) -> float:
        """Outer radius of the container's rim (the footprint radius when it is none), m."""
        s = self.shell
        return self.radius if s is None else s.dims["radius"]

    @property
    def rim_height(self) -> float:
        """Height of the container's rim (the object's height when it is none), m."""
        s = self.shell
        return self.height if s is None else s.top

    @property
    def floor(self) -> float:
        """Height of the container's floor (inside) above the base, m (0 when none)."""
        s = self.shell
        return 0.0 if s is None else s.at[2] + s.dims.get("floor", s.dims["wall"])

    @property
    def slots(self) -> list[Slot]:
        """The slots of its racks (``shape rack``; none when it has no rack), object frame."""
        return [slot for s in self.solids if s.kind == "rack" for slot in rack_slots(s.dims, s.at)]

    @property
    def round(self) -> bool:
        """Rotationally symmetric about z (a grasp may come from any azimuth)."""
        return bool(self.solids) and all(s.centred for s in self.solids) and not self.mesh_extent[0]

    @property
    def markers(self) -> tuple[tuple[float, float, float], ...]:
        """A few points in the object frame for recorded trajectories: the language's
        ``markers``, else the top centre, a point on the side and one low on the other side."""
        if self.points:
            return self.points
        r, h = self.radius, self.height
        return ((0.0, 0.0, h), (r, 0.0, h / 2), (0.0, r, 0.0))


def colour_for(name: str, colour: str | None) -> tuple[float, float, float, float]:
    """A colour word in the instance name wins, else the geometry's colour, else grey."""
    for word, rgba in COLOURS.items():
        if word in name:
            return rgba
    return COLOURS.get(colour or "", _GREY)


def _solids(geo: ResolvedGeometry) -> tuple[Solid, ...]:
    out = []
    for shape in geo.shapes:
        kinds = PRIMITIVES[shape.primitive].params
        dims = {d.name: si(d.value, kinds.get(d.name, "length")) for d in shape.dims}
        mass = dims.pop("mass", None)
        scale = dims.pop("scale", 1.0)
        at = point_si(shape.at) if shape.at is not None else (0.0, 0.0, 0.0)
        file = geo.base_dir / shape.file if shape.file is not None else None
        out.append(Solid(shape.primitive, dims, at, mass, file, scale))
    return tuple(out)


def mesh_extent(solid: Solid) -> tuple[float, float]:
    """(horizontal extent around z, top height) of a mesh solid placed at its ``at``, metres."""
    import mujoco
    import numpy as np

    spec = mujoco.MjSpec()
    mesh = spec.add_mesh()
    mesh.name, mesh.file, mesh.scale = "m", str(solid.file), (solid.scale,) * 3
    g = spec.worldbody.add_body().add_geom()
    g.type, g.meshname = mujoco.mjtGeom.mjGEOM_MESH, "m"
    try:
        model = spec.compile()
    except ValueError as error:
        raise RuntimeFailure(f"cannot load mesh {solid.file}: {error}") from None
    verts = model.mesh_vert[: model.mesh_vertnum[0]]
    data = mujoco.MjData(model)
    mujoco.mj_forward(model, data)
    world = verts @ data.geom_xmat[0].reshape(3, 3).T + data.geom_xpos[0] + np.asarray(solid.at)
    return float(np.max(np.hypot(world[:, 0], world[:, 1]))), float(np.max(world[:, 2]))


def body_from(geo: ResolvedGeometry, name: str, graspable: bool) -> Body:
    """The :class:`Body` of instance ``name`` with resolved geometry ``geo``."""
    role = geo.role
    mass = si(geo.mass, "mass") if geo.mass is not None else None
    rgba = colour_for(name, geo.colour)
    points = tuple(point_si(p) for p in geo.markers)
    if role == ROLE_LIQUID:
        balls = geo.shapes[0]
        radius = si(balls.dim("radius"), "length")  # type: ignore[arg-type]
        each = balls.dim("mass")
        ball_mass = si(each, "mass") if each is not None else DEFAULT_DENSITY * 4 / 3 * math.pi * radius**3
        return Body(role, rgba=rgba, ball_radius=radius, ball_mass=ball_mass)
    if role != ROLE_OBJECT:
        return Body(role, rgba=rgba)
    solids = _solids(geo)
    extents = [mesh_extent(s) for s in solids if s.kind == "mesh"]
    extent = (max(e[0] for e in extents), max(e[1] for e in extents)) if extents else (0.0, 0.0)
    if mass is None:
        mass = sum(s.mass if s.mass is not None else DEFAULT_DENSITY * s.volume for s in solids)
    return Body(role, solids, mass, geo.friction, rgba, points, graspable, mesh_extent=extent)


def bodies_for_scene(library: Library, scene: Scene) -> dict[str, Body]:
    """Instance name → its :class:`Body`; a located failure for an instance without shapes."""
    classes = library.instance_classes(scene)
    out: dict[str, Body] = {}
    for inst in scene.instances:
        geo = resolve(library, inst)
        if geo is None:
            shaped = sorted(
                n for n, c in library.classes.items() if c.geometry is not None and c.geometry.shapes
            )
            where = f" ({inst.span})" if inst.span is not None else ""
            raise RuntimeFailure(
                f"instance {inst.name!r} of scene {scene.name!r}{where}"
                f" (classes {', '.join(sorted(classes[inst.name]))})"
                " has no shape: give its class (or the instance) one,"
                " e.g. `{ shape cylinder(radius 4cm, height 10cm) }`;"
                f" classes with a shape: {', '.join(shaped) or 'none'}"
            )
        out[inst.name] = body_from(geo, inst.name, library.grasp_for(classes[inst.name]) is not None)
    return out
