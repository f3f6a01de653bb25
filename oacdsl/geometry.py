"""What the language's geometry means: shapes, their parameters, units, and inheritance.

One table (:data:`PRIMITIVES`) says which shapes exist, which named sizes each takes
and in which unit kind; the compiler checks ``.oac`` files against it
(:mod:`oacdsl.compiler.check_geometry`) and the runtime builds objects from it
(:mod:`oacdsl.runtime.bodies`). :func:`resolve` merges an instance's geometry with its
classes': every property (shapes, mass, friction, colour, markers) comes from the
instance if it sets it, else from the most specific of its classes (parents
included) that sets it.

Units: lengths ``m``, ``cm``, ``mm`` (no unit: metres); masses ``kg``, ``g`` (no unit:
kilograms). Every shape stands with the centre of its base at ``at`` (default the
object frame's origin), its axis along the object's z.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass
from pathlib import Path

from oacdsl.errors import LanguageError
from oacdsl.library import Library
from oacdsl.model import Geometry, Instance, Point, Quantity, Scene, Shape

__all__ = [
    "UNITS",
    "COLOURS",
    "PRIMITIVES",
    "Primitive",
    "ROLE_SHAPES",
    "ROLE_OBJECT",
    "ROLE_HAND",
    "ROLE_TABLE",
    "ROLE_LIQUID",
    "RACK_FLOOR_M",
    "RACK_WALL_M",
    "ResolvedGeometry",
    "si",
    "point_si",
    "resolve",
    "resolve_scene",
]

#: Unit kind → accepted spellings and their factor to SI ("" = written without a unit).
UNITS: dict[str, dict[str, float]] = {
    "length": {"": 1.0, "m": 1.0, "cm": 0.01, "mm": 0.001},
    "mass": {"": 1.0, "kg": 1.0, "g": 0.001},
    "factor": {"": 1.0},
    "count": {"": 1.0},
}


#: A rack's base board and walls when it does not say (``rack(…, floor 1cm, wall 5mm)``), m.
RACK_FLOOR_M = 0.01
RACK_WALL_M = 0.005


@dataclass(frozen=True)
class Primitive:
    """A shape the language knows: its named sizes (name → unit kind), the required ones,
    whether it takes a file (a mesh) and a one-line description for the docs and messages."""

    params: dict[str, str]
    required: tuple[str, ...]
    about: str
    takes_file: bool = False


PRIMITIVES: dict[str, Primitive] = {
    "box": Primitive(
        {"length": "length", "width": "length", "height": "length", "mass": "mass"},
        ("length", "width", "height"),
        "a box, length along x, width along y, height along z",
    ),
    "cylinder": Primitive(
        {"radius": "length", "height": "length", "mass": "mass"}, ("radius", "height"), "an upright cylinder"
    ),
    "sphere": Primitive({"radius": "length", "mass": "mass"}, ("radius",), "a sphere"),
    "capsule": Primitive(
        {"radius": "length", "height": "length", "mass": "mass"},
        ("radius", "height"),
        "an upright capsule; height from the bottom to the top of its caps",
    ),
    "shell": Primitive(
        {"radius": "length", "height": "length", "wall": "length", "floor": "length", "mass": "mass"},
        ("radius", "height", "wall"),
        "an open round container: outer radius, height to the rim, wall and floor thickness"
        " (floor defaults to wall)",
    ),
    "rack": Primitive(
        {"length": "length", "width": "length", "height": "length", "slots": "count", "wall": "length",
         "floor": "length", "mass": "mass"},
        ("length", "width", "height", "slots"),
        "a rack things stand in on edge (a dish rack): a base board (floor, default 1 cm) and"
        " walls (wall thick, default 5 mm) along its length, as high as the rack, that divide"
        " its width into equal slots",
    ),
    "mesh": Primitive(
        {"scale": "factor", "mass": "mass"},
        (),
        'a mesh file beside the .oac file (STL or OBJ), e.g. mesh("jug.stl", scale 0.001)',
        takes_file=True,
    ),
    "balls": Primitive(
        {"radius": "length", "mass": "mass"},
        ("radius",),
        "a liquid: small free balls that start inside a container (mass: of one ball)",
    ),
    "hand": Primitive({}, (), "one of the robot's hands (bound by the instance's name: left or right)"),
    "table": Primitive({}, (), "the robot's fixed work table (environment)"),
}

#: Colour words a geometry may name (``colour red``), RGBA. A colour word in an instance's
#: name (``red_cup``) wins over its class's colour.
COLOURS: dict[str, tuple[float, float, float, float]] = {
    "red": (0.8, 0.15, 0.12, 1.0),
    "green": (0.15, 0.65, 0.2, 1.0),
    "blue": (0.15, 0.3, 0.8, 1.0),
    "orange": (0.95, 0.55, 0.1, 1.0),
    "yellow": (0.95, 0.85, 0.2, 1.0),
    "white": (0.9, 0.9, 0.9, 1.0),
    "grey": (0.6, 0.6, 0.65, 1.0),
    "steel": (0.9, 0.9, 0.92, 1.0),
    "brown": (0.45, 0.3, 0.2, 1.0),
    "black": (0.15, 0.15, 0.15, 1.0),
}

#: Roles of an instance (:attr:`ResolvedGeometry.role`): what its shape makes it for the runtime.
ROLE_OBJECT, ROLE_HAND, ROLE_TABLE, ROLE_LIQUID = "object", "hand", "table", "liquid"

#: Shapes that stand for something the runtime provides; they cannot be combined with others.
ROLE_SHAPES = frozenset({"hand", "table", "balls"})


def si(q: Quantity, kind: str) -> float:
    """The SI value of ``q`` as a quantity of ``kind`` (``length``: m, ``mass``: kg)."""
    factors = UNITS[kind]
    if q.unit not in factors:
        raise LanguageError(
            f"unknown unit '{q.unit}' for a {kind} (valid: {', '.join(u for u in factors if u)})"
        )
    return q.value * factors[q.unit]


def point_si(p: Point) -> tuple[float, float, float]:
    """A point in metres."""
    return (si(p.x, "length"), si(p.y, "length"), si(p.z, "length"))


@dataclass(frozen=True)
class ResolvedGeometry:
    """An instance's geometry after inheritance; ``base_dir`` is the folder of the ``.oac``
    file its shapes were written in (mesh files are relative to it). None when nothing
    (class or instance) gives it shapes."""

    shapes: tuple[Shape, ...]
    mass: Quantity | None
    friction: float | None
    colour: str | None
    markers: tuple[Point, ...]
    base_dir: Path

    @property
    def container(self) -> bool:
        """True when one of its shapes is an open container (``shell``)."""
        return any(s.primitive == "shell" for s in self.shapes)

    @property
    def role(self) -> str:
        """``hand``, ``table``, ``liquid`` (balls) or ``object``."""
        kinds = {s.primitive for s in self.shapes}
        if "hand" in kinds:
            return ROLE_HAND
        if "table" in kinds:
            return ROLE_TABLE
        return ROLE_LIQUID if "balls" in kinds else ROLE_OBJECT


def _most_specific(library: Library, classes: Iterable[str]) -> list[str]:
    """Classes (parents included) from the most specific (most ancestors) to the least."""
    every: set[str] = set()
    for c in classes:
        every |= library.ancestors(c)
    return sorted(every, key=lambda c: (-len(library.ancestors(c)), c))


def _base_dir(node: Geometry) -> Path:
    return Path(node.span.file).parent if node.span is not None else Path(".")


def resolve(library: Library, instance: Instance) -> ResolvedGeometry | None:
    """The geometry of ``instance`` (see the module docstring); None without shapes."""
    layers: list[Geometry] = [instance.geometry] if instance.geometry is not None else []
    for name in _most_specific(library, instance.classes):
        cls = library.classes.get(name)
        if cls is not None and cls.geometry is not None:
            layers.append(cls.geometry)
    shaped = next((g for g in layers if g.shapes), None)
    if shaped is None:
        return None
    return ResolvedGeometry(
        shapes=shaped.shapes,
        mass=next((g.mass for g in layers if g.mass is not None), None),
        friction=next((g.friction for g in layers if g.friction is not None), None),
        colour=next((g.colour for g in layers if g.colour is not None), None),
        markers=next((g.markers for g in layers if g.markers), ()),
        base_dir=_base_dir(shaped),
    )


def resolve_scene(library: Library, scene: Scene) -> dict[str, ResolvedGeometry | None]:
    """Instance name → its resolved geometry (None when it has none)."""
    return {inst.name: resolve(library, inst) for inst in scene.instances}
