"""Closed-loop verification: changes between world states and their edit distance."""

import json

import pytest
from hypothesis import given
from hypothesis import strategies as st

from oacdsl.verify import Change, align, changes, states_from_segment_json, verify
from oacdsl.world import WorldState

NAMES = ["left_hand", "right_hand", "red_cup", "green_cup",
         "liquid_one", "liquid_two", "orange_bowl", "mixer"]
INITIAL = [("liquid_one", "red_cup"), ("liquid_two", "green_cup")]

# The dough task as (added, removed) per keyframe transition.
GRASP_RED = ([("left_hand", "red_cup")], [])
POUR_ONE = ([("liquid_one", "orange_bowl")], [("liquid_one", "red_cup")])
PLACE_RED = ([], [("left_hand", "red_cup")])
GRASP_GREEN = ([("green_cup", "right_hand")], [])
POUR_TWO = ([("liquid_two", "orange_bowl")], [("liquid_two", "green_cup")])
PLACE_GREEN = ([], [("green_cup", "right_hand")])
GRASP_MIXER = ([("mixer", "right_hand")], [])
MIX = ([("mixer", "orange_bowl")], [])
DOUGH = [GRASP_RED, POUR_ONE, PLACE_RED, GRASP_GREEN, POUR_TWO, PLACE_GREEN, GRASP_MIXER, MIX]


def run(steps, initial=INITIAL):
    state = WorldState.of(NAMES, initial)
    states = [state]
    for added, removed in steps:
        state = state.with_changes(added, removed)
        states.append(state)
    return states


def test_changes_of_the_dough_task():
    ch = changes(run(DOUGH), frames=[0, 10, 20, 30, 40, 50, 60, 70, 80])
    assert len(ch) == 8
    assert ch[1].added == {("liquid_one", "orange_bowl")} and ch[1].removed == {("liquid_one", "red_cup")}
    assert (ch[1].index, ch[1].frame) == (2, 20)
    assert ch[1].label() == "+ liquid_one <-> orange_bowl, − liquid_one <-> red_cup"
    assert ch[1].items() == ["+liquid_one<->orange_bowl", "-liquid_one<->red_cup"]


def test_transitions_that_change_nothing_are_dropped():
    states = run([GRASP_RED, ([], []), PLACE_RED])
    assert [c.index for c in changes(states)] == [1, 3]


def test_identical_sequences_verify_with_distance_zero():
    v = verify(run(DOUGH), run(DOUGH))
    assert (v.distance, v.relation_distance, v.fidelity, v.verified) == (0, 0, 1.0, True)
    assert [s.op for s in v.alignment] == ["match"] * 8
    assert v.verdict().startswith("verified: the robot made the demonstration's 8 world-state changes")


def test_one_missing_step_costs_one():
    robot = [s for s in DOUGH if s is not PLACE_GREEN]
    # The robot never sets the green cup down.
    v = verify(run(DOUGH), run(robot))
    assert v.distance == 1 and not v.verified
    assert [s.op for s in v.alignment].count("missing") == 1
    missing = next(s for s in v.alignment if s.op == "missing")
    assert v.demonstration[missing.demonstration].removed == {("green_cup", "right_hand")}
    assert v.counts() == {"match": 7, "split": 0, "merge": 0, "substitute": 0, "missing": 1, "extra": 0}
    assert v.fidelity == pytest.approx(7 / 8)
    assert "not verified: edit distance 1" in v.verdict() and "1 missing" in v.verdict()


def test_an_extra_step_costs_one():
    robot = DOUGH[:3] + [GRASP_RED, PLACE_RED] + DOUGH[3:]  # re-grasps the red cup
    v = verify(run(DOUGH), run(robot))
    assert v.distance == 2 and v.counts()["extra"] == 2
    v1 = verify(run(DOUGH), run(DOUGH + [([("left_hand", "red_cup")], [])]))
    assert v1.distance == 1 and v1.alignment[-1].op == "extra" and v1.alignment[-1].demonstration is None


def test_reordered_steps_cost_two():
    moved = DOUGH[:3] + [GRASP_MIXER] + DOUGH[3:6] + [MIX]  # one step moved three places earlier
    swapped = DOUGH[3:6] + DOUGH[:3] + DOUGH[6:]  # liquid two poured first
    v = verify(run(DOUGH), run(swapped))
    assert v.distance == 6  # three steps moved past three others: 3 missing + 3 extra
    assert v.final[0] == v.final[1]  # the same end state, reached in another order
    assert not v.verified
    v2 = verify(run(DOUGH), run(moved))
    assert v2.distance == 2 and v2.counts()["missing"] == v2.counts()["extra"] == 1


def test_a_partly_wrong_step_is_a_substitution_and_the_relation_distance_sees_how_much():
    spill = ([("liquid_one", "orange_bowl")], [])  # poured, but the liquid still touches the cup
    robot = [GRASP_RED, spill] + DOUGH[2:]
    v = verify(run(DOUGH), run(robot))
    assert v.distance >= 1 and any(s.op == "substitute" for s in v.alignment)
    assert v.relation_distance >= 1


def test_initial_state_must_agree():
    v = verify(run(DOUGH), run(DOUGH, initial=INITIAL[:1]))
    assert not v.verified and v.verdict().startswith("not verified: the robot's initial world state differs")
    assert v.to_json()["initial"]["equal"] is False


def test_tolerance_and_instance_restriction():
    v = verify(run(DOUGH), run(DOUGH[:-1]), tolerance=1)
    assert v.distance == 1 and v.verified and v.verdict().startswith("verified within tolerance")
    # Restricting to the hands and cups hides the mixing step entirely.
    v2 = verify(run(DOUGH), run(DOUGH[:-1]), instances=["left_hand", "right_hand", "red_cup", "green_cup"])
    assert v2.distance == 0 and len(v2.demonstration) == 4
    with pytest.raises(ValueError):
        verify([], run(DOUGH))


def test_json_document_is_serialisable_and_complete():
    doc = verify(run(DOUGH), run(DOUGH[:-1]), demonstration_frames=list(range(0, 90, 10))).to_json()
    doc = json.loads(json.dumps(doc))
    assert doc["distance"] == 1 and doc["verified"] is False
    assert doc["demonstration"][1] == {"index": 2, "frame": 20, "time_s": None,
                                       "added": [["liquid_one", "orange_bowl"]],
                                       "removed": [["liquid_one", "red_cup"]]}
    assert doc["alignment"][-1] == {"op": "missing", "demonstration": 7, "robot": None}
    assert set(doc) >= {"fidelity", "final", "instances", "counts", "verdict", "relation_distance"}


def test_states_from_segment_json():
    doc = {"recording": "x", "rate_hz": 100.0, "frames": 300, "parameters": {}, "instances": NAMES,
           "keyframes": [{"frame": 0, "time_s": 0.0, "relations": [["liquid_one", "red_cup"]]},
                         {"frame": 120, "time_s": 1.2, "relations": [["left_hand", "red_cup"],
                                                                     ["liquid_one", "red_cup"]]}]}
    states, frames, times = states_from_segment_json(doc)
    assert frames == [0, 120] and times == [0.0, 1.2]
    assert changes(states)[0] == Change(frozenset({("left_hand", "red_cup")}), frozenset())


words = st.lists(st.sampled_from("abcd"), max_size=7)


def _brute(a, b):
    if not a or not b:
        return len(a) + len(b)
    return min(_brute(a[1:], b[1:]) + (a[0] != b[0]), _brute(a[1:], b) + 1, _brute(a, b[1:]) + 1)


@given(words, words)
def test_align_is_levenshtein_and_its_alignment_is_consistent(a, b):
    distance, steps = align(a, b)
    assert distance == _brute(a, b)
    assert [s.demonstration for s in steps if s.demonstration is not None] == list(range(len(a)))
    assert [s.robot for s in steps if s.robot is not None] == list(range(len(b)))
    assert sum(s.op != "match" for s in steps) == distance
    assert all((a[s.demonstration] == b[s.robot]) == (s.op == "match")
               for s in steps if s.op in ("match", "substitute"))


# --- split changes: a demonstration change the robot makes in several keyframes -------------

KIT_NAMES = ["left_hand", "right_hand", "cup_small", "milk_small"]
HOLD = [("cup_small", "left_hand"), ("milk_small", "right_hand")]
TOUCH = ([("cup_small", "milk_small")], [])
#: KIT Pour at frame 56: the pour's contact and both hands end within 0.3 s (one keyframe)
RELEASE_ALL = ([], [("cup_small", "milk_small"), ("cup_small", "left_hand"), ("milk_small", "right_hand")])
END_POUR = ([], [("cup_small", "milk_small")])
PLACE_CUP = ([], [("cup_small", "left_hand")])
PLACE_MILK = ([], [("milk_small", "right_hand")])
PLACE_BOTH = ([], [("cup_small", "left_hand"), ("milk_small", "right_hand")])



def _kit(steps):
    state = WorldState.of(KIT_NAMES, HOLD)
    states = [state]
    for added, removed in steps:
        state = state.with_changes(added, removed)
        states.append(state)
    return states


@pytest.mark.parametrize("robot", [
    [TOUCH, END_POUR, PLACE_BOTH],                 # the pour ends, then both objects go down
    [TOUCH, END_POUR, PLACE_CUP, PLACE_MILK],      # ... one after the other
    [TOUCH, PLACE_BOTH, END_POUR],                 # any order inside the run
])
def test_one_demonstration_change_made_in_several_robot_changes_is_a_split(robot):
    v = verify(_kit([TOUCH, RELEASE_ALL]), _kit(robot))
    assert v.verified and v.distance == 0
    assert [s.op for s in v.alignment] == ["match", "split"]
    split = v.alignment[1]
    assert (split.demonstration, split.robot, split.robot_last) == (1, 1, len(robot) - 1)
    assert "in several robot changes" in v.verdict()
    doc = json.loads(json.dumps(v.to_json()))
    last = len(robot) - 1
    assert doc["alignment"][1] == {"op": "split", "demonstration": 1, "robot": 1, "robot_last": last}
    assert doc["counts"]["split"] == 1


def test_a_run_that_changes_a_relation_twice_or_something_else_is_no_split():
    back_and_forth = [TOUCH, END_POUR, TOUCH, RELEASE_ALL]  # the pour's contact ends, starts, ends again
    assert not verify(_kit([TOUCH, RELEASE_ALL]), _kit(back_and_forth)).verified
    other = ([("cup_small", "right_hand")], [("cup_small", "milk_small")])  # ends the pour but grabs the cup
    assert not verify(_kit([TOUCH, RELEASE_ALL]), _kit([TOUCH, other, PLACE_BOTH])).verified
    partial = verify(_kit([TOUCH, RELEASE_ALL]), _kit([TOUCH, END_POUR, PLACE_CUP]))  # the carton is kept
    assert not partial.verified and "split" not in [s.op for s in partial.alignment]


def test_the_strict_comparison_is_kept_where_no_split_applies():
    """Two demonstration changes made by the robot at once are not a split (only one
    demonstration change may become several robot changes, not the other way round)."""
    both = (GRASP_RED[0] + POUR_ONE[0], POUR_ONE[1])
    v = verify(run(DOUGH), run([both, *DOUGH[2:]]))
    assert v.distance == 2 and "split" not in [s.op for s in v.alignment]


@given(words, words)
def test_splits_only_lower_the_distance_of_changes(a, b):
    """Plain items (strings) are never split: align stays the Levenshtein distance there."""
    assert align(a, b)[0] == _brute(a, b)


def test_merge_is_the_converse_of_a_split_and_only_when_asked() -> None:
    from oacdsl.verify import Change, align

    a = [Change(frozenset({("a", "b")}), frozenset()), Change(frozenset({("c", "d")}), frozenset())]
    b = [Change(frozenset({("a", "b"), ("c", "d")}), frozenset())]
    assert align(a, b)[0] == 2
    distance, steps = align(a, b, merge=True)
    assert distance == 0 and [(s.op, s.demonstration, s.demonstration_last, s.robot) for s in steps] == [
        ("merge", 0, 1, 0)]
    swapped = [a[1], a[0]]  # a merge keeps the order within the run free, but nothing else
    assert align(swapped + [Change(frozenset(), frozenset({("a", "b")}))], b, merge=True)[0] == 1
