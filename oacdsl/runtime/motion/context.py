"""What the motion layer needs of a skill's context (the skills' ``SkillContext`` has it).

A protocol, so that the motion layer does not import the skills package (which imports every
skill, each of which composes the motion layer): the dependency goes one way only.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any, Protocol

from oacdsl.library import Library
from oacdsl.runtime.bodies import Body
from oacdsl.runtime.control import Controller
from oacdsl.runtime.simworld import SimWorld

__all__ = ["MotionContext"]


class MotionContext(Protocol):
    """The controller, its world, the library and each instance's classes and body; ``picked``:
    per hand side, what the running skill picked up (released objects are dropped from it)."""

    ctl: Controller
    library: Library
    classes: Mapping[str, frozenset[str]]
    picked: dict[str, Any]

    @property
    def world(self) -> SimWorld: ...

    def body(self, instance: str) -> Body: ...
