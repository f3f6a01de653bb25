"""The types of the skill signatures (:mod:`oacdsl.skills` holds the table).

A signature names a skill's arguments in order (each with the class its instance must have)
and its named parameters with SI unit, default and range (:class:`SkillParamSpec`), and where
the composer takes a parameter from the demonstrated motion (:class:`MotionSource`).

Units: every default, lower and upper bound is SI (metres, radians, seconds, newtons); a count
has unit ``""``.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

from oacdsl.units import unit_kind

__all__ = [
    "ANY",
    "MOTION_FEATURES",
    "PATH",
    "MotionSource",
    "SkillArg",
    "SkillParamSpec",
    "SkillSignature",
    "format_value",
]

#: The fields of :class:`oacdsl.segmentation.motionfeatures.MotionFeatures` a parameter may come
#: from (SI units; a test checks they exist). ``extent_m`` is a triple: ``axis`` picks one.
MOTION_FEATURES: tuple[str, ...] = (
    "cycles",
    "duration_s",
    "end_tilt_rad",
    "extent_m",
    "path_length_m",
    "period_s",
    "radius_m",
    "tilt_max_rad",
    "tilt_rise_s",
    "tilt_time_s",
    "twist_rad",
)


#: The unit of a parameter whose value is a path (``path [ 0s (x, y, z) (rx, ry, rz), … ]``):
#: keyframes of time (s), position (m) and rotation vector (rad), written by the composer from the
#: demonstrated motion (``follow``; docs/language.md).
PATH = "path"


@dataclass(frozen=True)
class SkillArg:
    """One argument of a skill: its name and the class the instance must have."""

    name: str
    cls: str


@dataclass(frozen=True)
class MotionSource:
    """Where a skill parameter comes from in the demonstration (docs/motion.md, docs/language.md).

    The composer sets the parameter of a step to ``scale`` × the sub-action's
    :class:`~oacdsl.segmentation.motion.SubActionMotion` feature ``feature`` (SI units;
    ``axis`` picks a component of ``extent_m``, 0 = along the main axis), rounded for a
    count, then retargets it to the robot (clamped into the parameter's range and, for a
    length, the target object's size). ``needs`` names another feature that must be defined
    (not None) for the parameter to be taken: a stirring radius only where an oscillation
    was found (``needs="period_s"``), a tilt only where the object really tilted
    (``needs="tilt_rise_s"``). ``least`` raises a value below what the robot's skill is known
    to work with. Without a value the skill's default applies.

    Example: ``MotionSource("radius_m", scale=1.41, needs="period_s")`` — a wipe's stroke
    goes √2 × the strokes' median distance from their middle to either side of it.
    """

    feature: str
    scale: float = 1.0
    axis: int = 0
    needs: str | None = None
    #: The least value the robot's skill is known to work with (SI; None: the range's low end):
    #: a smaller demonstrated value is raised to it (a pour's balls leave the robot's cup
    #: reliably only from 125° on; people pour liquids at 90-110°).
    least: float | None = None
    #: A length is clamped to the room on the skill's target (its last argument) unless this is
    #: False: a saw's strokes go along the tool's blade, which passes over the target (a knife
    #: across a cucumber 4.5 cm wide), so only the tool bounds them (the skill does).
    within_target: bool = True

    def __post_init__(self) -> None:
        for name in (self.feature, self.needs):
            if name is not None and name not in MOTION_FEATURES:
                raise ValueError(f"no motion feature {name!r}; features: {', '.join(MOTION_FEATURES)}")
        if not 0 <= self.axis <= 2 or (self.axis and self.feature != "extent_m"):
            raise ValueError(f"axis {self.axis}: only extent_m has axes 0, 1, 2")
        if not (math.isfinite(self.scale) and self.scale > 0):
            raise ValueError(f"scale {self.scale}: a positive number")

    def describe(self, unit: str | None = None) -> str:
        """``0.5 x extent_m[0] (where period_s is found)``; ``unit``: the parameter's, for ``least``."""
        name = f"{self.feature}[{self.axis}]" if self.feature == "extent_m" else self.feature
        text = name if self.scale == 1.0 else f"{self.scale:g} x {name}"
        text += f" (where {self.needs} is found)" if self.needs else ""
        if self.least is not None:
            text += f", at least {format_value(self.least, unit) if unit is not None else f'{self.least:g}'}"
        return text


@dataclass(frozen=True)
class SkillParamSpec:
    """A named parameter: SI unit (``m``, ``rad``, ``s``, ``N``; ``""`` a whole count), default, range.

    ``source``: the demonstrated motion feature the composer fills it from
    (:class:`MotionSource`; None: never taken from the demonstration).
    """

    name: str
    unit: str
    default: float
    low: float
    high: float
    doc: str
    source: MotionSource | None = None

    @property
    def whole(self) -> bool:
        """A count: written without unit, a whole number."""
        return self.unit == ""

    def describe(self) -> str:
        """``tilt: angle, default 125deg (30deg to 180deg) — final tilt of the container``."""
        if self.unit == PATH:
            return f"{self.name}: a path (keyframes: time, position, rotation) — {self.doc}"
        kind = unit_kind(self.unit).split(" (")[0].removeprefix("a ").removeprefix("an ")
        return (
            f"{self.name}: {kind}, default {format_value(self.default, self.unit)}"
            f" ({format_value(self.low, self.unit)} to {format_value(self.high, self.unit)}) — {self.doc}"
            + (f"; from the demonstration: {self.source.describe(self.unit)}" if self.source else "")
        )


@dataclass(frozen=True)
class SkillSignature:
    """What a skill takes: its arguments in order and its named parameters."""

    name: str
    doc: str
    args: tuple[SkillArg, ...]
    params: tuple[SkillParamSpec, ...] = ()
    #: The parameters taken from the demonstration (:class:`MotionSource`) are measured on the
    #: motion of the held object (the second argument) relative to this argument (its index;
    #: default the last, the skill's target): ``tip_out(h, o, c, b)`` tips ``o`` over ``c``.
    measured_in: int = -1

    def measured_pair(self, args: Sequence[str]) -> tuple[str, str] | None:
        """(moved, frame) of a call's ``args`` the demonstrated parameters are measured on
        (None with fewer than three arguments: no held object and target)."""
        return (args[1], args[self.measured_in]) if len(args) >= 3 else None

    def param(self, name: str) -> SkillParamSpec | None:
        return next((p for p in self.params if p.name == name), None)

    def defaults(self) -> dict[str, float]:
        """Every parameter's default (SI); a path has none (the skill's own applies)."""
        return {p.name: p.default for p in self.params if p.unit != PATH}

    def text(self) -> str:
        """``pour(h: Hand, c: Container, l: Liquid, b: Container) { tilt duration height }``."""
        head = f"{self.name}(" + ", ".join(f"{a.name}: {a.cls}" for a in self.args) + ")"
        if self.params:
            head += " { " + "  ".join(p.name for p in self.params) + " }"
        return head


def format_value(value: float, unit: str) -> str:
    """A parameter value as an author would write it: 0.03 m → ``3cm``, 2.18 rad → ``125deg``."""
    if unit == "m":
        return f"{value * 100:g}cm" if abs(value) >= 0.01 or value == 0 else f"{value * 1000:g}mm"
    if unit == "rad":
        return f"{math.degrees(value):g}deg"
    if unit == "m/s":
        return f"{value * 100:g}cm/s"
    if unit == "":
        return f"{value:g}"
    return f"{value:g}{unit}"


#: The class of an argument that may be any object of the scene (``touch``'s target).
ANY = "any"
