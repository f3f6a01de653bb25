"""Diagnostics: one table of bad snippets (code, message, position), rendering, JSON."""

from pathlib import Path

import pytest

from oacdsl.compiler import CODES, compile_sources, load_library, parse_text, render
from oacdsl.errors import LanguageError

ROOT = Path(__file__).resolve().parents[1]
LIBRARY = {
    str(p.relative_to(ROOT)): p.read_text(encoding="utf-8") for p in sorted((ROOT / "library").glob("*.oac"))
}

G = "oac g(h: Hand, o: Graspable) {\n"  # a prefix for OAC snippets; the body starts on line 2
#: A composed OAC up to its steps; the steps start on line 5.
STEPS = ("oac d(h: Hand, c: Cup, l: Liquid, b: Bowl) {\n  pre h <-> nothing, c <-> l\n"
         "  effect l <-> b\n  steps {\n")

#: (snippet, code, message fragment, "line:col" of the first diagnostic with that code).
#: Each snippet is compiled as bad.oac together with the standard library.
BAD = [
    # syntax: what was expected, in words
    ("class", "E001", "unexpected end of input, expected a class name", "1:6"),
    ("class Mug : Cup,\n", "E001", "expected a class name", "1:17"),
    (
        "class Mug Cup",
        "E001",
        "unexpected 'Cup', expected ':' and the parent classes, '{' and the class's geometry,"
        " or a declaration",
        "1:11",
    ),
    ("scene s {\n  a = b\n}", "E001", "unexpected '=', expected ':' and the instance's classes", "2:5"),
    ("scene s {\n  c : Cup\n  layuot auto\n}", "E045", "unknown scene statement 'layuot auto'", "3:3"),
    ('scene s { a : Cup markers ("m1" }', "E001", "expected ',' or ')' in the marker list", "1:33"),
    ("grasp Cup { approach side }", "E001", "expected 'type' and a grasp type", "1:13"),
    (
        G + "  pre h <-> nothing\n  effect h <-> o\n",
        "E001",
        "unexpected end of input, expected ',', 'execute SKILL' or 'steps { … }'",
        "3:17",
    ),
    (G + "  pre h <-> }", "E001", "unexpected '}', expected an object or 'nothing' after '<->'", "2:13"),
    (G + "  execute\n}", "E001", "unexpected '}', expected the name of a skill", "3:1"),
    ("oac g(h Hand) { }", "E001", "unexpected 'Hand', expected ':' and the parameter's class", "1:9"),
    (G + "  effect h <-> o execute place steps { }", "E001", "or '}' to close the OAC", "2:32"),
    (G + "  pre h <- o", "E002", "unexpected character '<', expected '<->' between the two objects", "2:9"),
    (G + "  pre h <-> o;", "E002", "unexpected character ';'", "2:14"),
    # at the start of a file: what is expected in words, not the grammar's rule names
    ("@class A", "E002", "unexpected character '@', expected a declaration ('class', 'scene'", "1:1"),
    ("\n  $", "E002", "unexpected character '$', expected a declaration ('class', 'scene'", "2:3"),
    ('scene s { a : Cup markers ("m1) }', "E002", "unterminated string", "1:28"),
    # semantic
    ("scene s {\n  a : Cpu\n}", "E003", "unknown class 'Cpu' (did you mean 'Cup'?)", "2:7"),
    (
        "class Mug : Graspable, Contaner",
        "E003",
        "unknown parent class 'Contaner' (did you mean 'Container'?)",
        "1:24",
    ),
    ("grasp Spoon { type power approach side }", "E003", "unknown class 'Spoon'", "1:7"),
    ("oac g(h: Hadn) { effect h <-> nothing execute place }", "E003", "did you mean 'Hand'", "1:10"),
    (
        "oac g(h: Hand = left_hnd) { effect h <-> nothing execute place }",
        "E004",
        "unknown instance 'left_hnd' (did you mean 'left_hand'?)",
        "1:17",
    ),
    (
        G + "  pre h <-> nothing\n  effect h <-> obj\n  execute reach_and_grasp\n}",
        "E005",
        "unbound variable 'obj'",
        "3:16",
    ),
    ("class Cup", "E006", "class 'Cup' is defined twice", "1:7"),
    (
        "oac g(h: Hand, h: Hand) { effect h <-> nothing execute place }",
        "E006",
        "parameter 'h' is defined twice",
        "1:16",
    ),
    ("scene s {\n  a : Cup\n  a : Bowl\n}", "E006", "instance 'a' is defined twice in scene 's'", "3:3"),
    ("scene kitchen { }", "E006", "scene 'kitchen' is defined twice", "1:7"),
    ("grasp Cup { type rim approach top }", "E006", "grasp for class 'Cup' is defined twice", "1:7"),
    ("oac pour(h: Hand) { effect h <-> nothing execute pour }", "E006", "OAC 'pour' is defined twice", "1:5"),
    ("class A : B\nclass B : C\nclass C : A", "E007", "cycle in the class hierarchy: A → B → C → A", "1:7"),
    ("class Loop : Loop", "E007", "cycle in the class hierarchy: Loop → Loop", "1:7"),
    (G + "  pre h <-> h\n  effect h <-> o\n  execute place\n}", "E008", "relates 'h' with itself", "2:7"),
    (
        G + "  pre h <-> nothing, h <-> o\n  effect not h <-> o\n  execute place\n}",
        "E009",
        "the precondition contradicts itself: 'h <-> nothing' and 'h <-> o'",
        "2:7",
    ),
    (
        G + "  pre h <-> nothing\n  effect h <-> o, not h <-> o\n  execute place\n}",
        "E010",
        "the effect contradicts itself: 'not h <-> o' and 'h <-> o'",
        "3:19",
    ),
    (G + "  pre h <-> nothing\n  execute reach_and_grasp\n}", "E011", "OAC 'g' states no effect", "1:5"),
    (
        G + "  pre h <-> o\n  effect o <-> h\n  execute place\n}",
        "E012",
        "the effect of 'g' changes nothing: every effect is also a precondition",
        "3:3",
    ),
    (  # a composed one that ends as it began (a hand-over) is told to leave 'effect' out
        G + "  pre h <-> nothing\n  effect h <-> nothing\n"
        "  steps {\n    grasp(h, o)\n    place(h, o)\n  }\n}",
        "E012",
        "changes nothing: every effect is also a precondition; a composed OAC that ends as it began states no"
        " effect (leave 'effect' out)",
        "3:3",
    ),
    (
        G + "  effect h <-> o\n  steps { grap(h, o) }\n}",
        "E013",
        "unknown OAC 'grap' (did you mean 'grasp'?)",
        "3:11",
    ),
    (G + "  effect h <-> o\n  steps { grasp(h) }\n}", "E014", "'grasp' takes 2 arguments, 1 given", "3:11"),
    (
        "oac g(h: Hand, l: Liquid) {\n  effect h <-> l\n  steps { grasp(h, l) }\n}",
        "E015",
        "argument 'l' is a Liquid, but 'grasp' expects a Graspable for 'o'",
        "3:20",
    ),
    (
        G + "  effect h <-> o\n  steps { grasp(h, liquid_one) }\n}",
        "E015",
        "argument 'liquid_one' is a Liquid, but 'grasp' expects a Graspable",
        "3:20",
    ),
    (
        G + "  pre h <-> nothing\n  effect h <-> o\n  execute reach_and_grap\n}",
        "E016",
        "unknown skill 'reach_and_grap' (did you mean 'reach_and_grasp'?)",
        "4:11",
    ),
    (
        "oac g(h: Hand = red_cup) { effect h <-> nothing execute place }",
        "E017",
        "'red_cup' is a Cup, not a Hand",
        "1:17",
    ),
    (
        "oac g(nothing: Hand) { effect nothing <-> nothing execute place }",
        "E018",
        "'nothing' is a reserved word and cannot name a parameter",
        "1:7",
    ),
    ("scene s { not : Cup }", "E018", "'not' is a reserved word and cannot name an instance", "1:11"),
    (
        "oac a(h: Hand) { effect h <-> nothing steps { b(h) } }\n"
        "oac b(h: Hand) { effect h <-> nothing steps { a(h) } }",
        "E019",
        "composed OAC 'a' calls itself: a → b → a",
        "1:5",
    ),
    ("grasp Bowl { type fist approach side }", "E020", "unknown grasp type 'fist'", "1:19"),
    (
        "grasp Bowl { type power approach sideways }",
        "E020",
        "unknown approach direction 'sideways' (did you mean 'side'?)",
        "1:34",
    ),
    (
        G + "  pre h <-> o\n  effect o <-> table\n  execute place\n}",
        "E021",
        "'table' is environment in scene 'kitchen'",
        "3:16",
    ),
    (
        'scene s {\n  a : Cup markers ("m1", "m2")\n  b : Cup markers ("m3", "m1")\n}',
        "E022",
        "marker \"m1\" is assigned to 'a' and to 'b'",
        "3:26",
    ),
    (G + "  effect h <-> o\n  steps { }\n}", "E023", "composed OAC 'g' has no steps", "3:3"),
    # the file's bytes (as compile_paths passes them): the column counts characters
    ("class A\n# caf\u00e9 ".encode() + b"\xff", "E024", "not UTF-8 text (byte 0xff on line 2)", "2:8"),
    # geometry
    (
        "class Jug { shape cylindre(radius 5cm, height 20cm) }",
        "E030",
        "unknown shape 'cylindre' (did you mean 'cylinder'?)",
        "1:19",
    ),
    ("class Jug { shape cylinder(radius 5cm, hieght 20cm) }", "E031", "needs height", "1:19"),
    (
        "class Jug {\n  shape cylinder(radius 5cm, height 2cm, hieght 20cm)\n}",
        "E031",
        "no parameter 'hieght' (did you mean 'height'?)",
        "2:42",
    ),
    (
        "class Jug { shape hand(radius 5cm) }",
        "E031",
        "hand has no parameter 'radius' (it takes no sizes)",
        "1:24",
    ),
    (
        "class Jug { shape cylinder(radius 5cms, height 20cm) }",
        "E032",
        "unknown unit 'cms' in 'radius' of cylinder (did you mean 'cm'?)",
        "1:36",
    ),
    (
        "class Jug { shape cylinder(radius 5g, height 20cm) }",
        "E032",
        "'g' is a unit of mass, but 'radius' of cylinder is a length",
        "1:36",
    ),
    (
        "class Jug { shape cylinder(radius 0, height 20cm) }",
        "E033",
        "'radius' of cylinder must be a positive, finite length",
        "1:35",
    ),
    (
        "scene s { jug : Cup { mass -1kg } }",
        "E033",
        "the mass of instance 'jug' must be a positive, finite mass",
        "1:28",
    ),
    (
        "class Jug { shape shell(radius 5cm, height 20cm, wall 6cm) }",
        "E033",
        "shell wall must be thinner than its radius",
        "1:13",
    ),
    ('class Jug { shape mesh("nowhere.stl") }', "E034", "mesh file 'nowhere.stl' not found", "1:24"),
    (
        "class Jug { shape sphere(radius 1cm) mass 1kg mass 2kg }",
        "E035",
        "'mass' is given twice in one geometry",
        "1:47",
    ),
    (
        "class Jug { shape hand shape sphere(radius 1cm) }",
        "E036",
        "hand stands for what the runtime provides",
        "1:13",
    ),
    (
        "class Jug { shape sphere(radius 2cm) colour rde }",
        "E037",
        "unknown colour 'rde' (did you mean 'red'?)",
        "1:38",
    ),
    (
        "oac g(h: Hand, o: Graspable, c: Cup) {\n  pre h <-> nothing\n  effect h <-> c\n"
        "  steps { grasp(h, c) }\n}",
        "W001",
        "parameter 'o' of 'g' is never used",
        "1:16",
    ),
    ("class Mug : Cup, Cup", "W002", "parent class 'Cup' is listed twice", "1:18"),
    (
        G + "  pre h <-> o, h <-> o\n  effect o <-> nothing\n  execute place\n}",
        "W002",
        "precondition 'h <-> o' is listed twice",
        "2:16",
    ),
    (
        "oac g(h: Hand, o: Graspable, c: Container) {\n"
        "  pre h <-> o\n  effect h <-> o, o <-> c\n  execute place\n}",
        "W003",
        "effect 'h <-> o' already holds before",
        "3:10",
    ),
    (
        "class Spoon : Graspable\nscene s { spoon : Spoon }",
        "W004",
        "instance 'spoon' is Graspable but no grasp",
        "2:11",
    ),
    ("grasp Bowl { type power approach side offset (0.0, 0.0, 60.0) }", "W005", "offsets are metres", "1:39"),
    ("grasp Bowl { type pinch approach top offset (0.0, 0.0, 0.03) }", "E049",
     "a pinch grasp takes a flat object's edge", "1:38"),
    # scene state and skill calls
    (
        "oac pour3(h: Hand, c: Container, b: Container) {\n  pre h <-> c\n  effect h <-> b\n"
        "  execute pour\n}",
        "E040",
        "skill 'pour' takes 4 arguments, but 'pour3' passes its 3 parameters; write the arguments:"
        " 'execute pour(h, c, l, b)'",
        "4:11",
    ),
    (
        G + "  pre h <-> nothing\n  effect h <-> o\n  execute reach_and_grasp(h)\n}",
        "E040",
        "skill 'reach_and_grasp' takes 2 arguments, 1 given",
        "4:11",
    ),
    (
        "oac pour3(h: Hand, c: Container, b: Container) {\n  pre h <-> c\n  effect h <-> b\n"
        "  execute pour(h, c, b, b)\n}",
        "E041",
        "argument 'b' is a Container, but skill 'pour' expects a Liquid for 'l'",
        "4:22",
    ),
    (
        G + "  pre h <-> nothing\n  effect h <-> o\n  execute reach_and_grasp(h, table)\n}",
        "E021",
        "'table' is environment in scene 'kitchen'",
        "4:30",
    ),
    (
        "oac p(h: Hand, c: Cup, l: Liquid, b: Bowl) {\n  pre h <-> c\n  effect l <-> b\n"
        "  execute pour { tlt 110deg }\n}",
        "E042",
        "skill 'pour' has no parameter 'tlt' (did you mean 'tilt'?)",
        "4:18",
    ),
    (
        "oac p(h: Hand, c: Cup, l: Liquid, b: Bowl) {\n  pre h <-> c\n  effect l <-> b\n"
        "  execute pour { tilt 110deg  tilt 90deg }\n}",
        "E006",
        "skill parameter 'tilt' is given twice",
        "4:31",
    ),
    (
        "oac p(h: Hand, c: Cup, l: Liquid, b: Bowl) {\n  pre h <-> c\n  effect l <-> b\n"
        "  execute pour { tilt 3cm }\n}",
        "E043",
        "'tilt' of skill 'pour' is an angle (deg, rad), but '3cm' has a unit of length",
        "4:23",
    ),
    (
        "oac p(h: Hand, c: Cup, l: Liquid, b: Bowl) {\n  pre h <-> c\n  effect l <-> b\n"
        "  execute pour { height 3furlongs }\n}",
        "E043",
        "but '3furlongs' has an unknown unit 'furlongs'",
        "4:25",
    ),
    (
        "oac p(h: Hand, c: Cup, l: Liquid, b: Bowl) {\n  pre h <-> c\n  effect l <-> b\n"
        "  execute pour { tilt 270deg }\n}",
        "E044",
        "'tilt' of skill 'pour' must lie between 30deg and 180deg, not 270deg",
        "4:23",
    ),
    (
        "oac w(h: Hand, s: Sponge, t: Tray) {\n  pre h <-> s\n  effect s <-> t\n"
        "  execute wipe { strokes 2.5 }\n}",
        "E044",
        "'strokes' of skill 'wipe' is a count: '2.5' is not a whole number",
        "4:26",
    ),
    ("scene s {\n  a : Liquid\n  c : Cup\n  a in c balls 99\n}", "E044", "'a' has 99 balls", "4:16"),
    # skill parameters on a step: checked against the called OAC's skill
    (
        STEPS + "    grasp(h, c)\n    pour(h, c, l, b) { tlt 105deg }\n  }\n}",
        "E042",
        "skill 'pour' has no parameter 'tlt' (did you mean 'tilt'?)",
        "6:24",
    ),
    (
        STEPS + "    grasp(h, c) { lift 3s }\n    pour(h, c, l, b)\n  }\n}",
        "E043",
        "'lift' of skill 'reach_and_grasp' is a length (m, cm, mm), but '3s' has a unit of duration",
        "5:24",
    ),
    (
        STEPS + "    grasp(h, c)\n    pour(h, c, l, b) { duration 20s }\n  }\n}",
        "E044",
        "'duration' of skill 'pour' must lie between 0.3s and 10s, not 20s",
        "6:33",
    ),
    (
        STEPS + "    grasp(h, c)\n    pour(h, c, l, b) { tilt 100deg tilt 90deg }\n  }\n}",
        "E006",
        "skill parameter 'tilt' is given twice",
        "6:36",
    ),
    (
        STEPS + "    grasp(h, c)\n    pour(h, c, l, b)\n  }\n}\n"
        "oac e(h: Hand, c: Cup, l: Liquid, b: Bowl) {\n  pre h <-> nothing, c <-> l\n  effect l <-> b\n"
        "  steps { d(h, c, l, b) { strokes 3 } }\n}",
        "E047",
        "'d' is a composed OAC and no step inside it executes a skill that takes 'strokes'",
        "12:27",
    ),
    (
        "oac p(h: Hand, c: Cup, l: Liquid, b: Bowl) {\n  pre h <-> c\n  effect l <-> b\n"
        "  execute pour { tilt 110 }\n}",
        "W040",
        "'tilt' of skill 'pour' '110' has no unit and is read as 110 rad (radians); write the unit",
        "4:23",
    ),
    ("scene s {\n  c : Cup\n  c at (56, 0)\n}", "W040", "read as 56 m (metres)", "3:9"),
    ("scene s {\n  c : Cup\n  layout demonstratd\n}", "E045",
     "unknown layout 'demonstratd' (did you mean 'demonstrated'?)", "3:10"),
    (
        "scene s {\n  c : Cup\n  layout auto\n  layout auto\n}",
        "E006",
        "the layout of scene 's' is given twice",
        "4:10",
    ),
    (
        "scene s {\n  c : Cup\n  cp at (56cm, 0)\n}",
        "E004",
        "unknown instance 'cp' in scene 's' (did you mean 'c'?)",
        "3:3",
    ),
    ("scene s {\n  c : Cup\n  c at (56cm, 0)\n  c at (60cm, 0)\n}", "E006", "the place of 'c' is given twice",
     "4:3"),
    ("scene s {\n  c : Cup\n  c at (5s, 0)\n}", "E043", "the position of 'c' is a length (m, cm, mm)", "3:9"),
    ("scene s {\n  c : Cup\n  c at (56cm, 0) turned 5cm\n}", "E043",
     "the yaw of 'c' is an angle (deg, rad), but '5cm' has a unit of length", "3:25"),
    ("scene s {\n  c : Cup\n  c at (56cm, 0) turned 0cm\n}", "E043", "the yaw of 'c' is an angle", "3:25"),
    ("scene s {\n  c : Cup\n  c at (56cm, 0) turned 90dgs\n}", "E043", "an unknown unit 'dgs'", "3:25"),
    ("scene s {\n  c : Cup\n  c at (56cm, 0) turned 400deg\n}", "E044",
     "the yaw of 'c' must lie between -360deg and 360deg, not 400deg", "3:25"),
    ("scene s {\n  c : Cup\n  c at (56cm, 0) turned 90\n}", "W040",
     "the yaw of 'c' '90' has no unit and is read as 90 rad", "3:25"),
    ("scene s {\n  h : Hand\n  h at (56cm, 0)\n}", "E046", "'h' is a Hand of the robot: it has no", "3:3"),
    ("scene s {\n  l : Liquid\n  m : Mixer\n  l in m\n}", "E046", "'m' is a Mixer, not a Container", "4:8"),
    ("scene s {\n  c : Cup\n  m : Mixer\n  m in c\n}", "E046", "'m' is a Mixer, not a Liquid", "4:3"),
    (
        "scene s {\n  l : Liquid\n  c, d : Cup\n  l in c\n  l in d\n}",
        "E006",
        "the container of 'l' is given twice",
        "5:3",
    ),
    (
        "scene s {\n  h : Hand\n  rack : Cup ignored\n}\n"
        "oac g(a: Hand) {\n  pre a <-> nothing\n  effect a <-> rack\n  execute place(a, rack)\n}",
        "E021",
        "'rack' is ignored in scene 's': it takes part in no relation",
        "7:16",
    ),
    (
        STEPS + "    together {\n      grasp(h, c)\n      pour(h, c, l, b)\n    }\n  }\n}",
        "E051",
        "steps 'grasp(h, c)' and 'pour(h, c, l, b)' of one together block depend on each other",
        "7:7",
    ),
    (STEPS + "    together { grasp(h, c) }\n    pour(h, c, l, b)\n  }\n}", "W008",
     "a together block of 1 step: it says nothing", "5:5"),
    ("scene s {\n  h : Hand untracked\n}", "E048", "'h' is a Hand: the demonstrator's hands", "2:3"),
    ('scene s {\n  l : Liquid markers ("l1") untracked\n}', "E048", "'l' is untracked: it has no", "2:23"),
    ("grasp Bowl { type power approach side offset (0.0, 1e400, 0.0) }", "E025", "too large to be", "1:39"),
    ("grasp Bowl { type power approach side offset (-1e309, 0, 0) }", "E025", "too large to be", "1:39"),
    (
        "class Spoon : Graspable\nscene s { spoon : Spoon }",
        "W007",
        "instance 'spoon' has no shape: the robot's simulation cannot build it (give Spoon a shape",
        "2:11",
    ),
    (
        "class Jug { shape sphere(radius 20) }",
        "W006",
        "'radius' of sphere is 20 m: a size without a unit is metres",
        "1:33",
    ),
]


@pytest.mark.parametrize(
    ("snippet", "code", "fragment", "where"), BAD, ids=[f"{b[1]}-{i}" for i, b in enumerate(BAD)]
)
def test_bad_snippet(snippet, code, fragment, where):
    result = compile_sources({**LIBRARY, "bad.oac": snippet})
    found = [d for d in result.diagnostics if d.code == code]
    assert found, f"no {code}; got: " + "; ".join(d.header() for d in result.diagnostics)
    first = found[0]
    assert fragment in first.message
    assert first.span is not None and first.span.file == "bad.oac"
    assert f"{first.span.line}:{first.span.column}" == where
    # no Lark terminal names in what authors read
    for name in ("NAME", "RBRACE", "LBRACE", "$END", "__ANON", "COMMA", "LPAR"):
        assert name not in first.message


def test_every_code_is_exercised_by_the_table():
    assert {b[1] for b in BAD} == set(CODES)


def test_every_code_is_documented():
    doc = (ROOT / "docs" / "language.md").read_text(encoding="utf-8")
    for code in CODES:
        assert f"| {code} |" in doc, f"{code} missing from docs/language.md"


def test_rendering_has_location_source_line_caret_and_notes():
    text = "scene s {\n\tmug : Cpu\n}\n"
    result = compile_sources({**LIBRARY, "bad.oac": text})
    out = render(result.diagnostics, result.sources)
    lines = out.splitlines()
    assert lines[0] == "bad.oac:2:8: error[E003]: unknown class 'Cpu' (did you mean 'Cup'?)"
    assert lines[1] == "  2 | \tmug : Cpu"
    assert lines[2] == "    | \t      ^^^"  # the tab is kept so that the caret lines up
    assert lines[3].startswith("  library/classes.oac:") and lines[3].endswith(
        "note: class 'Cup' is defined here"
    )
    assert lines[-1] == "1 error, 0 warnings"


def test_duplicates_point_at_the_other_definition():
    result = compile_sources({**LIBRARY, "bad.oac": "\n\nclass Hand\n"})
    (dup,) = [d for d in result.diagnostics if d.code == "E006"]
    assert dup.notes[0].message == "first defined here"
    assert str(dup.notes[0].span) == "library/classes.oac:10:7"


def test_all_errors_are_collected_and_sorted():
    text = "scene s {\n  a : Cpu\n  b : Bwl\n}\nclass Mug : Cupp\n"
    result = compile_sources({**LIBRARY, "bad.oac": text})
    positions = [(d.span.line, d.span.column) for d in result.diagnostics]
    assert positions == [(2, 7), (3, 7), (5, 13)]
    assert not result.ok


def test_syntax_error_in_one_file_is_reported_with_the_others():
    result = compile_sources({**LIBRARY, "a.oac": "class", "b.oac": "scene {"})
    assert [(d.span.file, d.code) for d in result.diagnostics] == [("a.oac", "E001"), ("b.oac", "E001")]


def test_language_error_str_is_the_first_error_line():
    with pytest.raises(LanguageError) as info:
        parse_text("oac f(h: Hand) { pre h <-> }", "x.oac")
    assert (
        str(info.value)
        == "x.oac:1:28: error[E001]: unexpected '}', expected an object or 'nothing' after '<->'"
    )
    assert [d.code for d in info.value.diagnostics] == ["E001"]
    assert "^" in info.value.rendered


def test_load_library_raises_with_all_diagnostics(tmp_path):
    (tmp_path / "a.oac").write_text("class A : Missing\nclass B : Gone\n", encoding="utf-8")
    with pytest.raises(LanguageError) as info:
        load_library([tmp_path])
    assert str(info.value).startswith(
        f"{tmp_path / 'a.oac'}:1:11: error[E003]: unknown parent class 'Missing'"
    )
    assert len(info.value.diagnostics) == 2


def test_json_diagnostics():
    from oacdsl.compiler.diagnostics import diagnostics_json

    result = compile_sources({**LIBRARY, "bad.oac": "class Mug : Cupp"})
    (doc,) = diagnostics_json(result.diagnostics)
    assert doc["code"] == "E003" and doc["severity"] == "error"
    assert (doc["file"], doc["line"], doc["column"], doc["end_column"]) == ("bad.oac", 1, 13, 17)
    assert doc["notes"][0]["message"] == "class 'Cup' is defined here"


# --- issue 21: rendering is bounded (a window of each line, a capped number of diagnostics) --------

def test_a_long_line_with_many_warnings_renders_in_bounded_size():
    """A 100 kB one-line list of 20,000 repeated parents: each excerpt used to be the whole line."""
    from oacdsl.compiler import diagnostics

    n = 20_000
    text = "class Cup\nclass Mug : " + ", ".join(["Cup"] * n) + "\n"
    result = compile_sources({"x.oac": text})
    assert len(result.diagnostics) == n - 1
    out = render(result.diagnostics, result.sources)
    assert len(out) < 400 * diagnostics.MAX_RENDERED  # was 20,000 × 2 × 100 kB
    assert out.count("warning[W002]") == diagnostics.MAX_RENDERED
    assert out.endswith(f"… {n - 1 - diagnostics.MAX_RENDERED} more not shown (0 errors,"
                        f" {n - 1 - diagnostics.MAX_RENDERED} warnings; --format json lists every one)\n"
                        f"0 errors, {n - 1} warnings")


def test_a_clipped_line_keeps_the_caret_under_the_span():
    from oacdsl.compiler import diagnostics

    many = ", ".join(["Cup"] * 2000)
    text = f"class Cup\nclass Mug : Cpu, {many}\nclass Pot : {many}, Cpu, {many}\nclass Jar : {many}, Cpu\n"
    result = compile_sources({"x.oac": text})
    out = render(result.diagnostics, result.sources).splitlines()
    assert all(len(line) <= diagnostics.MAX_MESSAGE + 20 for line in out)
    unknown = [i for i, row in enumerate(out) if "error[E003]" in row]
    assert len(unknown) == 3
    for at, (starts, ends) in zip(unknown, [(False, True), (True, True), (True, False)], strict=True):
        source, carets = out[at + 1], out[at + 2]
        assert len(source) <= diagnostics.EXCERPT_WIDTH + 10 and len(carets) <= len(source)
        column = carets.index("^")
        assert source[column : column + 3] == "Cpu" and carets.count("^") == 3
        assert (source.split("| ", 1)[1].startswith("…"), source.endswith("…")) == (starts, ends)


def test_a_long_message_is_clipped_in_the_middle():
    from oacdsl.compiler import diagnostics

    result = compile_sources({"x.oac": "class Cup : " + "B" * 1_000_000 + "\n"})
    out = render(result.diagnostics, result.sources)
    assert len(out) < 2 * diagnostics.MAX_MESSAGE + 2 * diagnostics.EXCERPT_WIDTH
    assert "characters]…" in out and str(result.error()).count("B") < diagnostics.MAX_MESSAGE


def test_many_errors_are_capped_errors_first():
    from oacdsl.compiler import diagnostics

    lines = ["class Cup"] + ["class Mug : Cup, Cup"] * 1 + [f"class C{i} : Cpu" for i in range(300)]
    result = compile_sources({"x.oac": "\n".join(lines) + "\n"})
    out = render(result.diagnostics, result.sources)
    assert out.count("error[E003]") == diagnostics.MAX_RENDERED and "warning[W002]" not in out
