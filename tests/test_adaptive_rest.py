"""After a step fails with the composed OAC's effects already holding, the demonstrated steps
still to come run when they apply (KIT Pour left-handed: the pour's own check failed with 7 of
8 balls in the cup, and the run stopped with the cup and the carton still held); else the run
is done, as before."""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace

from oacdsl.compiler import load_library
from oacdsl.runtime.adaptive_plan import AdaptivePlan, step_key
from oacdsl.runtime.binding import Step
from oacdsl.world import WorldState

ROOT = Path(__file__).resolve().parents[1]
INSTANCES = ["left_hand", "right_hand", "cup_small", "milk_small", "milk"]


def _after_a_failed_pour(held: list[tuple[str, str]]) -> tuple[AdaptivePlan, Step]:
    lib = load_library([ROOT / "library" / "kit"])
    pour = Step(lib.oacs["pour"], {"h": "left_hand", "c": "milk_small", "l": "milk", "b": "cup_small"})
    place = Step(lib.oacs["place_both"],
                 {"h1": "right_hand", "o1": "cup_small", "h2": "left_hand", "o2": "milk_small"})
    state = WorldState.of(INSTANCES, [*held, ("cup_small", "milk")])  # the milk (most of it) in the cup
    # the composed OAC's effects: the pour's (the milk in the cup, none in the carton)
    composed = SimpleNamespace(composed=True, effect=lib.oacs["pour"].effect)
    run = SimpleNamespace(
        context=SimpleNamespace(library=lib), oac=composed, steps=[pour, place], binding=pour.binding,
        world=SimpleNamespace(relations=lambda: state),
    )
    adaptive = AdaptivePlan(run, 3, "fast-downward")  # type: ignore[arg-type]  # a stand-in run
    adaptive.queue = [place]  # the pour was popped and ran; its skill failed
    adaptive.banned.add(step_key(pour))
    return adaptive, place


def test_the_hands_still_put_down_what_they_hold():
    adaptive, place = _after_a_failed_pour([("right_hand", "cup_small"), ("left_hand", "milk_small")])
    assert adaptive.repair(4, "step 4 pour failed")
    assert adaptive.queue == [place]
    note = adaptive.adaptations[-1]
    assert "the demonstrated steps still to come run" in note["text"]
    assert note["plan"] == ["place_both(right_hand, cup_small, left_hand, milk_small)"]


def test_done_when_the_steps_still_to_come_do_not_apply():
    adaptive, _ = _after_a_failed_pour([("left_hand", "milk_small")])  # the cup was dropped
    assert adaptive.repair(4, "step 4 pour failed")
    assert adaptive.queue == []
    assert adaptive.adaptations[-1]["text"].endswith("the composed OAC's effects hold already: done")
