"""A liquid touching a tool that stands in its own container is no change of the task
(oacdsl/verify_liquids.py): left out of both recordings' world states."""

from __future__ import annotations

from oacdsl.segmentation.result import Keyframe, Segmentation
from oacdsl.verify_liquids import in_shared_container, without_shared_container
from oacdsl.world import WorldState, relation

NAMES = ("green_cup", "left_hand", "liquid_two", "mixer", "orange_bowl", "right_hand")
LIQUIDS = {"liquid_two"}
CONTAINERS = {"green_cup", "orange_bowl"}


def is_agent(x: str) -> bool:
    return x.endswith("_hand")


def state(*pairs: tuple[str, str]) -> WorldState:
    return WorldState.of(NAMES, pairs)


def seg(*states: WorldState) -> Segmentation:
    kfs = tuple(Keyframe(100 * i, float(i), s) for i, s in enumerate(states))
    return Segmentation("test", 100.0, 100 * len(states), NAMES, kfs)


MIXING = (("liquid_two", "orange_bowl"), ("mixer", "orange_bowl"), ("mixer", "right_hand"))


def test_a_ball_against_the_stirring_mixer_is_no_change():
    # the dough's stories: a ball of liquid_two rests against the mixer for 0.1-0.5 s as it
    # stirs the bowl both are in; read as + and - liquid_two <-> mixer, two extra changes
    s = seg(state(*MIXING), state(*MIXING, ("liquid_two", "mixer")), state(*MIXING))
    out = without_shared_container(s, LIQUIDS, CONTAINERS, is_agent)
    assert [k.state for k in out.keyframes] == [state(*MIXING)]
    assert in_shared_container(relation("liquid_two", "mixer"), s.keyframes[1].state, LIQUIDS,
                               CONTAINERS, is_agent)


def test_the_change_it_came_with_stays():
    before = state(("liquid_two", "orange_bowl"), ("mixer", "right_hand"))
    s = seg(before, state(*MIXING, ("liquid_two", "mixer")))
    out = without_shared_container(s, LIQUIDS, CONTAINERS, is_agent)
    assert [k.state for k in out.keyframes] == [before, state(*MIXING)]


def test_a_liquid_reaching_a_container_or_a_hand_is_judged_as_before():
    # poured from a cup resting on the bowl's rim: liquid <-> bowl is the pour's change
    pouring = state(("green_cup", "liquid_two"), ("green_cup", "orange_bowl"), ("green_cup", "right_hand"))
    poured = pouring.with_changes(added=[relation("liquid_two", "orange_bowl")])
    # a ball on the fingers of the hand holding the cup: a spill, still a relation
    spilled = pouring.with_changes(added=[relation("liquid_two", "right_hand")])
    for s in (seg(pouring, poured), seg(pouring, spilled)):
        assert without_shared_container(s, LIQUIDS, CONTAINERS, is_agent) == s


def test_a_tool_touching_the_liquid_outside_its_container_is_a_change():
    # the mixer not in the bowl (held up): a ball on it is not explained by a shared container
    s = seg(state(("liquid_two", "orange_bowl"), ("mixer", "right_hand")),
            state(("liquid_two", "orange_bowl"), ("liquid_two", "mixer"), ("mixer", "right_hand")))
    assert without_shared_container(s, LIQUIDS, CONTAINERS, is_agent) == s


def test_no_liquids_nothing_changes():
    s = seg(state(*MIXING), state(*MIXING, ("liquid_two", "mixer")))
    assert without_shared_container(s, set(), CONTAINERS, is_agent) is s


def test_a_kept_keyframe_keeps_when_its_change_happened():
    before = state(("liquid_two", "orange_bowl"), ("mixer", "right_hand"))
    s = seg(before, state(*MIXING, ("liquid_two", "mixer")))
    timed = Segmentation(s.recording, s.rate_hz, s.frames, s.instances,
                         (s.keyframes[0], Keyframe(100, 1.0, s.keyframes[1].state, change_s=0.996)))
    out = without_shared_container(timed, LIQUIDS, CONTAINERS, is_agent)
    assert out.keyframes[1].change_s == 0.996 and out.keyframes[1].state == state(*MIXING)
