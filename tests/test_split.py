"""Simultaneous changes of the two hands (issue 20): a keyframe that matches no OAC as a whole is
split into matched parts, independent ones grouped into a ``together`` block."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import pytest

from oacdsl.compiler import compile_sources, load_library, parse_text, print_module
from oacdsl.matching import Matcher
from oacdsl.matching.demonstration import compose_demonstration, match_segmentation
from oacdsl.matching.split import split_change
from oacdsl.model import Module, Oac
from oacdsl.segmentation import segment
from oacdsl.segmentation.adaptive import AdaptiveDetector, AdaptiveSettings
from oacdsl.segmentation.params import AasParams
from oacdsl.segmentation.readers import read_recording
from oacdsl.segmentation.recording import Recording
from tests.kitchen import GRASP, KITCHEN, OACS, atom, kitchen_library, state

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def matcher() -> Matcher:
    return Matcher.from_library(kitchen_library(), KITCHEN)


def test_two_hands_grasping_at_once_are_two_grasps_together(matcher):
    before, after = state(), state(("left_hand", "red_cup"), ("right_hand", "green_cup"))
    assert matcher.match(before, after).chosen is None  # the library has no grasp_both
    split = split_change(matcher.match, before, after)
    assert split is not None
    assert split.text() == "together { grasp(h=left_hand, o=red_cup), grasp(h=right_hand, o=green_cup) }"
    assert [p.together for p in split.parts] == [False, True]
    assert split.parts[0].before == before and split.parts[-1].after == after
    assert split.parts[0].after == split.parts[1].before
    assert [g["group"] for g in split.to_json()] == [0, 0]


def test_a_part_that_needs_another_comes_after_it(matcher):
    """The grasp makes the hand hold the cup that the pour needs: two groups, in that order."""
    before = state(("liquid_one", "red_cup"))
    after = state(("left_hand", "red_cup"), ("liquid_one", "orange_bowl"))
    split = split_change(matcher.match, before, after)
    assert split is not None
    assert split.text() == ("grasp(h=left_hand, o=red_cup), then"
                            " pour(h=left_hand, c=red_cup, l=liquid_one, b=orange_bowl)")
    assert [p.together for p in split.parts] == [False, False]


def test_the_fewest_groups_then_the_most_parts(matcher):
    """Left hand lets go of one cup while the right takes the other and the mixer touches the bowl:
    nothing depends on anything, so one group of single OACs."""
    before = state(("left_hand", "red_cup"), ("right_hand", "mixer"))
    after = state(("right_hand", "mixer"), ("mixer", "orange_bowl"))
    split = split_change(matcher.match, before, after)
    assert split is not None
    assert split.text() == ("together { mix(h=right_hand, m=mixer, b=orange_bowl),"
                            " place(h=left_hand, o=red_cup) }")


def test_parts_on_one_object_run_one_after_the_other_in_the_order_they_happened(matcher):
    """The left hand lets go of the red cup while the right pours into it: independent, but both
    about the red cup, so not together; the recording's times order them."""
    before = state(("left_hand", "red_cup"), ("right_hand", "green_cup"), ("green_cup", "liquid_two"))
    after = state(("right_hand", "green_cup"), ("liquid_two", "red_cup"))
    place, pour = ("place(h=left_hand, o=red_cup)",
                   "pour(h=right_hand, c=green_cup, l=liquid_two, b=red_cup)")
    let_go = {("left_hand", "red_cup"): 1.0, ("liquid_two", "red_cup"): 1.2, ("green_cup", "liquid_two"): 1.2}
    split = split_change(matcher.match, before, after, times_s=let_go)
    assert split is not None and split.text() == f"{place}, then {pour}"
    poured = {r: 2.4 - t for r, t in let_go.items()}
    assert split_change(matcher.match, before, after, times_s=poured).text() == f"{pour}, then {place}"


def test_a_combination_oac_matches_the_whole_and_nothing_is_split():
    lib = kitchen_library()
    both = GRASP.model_copy(update={
        "name": "grasp_both",
        "params": (*GRASP.params, *(p.model_copy(update={"name": p.name + "2"}) for p in GRASP.params)),
        "pre": (atom("h"), atom("h2")), "effect": (atom("h", "o"), atom("h2", "o2"))})
    m = Matcher([*OACS, both], lib.instance_classes(KITCHEN), ancestors=lib.ancestors)
    assert m.match(state(), state(("left_hand", "red_cup"), ("right_hand", "green_cup"))).chosen.oac.name \
        == "grasp_both"


def test_nothing_to_split_into(matcher):
    before, after = state(), state(("red_cup", "green_cup"), ("left_hand", "red_cup"))
    assert split_change(matcher.match, before, after) is None  # cups touching: no OAC says so


# ------------------------------------------------------------------ the bundled demonstration


def shifted(rec: Recording, names: list[str], by_s: float) -> Recording:
    """``rec`` with the groups ``names`` delayed by ``by_s`` (their first frame held meanwhile)."""
    k = int(round(by_s * rec.rate_hz))
    pos = rec.positions_m.copy()
    idx = [i for n in names for i in rec.groups[n]]
    pos[k:, idx] = rec.positions_m[:-k, idx]
    pos[:k, idx] = rec.positions_m[0, idx]
    return dataclasses.replace(rec, positions_m=pos)


@pytest.fixture(scope="module")
def dough():
    lib = load_library([ROOT / "library"])
    return read_recording(ROOT / "data" / "dough.c3d"), lib, lib.scenes["kitchen"]


def _paper_merge(params: AasParams, rate_hz: float) -> AdaptiveDetector:
    """The default detector with the paper's merging and fixed constants (no rescaling)."""
    return AdaptiveDetector(params.resolved(rate_hz), AdaptiveSettings(merge="paper", rescale=False))


@pytest.mark.parametrize("delay_s", [2.9, 3.0, 3.2])
def test_the_left_hand_letting_go_while_the_right_grasps(dough, delay_s):
    """The left hand's part of the dough task delayed by about 3 s: its cup is set down while the
    right hand grasps the green cup (one keyframe under the paper's merging). It composes to the
    dough's steps, those two in a together block, and the new OAC compiles and prints back to
    itself."""
    rec, lib, scene = dough
    take = shifted(rec, ["left_hand", "red_cup", "liquid_one"], delay_s)
    seg = segment(take, AasParams(), detector=_paper_merge(AasParams(), take.rate_hz))
    unmerged = dataclasses.replace(AasParams(), merge_s=0.0)
    raw = _paper_merge(unmerged, take.rate_hz)
    matches = match_segmentation(seg, Matcher.from_library(lib, scene),
                                 unmerged=lambda: segment(take, unmerged, detector=raw))
    assert all(m.matched for m in matches)
    split = [m for m in matches if m.split is not None]
    assert len(split) == 1 and split[0].result.chosen is None
    # the left hand let go at 8.24 s + the delay, the right hand grasped at 11.34 s: in that order
    first, second = ("place", "grasp") if 8.24 + delay_s < 11.34 else ("grasp", "place")
    calls = {"grasp": "grasp(h=right_hand, o=green_cup)", "place": "place(h=left_hand, o=red_cup)"}
    assert split[0].text() == f"split: together {{ {calls[first]}, {calls[second]} }}"
    comp = compose_demonstration("dough_overlap", matches, lib, scene).composition
    names = [s.oac.name for s in comp.steps]
    assert names == ["grasp", "pour", first, second, "pour", "place", "grasp", "mix"]
    assert [c.together for c in comp.oac.steps] == [False, False, False, True, False, False, False, False]
    assert [c.oac for c in comp.oac.steps] == names  # the OAC's steps and the composition's: one order
    text = print_module(Module(path="d.oac", decls=(comp.oac,)))
    shown = {"grasp": "grasp(hand2, cup2)", "place": "place(hand1, cup1)"}
    assert f"        together {{\n            {shown[first]}\n            {shown[second]}\n        }}" in text
    assert parse_text(text, "d.oac").decls[0] == comp.oac
    sources = {m.path: Path(m.path).read_text() for m in lib.modules}
    assert compile_sources({**sources, "d.oac": text}).ok
    # notes count steps (8) and keyframes (7) apart: the grasp starts at the split keyframe 2,
    # the pour after it is step 5 but starts at keyframe 3
    assert f"hand2 <-> nothing,  # step {3 if first == 'grasp' else 4} grasp, keyframe 2" in text
    assert "cup2 <-> liquid2  # step 5 pour, keyframe 3" in text


@pytest.mark.parametrize("delay_s", [2.9, 3.0, 3.2])
def test_by_default_independent_changes_of_the_two_hands_stay_apart(dough, delay_s):
    """The same take with the default detector (connected merging): the left hand's let-go and
    the right hand's grasp are two keyframes, no OAC matches both at once (coincident.py), so
    they compose to two steps in the order they were seen, nothing split."""
    rec, lib, scene = dough
    take = shifted(rec, ["left_hand", "red_cup", "liquid_one"], delay_s)
    matches = match_segmentation(segment(take, AasParams()), Matcher.from_library(lib, scene))
    assert all(m.matched for m in matches) and all(m.split is None and not m.joined for m in matches)
    comp = compose_demonstration("dough_overlap", matches, lib, scene).composition
    names = [s.oac.name for s in comp.steps]
    assert names[:2] + names[4:] == ["grasp", "pour", "pour", "place", "grasp", "mix"]
    assert sorted(names[2:4]) == ["grasp", "place"] and not any(c.together for c in comp.oac.steps)


def test_the_bundled_demonstration_is_not_split(dough):
    rec, lib, scene = dough
    matches = match_segmentation(segment(rec, AasParams()), Matcher.from_library(lib, scene))
    assert [m.split for m in matches] == [None] * 8


# ------------------------------------------------------------------ the language


def test_together_blocks_keep_their_order_and_round_trip():
    text = ("class Hand\nclass Graspable\n"
            "oac grasp(h: Hand, o: Graspable) {\n  pre h <-> nothing\n  effect h <-> o\n"
            "  execute reach_and_grasp\n}\n"
            "oac both(a: Hand, b: Hand, x: Graspable, y: Graspable) {\n  pre a <-> nothing, b <-> nothing\n"
            "  effect a <-> x, b <-> y\n  steps {\n    together {\n      grasp(b, y)\n      grasp(a, x)\n"
            "    }\n  }\n}\n")
    module = parse_text(text, "t.oac")
    oac = module.decls[-1]
    assert isinstance(oac, Oac)
    assert [(c.args, c.together) for c in oac.steps] == [(("b", "y"), False), (("a", "x"), True)]
    printed = print_module(module)
    assert "    steps {\n        together {\n            grasp(b, y)\n            grasp(a, x)\n        }\n" \
        in printed
    assert parse_text(printed, "t.oac") == module
    assert print_module(parse_text(printed, "t.oac")) == printed
    assert compile_sources({"t.oac": text}).ok
    swapped = text.replace("grasp(b, y)\n      grasp(a, x)", "grasp(a, x)\n      grasp(b, y)")
    assert parse_text(swapped, "t.oac") != module  # the order is what the runtime runs
