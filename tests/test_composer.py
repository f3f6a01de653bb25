"""The composer: Algorithm 1 per relation, soundness, lifting, provenance."""

from __future__ import annotations

import pytest
from hypothesis import HealthCheck, assume, event, given, settings
from hypothesis import strategies as st

from oacdsl.errors import MatchingError
from oacdsl.library import Library
from oacdsl.matching import Matcher, apply_effects, atom_text, bind_atoms, holds
from oacdsl.matching.composer import Step, compose
from oacdsl.matching.lift import lift, snake
from oacdsl.model import Instance, Module, ObjectClass, Scene
from tests.kitchen import (
    CLASSES,
    DOUGH_STATES,
    DOUGH_STEPS,
    GRASP,
    KITCHEN,
    MIX,
    OACS,
    PLACE,
    POUR,
    kitchen_library,
    state,
)
from tests.random_cases import demonstrations, states_satisfying


def dough_steps() -> list[Step]:
    m = Matcher.from_library(kitchen_library(), KITCHEN)
    out = []
    for k, (before, after) in enumerate(zip(DOUGH_STATES, DOUGH_STATES[1:], strict=False)):
        chosen = m.match(before, after).chosen
        out.append(Step(chosen.oac, chosen.binding, before, after, k, 100 * k, 100 * k + 100))
    return out


def step(oac, k, before, after, **binding):
    return Step(oac, tuple((p.name, binding[p.name]) for p in oac.params), before, after, k)


def test_golden_dough_composition_is_the_papers():
    comp = compose("dough", dough_steps(), kitchen_library(), KITCHEN)
    doc = comp.to_json("library/learned/dough.oac")
    assert sorted(doc["pre"]) == [["green_cup", "liquid_two"], ["left_hand", "nothing"],
                                  ["liquid_one", "red_cup"], ["right_hand", "nothing"]]
    assert doc["effect"] == [["liquid_one", "orange_bowl"], ["liquid_two", "orange_bowl"],
                             ["mixer", "orange_bowl"], ["mixer", "right_hand"]]
    assert doc["ended"] == [["green_cup", "liquid_two"], ["liquid_one", "red_cup"]]
    assert [s["oac"] for s in doc["steps"]] == DOUGH_STEPS
    assert doc["steps"][7]["binding"] == {"h": "right_hand", "m": "mixer", "b": "orange_bowl"}
    assert set(doc) == {"name", "pre", "effect", "ended", "steps", "file"}
    oac = comp.oac
    assert [(p.name, p.cls, p.default) for p in oac.params] == [
        ("hand1", "Hand", "left_hand"), ("cup1", "Cup", "red_cup"), ("liquid1", "Liquid", "liquid_one"),
        ("bowl", "Bowl", "orange_bowl"), ("hand2", "Hand", "right_hand"), ("cup2", "Cup", "green_cup"),
        ("liquid2", "Liquid", "liquid_two"), ("mixer", "Mixer", "mixer")]
    assert [atom_text(a) for a in oac.pre] == ["cup1 <-> liquid1", "cup2 <-> liquid2", "hand1 <-> nothing",
                                               "hand2 <-> nothing"]
    assert {atom_text(a) for a in oac.effect} == {
        "bowl <-> liquid1", "bowl <-> liquid2", "bowl <-> mixer", "hand2 <-> mixer",
        "not cup1 <-> liquid1", "not cup2 <-> liquid2"}
    assert [f"{c.oac}({', '.join(c.args)})" for c in oac.steps][:3] == [
        "grasp(hand1, cup1)", "pour(hand1, cup1, liquid1, bowl)", "place(hand1, cup1)"]
    assert not comp.warnings


def test_provenance_and_the_second_grasp_adds_no_precondition():
    comp = compose("dough", dough_steps(), kitchen_library(), KITCHEN)
    notes = {atom_text(a): a.note for a in (*comp.oac.pre, *comp.oac.effect)}
    # grasp(right_hand, mixer), step 7, follows place(right_hand, green_cup): established.
    assert notes["hand2 <-> nothing"] == "step 4 grasp, keyframe 3, frame 300"
    assert notes["cup1 <-> liquid1"] == "step 2 pour, keyframe 1, frame 100"
    assert notes["hand2 <-> mixer"] == "step 7 grasp, keyframe 7, frame 700"
    assert notes["bowl <-> mixer"] == "step 8 mix, keyframe 8, frame 800"
    records = {(r["kind"], tuple(r["relation"]), r["negated"]): (r["step"], r["keyframe"])
               for r in comp.provenance}
    assert records[("pre", ("right_hand", "nothing"), False)] == (3, 3)
    assert records[("effect", ("mixer", "orange_bowl"), False)] == (7, 8)
    assert records[("effect", ("liquid_one", "red_cup"), True)] == (1, 2)
    assert records[("ended", ("green_cup", "liquid_two"), False)] == (4, 5)
    assert len(records) == 4 + 6 + 2


def test_paper_effects_view_and_its_warning():
    comp = compose("dough", dough_steps(), kitchen_library(), KITCHEN, paper_effects=True)
    assert {atom_text(a) for a in comp.effect} == {
        "liquid_one <-> orange_bowl", "liquid_two <-> orange_bowl", "mixer <-> orange_bowl",
        "mixer <-> right_hand"}
    assert any("not sound" in w for w in comp.warnings)


def test_a_removed_relation_a_later_step_needs_is_an_error_naming_both_steps():
    s0 = state(("left_hand", "red_cup"), ("liquid_one", "red_cup"))
    s1 = state(("liquid_one", "red_cup"))
    s2 = state(("liquid_one", "orange_bowl"))
    steps = [step(PLACE, 0, s0, s1, h="left_hand", o="red_cup"),
             step(POUR, 1, s1, s2, h="left_hand", c="red_cup", l="liquid_one", b="orange_bowl")]
    with pytest.raises(MatchingError) as e:
        compose("bad", steps, kitchen_library(), KITCHEN)
    assert str(e.value) == (
        "step 2 pour(h=left_hand, c=red_cup, l=liquid_one, b=orange_bowl) needs left_hand <-> red_cup,"
        " but step 1 place(h=left_hand, o=red_cup) removed it (effect left_hand <-> nothing)")


def test_an_effect_overwritten_later_keeps_the_last_writer():
    s0, s1 = state(), state(("left_hand", "red_cup"))
    steps = [step(GRASP, 0, s0, s1, h="left_hand", o="red_cup"),
             step(PLACE, 1, s1, s0, h="left_hand", o="red_cup"),
             step(GRASP, 2, s0, s1, h="left_hand", o="red_cup")]
    comp = compose("regrasp", steps, kitchen_library(), KITCHEN)
    assert [atom_text(a) for a in comp.pre] == ["left_hand <-> nothing"]
    assert [(atom_text(a), a.note) for a in comp.effect] == [
        ("left_hand <-> red_cup", "step 3 grasp, keyframe 3")]


def test_a_hand_holding_something_at_the_start_is_an_assumption_with_a_warning():
    s0 = state(("green_cup", "right_hand"))
    s1, s2 = state(), state(("mixer", "right_hand"))
    steps = [step(PLACE, 0, s0, s1, h="right_hand", o="green_cup"),
             step(GRASP, 1, s1, s2, h="right_hand", o="mixer"),
             step(MIX, 2, s2, state(("mixer", "right_hand"), ("mixer", "orange_bowl")),
                  h="right_hand", m="mixer", b="orange_bowl")]
    comp = compose("swap", steps, kitchen_library(), KITCHEN)
    assert [atom_text(a) for a in comp.pre] == ["green_cup <-> right_hand"]
    assert {atom_text(a) for a in comp.effect} == {"not green_cup <-> right_hand", "mixer <-> right_hand",
                                                   "mixer <-> orange_bowl"}
    assert len(comp.warnings) == 1
    assert "assumes right_hand touches nothing else at the start" in comp.warnings[0]


def test_lifting_picks_the_most_specific_class_that_fits_every_step():
    lib = kitchen_library()
    classes = lib.instance_classes(KITCHEN)
    params, names = lift(["red_cup", "left_hand"], classes, {"red_cup": ["Graspable", "Container"]},
                         lib.ancestors)
    assert [(p.name, p.cls, p.default) for p in params] == [("cup", "Cup", "red_cup"),
                                                           ("hand", "Hand", "left_hand")]
    odd = Scene(name="odd", instances=(Instance(name="thing", classes=("Graspable", "Container")),))
    lib2 = Library([Module(path="x", decls=(*CLASSES, odd))])
    with pytest.raises(MatchingError, match="instance thing is bound as Container, Graspable"):
        lift(["thing"], lib2.instance_classes(odd), {"thing": ["Graspable", "Container"]}, lib2.ancestors)
    assert snake("GraspableObject") == "graspable_object"
    grasp_cls = ObjectClass(name="Grasp")
    lib3 = Library([Module(path="x", decls=(grasp_cls,))])
    params, _ = lift(["g"], {"g": frozenset({"Grasp"})}, {}, lib3.ancestors)
    assert params[0].name == "grasp1"  # a keyword is never a parameter name


def test_composition_does_not_depend_on_instance_names():
    ren = {i.name: f"x_{k}" for k, i in enumerate(reversed(KITCHEN.instances))}
    scene2 = KITCHEN.model_copy(update={"instances": tuple(i.model_copy(update={"name": ren[i.name]})
                                                           for i in KITCHEN.instances)})
    lib = kitchen_library()

    def rn(s):
        return type(s).of([ren[i] for i in s.instances], [(ren[a], ren[b]) for a, b in s.relations])

    steps2 = [Step(s.oac, tuple((v, ren[i]) for v, i in s.binding), rn(s.before), rn(s.after), s.index)
              for s in dough_steps()]
    one = compose("dough", dough_steps(), lib, KITCHEN).oac
    two = compose("dough", steps2, lib, scene2).oac
    assert one.pre == two.pre and one.effect == two.effect and one.steps == two.steps
    assert [(p.name, p.cls, ren[p.default]) for p in one.params] == [
        (p.name, p.cls, p.default) for p in two.params]


def test_nothing_to_compose():
    with pytest.raises(MatchingError, match="no sub-actions"):
        compose("x", [], kitchen_library(), KITCHEN)
    assert OACS  # the fixture library is in use


@settings(max_examples=100, deadline=None,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])
@given(demonstrations(), st.data())
def test_composition_is_sound(demo, data):
    library, scene, steps = demo
    assume(steps)
    try:
        comp = compose("c", steps, library, scene)
    except MatchingError as error:
        event(f"not composable: {str(error).split(',')[0][:40]}")
        assume(False)
        return
    event("with assumptions" if comp.warnings else "sound")
    # The composition holds on its own demonstration.
    assert all(holds(a, steps[0].before) for a in comp.pre)
    assert apply_effects(steps[0].before, comp.effect) == steps[-1].after
    if comp.warnings:
        return
    instances = sorted(steps[0].before.instances)
    for _ in range(5):
        s = data.draw(states_satisfying(instances, comp.pre))
        if s is None:
            continue
        current = s
        for st_ in steps:
            mapping = st_.mapping
            assert all(holds(a, current) for a in bind_atoms(st_.oac.pre, mapping)), (st_.text(), current)
            current = apply_effects(current, bind_atoms(st_.oac.effect, mapping))
        assert apply_effects(s, comp.effect) == current
