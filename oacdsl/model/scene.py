"""A scene: the named :class:`Instance` objects of one demonstration setting and its initial
state (:class:`ScenePlace`, :class:`SceneFill`) (see :mod:`oacdsl.model`)."""

from __future__ import annotations

from typing import Literal

from pydantic import field_validator

from oacdsl.model.node import Node, Quantity
from oacdsl.model.objects import Geometry
from oacdsl.units import language_si

__all__ = ["LAYOUTS", "MAX_BALLS", "Instance", "Scene", "SceneFill", "ScenePlace", "fill_key", "place_key"]

#: Where a scene's objects start when no ``at`` says (``layout …``).
LAYOUTS: tuple[str, ...] = ("auto", "demonstrated")
#: Most balls one liquid may have (``balls N``; each ball is a free body in the simulation).
MAX_BALLS = 40


class Instance(Node):
    """A named object of a scene; its name is the label of its marker group.

    ``markers`` optionally lists the motion-capture marker names of the group
    (an explicit mapping); ``environment`` marks geometry that is not tracked
    (the table in the paper's scene): it takes no part in touching relations;
    ``ignored`` marks a marker group of the recording that is neither tracked nor built;
    ``untracked`` an object the recording does not track (KIT's milk: no markers) that
    is built and takes part in relations, which OAC effects predict (docs/language.md).
    ``geometry`` overrides its class's geometry property by property.
    """

    name: str
    classes: tuple[str, ...]
    markers: tuple[str, ...] = ()
    environment: bool = False
    #: A marker group nobody uses (``rack : Rack ignored``): not tracked, not built.
    ignored: bool = False
    #: Built and related, but not in the recording (``milk : Milk untracked``): its relations
    #: are predicted by OAC effects, never observed in the demonstration.
    untracked: bool = False
    geometry: Geometry | None = None

    @field_validator("classes")
    @classmethod
    def _sort_classes(cls, v: tuple[str, ...]) -> tuple[str, ...]:
        return tuple(sorted(set(v)))


class ScenePlace(Node):
    """``red_cup at (56cm, 28cm)`` — where an object starts on the robot's table, and
    ``rolling_pin at (58cm, 0) turned 90deg`` — how it is turned there.

    ``x`` is forward from the robot's platform centre, ``y`` to its left (metres); ``yaw``
    (an angle as written; None: not turned, a zero yaw is None) turns the object about the
    vertical through its origin, from the robot's x axis towards its y axis (:attr:`yaw_rad`).
    """

    instance: str
    x: Quantity
    y: Quantity
    yaw: Quantity | None = None

    @field_validator("yaw")
    @classmethod
    def _no_zero_yaw(cls, v: Quantity | None) -> Quantity | None:
        return None if v is None or v.value == 0 else v

    @property
    def yaw_rad(self) -> float:
        """The yaw in radians (0 when not turned; a bare number is radians)."""
        if self.yaw is None:
            return 0.0
        return language_si(self.yaw.value, self.yaw.unit)[0]


class SceneFill(Node):
    """``liquid_one in red_cup balls 12`` — a liquid that starts inside a container.

    ``balls`` is the number of simulated balls (None: the runtime's default).
    """

    liquid: str
    container: str
    balls: int | None = None


class Scene(Node):
    """``scene kitchen { … }`` — the instances of one demonstration setting.

    ``layout`` says where objects without an ``at`` start (``auto`` or
    ``demonstrated``; None: ``auto``); ``places`` and ``fills`` are the scene's
    initial state, sorted by instance name.
    """

    kind: Literal["scene"] = "scene"
    name: str
    instances: tuple[Instance, ...]
    layout: str | None = None
    places: tuple[ScenePlace, ...] = ()
    fills: tuple[SceneFill, ...] = ()

    @field_validator("instances")
    @classmethod
    def _sort_instances(cls, v: tuple[Instance, ...]) -> tuple[Instance, ...]:
        return tuple(sorted(v, key=lambda i: i.name))

    @field_validator("places")
    @classmethod
    def _sort_places(cls, v: tuple[ScenePlace, ...]) -> tuple[ScenePlace, ...]:
        return tuple(sorted(v, key=place_key))

    @field_validator("fills")
    @classmethod
    def _sort_fills(cls, v: tuple[SceneFill, ...]) -> tuple[SceneFill, ...]:
        return tuple(sorted(v, key=fill_key))

    def instance(self, name: str) -> Instance | None:
        """The instance called ``name``, or None."""
        for inst in self.instances:
            if inst.name == name:
                return inst
        return None

    def tracked(self) -> tuple[Instance, ...]:
        """Instances whose marker groups the recording holds: they take part in touching
        relations (neither environment, ignored nor untracked)."""
        return tuple(i for i in self.instances if not (i.environment or i.ignored or i.untracked))

    def untracked(self) -> tuple[Instance, ...]:
        """Instances marked ``untracked``: built and related, but not in the recording."""
        return tuple(i for i in self.instances if i.untracked)

    def ignored(self) -> tuple[Instance, ...]:
        """Instances marked ``ignored``: marker groups that are neither tracked nor built."""
        return tuple(i for i in self.instances if i.ignored)

    def place(self, name: str) -> ScenePlace | None:
        """The ``at`` statement of instance ``name``, or None."""
        return next((p for p in self.places if p.instance == name), None)


def place_key(p: ScenePlace) -> tuple[str, float, str, float, str, float, str]:
    """Sort key of scene placements (by instance, then position and yaw as written)."""
    yaw = (0.0, "") if p.yaw is None else (p.yaw.value, p.yaw.unit)
    return (p.instance, p.x.value, p.x.unit, p.y.value, p.y.unit, *yaw)


def fill_key(f: SceneFill) -> tuple[str, str, int]:
    """Sort key of scene contents (by liquid, then container)."""
    return (f.liquid, f.container, -1 if f.balls is None else f.balls)
