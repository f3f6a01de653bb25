"""Adaptive execution of the composed dough OAC (issue 22): the world decides which steps run."""

from __future__ import annotations

import functools
import shutil
from pathlib import Path

import pytest

pytest.importorskip("mujoco", reason="the robot runtime needs the 'robot' extra (mujoco)")
pytest.importorskip("placo", reason="the robot runtime needs the 'robot' extra (placo)")
pytest.importorskip("unified_planning", reason="replanning needs the 'plan' extra")

from oacdsl.compiler import load_library  # noqa: E402
from oacdsl.matching.conditions import bind_atoms, holds  # noqa: E402
from oacdsl.runtime.adaptive import run_adaptive  # noqa: E402
from oacdsl.runtime.executor import prepare, run_prepared  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]


@functools.cache
def _dough_text() -> str:
    import oacdsl

    demo = oacdsl.load_demonstration(str(ROOT / "data" / "dough.c3d"), str(ROOT / "library"))
    return oacdsl.compose(demo, "dough").text


@pytest.fixture
def dough_library(tmp_path: Path):
    folder = tmp_path / "library"
    shutil.copytree(ROOT / "library", folder)
    (folder / "learned").mkdir(exist_ok=True)
    (folder / "learned" / "dough.oac").write_text(_dough_text())
    return load_library([folder])


def _executed(result) -> list[str]:
    return [f"{s.oac}({', '.join(s.binding.values())})" for s in result.steps]


def _ends_with_the_demonstrated_effects(library, result, run) -> None:
    assert result.success, result.error
    final = result.states[-1]
    goal = bind_atoms(library.oacs["dough"].effect, run.binding)
    assert all(holds(a, final) for a in goal), final.sorted_relations()


@pytest.mark.slow
def test_liquid_one_already_in_the_bowl_skips_the_first_pour(dough_library, tmp_path):
    run = prepare(dough_library, "dough", scene="kitchen", fill={"liquid_one": "orange_bowl"})
    result = run_adaptive(run)
    _ends_with_the_demonstrated_effects(dough_library, result, run)
    assert not any(s.startswith("pour(left_hand, red_cup, liquid_one") for s in _executed(result))
    skipped = [a["text"] for a in result.adaptations if a["kind"] == "skipped"]
    assert any("pour(left_hand, red_cup, liquid_one, orange_bowl)" in t for t in skipped), result.adaptations
    assert "adaptations" in result.to_json()
    # the run store keeps them as `oacc run --db` records them, `oacc stats` lists them
    from oacdsl.stats import RunStore

    with RunStore(tmp_path / "runs.sqlite3") as store:
        store.record_run_json(result.to_json(), command="run")
        stored = store.adaptations("dough")
    assert [a["text"] for a in stored] == [a["text"] for a in result.adaptations]
    # the strict run stops where the demonstration no longer fits
    again = prepare(dough_library, "dough", scene="kitchen", fill={"liquid_one": "orange_bowl"})
    strict = run_prepared(again)
    assert not strict.success


@pytest.mark.slow
@pytest.mark.xfail(strict=True, reason="the left hand's pour of liquid_two from the red cup stops on the"
                   " right wrist (68 N into the orange bowl, after the mix; then 125 N into the green cup):"
                   " the run read as success only because the composed OAC's effects held already")
def test_liquids_in_each_others_cups_are_poured_from_the_cup_that_holds_them(dough_library):
    fill = {"liquid_one": "green_cup", "liquid_two": "red_cup"}
    run = prepare(dough_library, "dough", scene="kitchen", fill=fill)
    result = run_adaptive(run)
    _ends_with_the_demonstrated_effects(dough_library, result, run)
    pours = [s for s in result.steps if s.oac == "pour"]
    poured = {(s.binding["c"], s.binding["l"]) for s in pours}
    assert poured == {("green_cup", "liquid_one"), ("red_cup", "liquid_two")}
    assert any(a["kind"] == "replanned" for a in result.adaptations)


@pytest.mark.slow
def test_a_cup_dropped_during_the_carry_is_picked_up_again(dough_library):
    run = prepare(dough_library, "dough", scene="kitchen")
    dropped = []

    def drop(index, step, world):  # after the first grasp has lifted the red cup: let go of it
        if index == 0 and step.oac.name == "grasp":
            side = run.context.side(step.binding["h"])
            world.release(side)
            run.controller.open_hand(side)
            run.controller.wait(1.0)
            dropped.append(step.binding["o"])

    result = run_adaptive(run, fault=drop)
    assert dropped == ["red_cup"]
    _ends_with_the_demonstrated_effects(dough_library, result, run)
    # taken, dropped, taken again, and then the demonstration goes on in its order
    assert _executed(result) == [
        "grasp(left_hand, red_cup)",
        "grasp(left_hand, red_cup)",
        "pour(left_hand, red_cup, liquid_one, orange_bowl)",
        "place(left_hand, red_cup)",
        "grasp(right_hand, green_cup)",
        "pour(right_hand, green_cup, liquid_two, orange_bowl)",
        "place(right_hand, green_cup)",
        "grasp(right_hand, mixer)",
        "mix(right_hand, mixer, orange_bowl)",
    ]
    [replanned] = [a for a in result.adaptations if a["kind"] == "replanned"]
    assert "precondition of pour not met" in replanned["text"]


@pytest.mark.slow
@pytest.mark.parametrize(
    ("cup", "xy", "hand", "far"),
    [
        ("green_cup", (0.45, 0.62), "left_hand", "right_hand"),  # demonstrated: the right hand
        ("red_cup", (0.45, -0.62), "right_hand", "left_hand"),  # demonstrated: the left hand
    ],
)
def test_a_cup_only_the_other_hand_reaches_is_taken_by_it(dough_library, cup, xy, hand, far):
    run = prepare(dough_library, "dough", scene="kitchen", places={cup: xy})
    result = run_adaptive(run)
    _ends_with_the_demonstrated_effects(dough_library, result, run)
    executed = _executed(result)
    liquid = run.binding["liquid2" if cup == "green_cup" else "liquid1"]
    # the near hand takes, pours and puts down the cup, in the demonstration's order; the far
    # hand is never sent for it (no failed step, no safety stop)
    assert f"grasp({hand}, {cup})" in executed and f"grasp({far}, {cup})" not in executed
    assert f"pour({hand}, {cup}, {liquid}, orange_bowl)" in executed
    assert all(s.success for s in result.steps)
    assert executed.index(f"pour({hand}, {cup}, {liquid}, orange_bowl)") < executed.index(
        "mix(right_hand, mixer, orange_bowl)"
    )
    [chosen] = [a for a in result.adaptations if a["kind"] == "replanned"]
    assert f"{cup} is out of {far}'s reach" in chosen["text"] and f"{hand} takes it" in chosen["text"]


def test_the_other_hand_takes_the_steps_up_to_letting_go():
    """with_other_hand: the far hand's steps with the object become the other hand's, up to
    the step that lets go of it; what follows stays; a busy other hand gives None."""
    from oacdsl.runtime.binding import Step
    from oacdsl.runtime.reach import FarHand, with_other_hand

    lib = load_library([ROOT / "library"])
    oacs = lib.oacs
    right = "right_hand"
    steps = [
        Step(oacs["grasp"], {"h": right, "o": "green_cup"}),
        Step(oacs["pour"], {"h": right, "c": "green_cup", "l": "liquid_two", "b": "orange_bowl"}),
        Step(oacs["place"], {"h": right, "o": "green_cup"}),
        Step(oacs["grasp"], {"h": right, "o": "mixer"}),
    ]
    far = FarHand(right, "left_hand", "green_cup", "")
    got = with_other_hand(steps, far)
    assert got is not None
    assert [s.binding["h"] for s in got] == ["left_hand", "left_hand", "left_hand", right]
    assert got[1].binding["c"] == "green_cup"
    busy = [*steps[:1], Step(oacs["grasp"], {"h": "left_hand", "o": "red_cup"}), *steps[1:]]
    assert with_other_hand(busy, far) is None


@pytest.mark.slow
def test_a_cup_dropped_as_the_carry_to_the_bowl_begins_is_taken_again(dough_library):
    """The fault in the middle of a step: the left hand lets go of the red cup as the pour starts
    to carry it over the bowl. The pour fails (no ball in the bowl), the repair takes the cup
    again — with the left hand, the right's arm does not reach it — and the task goes on."""
    run = prepare(dough_library, "dough", scene="kitchen")
    dropped: list[float] = []

    class Drop:
        rate_hz = 50.0

        def __call__(self, world):
            if not dropped and run.controller.activity == "bringing red_cup over orange_bowl":
                world.release("l")
                dropped.append(world.time_s)

    run.controller.add_observer(Drop())
    result = run_adaptive(run)
    assert len(dropped) == 1
    _ends_with_the_demonstrated_effects(dough_library, result, run)
    executed = _executed(result)
    pour = "pour(left_hand, red_cup, liquid_one, orange_bowl)"
    assert executed[:2] == ["grasp(left_hand, red_cup)", pour] and not result.steps[1].success
    assert executed.count("grasp(left_hand, red_cup)") == 2 and result.steps[executed.index(pour, 2)].success
    assert "grasp(right_hand, red_cup)" not in executed
    replanned = [a["text"] for a in result.adaptations if a["kind"] == "replanned"]
    assert replanned[0].startswith(f"replanned after step 2 {pour} failed")


def test_max_repairs_is_checked_before_the_simulation(capsys):
    from oacdsl.cli import main

    assert main(["run", "dough", "--max-repairs", "-1", "--no-record"]) == 2
    assert capsys.readouterr().err.strip() == "oacc: error: --max-repairs: a whole number ≥ 0"
    assert main(["reproduce", "--max-repairs", "-2", "--no-record"]) == 2


def test_a_step_that_changes_nothing_by_design_is_never_skipped():
    """``keep`` (hold on: effect ``not h <-> nothing``, implied by its ``h <-> o``) runs even though
    its effect holds; ``dip_in`` whose ``l <-> b`` already holds is skipped (KIT Scoop: skipping
    its keeps merged the robot's changes and the run was not verified)."""
    from oacdsl.compiler import load_library
    from oacdsl.runtime.adaptive import _changes_nothing_by_design
    from oacdsl.runtime.binding import Step
    from oacdsl.world import WorldState

    lib = load_library([ROOT / "library" / "kit"])
    state = WorldState.of(["right_hand", "ladle", "bowl"], [("right_hand", "ladle"), ("ladle", "bowl")])
    keep = Step(lib.oacs["keep"], {"h": "right_hand", "o": "ladle"})
    dip = Step(lib.oacs["dip_in"], {"h": "right_hand", "l": "ladle", "b": "bowl"})
    assert _changes_nothing_by_design(keep, state)
    assert not _changes_nothing_by_design(dip, state)


@pytest.mark.slow
def test_a_hand_stated_to_hold_an_object_holds_it_when_the_run_starts(capsys):
    """``--state "mixer <-> right_hand"``: the hand grasps the mixer before the run (not part of
    it: the run's simulated time starts after), so that ``place`` can run at once."""
    import json

    from oacdsl.cli import main

    lib = load_library([ROOT / "library"])
    binding = {"h": "right_hand", "o": "mixer"}
    run = prepare(lib, "place", binding, scene="kitchen", held={"right_hand": "mixer"})
    assert run.world.relations().touches("mixer", "right_hand") and run.start_s > 0
    args = ["run", "place", "--bind", "h=right_hand", "--bind", "o=mixer", "--no-record", "--json"]
    assert main([*args, "--state", "mixer <-> right_hand"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["success"] and ["mixer", "nothing"] in doc["steps"][0]["observed"]
    assert doc["metrics"]["sim_time_s"] == pytest.approx(doc["steps"][0]["duration_s"], abs=0.5)
    assert main(args) == 1  # without it the hand holds nothing: place's precondition fails


def test_the_hands_are_exchanged_for_a_task_whose_objects_stand_on_the_other_arms_sides(dough_library):
    """exchanged_hands: the dough as demonstrated (each hand takes what stands on its side)
    keeps its hands; the same steps left-handed (a mirrored take in the same scene: the right
    hand sent for the red cup on the left, the left hand for the green cup and the mixer on the
    right) get both hands exchanged, every step of it."""
    from oacdsl.runtime.adaptive import _with_hands
    from oacdsl.runtime.reach import exchanged_hands

    run = prepare(dough_library, "dough", scene="kitchen")
    assert exchanged_hands(run.context, run.steps) is None
    swap = {"left_hand": "right_hand", "right_hand": "left_hand"}
    mirrored = _with_hands(run, swap)
    assert mirrored.steps[0].binding["h"] == "right_hand"  # grasp(hand1, red_cup), left-handed
    found = exchanged_hands(run.context, mirrored.steps)
    assert found is not None
    hands, text = found
    assert hands == swap and "exchanged" in text
    back = _with_hands(mirrored, hands)
    assert [s.binding for s in back.steps] == [s.binding for s in run.steps]
    assert back.binding == run.binding
