"""Untracked scene instances (``milk : Milk untracked``): the language, scene resolution, and
matching that predicts their relations instead of requiring them of the demonstration."""

from __future__ import annotations

from pathlib import Path

import pytest

from oacdsl.compiler import compile_paths, load_library, parse_text, print_module
from oacdsl.matching import Matcher
from oacdsl.matching.composer import Step, compose
from oacdsl.matching.demonstration import find_scene, match_segmentation
from oacdsl.segmentation.result import Keyframe, Segmentation
from oacdsl.world import WorldState

ROOT = Path(__file__).resolve().parents[1]
KIT = ROOT / "library" / "kit"
POUR = ("cup_small", "left_hand", "milk_small", "right_hand")


def _segmentation(states: list[list[tuple[str, str]]]) -> Segmentation:
    kfs = tuple(Keyframe(10 * k, float(k), WorldState.of(POUR, pairs)) for k, pairs in enumerate(states))
    return Segmentation("pour", 10.0, 10 * len(states), POUR, kfs)


#: The KIT Pour clip's keyframes (oacc segment): cup, carton, carton touches cup, all released.
POUR_STATES = [
    [],
    [("cup_small", "left_hand")],
    [("cup_small", "left_hand"), ("milk_small", "right_hand")],
    [("cup_small", "left_hand"), ("milk_small", "right_hand"), ("cup_small", "milk_small")],
    [],
]


def test_untracked_parses_prints_and_is_left_out_of_the_tracked_instances() -> None:
    text = "scene s {\n    cup : Cup\n    milk : Milk untracked\n}\n"
    module = parse_text(text, "s.oac")
    scene = module.decls[0]
    assert [i.name for i in scene.untracked()] == ["milk"]
    assert [i.name for i in scene.tracked()] == ["cup"]
    assert "milk : Milk untracked" in print_module(module)
    assert parse_text(print_module(module), "s.oac").decls[0] == scene


def test_the_scene_is_found_by_its_tracked_instances_alone() -> None:
    lib = load_library([KIT])
    assert find_scene(lib, list(POUR)).name == "kit_pour"
    assert "milk" in {i.name for i in lib.scenes["kit_pour"].instances}


@pytest.mark.parametrize(
    ("line", "message"),
    [
        ("    right_hand : Hand untracked", "'right_hand' is a Hand: the demonstrator's hands"),
        ('    foam : Milk markers ("f1") untracked', "'foam' is untracked: it has no marker group"),
    ],
)
def test_misused_untracked_is_e048(tmp_path: Path, line: str, message: str) -> None:
    (tmp_path / "kit").mkdir()
    for f in KIT.glob("*.oac"):
        (tmp_path / "kit" / f.name).write_text(f.read_text(encoding="utf-8"), encoding="utf-8")
    bad = tmp_path / "kit" / "bad.oac"
    bad.write_text(f"scene bad {{\n    left_hand : Hand\n{line}\n}}\n", encoding="utf-8")
    errors = [d for d in compile_paths([tmp_path / "kit"]).diagnostics if d.severity == "error"]
    assert [d.code for d in errors] == ["E048"]
    assert message in errors[0].message and errors[0].span.line == 3


def test_the_matcher_binds_the_untracked_milk_and_predicts_where_it_goes() -> None:
    lib = load_library([KIT])
    scene = lib.scenes["kit_pour"]
    matcher = Matcher.from_library(lib, scene)
    matches = match_segmentation(_segmentation(POUR_STATES), matcher)
    chosen = [m.result.chosen for m in matches]
    assert all(c is not None for c in chosen)
    assert [c.oac.name for c in chosen] == ["grasp", "grasp", "bring_to", "pour_and_place_both"]
    # the milk, predicted in the carton, says which vessel was brought to the other
    assert chosen[2].mapping == {"h": "right_hand", "c": "milk_small", "l": "milk", "b": "cup_small"}
    assert chosen[3].mapping["l"] == "milk" and chosen[3].mapping["c"] == "milk_small"
    # the predicted relations ride along: milk in the carton, then in the cup
    assert ("milk", "milk_small") in matches[2].result.before.relations
    assert ("milk", "milk_small") in matches[2].result.after.relations
    assert ("cup_small", "milk") in matches[3].result.after.relations
    assert ("milk", "milk_small") not in matches[3].result.after.relations
    # and the composition says so: the milk starts in the carton and ends in the cup
    steps = [Step(m.result.chosen.oac, m.result.chosen.binding, m.sub_action.before, m.sub_action.after,
                  m.index, m.sub_action.start.frame, m.sub_action.end.frame) for m in matches]
    comp = compose("pour", steps, lib, scene)
    effects = {(a.left, a.right, a.negated) for a in comp.oac.effect}
    pre = {(a.left, a.right, a.negated) for a in comp.oac.pre}
    assert ("milk", "small_cup", False) in effects or ("small_cup", "milk", False) in effects
    assert ("milk_carton", "milk", False) in pre or ("milk", "milk_carton", False) in pre


def test_the_demonstration_is_never_asked_for_the_untracked_relations() -> None:
    """Without the scene's 'untracked' declaration no OAC can bind a liquid: the sub-action
    where the carton comes onto the cup then matches only the generic touch, either way round
    (ambiguous); with it, bring_to binds the milk the carton holds."""
    lib = load_library([KIT])
    scene = lib.scenes["kit_pour"]
    tracked_only = scene.model_copy(update={"instances": scene.tracked()})
    before = WorldState.of(POUR, POUR_STATES[2])
    after = WorldState.of(POUR, POUR_STATES[3])
    plain = Matcher.from_library(lib, tracked_only).match(before, after)
    assert plain.chosen is not None and plain.chosen.oac.name == "touch" and plain.ambiguous
    with_milk = Matcher.from_library(lib, scene)
    assert with_milk.untracked is not None
    result = with_milk.match(with_milk.untracked.with_predicted(before, with_milk.untracked.initial),
                             with_milk.untracked.with_predicted(after, with_milk.untracked.initial))
    assert result.chosen is not None and not result.ambiguous
    assert with_milk.untracked.original(result.chosen).mapping == {
        "h": "right_hand", "c": "milk_small", "l": "milk", "b": "cup_small"}
