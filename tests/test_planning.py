"""The library as a planning domain: PDDL export, planning with two engines, replay by the
matcher's semantics, goals and why a goal has no plan."""

from __future__ import annotations

import functools
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from oacdsl.cli import main
from oacdsl.compiler import load_library
from oacdsl.compiler.loader import compile_sources
from oacdsl.errors import PlanningError, UsageError
from oacdsl.library import Library
from oacdsl.matching.conditions import holds
from oacdsl.model import atom_text
from oacdsl.planning import (
    domain_text,
    goal_task,
    parse_atoms,
    plan_goal,
    problem_text,
    replay,
    scene_state,
    stated,
)
from oacdsl.planning.engines import PlannedStep
from oacdsl.world import WorldState

pytest.importorskip("unified_planning")

DOUGH_GOAL = "liquid_one <-> orange_bowl, liquid_two <-> orange_bowl, mixer <-> orange_bowl"


@functools.cache
def library() -> Library:
    return load_library(["library"])


def kitchen():
    return library().scenes["kitchen"]


def test_scene_state_is_the_scenes_fills_and_leaves_out_the_environment():
    state = scene_state(kitchen())
    assert "table" not in state.instances
    assert state.sorted_relations() == [("green_cup", "liquid_two"), ("liquid_one", "red_cup")]
    assert state.touches_nothing("mixer")


def test_pddl_is_read_back_by_the_pddl_package(tmp_path: Path):
    from pddl import parse_domain, parse_problem

    out = tmp_path / "out"
    assert main(["pddl", "library", "--scene", "kitchen", "--goal", DOUGH_GOAL, "-o", str(out)]) == 0
    domain = parse_domain(out / "domain.pddl")
    problem = parse_problem(out / "problem.pddl")
    assert sorted(a.name for a in domain.actions) == ["grasp", "mix", "place", "pour"]  # no sponge: no wipe
    assert sorted(o.name for o in problem.objects) == sorted(scene_state(kitchen()).instances)
    init = {str(f) for f in problem.init}
    # touching is symmetric, classes are inherited
    assert "(touching liquid_one red_cup)" in init and "(touching red_cup liquid_one)" in init
    assert "(is-graspable red_cup)" in init and "(is-container red_cup)" in init
    assert "(is-tool mixer)" in init
    before = (out / "domain.pddl").read_bytes(), (out / "problem.pddl").read_bytes()
    assert main(["pddl", "library", "--scene", "kitchen", "--goal", DOUGH_GOAL, "-o", str(out)]) == 0
    assert ((out / "domain.pddl").read_bytes(), (out / "problem.pddl").read_bytes()) == before


def test_the_encoding_follows_the_matchers_semantics():
    task = goal_task(library(), kitchen(), scene_state(kitchen()), parse_atoms("mixer <-> nothing"))
    domain = domain_text(task)
    place = domain[domain.index("(:action place") :]
    # 'h <-> nothing' as an effect takes every relation of h away, in both orders
    assert "(forall (?other - instance) (and (not (touching ?h ?other)) (not (touching ?other ?h))))" in place
    grasp = domain[domain.index("(:action grasp") : domain.index("(:action mix")]
    assert "(forall (?other - instance) (not (touching ?h ?other)))" in grasp  # pre h <-> nothing
    assert "(not (= ?h ?o))" in grasp  # bindings are injective
    assert "(forall (?other0 - instance) (not (touching mixer ?other0)))" in problem_text(task)


def test_goal_atoms_are_parsed_with_the_languages_syntax():
    atoms = parse_atoms("orange_bowl <-> liquid_one, not mixer <-> nothing")
    assert [atom_text(a) for a in atoms] == ["liquid_one <-> orange_bowl", "not mixer <-> nothing"]
    with pytest.raises(UsageError, match=r"^--goal:1:12: "):
        parse_atoms("liquid_one <- mixer")


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("mixer <->", "--goal:1:10: the text ends, expected an object or 'nothing' after '<->'"),
        ("not", "--goal:1:4: the text ends, expected an object after 'not'"),
        ("a <-> b c", "--goal:1:9: unexpected 'c', expected ',' and another relation"),
        ("a <-> b effect c <-> d", "--goal:1:9: unexpected 'effect', expected ',' and another relation"),
        ("a <-> b execute x", "--goal:1:9: unexpected 'execute', expected ',' and another relation"),
        ("a <-> b }", "--goal:1:9: unexpected '}', expected ',' and another relation"),
        ("a <-> b,, c <-> d", "--goal:1:9: unexpected ',', expected a relation such as 'h <-> o'"),
    ],
)
def test_a_goal_that_is_not_only_atoms_is_refused_at_its_column(text, message):
    """Nothing of an OAC around the atoms shows (no 'effect', 'execute SKILL' expected), and
    nothing after them is taken for another part of an OAC (``effect c <-> d`` was dropped)."""
    with pytest.raises(UsageError) as caught:
        parse_atoms(text)
    assert str(caught.value).startswith(message)


def test_repeated_goal_atoms_are_one_and_columns_point_at_each_atom():
    atoms = parse_atoms("b <-> a, a <-> b,  not x <-> nothing,")
    assert [atom_text(a) for a in atoms] == ["a <-> b", "not x <-> nothing"]
    assert [a.span.column for a in atoms] == [1, 20]


def test_unknown_instances_are_one_line_with_did_you_mean(capsys):
    assert main(["plan", "--scene", "kitchen", "--goal", "mixer <-> orange_bowl, liquid_on <-> mixer"]) == 2
    err = capsys.readouterr().err.strip()
    assert err == (
        "oacc: error: --goal:1:24: no instance 'liquid_on' in the scene (did you mean 'liquid_one'?)"
    )
    assert main(["plan", "--scene", "kitchn", "--goal", "mixer <-> orange_bowl"]) == 2
    assert "did you mean 'kitchen'" in capsys.readouterr().err


def test_stated_relations_change_the_start_and_are_checked():
    state = stated(scene_state(kitchen()), parse_atoms("mixer <-> right_hand, not liquid_one <-> red_cup"))
    assert state.touches("mixer", "right_hand") and not state.touches("liquid_one", "red_cup")
    with pytest.raises(UsageError, match="contradict"):
        stated(scene_state(kitchen()), parse_atoms("mixer <-> right_hand, mixer <-> nothing"))


def test_a_plan_replayed_by_the_matchers_semantics_reaches_the_goal():
    goal = parse_atoms(DOUGH_GOAL)
    result = plan_goal(library(), kitchen(), scene_state(kitchen()), goal)
    assert result.plan
    states = replay(library(), scene_state(kitchen()), result.plan)
    assert all(holds(a, states[-1]) for a in goal)
    # and a wrong plan is caught by the replay
    binding = {"h": "left_hand", "c": "red_cup", "l": "liquid_one", "b": "orange_bowl"}
    bad = [PlannedStep("pour", binding, "pour")]
    with pytest.raises(PlanningError, match=r"step 1 pour\(.*left_hand <-> red_cup"):
        replay(library(), scene_state(kitchen()), bad)


def test_no_plan_names_the_unreachable_atoms(capsys):
    code = main(["plan", "--goal", "liquid_one <-> mixer, mixer <-> orange_bowl", "--scene", "kitchen"])
    out = capsys.readouterr()
    assert code == 1
    assert "liquid_one <-> mixer: no OAC of the library makes liquid_one <-> mixer true" in out.out
    assert "mixer <-> orange_bowl" not in out.out.split("\n", 1)[1]  # reachable: not listed
    assert out.err.startswith("oacc: error: no plan: ")


def test_unreachable_because_a_precondition_never_holds():
    # a bowl is no Graspable: no hand ever holds it, so nothing is poured out of it
    lib = _library_with("hand : Hand\nred_cup : Cup\nliquid_one : Liquid\norange_bowl : Bowl\n"
                        "liquid_one in orange_bowl")
    scene = lib.scenes["s"]
    result = plan_goal(lib, scene, scene_state(scene), parse_atoms("liquid_one <-> red_cup"))
    assert result.plan is None
    [(atom, why)] = result.unreachable
    assert why == "pour(hand, orange_bowl, liquid_one, red_cup) needs hand <-> orange_bowl, which never holds"


def test_unreachable_because_the_scene_cannot_bind_an_oac():
    lib = _library_with("red_cup : Cup\nliquid_one : Liquid\norange_bowl : Bowl\nliquid_one in red_cup")
    scene = lib.scenes["s"]
    result = plan_goal(lib, scene, scene_state(scene), parse_atoms("liquid_one <-> orange_bowl"))
    [(atom, why)] = result.unreachable
    assert "pour needs a Hand, which the scene has none of" in why


def _library_with(scene: str) -> Library:
    actions = Path("library/actions.oac").read_text()
    classes = Path("library/classes.oac").read_text()
    text = "scene s {\n" + scene + "\n}\n"
    return Library(compile_sources({"a.oac": actions, "c.oac": classes, "s.oac": text}).modules)


def test_jointly_unreachable_goal_says_so():
    # one hand: it cannot hold the mixer and a cup at once, each alone is reachable
    lib = _library_with("hand : Hand\ncup : Cup\nmixer : Mixer")
    scene = lib.scenes["s"]
    result = plan_goal(lib, scene, scene_state(scene), parse_atoms("hand <-> cup, hand <-> mixer"))
    assert result.plan is None and result.unreachable == []
    assert "not all of them together" in result.why


@pytest.mark.slow
def test_the_dough_goal_from_the_composed_oac_is_planned_from_the_scene():
    import oacdsl

    demo = oacdsl.load_demonstration("data/dough.c3d", "library")
    dough = oacdsl.compose(demo, "dough").oac
    binding = {p.name: p.default for p in dough.params}
    from oacdsl.matching.conditions import bind_atoms

    goal = bind_atoms(dough.effect, binding)
    start = scene_state(kitchen())
    assert all(holds(a, start) for a in bind_atoms(dough.pre, binding))
    for engine in ("fast-downward", "pyperplan"):
        result = plan_goal(library(), kitchen(), start, goal, engine)
        assert result.plan is not None
        assert all(holds(a, result.states[-1]) for a in goal)
        assert len(result.plan) <= len(dough.steps or ())


# --- generated problems: both engines find shortest plans of the same length -------------------

_CLASSES = Path("library/classes.oac").read_text()
_ACTIONS = Path("library/actions.oac").read_text()


@st.composite
def problems(draw):
    hands = draw(st.integers(1, 2))
    cups = draw(st.integers(1, 2))
    liquids = draw(st.integers(0, 2))
    bowl = draw(st.booleans())
    mixer = draw(st.booleans())
    names = {f"hand{i}": "Hand" for i in range(hands)} | {f"cup{i}": "Cup" for i in range(cups)}
    names |= {f"liquid{i}": "Liquid" for i in range(liquids)}
    if bowl:
        names["bowl"] = "Bowl"
    if mixer:
        names["mixer"] = "Mixer"
    containers = [n for n, c in names.items() if c in ("Cup", "Bowl")]
    fills = [f"liquid{i} in {draw(st.sampled_from(containers))}" for i in range(liquids)]
    lines = [f"{n} : {c}" for n, c in names.items()] + fills
    scene = "scene gen {\n" + "\n".join(lines) + "\n}"
    lib = Library(compile_sources({"a.oac": _ACTIONS, "c.oac": _CLASSES, "s.oac": scene}).modules)
    sc = lib.scenes["gen"]
    pairs = [(a, b) for a in sorted(names) for b in sorted(names) if a < b]
    chosen = draw(st.lists(st.sampled_from(pairs), min_size=1, max_size=3, unique=True))
    negated = draw(st.lists(st.booleans(), min_size=len(chosen), max_size=len(chosen)))
    goal = ", ".join(f"{'not ' if n else ''}{a} <-> {b}" for (a, b), n in zip(chosen, negated, strict=True))
    return lib, sc, parse_atoms(goal)


@pytest.mark.slow
@settings(max_examples=12, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(problems())
def test_fast_downward_and_pyperplan_plans_have_the_same_length(problem):
    lib, scene, goal = problem
    start: WorldState = scene_state(scene)
    fd = plan_goal(lib, scene, start, goal, "fast-downward", optimal=True)
    pp = plan_goal(lib, scene, start, goal, "pyperplan", optimal=True)
    assert (fd.plan is None) == (pp.plan is None), (fd.why if fd.plan is None else pp.why)
    if fd.plan is not None and pp.plan is not None:
        assert len(fd.plan) == len(pp.plan)
        for result in (fd, pp):  # replayed by the matcher's semantics (plan_goal does), the goal holds
            assert all(holds(a, result.states[-1]) for a in goal)


def test_oacc_run_state_sets_up_a_liquid_in_a_container_or_a_held_object_and_refuses_the_rest():
    from oacdsl.planning.state import state_as_setup

    fills, held = state_as_setup(library(), kitchen(), "orange_bowl <-> liquid_one, liquid_two <-> red_cup")
    assert fills == {"liquid_one": "orange_bowl", "liquid_two": "red_cup"} and held == {}
    fills, held = state_as_setup(library(), kitchen(), "liquid_one <-> red_cup, mixer <-> right_hand")
    assert fills == {"liquid_one": "red_cup"} and held == {"right_hand": "mixer"}
    with pytest.raises(UsageError, match=r"^--state:1:1: the simulation can start a liquid in a container"):
        state_as_setup(library(), kitchen(), "red_cup <-> orange_bowl")
    with pytest.raises(UsageError, match=r"^--state:1:1: the simulation can start"):
        state_as_setup(library(), kitchen(), "left_hand <-> right_hand")
    with pytest.raises(UsageError, match=r"^--state:1:23: a hand holds one object, an object one hand"):
        state_as_setup(library(), kitchen(), "mixer <-> right_hand, red_cup <-> right_hand")
    with pytest.raises(UsageError, match="did you mean 'orange_bowl'"):
        state_as_setup(library(), kitchen(), "liquid_one <-> orange_bow")


def test_the_planner_leaves_nothing_in_the_working_folder(tmp_path, monkeypatch):
    lib, scene = library(), kitchen()  # read before leaving the repository's folder
    monkeypatch.chdir(tmp_path)
    result = plan_goal(lib, scene, scene_state(scene), parse_atoms("mixer <-> orange_bowl"))
    assert result.plan is not None and len(result.plan) == 2
    assert list(tmp_path.iterdir()) == []  # Fast Downward's output.sas went to a folder of its own


def test_a_bad_from_document_is_one_line(tmp_path, capsys):
    goal = ["plan", "--scene", "kitchen", "--goal", "mixer <-> orange_bowl", "--from"]
    cases = {
        "cut.json": ('{"steps": [', ":1:12: not JSON: Expecting value"),
        "deep.json": ("[" * 50_000 + "]" * 50_000, ": nested too deeply; not a run document"),
        "empty_run.json": ('{"steps": []}', ": no executed steps to take the world state from"),
    }
    for name, (text, message) in cases.items():
        (tmp_path / name).write_text(text, encoding="utf-8")
        assert main([*goal, str(tmp_path / name)]) == 2
        err = capsys.readouterr().err
        assert err.splitlines() == [f"oacc: error: {tmp_path / name}{message}"], err
    assert main([*goal, str(tmp_path / "missing.json")]) == 2
    assert capsys.readouterr().err.strip() == f"oacc: error: {tmp_path / 'missing.json'}: no such file"
