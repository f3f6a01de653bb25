"""The standard library: clean, canonical, and what the other parts rely on."""

from pathlib import Path

import pytest

from oacdsl.compiler import compile_paths, compile_sources, load_library, print_module
from oacdsl.skills import SKILLS

ROOT = Path(__file__).resolve().parents[1]
#: The hand-written standard library: the top-level files (learned/ holds what oacc reproduce and
#: oacc compose write, drafts/ what oacc compose --propose writes).
LIBRARY = sorted((ROOT / "library").glob("*.oac"))


def test_library_compiles_without_errors_or_warnings():
    result = compile_paths(LIBRARY)
    assert result.diagnostics == [], [d.header() for d in result.diagnostics]
    assert len(result.modules) >= 3  # spread over several files that use each other's names


#: The libraries of their own beside it (a LIBRARY file each): the KIT clips' and the examples'.
OWN_LIBRARIES = [ROOT / "library" / "kit", ROOT / "library" / "examples"]


@pytest.mark.parametrize("files", [LIBRARY] + [sorted(d.glob("*.oac")) for d in OWN_LIBRARIES],
                         ids=["library", "kit", "examples"])
def test_library_files_are_in_canonical_form(files):
    result = compile_paths(files)
    assert len(result.modules) == len(files) >= 2
    for module in result.modules:
        assert print_module(module) == result.sources[module.path], (
            f"{module.path} is not canonical (oacc fmt)"
        )


def test_library_has_the_papers_oacs_exactly():
    lib = load_library(LIBRARY)
    assert set(lib.oacs) == {"grasp", "place", "pour", "mix", "wipe"}

    def sig(name):
        oac = lib.oacs[name]
        fmt = lambda atoms: sorted(("not " if a.negated else "") + f"{a.left} <-> {a.right}" for a in atoms)  # noqa: E731
        return [(p.name, p.cls) for p in oac.params], fmt(oac.pre), fmt(oac.effect), oac.skill

    assert sig("grasp") == (
        [("h", "Hand"), ("o", "Graspable")],
        ["h <-> nothing"],
        ["h <-> o"],
        "reach_and_grasp",
    )
    assert sig("place") == ([("h", "Hand"), ("o", "Graspable")], ["h <-> o"], ["h <-> nothing"], "place")
    assert sig("pour") == (
        [("h", "Hand"), ("c", "Container"), ("l", "Liquid"), ("b", "Container")],
        ["c <-> h", "c <-> l"],
        ["b <-> l", "not c <-> l"],
        "pour",
    )
    assert sig("mix") == (
        [("h", "Hand"), ("m", "Mixer"), ("b", "Container")],
        ["h <-> m"],
        ["b <-> m"],
        "mix",
    )
    assert sig("wipe") == (
        [("h", "Hand"), ("s", "Sponge"), ("t", "Surface")],
        ["h <-> s"],
        ["s <-> t"],
        "wipe",
    )
    assert {o.skill for o in lib.oacs.values()} <= set(SKILLS)


def test_library_scenes_and_graspability():
    lib = load_library(LIBRARY)
    kitchen = lib.scenes["kitchen"]
    assert {i.name for i in kitchen.tracked()} == {
        "left_hand",
        "right_hand",
        "red_cup",
        "green_cup",
        "liquid_one",
        "liquid_two",
        "orange_bowl",
        "mixer",
    }
    assert kitchen.instance("table").environment
    classes = lib.instance_classes(kitchen)
    assert {"Cup", "Graspable", "Container"} <= classes["red_cup"]
    assert "Graspable" in classes["mixer"] and "Graspable" not in classes["liquid_one"]
    assert lib.grasp_for(classes["red_cup"]).cls == "Cup"
    wiping = lib.scenes["wiping"]
    assert {"sponge", "tray"} <= {i.name for i in wiping.tracked()}
    assert lib.is_subclass("Tray", "Surface") and lib.is_subclass("Sponge", "Graspable")
    assert lib.grasp_for(lib.instance_classes(wiping)["sponge"]).cls == "Sponge"


def test_the_complete_example_of_the_docs_is_clean_and_canonical():
    import re

    doc = (ROOT / "docs" / "language.md").read_text(encoding="utf-8")
    block = re.search(r"## A complete example\n\n```\n(.*?)```", doc, re.S)
    assert block, "docs/language.md lost its complete example"
    result = compile_sources({"example.oac": block.group(1)})
    assert result.diagnostics == [], [d.header() for d in result.diagnostics]
    assert print_module(result.modules[0]) == block.group(1)
