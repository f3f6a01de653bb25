"""Scene state (layout, at, in, ignored) and skill calls in the language: model, printer, checks, CLI."""

import json
import math

import pytest
from test_lang_cli import STANDARD, oacc

from oacdsl.compiler import compile_sources, load_library, parse_text, print_module
from oacdsl.compiler.parser import read_source
from oacdsl.model import Quantity
from oacdsl.skills import SIGNATURES
from oacdsl.units import language_si

LIBRARY = {p: read_source(p) for p in STANDARD}

SCENE = """\
scene bench {
    cup, mug              : Cup
    left_hand, right_hand : Hand
    milk                  : Liquid
    rack                  : Cup ignored
    table                 : Table environment

    layout demonstrated
    cup  at (56cm, -0.28)  # a note
    mug  at (640mm, 10cm)
    milk in cup balls 12
}

oac pour_slowly(h: Hand, c: Cup, l: Liquid, b: Cup) {
    pre     h <-> c, c <-> l
    effect  l <-> b, not c <-> l
    execute pour(h, c, l, b) { duration 3s  tilt 110deg }
}
"""


def test_scene_state_and_skill_calls_print_canonically_and_parse_back_equal():
    module = parse_text(SCENE, "bench.oac")
    assert print_module(module) == SCENE  # already canonical: printing keeps it, units as written
    scene, oac = module.decls
    assert scene.layout == "demonstrated" and [i.name for i in scene.ignored()] == ["rack"]
    assert "rack" not in {i.name for i in scene.tracked()} and "table" not in {
        i.name for i in scene.tracked()
    }
    cup = scene.place("cup")
    assert (cup.x.value, cup.x.unit, cup.y.value, cup.y.unit) == (56.0, "cm", -0.28, "")  # as written
    mug = scene.place("mug")
    assert language_si(mug.x.value, mug.x.unit) == (0.64, "m") and language_si(mug.y.value, mug.y.unit) == (
        0.1,
        "m",
    )
    assert [(f.liquid, f.container, f.balls) for f in scene.fills] == [("milk", "cup", 12)]
    assert oac.skill_args == ("h", "c", "l", "b")
    assert {p.name: language_si(p.value.value, p.value.unit) for p in oac.skill_params} == {
        "duration": (3.0, "s"),
        "tilt": (pytest.approx(math.radians(110)), "rad"),
    }
    again = parse_text(print_module(module), "bench.oac")
    assert again == module and print_module(again) == SCENE


def test_the_same_quantity_in_other_units_means_the_same_si_value():
    def place_si(text):
        x = parse_text(f"scene s {{\n    c : Cup\n    c at ({text}, 0)\n}}\n").decls[0].places[0].x
        return language_si(x.value, x.unit)

    assert place_si("56cm") == place_si("560mm") == place_si("0.56m") == (0.56, "m")
    assert place_si("0.56") == (0.56, "")  # bare: metres where a length is expected
    assert place_si("56cm") != place_si("57cm")


def test_quantities_built_in_python_print_and_parse_back():
    module = parse_text(SCENE, "bench.oac")
    scene, oac = module.decls
    speed = oac.skill_params[0].model_copy(update={"value": Quantity(value=0.05, unit="m/s")})
    changed = oac.model_copy(update={"skill_params": (speed, *oac.skill_params[1:])})
    text = print_module(module.model_copy(update={"decls": (scene, changed)}))
    assert "duration 0.05m/s" in text
    assert parse_text(text, "bench.oac").decls[1] == changed


def test_the_bench_scene_compiles_with_the_standard_library():
    result = compile_sources({**LIBRARY, "bench.oac": SCENE})
    assert result.ok, [d.header() for d in result.diagnostics]


def test_the_standard_library_declares_its_scenes_initial_state():
    lib = load_library(STANDARD)
    kitchen = lib.scenes["kitchen"]
    assert {f.liquid: f.container for f in kitchen.fills} == {
        "liquid_one": "red_cup",
        "liquid_two": "green_cup",
    }
    assert {p.instance for p in kitchen.places} == {"red_cup", "green_cup", "orange_bowl", "mixer"}
    assert kitchen.place("red_cup").y.value > 0 > kitchen.place("green_cup").y.value  # red left, green right
    assert {p.instance for p in lib.scenes["wiping"].places} == {"sponge", "tray"}


def test_a_mis_called_skill_is_a_located_compile_error_not_a_traceback(tmp_path):
    bad = tmp_path / "pour3.oac"
    bad.write_text(
        "oac pour3(h: Hand, c: Container, b: Container) {\n"
        "    pre     h <-> c\n    effect  h <-> b\n    execute pour\n}\n",
        encoding="utf-8",
    )
    out = oacc("compile", *STANDARD, bad)
    assert out.returncode == 1
    first = out.stderr.splitlines()[0]
    assert first.startswith(
        f"{bad}:4:13: error[E040]: skill 'pour' takes 4 arguments, but 'pour3' passes its 3"
    )
    assert "note: skill 'pour(h: Hand, c: Container, l: Liquid, b: Container)'" in out.stderr
    # the same library given to the robot stops at the same error, one line, exit 1
    run = oacc("run", "pour3", *(a for p in (*STANDARD, bad) for a in ("--library", p)))
    assert run.returncode == 1 and run.stderr.startswith(f"oacc: error: {bad}:4:13: error[E040]")


def test_oacc_skills_lists_every_signature_with_units_and_json():
    out = oacc("skills")
    assert out.returncode == 0
    assert "pour(h: Hand, c: Container, l: Liquid, b: Container)" in out.stdout
    assert "tilt: angle, default 125deg (30deg to 180deg)" in out.stdout
    assert "strokes: count, default 3 (1 to 20)" in out.stdout
    doc = json.loads(oacc("skills", "--json").stdout)
    assert set(doc) == set(SIGNATURES)
    tilt = next(p for p in doc["pour"]["params"] if p["name"] == "tilt")
    assert tilt["unit"] == "rad" and tilt["default"] == pytest.approx(math.radians(125))
    assert [a["class"] for a in doc["wipe"]["args"]] == ["Hand", "Graspable", "Surface"]


def test_composed_oacs_still_print_and_parse():
    composed = (
        "oac pick(h: Hand = right_hand, c: Cup = green_cup) {\n"
        "    pre     h <-> nothing\n    effect  h <-> c\n    steps {\n        grasp(h, c)\n    }\n}\n"
    )
    module = parse_text(composed)
    assert print_module(module) == composed and module.decls[0].skill_args is None
    assert compile_sources({**LIBRARY, "pick.oac": composed}).ok


TURNED = """\
scene rolling {
    pin : Cup

    pin at (58cm, 0) turned 90deg
}
"""


def test_a_turned_place_prints_canonically_with_its_yaw_and_parses_back_equal():
    module = parse_text(TURNED, "rolling.oac")
    assert print_module(module) == TURNED
    place = module.decls[0].place("pin")
    assert (place.yaw.value, place.yaw.unit) == (90.0, "deg")
    assert place.yaw_rad == pytest.approx(math.pi / 2) and place.part("yaw").column == 29
    assert parse_text(print_module(module), "rolling.oac") == module
    # radians as written; a zero yaw is no yaw: neither kept nor printed
    rad = parse_text(TURNED.replace("90deg", "-1.2rad"))
    assert rad.decls[0].place("pin").yaw_rad == -1.2 and "turned -1.2rad" in print_module(rad)
    zero = parse_text(TURNED.replace("90deg", "0deg"))
    assert zero.decls[0].place("pin").yaw is None and "turned" not in print_module(zero)
    assert zero.decls[0].place("pin").yaw_rad == 0.0


def test_turned_compiles_with_the_standard_library_and_is_a_reserved_word():
    text = TURNED.replace("pin : Cup", "pin : Cup\n    table : Table environment")
    assert compile_sources({**LIBRARY, "rolling.oac": text}).ok
    bad = compile_sources({**LIBRARY, "bad.oac": "scene s {\n    turned : Cup\n}\n"})
    assert "E018" in {d.code for d in bad.diagnostics}
