"""Object classes and how the robot grasps them: :class:`ObjectClass` with its
:class:`Geometry` of :class:`Shape` primitives, and :class:`Grasp` (see :mod:`oacdsl.model`)."""

from __future__ import annotations

from typing import Literal

from pydantic import field_validator

from oacdsl.model.node import Dim, Node, Point, Quantity

__all__ = ["APPROACHES", "GRASP_TYPES", "Geometry", "Grasp", "ObjectClass", "Shape"]

#: Hand shapes a ``grasp`` declaration may name (``type``).
GRASP_TYPES: tuple[str, ...] = ("handle", "pinch", "power", "precision", "rim")
#: Directions a hand may approach an object from (``approach``), in the object frame.
APPROACHES: tuple[str, ...] = ("front", "side", "top")


class Shape(Node):
    """One primitive of an object's geometry: ``shell(radius 4cm, height 10cm, wall 6mm) at (0, 0, 1cm)``.

    ``primitive`` is the shape's name (``cylinder``, ``box``, ``sphere``, ``capsule``,
    ``shell``, ``mesh``, ``balls``, ``hand``, ``table``: see :mod:`oacdsl.geometry`),
    ``dims`` its named sizes in written order, ``file`` a mesh file (relative to the
    ``.oac`` file) and ``at`` where the centre of its base sits in the object frame.
    """

    primitive: str
    dims: tuple[Dim, ...] = ()
    file: str | None = None
    at: Point | None = None

    def dim(self, name: str) -> Quantity | None:
        for d in self.dims:
            if d.name == name:
                return d.value
        return None


class Geometry(Node):
    """``{ shape … mass … }`` — an object's physical description (of a class or an instance).

    Several shapes make a compound. Unset properties come from the class (for an
    instance) or the nearest parent class that sets them (for a class).
    """

    shapes: tuple[Shape, ...] = ()
    mass: Quantity | None = None
    friction: float | None = None
    colour: str | None = None
    markers: tuple[Point, ...] = ()


class ObjectClass(Node):
    """``class Cup : Graspable, Container { … }`` — a class with zero or more parents and,
    optionally, its geometry."""

    kind: Literal["class"] = "class"
    name: str
    parents: tuple[str, ...] = ()
    geometry: Geometry | None = None

    @field_validator("parents")
    @classmethod
    def _sort_parents(cls, v: tuple[str, ...]) -> tuple[str, ...]:
        return tuple(sorted(set(v)))


class Grasp(Node):
    """``grasp Cup { … }`` — how the robot grasps objects of a class.

    ``offset`` is the grasp point in the object frame, metres; ``approach`` is the
    direction the hand comes from (``side``, ``top``, ``front``); ``type`` is the
    hand shape (``power``, ``precision``, ``pinch``, ``rim``, ``handle``).
    """

    kind: Literal["grasp"] = "grasp"
    cls: str
    type: str
    approach: str
    offset: tuple[float, float, float] = (0.0, 0.0, 0.0)
