"""The strict rule's second condition: every instance a bound effect names takes part in a change
(oacdsl/matching/strict.py), on the new user's Stack task (library/examples/stacking.oac)."""

from __future__ import annotations

from pathlib import Path

import pytest

from oacdsl.compiler import load_library
from oacdsl.matching import Matcher
from oacdsl.world import WorldState

ROOT = Path(__file__).resolve().parents[1]
HANDS_AND_BOXES = ("block", "crate", "left_hand", "right_hand")


@pytest.fixture(scope="module")
def library():
    return load_library([ROOT / "library" / "kit", ROOT / "library" / "examples"])


def _state(*pairs: tuple[str, str]) -> WorldState:
    return WorldState.of(HANDS_AND_BOXES, pairs)


#: The right hand, holding the block, sets it on the crate; the left hand touches nothing throughout.
ONTO_CRATE = (_state(("right_hand", "block")), _state(("right_hand", "block"), ("block", "crate")))


def test_a_whole_task_oac_is_no_candidate_where_its_hand_takes_no_part(library):
    # stack_block(h, b, c): pre h <-> nothing, not b <-> c; effect b <-> c, not h <-> b. With the idle
    # left hand as h every condition holds (its 'not h <-> b' held all along), so the paper's rule
    # accepts it; the strict rule does not: the left hand takes part in no change.
    matcher = Matcher.from_library(library, library.scenes["stacking"])
    paper = [m.text() for m in matcher.match(*ONTO_CRATE, mode="paper").matches]
    assert "stack_block(h=left_hand, b=block, c=crate)" in paper
    strict = matcher.match(*ONTO_CRATE)
    assert [m.text() for m in strict.matches] == ["set_on(h=right_hand, o=block, s=crate)"]


def test_the_explanation_names_the_instance_the_effects_do_not_change(library):
    matcher = Matcher.from_library(library, library.scenes["stacking"], exclude=["set_on"])
    result = matcher.match(*ONTO_CRATE)
    assert result.chosen is None
    miss = next(m for m in result.near_misses if m.oac.name == "stack_block")
    assert miss.failed == ("the effects name left_hand, which takes part in no change (an OAC's effects"
                           " say what it changes)",)
    assert miss.text().startswith("stack_block(h=left_hand, b=block, c=crate) fails 1 of 6 conditions")


def test_an_effect_that_held_before_is_accepted_when_its_instances_change(library):
    # place_both's 'not o1 <-> o2' already holds when the two objects never touched; both objects
    # leave their hands, so the OAC still matches the two hands letting go at once.
    scene = library.scenes["bottle_lid"]
    tracked = sorted(i.name for i in scene.tracked())
    matcher = Matcher.from_library(library, scene)
    before = WorldState.of(tracked, [("right_hand", "bottle"), ("left_hand", "lid")])
    result = matcher.match(before, WorldState.of(tracked, []))
    assert result.chosen is not None and result.chosen.oac.name == "place_both"
    assert result.chosen.idle == 1


def test_the_clingo_reference_agrees(library):
    pytest.importorskip("clingo")
    from asp_matcher import asp_matches

    matcher = Matcher.from_library(library, library.scenes["stacking"])
    pairs = [ONTO_CRATE]
    found = asp_matches(matcher.oacs, matcher.instance_classes, pairs, "strict")
    assert {matcher.oacs[k].name for k, _, _ in found} == {"set_on"}
    ours = {(co.index, 0, b[: co.n_params]) for co, b in matcher.raw_matches(*ONTO_CRATE)}
    assert found == ours


def _kit_only(library) -> list[str]:
    kit = load_library([ROOT / "library" / "kit"])
    return [n for n in library.oacs if n not in kit.oacs]


def test_the_closest_oac_may_bind_an_instance_of_another_class_and_says_so(library):
    # What the new user met: the KIT library's touch wants a Graspable target, the crate is a
    # Surface. The explanation now names touch and that one class, not an OAC that changes nothing.
    matcher = Matcher.from_library(library, library.scenes["stacking"], exclude=_kit_only(library))
    result = matcher.match(*ONTO_CRATE)
    assert result.chosen is None
    assert result.near_misses[0].text() == ("touch(h=right_hand, o=block, t=crate) fails 1 of 5 conditions:"
                                            " crate is not a Graspable (parameter t; crate: Crate, Surface)")
    # agents and objects do not stand for each other: no hand as an object, no box as a hand
    from oacdsl.matching.explain import closest_binding

    hands = {"left_hand", "right_hand"}
    for co in matcher.compiled:
        miss = closest_binding(co, matcher._members, *ONTO_CRATE, "strict")
        for (_, x), param in zip(miss.binding, co.oac.params, strict=False):
            assert (x in hands) == (param.cls == "Hand"), miss.text()


def test_the_effects_instance_rule_is_reported_only_as_the_one_reason_left(library):
    matcher = Matcher.from_library(library, library.scenes["stacking"], exclude=_kit_only(library))
    result = matcher.match(*ONTO_CRATE)
    assert "takes part in no change" not in (result.explanation or "")
