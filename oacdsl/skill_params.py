"""Skill parameters several skills share: the same unit, range, meaning and demonstrated source
(:data:`oacdsl.skills.SIGNATURES` uses them). SI units: metres, radians, seconds, newtons."""

from __future__ import annotations

import math

from oacdsl.skill_types import MotionSource, SkillParamSpec

__all__ = ["deg", "guard", "hover", "period", "press_on", "radius", "strokes", "sway", "tool_lean", "turns"]


def deg(x: float) -> float:
    """Degrees → radians."""
    return math.radians(x)


def hover(top: str = "the target's top") -> SkillParamSpec:
    """Where a guarded descent starts: 4 cm (1-20 cm) above ``top``."""
    return SkillParamSpec("hover", "m", 0.04, 0.01, 0.20, f"height above {top} where the descent starts")


def guard(doc: str = "on the way down that means something else is in the way",
          default_n: float = 8.0, low_n: float = 2.0, high_n: float = 30.0) -> SkillParamSpec:
    """The wrist force change (N) that stops a guarded descent."""
    return SkillParamSpec("force", "N", default_n, low_n, high_n, f"wrist force change {doc}")


def press_on(what: str = "the tool") -> SkillParamSpec:
    """How far (m) ``what`` is pressed on once a guarded descent has found contact: 3 mm (0-3 cm)."""
    return SkillParamSpec("press", "m", 0.003, 0.0, 0.03, f"how far {what} is pressed on once it touches")


def strokes(doc: str = "number of strokes there and back") -> SkillParamSpec:
    return SkillParamSpec("strokes", "", 3.0, 1.0, 20.0, doc, MotionSource("cycles"))


def sway(default_m: float, low_m: float, high_m: float, doc: str,
         within_target: bool = True) -> SkillParamSpec:
    """How far (m) a to-and-fro stroke goes to either side of its middle.

    From the demonstration: a sinusoid's median distance from its middle is 1/sqrt(2) of how
    far it goes (the extent would count the way onto and off the target too).
    """
    return SkillParamSpec("length", "m", default_m, low_m, high_m, doc,
                          MotionSource("radius_m", scale=1.41, needs="period_s", within_target=within_target))


def period(default_s: float, low_s: float = 0.3, doc: str = "time for one circle") -> SkillParamSpec:
    return SkillParamSpec("period", "s", default_s, low_s, 5.0, doc, MotionSource("period_s"))


def turns(default: float) -> SkillParamSpec:
    return SkillParamSpec("turns", "", default, 1.0, 10.0, "number of circles", MotionSource("cycles"))


def radius(default_m: float, doc: str) -> SkillParamSpec:
    """The radius (m, 0-8 cm) of circles, from the demonstrated oscillation's."""
    return SkillParamSpec("radius", "m", default_m, 0.0, 0.08, doc,
                          MotionSource("radius_m", needs="period_s"))


def tool_lean() -> SkillParamSpec:
    return SkillParamSpec("tilt", "rad", deg(15.0), 0.0, deg(45.0), "lean of the tool from the vertical")
