"""Planning in a sub-task (the goal's instances, what touches them, spares of each class) and
Fast Downward run on the PDDL files directly."""

from __future__ import annotations

from pathlib import Path

import pytest

from oacdsl.compiler.loader import compile_sources
from oacdsl.library import Library
from oacdsl.matching.conditions import holds
from oacdsl.planning import engines as engines_module
from oacdsl.planning import goal_task, parse_atoms, plan_goal, scene_state
from oacdsl.planning.subtask import sub_task

pytest.importorskip("up_fast_downward")

ROOT = Path(__file__).resolve().parents[1]

SCENE = """scene many {
    left_hand, right_hand : Hand
    cup0 : Cup
    cup1 : Cup
    cup2 : Cup
    cup3 : Cup
    cup4 : Cup
    liquid0 : Liquid
    liquid1 : Liquid
    liquid2 : Liquid
    bowl0 : Bowl
    bowl1 : Bowl
    bowl2 : Bowl
    mixer0 : Mixer
    mixer1 : Mixer
    sponge0 : Sponge
    tray0 : Tray
    liquid0 in cup0
    liquid1 in cup1
    liquid2 in cup2
}
"""


def _library() -> Library:
    sources = {
        "actions.oac": (ROOT / "library" / "actions.oac").read_text(),
        "classes.oac": (ROOT / "library" / "classes.oac").read_text(),
        "many.oac": SCENE,
    }
    return Library(compile_sources(sources).modules)


def _task(goal: str, state_text: str = ""):
    lib = _library()
    scene = lib.scenes["many"]
    start = scene_state(scene)
    if state_text:
        from oacdsl.planning import stated

        start = stated(start, parse_atoms(state_text, "--state"))
    return lib, scene, start, goal_task(lib, scene, start, parse_atoms(goal))


def test_the_sub_task_keeps_the_goal_what_touches_it_and_two_of_each_class():
    _, _, _, task = _task("liquid0 <-> bowl0")
    part = sub_task(task)
    assert part is not None
    kept = set(part.classes)
    assert {"liquid0", "cup0", "bowl0"} <= kept  # the goal's, and the cup liquid0 is in
    assert {"left_hand", "right_hand"} <= kept  # two hands (the scene's only two)
    # a second liquid (every liquid is in a cup: liquid1, with its cup), not a third
    assert {"liquid1", "cup1"} <= kept and "liquid2" not in kept and "cup2" not in kept
    assert "sponge0" in kept and "mixer1" in kept and "bowl2" not in kept
    for cls in ("Cup", "Container", "Mixer", "Liquid", "Graspable"):
        assert sum(cls in part.classes[i] for i in kept) >= 2, cls
    # cups that touch nothing are the spares, not the ones holding another liquid
    assert {"cup3"} <= kept
    # the sub-task never splits a relation of the start
    assert all((a in kept) == (b in kept) for a, b in task.init.relations)


def test_what_touches_a_kept_instance_is_kept_with_it():
    _, _, _, task = _task("left_hand <-> nothing", "left_hand <-> cup4")
    part = sub_task(task)
    assert part is not None and "cup4" in part.classes
    assert part.init.touches("left_hand", "cup4")


def test_a_scene_as_small_as_its_sub_task_is_planned_whole():
    _, _, _, task = _task("liquid0 <-> bowl0")
    part = sub_task(task)
    assert part is not None and sub_task(part) is None


def test_the_sub_tasks_plan_is_a_plan_of_the_whole_scene():
    lib, scene, start, _ = _task("liquid0 <-> bowl0")
    goal = parse_atoms("liquid0 <-> bowl0, mixer0 <-> bowl1, left_hand <-> nothing")
    result = plan_goal(lib, scene, start, goal)
    assert result.plan is not None  # plan_goal replays it on the whole state by the matcher's semantics
    assert all(holds(a, result.states[-1]) for a in result.goal)
    assert result.states[-1].touches("liquid1", "cup1")  # what the sub-task left out is as it was


def test_when_the_sub_task_has_no_plan_the_whole_task_is_planned(monkeypatch):
    lib, scene, start, _ = _task("liquid0 <-> bowl0")
    tried = []

    def without_hands(task, spares=2):  # a sub-task that cannot have a plan: no hand in it
        part = sub_task(task, spares=0)
        tried.append(part)
        return part

    monkeypatch.setattr(engines_module, "sub_task", without_hands)
    result = plan_goal(lib, scene, start, parse_atoms("liquid0 <-> bowl0"))
    assert tried and tried[0] is not None and "left_hand" not in tried[0].classes
    assert result.plan is not None and [s.oac for s in result.plan] == ["grasp", "pour"]


def test_optimal_planning_uses_the_whole_task(monkeypatch):
    lib, scene, start, _ = _task("liquid0 <-> bowl0")

    def refuse(task, spares=2):
        raise AssertionError("an optimal plan must not come from a sub-task")

    monkeypatch.setattr(engines_module, "sub_task", refuse)
    result = plan_goal(lib, scene, start, parse_atoms("liquid0 <-> bowl0"), optimal=True)
    assert result.plan is not None and len(result.plan) == 2


def test_fast_downward_failing_is_one_line(monkeypatch):
    from oacdsl.errors import PlanningError
    from oacdsl.planning import downward

    _, _, _, task = _task("liquid0 <-> bowl0")
    with pytest.raises(PlanningError, match=r"^fast-downward failed \(exit \d+\): "):
        downward.run(task, "no_such_search()")
