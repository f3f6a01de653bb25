"""A Python mirror of the standard library the runtime tests drive (classes, kitchen scene,
grasps, the five primitive OACs), as listed in the BRIEF; used until/unless tests load
``library/`` with the parser."""

from oacdsl.library import Library
from oacdsl.model import Atom, Call, Grasp, Instance, Module, Oac, ObjectClass, Param, Scene

CLASSES = [
    ObjectClass(name="Hand"),
    ObjectClass(name="Graspable"),
    ObjectClass(name="Container"),
    ObjectClass(name="Liquid"),
    ObjectClass(name="Surface"),
    ObjectClass(name="Tool", parents=("Graspable",)),
    ObjectClass(name="Cup", parents=("Graspable", "Container")),
    ObjectClass(name="Bowl", parents=("Container",)),
    ObjectClass(name="Mixer", parents=("Tool",)),
    ObjectClass(name="Sponge", parents=("Tool",)),
    ObjectClass(name="Tray", parents=("Surface",)),
    ObjectClass(name="Table", parents=("Surface",)),
]


def inst(name, *classes, environment=False):
    return Instance(name=name, classes=classes, environment=environment)


KITCHEN = Scene(
    name="kitchen",
    instances=(
        inst("left_hand", "Hand"),
        inst("right_hand", "Hand"),
        inst("red_cup", "Cup"),
        inst("green_cup", "Cup"),
        inst("liquid_one", "Liquid"),
        inst("liquid_two", "Liquid"),
        inst("orange_bowl", "Bowl"),
        inst("mixer", "Mixer"),
        inst("table", "Table", environment=True),
    ),
)
WIPING = Scene(
    name="wiping",
    instances=(
        inst("left_hand", "Hand"),
        inst("right_hand", "Hand"),
        inst("sponge", "Sponge"),
        inst("tray", "Tray"),
        inst("table", "Table", environment=True),
    ),
)
GRASPS = [
    Grasp(cls="Cup", type="power", approach="side", offset=(0.0, 0.0, 0.05)),
    Grasp(cls="Mixer", type="power", approach="side", offset=(0.0, 0.0, 0.22)),
    Grasp(cls="Sponge", type="power", approach="side", offset=(0.0, 0.0, 0.10)),
]


def a(x, y, neg=False):
    return Atom(left=x, right=y, negated=neg)


def p(name, cls, default=None):
    return Param(name=name, cls=cls, default=default)


OACS = [
    Oac(
        name="grasp",
        params=(p("h", "Hand"), p("o", "Graspable")),
        pre=(a("h", "nothing"),),
        effect=(a("h", "o"),),
        skill="reach_and_grasp",
    ),
    Oac(
        name="place",
        params=(p("h", "Hand"), p("o", "Graspable")),
        pre=(a("h", "o"),),
        effect=(a("h", "nothing"),),
        skill="place",
    ),
    Oac(
        name="pour",
        params=(p("h", "Hand"), p("c", "Container"), p("l", "Liquid"), p("b", "Container")),
        pre=(a("h", "c"), a("l", "c")),
        effect=(a("l", "b"), a("l", "c", True)),
        skill="pour",
    ),
    Oac(
        name="mix",
        params=(p("h", "Hand"), p("m", "Mixer"), p("b", "Container")),
        pre=(a("h", "m"),),
        effect=(a("m", "b"),),
        skill="mix",
    ),
    Oac(
        name="wipe",
        params=(p("h", "Hand"), p("s", "Sponge"), p("t", "Surface")),
        pre=(a("h", "s"),),
        effect=(a("s", "t"),),
        skill="wipe",
    ),
]

DOUGH = Oac(
    name="dough",
    params=(
        p("h1", "Hand", "left_hand"),
        p("h2", "Hand", "right_hand"),
        p("c1", "Cup", "red_cup"),
        p("c2", "Cup", "green_cup"),
        p("l1", "Liquid", "liquid_one"),
        p("l2", "Liquid", "liquid_two"),
        p("b", "Bowl", "orange_bowl"),
        p("m", "Mixer", "mixer"),
    ),
    pre=(a("h1", "nothing"), a("h2", "nothing"), a("l1", "c1"), a("l2", "c2")),
    effect=(a("h2", "m"), a("l1", "b"), a("l2", "b"), a("m", "b")),
    steps=(
        Call(oac="grasp", args=("h1", "c1")),
        Call(oac="pour", args=("h1", "c1", "l1", "b")),
        Call(oac="place", args=("h1", "c1")),
        Call(oac="grasp", args=("h2", "c2")),
        Call(oac="pour", args=("h2", "c2", "l2", "b")),
        Call(oac="place", args=("h2", "c2")),
        Call(oac="grasp", args=("h2", "m")),
        Call(oac="mix", args=("h2", "m", "b")),
    ),
)


def library(*extra):
    return Library([Module(path="std.oac", decls=(*CLASSES, KITCHEN, WIPING, *GRASPS, *OACS, DOUGH, *extra))])


# --- small scenes and OACs for testing one skill at a time -------------------------------------------
POURING = Scene(
    name="pouring",
    instances=(
        inst("left_hand", "Hand"),
        inst("right_hand", "Hand"),
        inst("green_cup", "Cup"),
        inst("liquid_two", "Liquid"),
        inst("orange_bowl", "Bowl"),
        inst("table", "Table", environment=True),
    ),
)
MIXING = Scene(
    name="mixing",
    instances=(
        inst("left_hand", "Hand"),
        inst("right_hand", "Hand"),
        inst("mixer", "Mixer"),
        inst("orange_bowl", "Bowl"),
        inst("table", "Table", environment=True),
    ),
)


def composed(name, params, calls):
    return Oac(
        name=name,
        params=tuple(p(*x) for x in params),
        steps=tuple(Call(oac=c, args=tuple(a)) for c, *a in calls),
    )


TASKS = [
    composed(
        "pick_and_place",
        [("h", "Hand", "right_hand"), ("o", "Cup", "green_cup")],
        [("grasp", "h", "o"), ("place", "h", "o")],
    ),
    composed(
        "pour_task",
        [
            ("h", "Hand", "right_hand"),
            ("c", "Cup", "green_cup"),
            ("l", "Liquid", "liquid_two"),
            ("b", "Bowl", "orange_bowl"),
        ],
        [("grasp", "h", "c"), ("pour", "h", "c", "l", "b"), ("place", "h", "c")],
    ),
    composed(
        "left_pour",
        [
            ("h", "Hand", "left_hand"),
            ("c", "Cup", "red_cup"),
            ("l", "Liquid", "liquid_one"),
            ("b", "Bowl", "orange_bowl"),
        ],
        [("grasp", "h", "c"), ("pour", "h", "c", "l", "b"), ("place", "h", "c")],
    ),
    composed(
        "mix_task",
        [("h", "Hand", "right_hand"), ("m", "Mixer", "mixer"), ("b", "Bowl", "orange_bowl")],
        [("grasp", "h", "m"), ("mix", "h", "m", "b")],
    ),
    composed(
        "wipe_task",
        [("h", "Hand", "right_hand"), ("s", "Sponge", "sponge"), ("t", "Tray", "tray")],
        [("grasp", "h", "s"), ("wipe", "h", "s", "t")],
    ),
]


def task_library():
    """The standard mirror plus the small scenes and the one-skill tasks."""
    return library(POURING, MIXING, *TASKS)
