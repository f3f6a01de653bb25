"""The signatures of the skills the robot runtime provides.

This table is light on purpose: ``oacc compile`` checks every ``execute SKILL``
against it (arity, the classes of the arguments, the names, units and ranges of
the named parameters) without importing MuJoCo or placo, and ``oacc skills``
prints it. The runtime registers one implementation per name
(:mod:`oacdsl.runtime.skills`) taking the arguments in this order and the
parameters by name, in SI units; a test checks the two agree.

Units: every default, lower and upper bound is SI (metres, radians, seconds,
newtons); a count has unit ``""``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from oacdsl.units import unit_kind

__all__ = [
    "ANY",
    "MOTION_FEATURES",
    "SIGNATURES",
    "SKILLS",
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


def _deg(x: float) -> float:
    return math.radians(x)


#: skill name → signature. The classes are those of the standard library (library/classes.oac).
SIGNATURES: dict[str, SkillSignature] = {
    s.name: s
    for s in (
        SkillSignature(
            "reach_and_grasp",
            "approach an object along its grasp's approach direction and close the hand",
            (SkillArg("h", "Hand"), SkillArg("o", "Graspable")),
            (SkillParamSpec("lift", "m", 0.10, 0.0, 0.30, "how high the object is lifted after closing"),),
        ),
        SkillSignature(
            "hold_up",
            "grasp an object, lift it and hold it up in front of the robot on the hand's side",
            (SkillArg("h", "Hand"), SkillArg("o", "Graspable")),
            (
                SkillParamSpec("lift", "m", 0.20, 0.0, 0.30, "how high it is lifted off its support"),
                SkillParamSpec("forward", "m", 0.5, 0.3, 0.8, "its middle held this far ahead of the base"),
                SkillParamSpec("aside", "m", 0.10, -0.10, 0.30, "… and to the hand's side of the middle"),
            ),
        ),
        SkillSignature(
            "place",
            "lower the held object until the wrist force sensor feels the support, then open the hand",
            (SkillArg("h", "Hand"), SkillArg("o", "Graspable")),
            (
                SkillParamSpec(
                    "force", "N", 3.0, 1.0, 20.0, "wrist force change that means the support took the object"
                ),
            ),
        ),
        SkillSignature(
            "pour",
            "tilt the held container over a target container until its content has left",
            (
                SkillArg("h", "Hand"),
                SkillArg("c", "Container"),
                SkillArg("l", "Liquid"),
                SkillArg("b", "Container"),
            ),
            (
                SkillParamSpec(
                    "tilt", "rad", _deg(125.0), _deg(30.0), _deg(180.0), "final tilt of the container",
                    MotionSource("tilt_max_rad", needs="tilt_rise_s", least=_deg(125.0)),
                ),
                # the skill tilts at a constant rate: its 10-90 % rise takes 0.8 of the duration
                SkillParamSpec(
                    "duration",
                    "s",
                    1.8,
                    0.3,
                    10.0,
                    "time to tilt it that far",
                    MotionSource("tilt_rise_s", scale=1.25),
                ),
                SkillParamSpec("height", "m", 0.045, 0.01, 0.20, "the lip's height above the target's rim"),
            ),
        ),
        SkillSignature(
            "mix",
            "put the held tool into a container and stir",
            (SkillArg("h", "Hand"), SkillArg("m", "Graspable"), SkillArg("b", "Container")),
            (
                SkillParamSpec(
                    "radius",
                    "m",
                    0.03,
                    0.0,
                    0.08,
                    "radius of the stirring circles",
                    MotionSource("radius_m", needs="period_s"),
                ),
                SkillParamSpec("turns", "", 2.0, 1.0, 10.0, "number of circles", MotionSource("cycles")),
                SkillParamSpec("period", "s", 1.2, 0.3, 5.0, "time for one circle", MotionSource("period_s")),
                SkillParamSpec(
                    "force", "N", 15.0, 3.0, 40.0, "wrist force that stops the descent into the container"
                ),
            ),
        ),
        SkillSignature(
            "wipe",
            "press the held tool onto a surface and move it to and fro",
            (SkillArg("h", "Hand"), SkillArg("s", "Graspable"), SkillArg("t", "Surface")),
            (
                SkillParamSpec("strokes", "", 3.0, 1.0, 20.0, "number of to-and-fro strokes",
                               MotionSource("cycles")),
                # the strokes' median distance from their middle is 1/sqrt(2) of how far they go
                # (a sinusoid's); the extent would count the way onto and off the surface too
                SkillParamSpec("length", "m", 0.06, 0.01, 0.20, "how far each stroke goes to either side",
                               MotionSource("radius_m", scale=1.41, needs="period_s")),
                SkillParamSpec(
                    "press", "m", 0.004, 0.0, 0.02, "how far the tool is pressed into the surface"
                ),
            ),
        ),
        SkillSignature(
            "hold",
            "keep the held object still while the other hand works on it",
            (SkillArg("h", "Hand"), SkillArg("o", "Graspable")),
            (
                # not from the demonstration: there the hold overlaps the other hand's work,
                # here the steps run one after the other
                SkillParamSpec("duration", "s", 0.5, 0.1, 10.0, "how long the hand keeps still"),
            ),
        ),
        SkillSignature(
            "touch",
            "bring the held object down onto another object (held or standing) until they touch",
            (SkillArg("h", "Hand"), SkillArg("o", "Graspable"), SkillArg("t", ANY)),
            (
                SkillParamSpec(
                    "hover", "m", 0.04, 0.01, 0.20, "height above the target's top where the descent starts"
                ),
                SkillParamSpec(
                    "force", "N", 8.0, 2.0, 30.0, "wrist force change that means something else is in the way"
                ),
                SkillParamSpec(
                    "press", "m", 0.003, 0.0, 0.03, "how far the object is pressed on once it touches"
                ),
                SkillParamSpec(
                    "steady", "", 1.0, 0.0, 1.0,
                    "1: the other hand's goal stays fixed meanwhile; 0: an idle hand's usual, weaker hold",
                ),
                SkillParamSpec(
                    "tilt", "rad", 0.0, 0.0, _deg(180.0),
                    "how far the object's axis ends from the target's (as it ends in the demonstration);"
                    " turned so only where that differs from how it is held by more than the runtime's"
                    " reorientation angle (a plate held flat set on edge into a rack's slot)",
                    MotionSource("end_tilt_rad"),
                ),
            ),
        ),
        SkillSignature(
            "retreat",
            "take the empty hand back to its home pose, out of the other hand's way",
            (SkillArg("h", "Hand"),),
            (SkillParamSpec("duration", "s", 1.6, 0.5, 10.0, "time to get there"),),
        ),
        SkillSignature(
            "grasp_both",
            "grasp an object with each hand at the same time, then lift both",
            (
                SkillArg("h1", "Hand"),
                SkillArg("o1", "Graspable"),
                SkillArg("h2", "Hand"),
                SkillArg("o2", "Graspable"),
            ),
            (SkillParamSpec("lift", "m", 0.10, 0.0, 0.30, "how high the objects are lifted after closing"),),
        ),
        SkillSignature(
            "place_both",
            "set two held objects down at the same time, each where its step's effect says",
            (
                SkillArg("h1", "Hand"),
                SkillArg("o1", "Graspable"),
                SkillArg("h2", "Hand"),
                SkillArg("o2", "Graspable"),
            ),
            (
                SkillParamSpec(
                    "force", "N", 3.0, 1.0, 20.0, "wrist force change that means the support took an object"
                ),
            ),
        ),
        SkillSignature(
            "lift",
            "raise the held object straight up, off what it touches (a tool off its work)",
            (SkillArg("h", "Hand"), SkillArg("o", "Graspable"), SkillArg("t", ANY)),
            (
                SkillParamSpec("height", "m", 0.12, 0.02, 0.30, "how far the object is raised"),
                SkillParamSpec("duration", "s", 1.0, 0.3, 5.0, "time to raise it"),
            ),
        ),
        SkillSignature(
            "stir",
            "circle the held tool's tip inside a container (standing or held by the other hand)",
            (SkillArg("h", "Hand"), SkillArg("s", "Graspable"), SkillArg("c", "Container")),
            (
                SkillParamSpec(
                    "radius",
                    "m",
                    0.015,
                    0.0,
                    0.08,
                    "radius of the tip's circles on the floor (clamped to the inside; along the wall"
                    " it touches, the wall's)",
                    MotionSource("radius_m", needs="period_s"),
                ),
                SkillParamSpec("period", "s", 0.8, 0.3, 5.0, "time for one circle", MotionSource("period_s")),
                SkillParamSpec("turns", "", 3.0, 1.0, 10.0, "number of circles", MotionSource("cycles")),
                SkillParamSpec(
                    "tilt", "rad", _deg(15.0), 0.0, _deg(45.0), "lean of the tool from the vertical"
                ),
                SkillParamSpec(
                    "depth", "m", 0.015, 0.0, 0.10, "height of the tip above the container's floor"
                ),
                SkillParamSpec(
                    "force", "N", 10.0, 3.0, 30.0, "wrist force change that stops the tip going down"
                ),
            ),
        ),
        SkillSignature(
            "roll",
            "move an object both hands hold to and fro on another one (a rolling pin on dough), still held",
            (SkillArg("h1", "Hand"), SkillArg("o", "Graspable"), SkillArg("h2", "Hand"), SkillArg("t", ANY)),
            (
                SkillParamSpec("strokes", "", 3.0, 1.0, 20.0, "number of strokes there and back",
                               MotionSource("cycles")),
                # a sinusoid's median distance from its middle is 1/sqrt(2) of how far it goes
                SkillParamSpec("length", "m", 0.06, 0.01, 0.20, "how far each stroke goes to either side",
                               MotionSource("radius_m", scale=1.41, needs="period_s")),
                SkillParamSpec("period", "s", 1.6, 0.5, 5.0, "time of one stroke there and back",
                               MotionSource("period_s")),
                SkillParamSpec("press", "m", 0.002, 0.0, 0.02,
                               "how far it is pressed into the target (harder: more friction)"),
                SkillParamSpec("force", "N", 15.0, 2.0, 40.0,
                               "wrist force change that stops the descent when they do not touch first"),
            ),
        ),
        SkillSignature(
            "stroke",
            "draw the held tool along an object, one way, and back through the air, several times"
            " (a peeler along a cucumber, a knife pushing pieces across a board towards a bowl)",
            (SkillArg("h", "Hand"), SkillArg("o", "Graspable"), SkillArg("t", ANY)),
            (
                SkillParamSpec("strokes", "", 3.0, 1.0, 20.0, "number of strokes", MotionSource("cycles")),
                SkillParamSpec("period", "s", 0.8, 0.3, 5.0, "time of one stroke along the target",
                               MotionSource("period_s")),
                # not from the demonstration: the composer retargets a length to the target's
                # narrow side (a container's inner radius), and a stroke goes along its long one
                SkillParamSpec("length", "m", 0.08, 0.01, 0.40,
                               "how far each stroke goes (at most the target's length allows)"),
                SkillParamSpec("press", "m", 0.004, 0.0, 0.02, "how far the tool is pressed into the target"),
                SkillParamSpec("force", "N", 15.0, 3.0, 40.0,
                               "wrist force on the way down that means something else is in the way"),
            ),
        ),
        SkillSignature(
            "saw",
            "bring the held tool (a knife) down onto an object until they touch and draw it to and"
            " fro along its blade, pressed on (cutting a cucumber the other hand holds)",
            (SkillArg("h", "Hand"), SkillArg("k", "Graspable"), SkillArg("t", ANY)),
            (
                SkillParamSpec("strokes", "", 3.0, 1.0, 20.0, "number of strokes there and back",
                               MotionSource("cycles")),
                # a sinusoid's median distance from its middle is 1/sqrt(2) of how far it goes;
                # along the blade, not bounded by the target's width (the skill keeps it on the blade)
                SkillParamSpec("length", "m", 0.03, 0.005, 0.10,
                               "how far each stroke goes to either side (at most the blade allows)",
                               MotionSource("radius_m", scale=1.41, needs="period_s", within_target=False)),
                SkillParamSpec("period", "s", 1.2, 0.3, 5.0,
                               "time of one stroke there and back (no faster than a slide)",
                               MotionSource("period_s")),
                SkillParamSpec("press", "m", 0.003, 0.0, 0.03,
                               "how far the tool is pressed on once it touches"),
                SkillParamSpec("hover", "m", 0.04, 0.01, 0.20,
                               "height above the target's top where the descent starts"),
                SkillParamSpec("force", "N", 8.0, 2.0, 30.0,
                               "wrist force change on the way down that means something else is in the way"),
            ),
        ),
        SkillSignature(
            "tip_out",
            "take the held tool out of the container it is in, tip it over that container (a ladle"
            " emptied into a cup), turn it back and bring it into another container until they touch",
            (SkillArg("h", "Hand"), SkillArg("o", "Graspable"), SkillArg("c", ANY),
             SkillArg("b", "Container")),
            (
                SkillParamSpec("tilt", "rad", _deg(90.0), 0.0, _deg(180.0), "how far the tool is tipped",
                               MotionSource("tilt_max_rad", needs="tilt_rise_s")),
                # the tip turns at a constant rate: its 10-90 % rise takes 0.8 of the duration
                SkillParamSpec("duration", "s", 1.2, 0.3, 10.0,
                               "time to tip it that far (no faster than the arms' joints allow)",
                               MotionSource("tilt_rise_s", scale=1.25)),
                SkillParamSpec("hover", "m", 0.04, 0.01, 0.20,
                               "height above the other container's top where the descent starts"),
                SkillParamSpec("force", "N", 8.0, 2.0, 30.0,
                               "wrist force change on the way down that means something else is in the way"),
                SkillParamSpec("press", "m", 0.003, 0.0, 0.03,
                               "how far the tool is pressed on once it touches"),
            ),
        ),
        SkillSignature(
            "twist",
            "turn the held object about its own axis on another one, regrasping between strokes"
            " (a lid screwed onto or off a bottle)",
            (SkillArg("h", "Hand"), SkillArg("o", "Graspable"), SkillArg("t", ANY)),
            (
                SkillParamSpec(
                    "angle", "rad", math.pi, -6 * math.pi, 6 * math.pi,
                    "how far it turns, counterclockwise seen from above (negative: clockwise, screwing on)",
                    MotionSource("twist_rad"),
                ),
                SkillParamSpec("duration", "s", 3.0, 0.5, 20.0, "time for the whole turn, regrasps included",
                               MotionSource("duration_s")),
                SkillParamSpec("stroke", "rad", _deg(40.0), _deg(10.0), _deg(120.0),
                               "most the hand turns before it lets go and takes the object again"),
                SkillParamSpec("lift", "m", 0.0, 0.0, 0.20,
                               "how far it is raised off the target afterwards (0: it stays on)"),
            ),
        ),
        SkillSignature(
            "mix_both",
            "both hands' tools into one container at once, circling side by side, left on its floor",
            (
                SkillArg("h1", "Hand"),
                SkillArg("t1", "Graspable"),
                SkillArg("h2", "Hand"),
                SkillArg("t2", "Graspable"),
                SkillArg("c", "Container"),
            ),
            (
                SkillParamSpec(
                    "radius",
                    "m",
                    0.02,
                    0.0,
                    0.08,
                    "radius of each tip's circles (clamped so that each tool stays clear of the wall)",
                    MotionSource("radius_m", needs="period_s"),
                ),
                SkillParamSpec("period", "s", 1.0, 0.3, 5.0, "time for one circle", MotionSource("period_s")),
                SkillParamSpec("turns", "", 3.0, 1.0, 10.0, "number of circles", MotionSource("cycles")),
                SkillParamSpec(
                    "tilt",
                    "rad",
                    _deg(15.0),
                    0.0,
                    _deg(45.0),
                    "lean of each tool from the vertical, its handle towards its hand",
                ),
                SkillParamSpec(
                    "depth", "m", 0.0, 0.0, 0.10,
                    "height of the tips above the floor while they circle (0: on it, pressed on)"
                ),
                SkillParamSpec(
                    "lean", "rad", 0.0, 0.0, _deg(60.0),
                    "at the end each tool's tip to the far side of its spot, the tool leaned this far"
                    " towards the robot (let go of, it comes to rest on the rim)",
                ),
                SkillParamSpec(
                    "force", "N", 10.0, 3.0, 30.0, "wrist force change that stops a tool going down"
                ),
            ),
        ),
        SkillSignature(
            "take_out",
            "lift the held object straight up until it clears a container (a spoon out of a cup)",
            (SkillArg("h", "Hand"), SkillArg("o", "Graspable"), SkillArg("c", "Container")),
            (
                SkillParamSpec("clear", "m", 0.03, 0.0, 0.20, "height of its base above the container's top"),
                SkillParamSpec("duration", "s", 1.0, 0.3, 10.0, "time to lift it out"),
            ),
        ),
        SkillSignature(
            "follow",
            "move the held object along the demonstrated path relative to another object,"
            " retargeted into the robot's reach (a sub-action no named skill knows)",
            (SkillArg("h", "Hand"), SkillArg("o", "Graspable"), SkillArg("t", ANY)),
            (
                SkillParamSpec(
                    PATH, PATH, 0.0, 0.0, 0.0,
                    "keyframes of o's pose relative to t: time, position and rotation vector in t's"
                    " frame turned so that x points from t to where o starts (the composer writes it"
                    " from the demonstration)",
                ),
                SkillParamSpec("speed", "m/s", 0.25, 0.02, 1.0,
                               "fastest the held object moves; faster parts of the path are slowed down"),
                SkillParamSpec("turn", "rad", _deg(30.0), 0.0, _deg(180.0),
                               "most the held object turns from its start orientation; larger"
                               " rotations are scaled down to it"),
                SkillParamSpec("press", "m", 0.003, 0.0, 0.02,
                               "how far it is pressed on where the path must end touching the target"),
                SkillParamSpec("force", "N", 10.0, 2.0, 40.0,
                               "wrist force change that stops a guarded approach to the target"),
            ),
        ),
    )
}

#: skill name → one-line description (what ``oacc compile`` hints show).
SKILLS: dict[str, str] = {name: s.doc for name, s in SIGNATURES.items()}
