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

from oacdsl.skill_params import deg as _deg
from oacdsl.skill_params import guard as _guard
from oacdsl.skill_params import hover as _hover
from oacdsl.skill_params import period as _period
from oacdsl.skill_params import press_on as _press_on
from oacdsl.skill_params import radius as _radius
from oacdsl.skill_params import strokes as _strokes
from oacdsl.skill_params import sway as _sway
from oacdsl.skill_params import tool_lean as _tool_lean
from oacdsl.skill_params import turns as _turns
from oacdsl.skill_types import (
    ANY,
    MOTION_FEATURES,
    PATH,
    MotionSource,
    SkillArg,
    SkillParamSpec,
    SkillSignature,
    format_value,
)

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


def _args(text: str) -> tuple[SkillArg, ...]:
    """``"h: Hand, o: Graspable"`` → the arguments in that order."""
    return tuple(SkillArg(*(part.strip() for part in arg.split(":"))) for arg in text.split(","))


#: skill name → signature. The classes are those of the standard library (library/classes.oac).
SIGNATURES: dict[str, SkillSignature] = {
    s.name: s
    for s in (
        SkillSignature(
            "reach_and_grasp",
            "approach an object along its grasp's approach direction and close the hand",
            _args("h: Hand, o: Graspable"),
            (SkillParamSpec("lift", "m", 0.10, 0.0, 0.30, "how high the object is lifted after closing"),),
        ),
        SkillSignature(
            "hold_up",
            "grasp an object, lift it and hold it up in front of the robot on the hand's side",
            _args("h: Hand, o: Graspable"),
            (
                SkillParamSpec("lift", "m", 0.20, 0.0, 0.30, "how high it is lifted off its support"),
                SkillParamSpec("forward", "m", 0.5, 0.3, 0.8, "its middle held this far ahead of the base"),
                SkillParamSpec("aside", "m", 0.10, -0.10, 0.30, "… and to the hand's side of the middle"),
            ),
        ),
        SkillSignature(
            "place",
            "lower the held object until the wrist force sensor feels the support, then open the hand",
            _args("h: Hand, o: Graspable"),
            (
                _guard("that means the support took the object", 3.0, 1.0, 20.0),
            ),
        ),
        SkillSignature(
            "pour",
            "tilt the held container over a target container until its content has left",
            _args("h: Hand, c: Container, l: Liquid, b: Container"),
            (
                SkillParamSpec(
                    "tilt", "rad", _deg(125.0), _deg(30.0), _deg(180.0), "final tilt of the container",
                    MotionSource("tilt_max_rad", needs="tilt_rise_s", least=_deg(125.0)),
                ),
                # the skill tilts at a constant rate: its 10-90 % rise takes 0.8 of the duration
                SkillParamSpec("duration", "s", 1.8, 0.3, 10.0, "time to tilt it that far",
                               MotionSource("tilt_rise_s", scale=1.25)),
                SkillParamSpec("height", "m", 0.045, 0.01, 0.20, "the lip's height above the target's rim"),
            ),
        ),
        SkillSignature(
            "mix",
            "put the held tool into a container and stir",
            _args("h: Hand, m: Graspable, b: Container"),
            (
                _radius(0.03, "radius of the stirring circles"),
                _turns(2.0),
                _period(1.2),
                SkillParamSpec("force", "N", 15.0, 3.0, 40.0,
                               "wrist force that stops the descent into the container"),
            ),
        ),
        SkillSignature(
            "wipe",
            "press the held tool onto a surface and move it to and fro",
            _args("h: Hand, s: Graspable, t: Surface"),
            (
                _strokes("number of to-and-fro strokes"),
                _sway(0.06, 0.01, 0.20, "how far each stroke goes to either side"),
                SkillParamSpec("press", "m", 0.004, 0.0, 0.02,
                               "how far the tool is pressed into the surface"),
            ),
        ),
        SkillSignature(
            "hold",
            "keep the held object still while the other hand works on it",
            _args("h: Hand, o: Graspable"),
            (
                # not from the demonstration: there the hold overlaps the other hand's work,
                # here the steps run one after the other
                SkillParamSpec("duration", "s", 0.5, 0.1, 10.0, "how long the hand keeps still"),
            ),
        ),
        SkillSignature(
            "touch",
            "bring the held object down onto another object (held or standing) until they touch",
            _args("h: Hand, o: Graspable, t: any"),
            (
                _hover(),
                _guard("that means something else is in the way"),
                _press_on("the object"),
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
            _args("h: Hand"),
            (SkillParamSpec("duration", "s", 1.6, 0.5, 10.0, "time to get there"),),
        ),
        SkillSignature(
            "grasp_both",
            "grasp an object with each hand at the same time, then lift both",
            _args("h1: Hand, o1: Graspable, h2: Hand, o2: Graspable"),
            (SkillParamSpec("lift", "m", 0.10, 0.0, 0.30, "how high the objects are lifted after closing"),),
        ),
        SkillSignature(
            "place_both",
            "set two held objects down at the same time, each where its step's effect says",
            _args("h1: Hand, o1: Graspable, h2: Hand, o2: Graspable"),
            (
                _guard("that means the support took an object", 3.0, 1.0, 20.0),
            ),
        ),
        SkillSignature(
            "lift",
            "raise the held object straight up, off what it touches (a tool off its work)",
            _args("h: Hand, o: Graspable, t: any"),
            (
                SkillParamSpec("height", "m", 0.12, 0.02, 0.30, "how far the object is raised"),
                SkillParamSpec("duration", "s", 1.0, 0.3, 5.0, "time to raise it"),
            ),
        ),
        SkillSignature(
            "stir",
            "circle the held tool's tip inside a container (standing or held by the other hand)",
            _args("h: Hand, s: Graspable, c: Container"),
            (
                _radius(0.015, "radius of the tip's circles on the floor (clamped to the inside;"
                        " along the wall it touches, the wall's)"),
                _period(0.8),
                _turns(3.0),
                _tool_lean(),
                SkillParamSpec("depth", "m", 0.015, 0.0, 0.10,
                               "height of the tip above the container's floor"),
                _guard("that stops the tip going down", 10.0, 3.0),
            ),
        ),
        SkillSignature(
            "roll",
            "move an object both hands hold to and fro on another one (a rolling pin on dough), still held",
            _args("h1: Hand, o: Graspable, h2: Hand, t: any"),
            (
                _strokes(),
                _sway(0.06, 0.01, 0.20, "how far each stroke goes to either side"),
                _period(1.6, 0.5, "time of one stroke there and back"),
                SkillParamSpec("press", "m", 0.002, 0.0, 0.02,
                               "how far it is pressed into the target (harder: more friction)"),
                _guard("that stops the descent when they do not touch first", 15.0, 2.0, 40.0),
            ),
        ),
        SkillSignature(
            "stroke",
            "draw the held tool along an object's longest side, one way, pressed on, and slide it back"
            " with the press eased, several times (a peeler along a cucumber, a knife pushing pieces"
            " across a board towards a bowl the other hand holds)",
            _args("h: Hand, o: Graspable, t: any"),
            (
                _strokes("number of strokes"),
                _period(0.8, doc="time of one stroke along the target"),
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
            _args("h: Hand, k: Graspable, t: any"),
            (
                _strokes(),
                # along the blade, not bounded by the target's width (the skill keeps it on the blade)
                _sway(0.03, 0.005, 0.10, "how far each stroke goes to either side (at most the blade allows)",
                      within_target=False),
                _period(1.2, doc="time of one stroke there and back (no faster than a slide)"),
                _press_on(),
                _hover(),
                _guard(),
            ),
        ),
        SkillSignature(
            "tip_out",
            "take the held tool out of the container it is in, tip it over that container (a ladle"
            " emptied into a cup), turn it back and bring it into another container until they touch",
            _args("h: Hand, o: Graspable, c: any, b: Container"),
            (
                SkillParamSpec("tilt", "rad", _deg(90.0), 0.0, _deg(180.0), "how far the tool is tipped",
                               MotionSource("tilt_max_rad", needs="tilt_rise_s")),
                # the tip turns at a constant rate: its 10-90 % rise takes 0.8 of the duration
                SkillParamSpec("duration", "s", 1.2, 0.3, 10.0,
                               "time to tip it that far (no faster than the arms' joints allow)",
                               MotionSource("tilt_rise_s", scale=1.25)),
                _hover("the other container's top"),
                _guard(),
                _press_on(),
            ),
            measured_in=2,  # the tilt over the container it tips into, not the next one
        ),
        SkillSignature(
            "twist",
            "turn the held object about its own axis on another one, regrasping between strokes"
            " (a lid screwed onto or off a bottle)",
            _args("h: Hand, o: Graspable, t: any"),
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
            _args("h1: Hand, t1: Graspable, h2: Hand, t2: Graspable, c: Container"),
            (
                _radius(0.02, "radius of each tip's circles (clamped so that each tool stays clear of"
                        " the wall)"),
                _period(1.0),
                _turns(3.0),
                SkillParamSpec("tilt", "rad", _deg(15.0), 0.0, _deg(45.0),
                               "lean of each tool from the vertical, its handle towards its hand"),
                SkillParamSpec(
                    "depth", "m", 0.0, 0.0, 0.10,
                    "height of the tips above the floor while they circle (0: on it, pressed on)"
                ),
                SkillParamSpec(
                    "lean", "rad", 0.0, 0.0, _deg(60.0),
                    "at the end each tool's tip to the far side of its spot, the tool leaned this far"
                    " towards the robot (let go of, it comes to rest on the rim)",
                ),
                _guard("that stops a tool going down", 10.0, 3.0),
            ),
        ),
        SkillSignature(
            "take_out",
            "lift the held object straight up until it clears a container (a spoon out of a cup)",
            _args("h: Hand, o: Graspable, c: Container"),
            (
                SkillParamSpec("clear", "m", 0.03, 0.0, 0.20, "height of its base above the container's top"),
                SkillParamSpec("duration", "s", 1.0, 0.3, 10.0, "time to lift it out"),
            ),
        ),
        SkillSignature(
            "follow",
            "move the held object along the demonstrated path relative to another object,"
            " retargeted into the robot's reach (a sub-action no named skill knows)",
            _args("h: Hand, o: Graspable, t: any"),
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
                               "most the held object turns at a time: a turn about its own axis"
                               " beyond it, where the object can rest on the target, goes on in"
                               " pieces with regrasps; other rotations are scaled down to it"),
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
