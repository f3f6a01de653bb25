"""The transient-state rule of matching: an object in flight does not split a sub-action."""

from __future__ import annotations

from oacdsl.matching.transient import agents_of, stable_segmentation
from oacdsl.segmentation.result import Keyframe, Segmentation
from oacdsl.world import WorldState

NAMES = ("bowl", "cup", "hand", "liquid")


def seg(*states: tuple[float, list[tuple[str, str]]]) -> Segmentation:
    kfs = tuple(Keyframe(int(t * 100), t, WorldState.of(NAMES, rels)) for t, rels in states)
    return Segmentation("test", 100.0, 10_000, NAMES, kfs)


def is_hand(name: str) -> bool:
    return name == "hand"


HELD = [("cup", "hand"), ("cup", "liquid")]
FLYING = [("cup", "hand")]
LANDED = [("cup", "hand"), ("bowl", "liquid")]


def test_liquid_in_flight_is_transient():
    s = seg((0, HELD), (5.0, FLYING), (6.0, LANDED), (9.0, []))
    stable, dropped = stable_segmentation(s, is_hand)
    assert [k.frame for k in stable.keyframes] == [0, 600, 900]
    found = [(t.keyframe.frame, t.objects, round(t.duration_s, 3)) for t in dropped]
    assert found == [(500, ("liquid",), 1.0)]
    assert stable.sub_actions()[0].after.sorted_relations() == sorted(LANDED)


def test_long_flight_agents_and_other_changes_are_not_transient():
    # 1.5 s or longer: a state of its own
    assert stable_segmentation(seg((0, HELD), (5.0, FLYING), (6.5, LANDED)), is_hand)[1] == ()
    # a hand touching nothing between two grasps is an agent at rest, not in flight
    regrasp = seg((0, [("cup", "hand")]), (2.0, []), (2.5, [("bowl", "hand")]), (5.0, []))
    assert stable_segmentation(regrasp, is_hand)[1] == ()
    # the bowl stops touching a cup set on it, then receives the liquid poured from that cup:
    # the change into the bowl's empty state also moves the liquid, so the bowl is not in flight
    on_bowl = [("cup", "hand"), ("cup", "liquid"), ("bowl", "cup")]
    poured = [("cup", "hand"), ("bowl", "liquid")]
    assert stable_segmentation(seg((0, on_bowl), (1.0, HELD), (2.0, poured), (5.0, [])), is_hand)[1] == ()
    # the rule can be switched off
    assert stable_segmentation(seg((0, HELD), (5.0, FLYING), (6.0, LANDED)), is_hand, 0.0)[1] == ()


def test_an_object_that_falls_back_leaves_no_change():
    # the liquid jumps out of the cup and back in: both keyframes go, nothing happened
    s = seg((0, HELD), (5.0, FLYING), (5.5, HELD), (9.0, []))
    stable, dropped = stable_segmentation(s, is_hand)
    assert [k.frame for k in stable.keyframes] == [0, 900] and len(dropped) == 1


def test_agents_are_the_hand_class_and_its_subclasses():
    classes = {"left": {"Hand"}, "robot_gripper": {"Gripper", "Hand"}, "cup": {"Cup", "Graspable"}}
    assert agents_of(classes) == {"left", "robot_gripper"}
