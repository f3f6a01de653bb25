"""Near-coincident independent changes of the two hands: one OAC for their union where the library
has one (oacdsl/matching/coincident.py), whatever the segmentation merged and in either order."""

from __future__ import annotations

from dataclasses import replace

import pytest

from oacdsl.library import Library
from oacdsl.matching import Matcher
from oacdsl.matching.coincident import REFERENCE_FRAME_S, coincidence_window_s, join_coincident
from oacdsl.matching.demonstration import compose_demonstration, match_segmentation
from oacdsl.model import Module, Oac, Param
from oacdsl.segmentation.keyframes import merge_keyframes
from oacdsl.segmentation.result import Keyframe, Segmentation
from oacdsl.world import WorldState
from tests.kitchen import CLASSES, KITCHEN, OACS, atom, state

GRASP_BOTH = Oac(
    name="grasp_both",
    params=(Param(name="h1", cls="Hand"), Param(name="o1", cls="Graspable"),
            Param(name="h2", cls="Hand"), Param(name="o2", cls="Graspable")),
    pre=(atom("h1"), atom("h2")), effect=(atom("h1", "o1"), atom("h2", "o2")), skill="grasp_both",
)
LEFT, RIGHT = ("left_hand", "red_cup"), ("right_hand", "green_cup")


def library(*extra: Oac) -> Library:
    return Library([Module(path="<kitchen>", decls=(*CLASSES, KITCHEN, *OACS, *extra))])


def segmentation(times_s: list[float], states: list[WorldState], merge_s: float = 0.3,
                 time_factor: float | None = 1.0) -> Segmentation:
    params: dict[str, object] = {"merge_s": merge_s}
    if time_factor is not None:
        params["scale"] = {"length": 1.0, "speed": 1 / time_factor, "time": time_factor}
    kfs = tuple(Keyframe(round(t * 10), t, s) for t, s in zip(times_s, states, strict=True))
    return Segmentation("demo", 10.0, 100, tuple(sorted(KITCHEN_TRACKED)), kfs, params)


KITCHEN_TRACKED = {i.name for i in KITCHEN.tracked()}


def steps(seg: Segmentation, lib: Library) -> list[str]:
    matches = match_segmentation(seg, Matcher.from_library(lib, KITCHEN))
    comp = compose_demonstration("demo", matches, lib, KITCHEN).composition
    return [f"{s.oac.name}({', '.join(v for _, v in s.binding)})" for s in comp.steps]


@pytest.mark.parametrize("first, second", [(LEFT, RIGHT), (RIGHT, LEFT)])
def test_two_grasps_close_in_time_are_one_grasp_both_in_either_order(first, second):
    seg = segmentation([0.0, 1.0, 1.2], [state(), state(first), state(first, second)])
    got = steps(seg, library(GRASP_BOTH))
    assert got in (["grasp_both(left_hand, red_cup, right_hand, green_cup)"],
                   ["grasp_both(right_hand, green_cup, left_hand, red_cup)"])
    # the same as when the segmentation put both in one keyframe
    merged = segmentation([0.0, 1.2], [state(), state(first, second)])
    assert steps(merged, library(GRASP_BOTH)) == got
    matches = match_segmentation(seg, Matcher.from_library(library(GRASP_BOTH), KITCHEN))
    assert [j.keyframe.frame for m in matches for j in m.joined] == [10]
    assert matches[0].to_json()["joined"] == [{"frame": 10, "time_s": 1.0, "gap_s": 0.2}]


def test_without_an_oac_for_both_they_stay_two_steps_in_the_order_seen():
    seg = segmentation([0.0, 1.0, 1.2], [state(), state(RIGHT), state(RIGHT, LEFT)])
    assert steps(seg, library()) == ["grasp(right_hand, green_cup)", "grasp(left_hand, red_cup)"]


def test_the_window_is_the_merge_window_and_a_reference_frame_in_the_demonstrations_time():
    seg = segmentation([0.0, 1.0, 1.5], [state(), state(LEFT), state(LEFT, RIGHT)])
    assert coincidence_window_s(seg) == pytest.approx(0.3 + REFERENCE_FRAME_S)
    assert steps(seg, library(GRASP_BOTH)) == ["grasp(left_hand, red_cup)", "grasp(right_hand, green_cup)"]
    slow = segmentation([0.0, 1.0, 1.5], [state(), state(LEFT), state(LEFT, RIGHT)], time_factor=2.0)
    assert coincidence_window_s(slow) == pytest.approx(2 * (0.3 + REFERENCE_FRAME_S))
    assert steps(slow, library(GRASP_BOTH)) == ["grasp_both(left_hand, red_cup, right_hand, green_cup)"]
    # no merging asked for, or not in the demonstration's pace (the paper's mode): nothing joined
    assert coincidence_window_s(segmentation([0.0], [state()], merge_s=0.0)) == 0.0
    paper = segmentation([0.0, 1.0, 1.2], [state(), state(LEFT), state(LEFT, RIGHT)], time_factor=None)
    assert coincidence_window_s(paper) == 0.0
    assert steps(paper, library(GRASP_BOTH)) == ["grasp(left_hand, red_cup)", "grasp(right_hand, green_cup)"]


def test_changes_that_share_an_instance_are_not_joined():
    """A grasp, then the same hand's cup touching the bowl: one hand's sequence, not two at once."""
    states = [state(), state(LEFT), state(LEFT, ("red_cup", "orange_bowl"))]
    seg = segmentation([0.0, 1.0, 1.1], states)
    got, joined = join_coincident(seg, lambda start, end: True, 1.0)
    assert got is seg and joined == ()


def test_a_chain_of_three_is_joined_left_to_right():
    mixer = ("mixer", "orange_bowl")
    states = [state(), state(LEFT), state(LEFT, RIGHT), state(LEFT, RIGHT, mixer)]
    seg = segmentation([0.0, 1.0, 1.2, 1.4], states)
    asked: list[tuple[int, int]] = []

    def whole(start: Keyframe, end: Keyframe) -> bool:
        asked.append((start.frame, end.frame))
        return True

    got, joined = join_coincident(seg, whole, 0.4)
    assert [k.frame for k in got.keyframes] == [0, 14] and [j.keyframe.frame for j in joined] == [10, 12]
    assert asked == [(0, 12), (0, 14)]


def test_connected_groups_stand_at_the_hands_change_else_at_their_last_frame():
    def kf(frame: int, *rels: tuple[str, str]) -> Keyframe:
        return Keyframe(frame, frame / 10, WorldState(frozenset("abch"), frozenset(rels)))

    ah, ac = ("a", "h"), ("a", "c")
    hands = frozenset("h")
    # h grasps a (10), a reaches c (12): at the grasp
    got = merge_keyframes([kf(0), kf(10, ah), kf(12, ah, ac)], 0.3, connected=True, agents=hands)
    assert [k.frame for k in got] == [0, 10]
    # b leaves c (10), b reaches a (12), no hand: at the last frame, as the paper's
    bc, ab = ("b", "c"), ("a", "b")
    got = merge_keyframes([kf(0, bc), kf(10), kf(12, ab)], 0.3, connected=True, agents=hands)
    assert [k.frame for k in got] == [0, 12]


def test_the_window_compares_when_the_changes_happened_not_their_frames():
    """A 10 Hz take at twice the speed (time factor 0.55: window 0.22 s): two grasps two frames
    apart (0.2 s) happened 0.26 s apart (KIT Wipe's, 0.52 s in the original) and stay two steps;
    two grasps three frames apart (0.3 s) happened 0.21 s apart and are one grasp_both."""
    lib = library(GRASP_BOTH)
    states = [state(), state(LEFT), state(LEFT, RIGHT)]
    apart = segmentation([0.0, 0.6, 0.8], states, time_factor=0.55)
    assert steps(apart, lib) == ["grasp_both(left_hand, red_cup, right_hand, green_cup)"]  # by frames
    kfs = apart.keyframes
    timed = replace(apart, keyframes=(kfs[0], replace(kfs[1], change_s=0.52),
                                      replace(kfs[2], change_s=0.78)))
    assert steps(timed, lib) == ["grasp(left_hand, red_cup)", "grasp(right_hand, green_cup)"]
    together = segmentation([0.0, 0.6, 0.9], states, time_factor=0.55)
    assert steps(together, lib) == ["grasp(left_hand, red_cup)", "grasp(right_hand, green_cup)"]
    kfs = together.keyframes
    timed = replace(together, keyframes=(kfs[0], replace(kfs[1], change_s=0.59),
                                         replace(kfs[2], change_s=0.80)))
    assert steps(timed, lib) == ["grasp_both(left_hand, red_cup, right_hand, green_cup)"]
