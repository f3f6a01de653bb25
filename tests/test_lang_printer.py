"""The canonical printer: golden texts, round trips, layout rules."""

from pathlib import Path

import pytest

from oacdsl.compiler import format_oac, parse_text, print_module
from oacdsl.errors import LanguageError
from oacdsl.model import Atom, Call, Module, Oac, Param

GOLDEN = Path(__file__).resolve().parent / "golden" / "printer"
CASES = sorted(
    p.name.removesuffix(".oac") for p in GOLDEN.glob("*.oac") if not p.name.endswith(".expected.oac")
)


@pytest.mark.parametrize("case", CASES)
def test_printer_golden(case):
    source = (GOLDEN / f"{case}.oac").read_text(encoding="utf-8")
    expected = (GOLDEN / f"{case}.expected.oac").read_text(encoding="utf-8")
    module = parse_text(source, f"{case}.oac")
    printed = print_module(module)
    assert printed == expected
    again = parse_text(printed)
    assert again == module
    assert print_module(again) == printed


def test_golden_cases_exist():
    assert {"messy", "composed"} <= set(CASES)


def test_comments_are_attached_where_they_belong():
    m = parse_text((GOLDEN / "messy.oac").read_text(encoding="utf-8"))
    assert m.comments == ("A file written by hand, in no particular layout.",)
    hand = m.decls[0]
    assert hand.comments == ("hands and things",)
    graspable = m.decls[2]
    assert graspable.note == "anything a hand can hold"
    scene = m.decls[4]
    z_cup = next(i for i in scene.instances if i.name == "z_cup")
    assert z_cup.comments == ("the one with markers",) and z_cup.markers == ("zc1", "zc2")
    pour = m.decls[-1]
    moved = next(a for a in pour.effect if not a.negated)
    assert (moved.left, moved.right, moved.note) == ("b", "l", "liquid moves")
    assert m.trailing == ("the end",)


def test_spans_point_at_the_source():
    m = parse_text(
        "class Hand\n\noac grasp(h: Hand, o: Graspable) {\n  pre h <-> nothing\n"
        "  effect o <-> h\n  execute reach_and_grasp\n}\n",
        "x.oac",
    )
    oac = m.decls[1]
    assert (oac.span.file, oac.span.line, oac.span.column, oac.span.end_line) == ("x.oac", 3, 1, 7)
    assert str(oac.part("name")) == "x.oac:3:5"
    atom = oac.effect[0]
    # stored sorted (h, o); the parts keep where each name was written
    assert (atom.left, atom.right) == ("h", "o")
    assert str(atom.part("left")) == "x.oac:5:16" and str(atom.part("right")) == "x.oac:5:10"
    assert str(oac.part("skill")) == "x.oac:6:11"


def test_format_oac_of_a_model_built_in_code():
    oac = Oac(
        name="serve",
        params=(Param(name="h", cls="Hand", default="left_hand"), Param(name="c", cls="Cup")),
        pre=(Atom(left="h", right="nothing"),),
        effect=(Atom(left="c", right="h", note="step 1 grasp, keyframe 2"),),
        steps=(Call(oac="grasp", args=("h", "c")),),
    )
    text = format_oac(oac)
    assert text == (
        "oac serve(h: Hand = left_hand, c: Cup) {\n"
        "    pre     h <-> nothing\n"
        "    effect  h <-> c  # step 1 grasp, keyframe 2\n"
        "    steps {\n"
        "        grasp(h, c)\n"
        "    }\n"
        "}\n"
    )
    back = parse_text(text).decls[0]
    assert back == oac and back.effect[0].note == "step 1 grasp, keyframe 2"


def test_long_sections_wrap_one_atom_per_line():
    names = [f"object_number_{i}" for i in range(8)]
    params = tuple(Param(name=n, cls="Thing") for n in names)
    atoms = tuple(Atom(left=a, right=b) for a, b in zip(names, names[1:], strict=False))
    text = format_oac(Oac(name="chain", params=params, effect=atoms, skill="place"))
    assert max(len(line) for line in text.splitlines()) <= 100
    assert parse_text(text).decls[0].effect == atoms


def test_printer_is_deterministic_over_equal_models():
    a = parse_text("class Cup : Graspable, Container\nscene s { b, a : Cup }")
    b = parse_text("class Cup : Container, Graspable, Container\nscene s {\n a : Cup\n b : Cup\n}")
    assert a == b and print_module(a) == print_module(b)


def test_empty_and_comment_only_files():
    assert print_module(parse_text("")) == ""
    assert print_module(parse_text("  \n\n")) == ""
    assert print_module(parse_text("# only\n\n# comments\n")) == "# only\n# comments\n"


def test_unprintable_models_are_language_errors():
    with pytest.raises(LanguageError, match="not a name"):
        print_module(Module(path="m", decls=(Oac(name="bad name", params=(), skill="place"),)))
    with pytest.raises(LanguageError, match="neither a skill nor steps"):
        format_oac(Oac(name="f", params=()))
    with pytest.raises(LanguageError, match="both a skill and steps"):
        format_oac(Oac(name="f", params=(), skill="place", steps=()))


def test_control_characters_in_a_marker_name_survive_printing():
    # A CR inside a quoted name was printed raw; CR line ends are normalised before
    # parsing, so the string came back unterminated (found by the property test).

    text = 'scene s {\n    a : A markers ("x\\ry", "t\\tn\\n")\n}\n'
    module = parse_text(text, "ctl.oac")
    assert module.decls[0].instances[0].markers == ("x\ry", "t\tn\n")
    printed = print_module(module)
    assert "\r" not in printed
    assert parse_text(printed, "ctl.oac") == module


ROOT = GOLDEN.parents[2]
#: Every .oac file of the repository: the libraries (all folders) and the test data.
FIXTURES = sorted(
    str(p.relative_to(ROOT))
    for d in ("library", "tests/data", "tests/golden")
    for p in (ROOT / d).rglob("*.oac")
)


def test_the_fixtures_are_found():
    assert len(FIXTURES) >= 30 and {"library/kitchen.oac", "tests/data/runtime_tasks.oac"} <= set(FIXTURES)


@pytest.mark.parametrize("path", FIXTURES)
def test_every_fixture_round_trips_through_the_printer(path):
    module = parse_text((ROOT / path).read_text(encoding="utf-8"), path)
    printed = print_module(module)
    again = parse_text(printed, path)
    assert again == module  # parse(print(m)) == m
    assert print_module(again) == printed  # printing is idempotent
