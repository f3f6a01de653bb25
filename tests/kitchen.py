"""The paper's kitchen library and dough demonstration, built in Python (no parser needed).

The OACs are the standard library's (BRIEF): grasp, place, pour, mix, wipe. The
demonstration is the paper's dough sequence as world states: left hand pours
liquid one from the red cup, right hand pours liquid two from the green cup,
then the right hand mixes with the mixer in the orange bowl.
"""

from __future__ import annotations

from oacdsl.library import Library
from oacdsl.model import Atom, Instance, Module, Oac, ObjectClass, Param, Scene
from oacdsl.world import NOTHING, WorldState


def atom(a: str, b: str = NOTHING, negated: bool = False) -> Atom:
    return Atom(left=a, right=b, negated=negated)


CLASSES = [
    ObjectClass(name="Hand"),
    ObjectClass(name="Graspable"),
    ObjectClass(name="Container"),
    ObjectClass(name="Liquid"),
    ObjectClass(name="Tool", parents=("Graspable",)),
    ObjectClass(name="Cup", parents=("Graspable", "Container")),
    ObjectClass(name="Bowl", parents=("Container",)),
    ObjectClass(name="Mixer", parents=("Tool",)),
    ObjectClass(name="Sponge", parents=("Tool",)),
    ObjectClass(name="Surface"),
    ObjectClass(name="Table", parents=("Surface",)),
]

KITCHEN = Scene(
    name="kitchen",
    instances=(
        Instance(name="left_hand", classes=("Hand",)),
        Instance(name="right_hand", classes=("Hand",)),
        Instance(name="red_cup", classes=("Cup",)),
        Instance(name="green_cup", classes=("Cup",)),
        Instance(name="orange_bowl", classes=("Bowl",)),
        Instance(name="liquid_one", classes=("Liquid",)),
        Instance(name="liquid_two", classes=("Liquid",)),
        Instance(name="mixer", classes=("Mixer",)),
        Instance(name="table", classes=("Table",), environment=True),
    ),
)

GRASP = Oac(name="grasp", params=(Param(name="h", cls="Hand"), Param(name="o", cls="Graspable")),
            pre=(atom("h"),), effect=(atom("h", "o"),), skill="reach_and_grasp")
PLACE = Oac(name="place", params=(Param(name="h", cls="Hand"), Param(name="o", cls="Graspable")),
            pre=(atom("h", "o"),), effect=(atom("h"),), skill="place")
POUR = Oac(name="pour",
           params=(Param(name="h", cls="Hand"), Param(name="c", cls="Container"),
                   Param(name="l", cls="Liquid"), Param(name="b", cls="Container")),
           pre=(atom("h", "c"), atom("l", "c")), effect=(atom("l", "b"), atom("l", "c", True)), skill="pour")
MIX = Oac(name="mix", params=(Param(name="h", cls="Hand"), Param(name="m", cls="Mixer"),
                              Param(name="b", cls="Container")),
          pre=(atom("h", "m"),), effect=(atom("m", "b"),), skill="mix")
WIPE = Oac(name="wipe", params=(Param(name="h", cls="Hand"), Param(name="s", cls="Sponge"),
                                Param(name="t", cls="Surface")),
           pre=(atom("h", "s"),), effect=(atom("s", "t"),), skill="wipe")
OACS = [GRASP, PLACE, POUR, MIX, WIPE]


def kitchen_library() -> Library:
    return Library([Module(path="<kitchen>", decls=(*CLASSES, KITCHEN, *OACS))])


TRACKED = sorted(i.name for i in KITCHEN.tracked())


def state(*pairs: tuple[str, str]) -> WorldState:
    return WorldState.of(TRACKED, pairs)


L1C, L2C = ("liquid_one", "red_cup"), ("liquid_two", "green_cup")
L1B, L2B = ("liquid_one", "orange_bowl"), ("liquid_two", "orange_bowl")
#: The dough demonstration's keyframe states (9 keyframes, 8 sub-actions).
DOUGH_STATES = [
    state(L1C, L2C),
    state(L1C, L2C, ("left_hand", "red_cup")),                       # grasp(left_hand, red_cup)
    state(L1B, L2C, ("left_hand", "red_cup")),                       # pour liquid one
    state(L1B, L2C),                                                 # place red cup
    state(L1B, L2C, ("right_hand", "green_cup")),                    # grasp green cup
    state(L1B, L2B, ("right_hand", "green_cup")),                    # pour liquid two
    state(L1B, L2B),                                                 # place green cup
    state(L1B, L2B, ("right_hand", "mixer")),                        # grasp mixer
    state(L1B, L2B, ("right_hand", "mixer"), ("mixer", "orange_bowl")),  # mix
]
DOUGH_STEPS = ["grasp", "pour", "place", "grasp", "pour", "place", "grasp", "mix"]
# Wächter et al. 2013, IV-B: the new OAC's preconditions and effects (sorted relations)
PAPER_PRE = [["green_cup", "liquid_two"], ["left_hand", "nothing"], ["liquid_one", "red_cup"],
             ["right_hand", "nothing"]]
PAPER_EFFECT = [["liquid_one", "orange_bowl"], ["liquid_two", "orange_bowl"], ["mixer", "orange_bowl"],
                ["mixer", "right_hand"]]


def dough_segmentation():
    """The dough keyframes as a Segmentation (100 Hz, a keyframe every 1.5 s)."""
    from oacdsl.segmentation.result import Keyframe, Segmentation

    keyframes = tuple(Keyframe(150 * k, 1.5 * k, s) for k, s in enumerate(DOUGH_STATES))
    return Segmentation("dough (hand-written)", 100.0, 150 * len(DOUGH_STATES), tuple(TRACKED), keyframes,
                        {"distance_m": 0.15})
