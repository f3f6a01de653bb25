"""A repair plan keeps the demonstrated order of what is left (dough with the liquids in each
other's cups: the planner's cheapest plan mixes before the second pour and keeps the red cup in
the left hand, and the robot's pour then stops on the mixer's wrist); no simulator."""

from __future__ import annotations

import functools
import shutil
from pathlib import Path
from types import SimpleNamespace

import pytest

pytest.importorskip("unified_planning", reason="replanning needs the 'plan' extra")

from oacdsl.compiler import load_library  # noqa: E402
from oacdsl.matching.conditions import bind_atoms  # noqa: E402
from oacdsl.runtime.adaptive_plan import AdaptivePlan  # noqa: E402
from oacdsl.runtime.binding import Step, expand  # noqa: E402
from oacdsl.runtime.executor import step_label  # noqa: E402
from oacdsl.world import WorldState  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
INSTANCES = ["green_cup", "red_cup", "left_hand", "right_hand", "liquid_one", "liquid_two", "mixer",
             "orange_bowl"]


@functools.cache
def _dough_text() -> str:
    import oacdsl

    demo = oacdsl.load_demonstration(str(ROOT / "data" / "dough.c3d"), str(ROOT / "library"))
    return oacdsl.compose(demo, "dough").text


def _adaptive(tmp_path: Path, relations: list[tuple[str, str]]) -> AdaptivePlan:
    folder = tmp_path / "library"
    shutil.copytree(ROOT / "library", folder)
    (folder / "learned").mkdir(exist_ok=True)
    (folder / "learned" / "dough.oac").write_text(_dough_text())
    lib = load_library([folder])
    dough = lib.oacs["dough"]
    binding = {p.name: p.default for p in dough.params}
    steps, _ = expand(lib, dough, binding)
    state = WorldState.of(INSTANCES, relations)
    run = SimpleNamespace(context=SimpleNamespace(library=lib), oac=dough, steps=steps, binding=binding,
                          scene=lib.scenes["kitchen"], world=SimpleNamespace(relations=lambda: state))
    return AdaptivePlan(run, 3, "fast-downward")  # type: ignore[arg-type]  # a stand-in run


def _labels(steps: list[Step]) -> list[str]:
    return [step_label(s.oac.name, s.binding) for s in steps]


def test_liquids_in_each_others_cups_pour_both_before_the_mix_and_put_each_cup_down(tmp_path):
    adaptive = _adaptive(tmp_path, [("green_cup", "liquid_one"), ("red_cup", "liquid_two")])
    assert adaptive.repair(0, "precondition of dough not met")
    assert _labels(adaptive.queue) == [
        "grasp(left_hand, red_cup)",
        "pour(left_hand, red_cup, liquid_two, orange_bowl)",
        "place(left_hand, red_cup)",  # the plan needs it not; the demonstration puts the cup down
        "grasp(right_hand, green_cup)",
        "pour(right_hand, green_cup, liquid_one, orange_bowl)",
        "place(right_hand, green_cup)",
        "grasp(right_hand, mixer)",
        "mix(right_hand, mixer, orange_bowl)",
    ]
    skipped = [a["text"] for a in adaptive.adaptations if a["kind"] == "skipped"]
    assert skipped == [
        "skipped pour(left_hand, red_cup, liquid_one, orange_bowl): not needed from the observed state",
        "skipped pour(right_hand, green_cup, liquid_two, orange_bowl): not needed from the observed state",
    ]


def test_a_planned_order_the_demonstration_keeps_stays_and_nothing_needless_is_added(tmp_path):
    adaptive = _adaptive(tmp_path, [("red_cup", "liquid_one"), ("green_cup", "liquid_two")])
    state = adaptive.run.world.relations()
    plan = adaptive.demo[3:]  # the right hand's part only: the left's steps are not needed ...
    adaptive.goal = bind_atoms(plan[1].oac.effect, plan[1].binding)
    # ... and grasp(left_hand, red_cup), which applies from the start, is not added
    assert adaptive._in_demonstrated_order(state, plan) == plan


def test_a_step_standing_in_for_a_demonstrated_one_takes_its_place(tmp_path):
    adaptive = _adaptive(tmp_path, [])
    pour, mix = adaptive.demo[1], adaptive.demo[7]
    other = Step(pour.oac, {**pour.binding, "l": "liquid_two"})
    assert adaptive._rank(other) == 1  # the left hand's pour from the red cup, not the right's
    assert adaptive._rank(mix) == 7
    assert adaptive._rank(Step(adaptive.library.oacs["wipe"], {})) == -1
