"""The matcher: the paper's rule, the strict rule, ranking, explanations, apply."""

from __future__ import annotations

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from oacdsl.errors import MatchingError, UsageError
from oacdsl.matching import Matcher, apply_effects, holds, match_sub_action
from oacdsl.model import Atom, Oac, Param
from oacdsl.world import WorldState
from tests.kitchen import DOUGH_STATES, DOUGH_STEPS, GRASP, KITCHEN, OACS, atom, kitchen_library, state
from tests.random_cases import brute_force, cases


@pytest.fixture(scope="module")
def matcher() -> Matcher:
    return Matcher.from_library(kitchen_library(), KITCHEN)


@pytest.mark.parametrize("mode", ["strict", "paper"])
def test_dough_sub_actions_match_the_papers_oacs(matcher, mode):
    chosen = []
    for before, after in zip(DOUGH_STATES, DOUGH_STATES[1:], strict=False):
        result = matcher.match(before, after, mode=mode)
        assert len(result.matches) == 1, result.matches
        chosen.append(result.chosen.text())
    assert [c.split("(")[0] for c in chosen] == DOUGH_STEPS
    assert chosen[1] == "pour(h=left_hand, c=red_cup, l=liquid_one, b=orange_bowl)"
    assert chosen[6] == "grasp(h=right_hand, o=mixer)"


def test_paper_rule_accepts_an_oac_that_explains_nothing_strict_does_not(matcher):
    # The left hand keeps holding the red cup while the right hand grasps the mixer.
    before = state(("left_hand", "red_cup"))
    after = state(("left_hand", "red_cup"), ("right_hand", "mixer"))
    paper = {m.text() for m in matcher.match(before, after, mode="paper").matches}
    strict = {m.text() for m in matcher.match(before, after).matches}
    assert strict == {"grasp(h=right_hand, o=mixer)"} and strict <= paper
    # An OAC whose effect merely stays true: the paper's rule accepts it, the strict rule does not.
    idle = Oac(name="hold", params=(Param(name="h", cls="Hand"), Param(name="o", cls="Graspable")),
               pre=(atom("h", "o"),), effect=(atom("h", "o"),), skill="place")
    m = Matcher([*OACS, idle], kitchen_library().instance_classes(KITCHEN))
    assert "hold(h=left_hand, o=red_cup)" in {x.text() for x in m.match(before, after, mode="paper").matches}
    assert "hold(h=left_hand, o=red_cup)" not in {x.text() for x in m.match(before, after).matches}
    ranked = m.match(before, after, mode="paper")
    assert ranked.chosen.text() == "grasp(h=right_hand, o=mixer)"
    assert "explains 1 of 1 changed relations" in ranked.reason


def test_specificity_ranks_and_reason_names_it():
    lib = kitchen_library()
    grasp_cup = GRASP.model_copy(update={"name": "grasp_cup", "params": (Param(name="h", cls="Hand"),
                                                                         Param(name="o", cls="Cup"))})
    m = Matcher([*OACS, grasp_cup], lib.instance_classes(KITCHEN), ancestors=lib.ancestors)
    result = m.match(state(), state(("left_hand", "red_cup")))
    assert [x.text() for x in result.matches] == ["grasp_cup(h=left_hand, o=red_cup)",
                                                   "grasp(h=left_hand, o=red_cup)"]
    assert result.reason.startswith(
        "2 matches; chose grasp_cup(h=left_hand, o=red_cup): its classes are more specific")
    assert not result.ambiguous


def test_ties_are_reported_as_ambiguous():
    lib = kitchen_library()
    twin = GRASP.model_copy(update={"name": "take"})
    m = Matcher([*OACS, twin], lib.instance_classes(KITCHEN), ancestors=lib.ancestors)
    result = m.match(state(), state(("left_hand", "red_cup")))
    assert result.ambiguous and "ambiguous" in result.reason
    assert result.chosen.oac.name == "grasp"


def test_no_match_explains_the_failed_bound_condition(matcher):
    # The left hand holds the red cup and also touches the green cup: grasp needs a free hand.
    before = state(("left_hand", "red_cup"))
    after = state(("left_hand", "red_cup"), ("green_cup", "left_hand"))
    result = matcher.match(before, after)
    assert not result.matches and result.chosen is None
    best = result.near_misses[0]
    assert best.text() == ("grasp(h=left_hand, o=green_cup) fails 1 of 3 conditions: "
                           "pre left_hand <-> nothing does not hold before: left_hand touches red_cup")
    assert result.explanation.startswith(
        "no OAC matches (strict rule) the change +green_cup <-> left_hand; closest: "
        "grasp(h=left_hand, o=green_cup) fails 1 of 3")


def test_explanation_names_unaccounted_change_and_missing_class(matcher):
    result = matcher.match(DOUGH_STATES[0], DOUGH_STATES[2])  # grasp and pour merged
    assert "change liquid_one <-> orange_bowl started, but no effect states liquid_one <-> orange_bowl" in \
        result.explanation
    nothing = matcher.match(DOUGH_STATES[0], DOUGH_STATES[0])
    assert not nothing.matches and "nothing changed" in nothing.explanation
    from oacdsl.matching.explain import closest_binding
    wipe_co = next(c for c in matcher.compiled if c.oac.name == "wipe")
    miss = closest_binding(wipe_co, matcher._members, state(), state(), "strict")
    assert miss.failed == ("no instance of class Sponge for parameter s",)


def test_mode_and_classes_are_checked():
    with pytest.raises(UsageError, match="unknown matching mode 'lax'"):
        Matcher(OACS, {}, mode="lax")  # type: ignore[arg-type]
    with pytest.raises(UsageError):
        match_sub_action(state(), state(), OACS, KITCHEN)


def test_match_sub_action_with_classes_given_directly():
    classes = kitchen_library().instance_classes(KITCHEN)
    r = match_sub_action(state(), state(("right_hand", "mixer")), OACS, classes)
    assert r.chosen.text() == "grasp(h=right_hand, o=mixer)"
    r2 = match_sub_action(state(), state(("right_hand", "mixer")), kitchen_library(), KITCHEN)
    assert r2.chosen.text() == r.chosen.text()


def test_apply_effects_removes_first_then_adds():
    s = state(("left_hand", "red_cup"), ("left_hand", "green_cup"), ("liquid_one", "red_cup"))
    out = apply_effects(s, [Atom(left="left_hand", right="nothing"), Atom(left="left_hand", right="mixer"),
                            Atom(left="liquid_one", right="red_cup", negated=True),
                            Atom(left="mixer", right="nothing", negated=True)])
    assert out.sorted_relations() == [("left_hand", "mixer")]
    with pytest.raises(MatchingError, match="'ghost'"):
        apply_effects(s, [Atom(left="ghost", right="left_hand")])


def test_holds_semantics():
    s = WorldState.of(["a", "b", "c"], [("a", "b")])
    assert holds(Atom(left="c", right="nothing"), s)
    assert holds(Atom(left="a", right="nothing", negated=True), s)
    assert not holds(Atom(left="c", right="nothing", negated=True), s)
    assert holds(Atom(left="b", right="a"), s) and holds(Atom(left="a", right="c", negated=True), s)
    assert not holds(Atom(left="ghost", right="nothing"), s)


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(cases(constants=True), st.sampled_from(["strict", "paper"]))
def test_matcher_equals_brute_force(case, mode):
    library, scene, before, after = case
    classes = library.instance_classes(scene)
    m = Matcher.from_library(library, scene)
    got = {(x.oac.name, x.binding) for x in m.match(before, after, mode=mode, explain=False).matches}
    assert got == brute_force(library, classes, before, after, mode)


@settings(max_examples=80, deadline=None)
@given(cases(), st.sampled_from(["strict", "paper"]), st.randoms(use_true_random=False))
def test_results_do_not_depend_on_instance_names_or_pair_order(case, mode, rnd):
    library, scene, before, after = case
    names = [i.name for i in scene.instances]
    new = [f"n{k}" for k in range(len(names))]
    rnd.shuffle(new)
    ren = dict(zip(names, new, strict=True))
    scene2 = scene.model_copy(update={"instances": tuple(i.model_copy(update={"name": ren[i.name]})
                                                         for i in scene.instances)})

    def rename(s: WorldState) -> WorldState:  # pairs written the other way round
        return WorldState.of([ren[i] for i in s.instances], [(ren[b], ren[a]) for a, b in s.relations])

    def flipped(o: Oac) -> Oac:
        def f(a: Atom) -> Atom:
            return a if a.about_nothing else Atom(left=a.right, right=a.left, negated=a.negated)
        return o.model_copy(update={"pre": tuple(map(f, o.pre)), "effect": tuple(map(f, o.effect))})

    m1 = Matcher.from_library(library, scene)
    oacs2 = [flipped(o) for o in library.oacs.values()]
    m2 = Matcher(oacs2, library.instance_classes(scene2), ancestors=library.ancestors)
    r1 = m1.match(before, after, mode=mode)
    r2 = m2.match(rename(before), rename(after), mode=mode)
    one = {(x.oac.name, tuple((v, ren[i]) for v, i in x.binding)) for x in r1.matches}
    two = {(x.oac.name, x.binding) for x in r2.matches}
    assert one == two
    assert [len(n.failed) for n in r1.near_misses] == [len(n.failed) for n in r2.near_misses]


def test_explanation_search_is_bounded_and_says_so():
    from oacdsl.matching.explain import closest_binding

    lib = kitchen_library()
    m = Matcher.from_library(lib, KITCHEN)
    pour = next(c for c in m.compiled if c.oac.name == "pour")
    before, after = state(("left_hand", "mixer")), state(("left_hand", "mixer"), ("mixer", "red_cup"))
    full = closest_binding(pour, m._members, before, after, "strict")
    cut = closest_binding(pour, m._members, before, after, "strict", node_cap=5)
    assert not full.truncated and cut.truncated and "cut off" in cut.text()
    assert len(cut.failed) >= len(full.failed)
