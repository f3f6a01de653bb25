"""Differential test: the indexed matcher against the clingo (ASP) reference on random cases."""

from __future__ import annotations

from asp_matcher import AspTimes, asp_matches
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from oacdsl.matching import Matcher
from tests.kitchen import DOUGH_STATES, KITCHEN, kitchen_library
from tests.random_cases import cases, states


def ours(matcher: Matcher, pairs, mode) -> set:
    out = set()
    for s, (before, after) in enumerate(pairs):
        for co, b in matcher.raw_matches(before, after, mode):
            out.add((co.index, s, b[: co.n_params]))
    return out


def test_asp_reference_on_the_dough_demonstration():
    lib = kitchen_library()
    m = Matcher.from_library(lib, KITCHEN)
    pairs = list(zip(DOUGH_STATES, DOUGH_STATES[1:], strict=False))
    times = AspTimes()
    got = asp_matches(m.oacs, m.instance_classes, pairs, "strict", times)
    assert got == ours(m, pairs, "strict") and len(got) == 8
    assert times.total_s > 0
    names = sorted((s, m.oacs[k].name) for k, s, _ in got)
    assert [n for _, n in names] == ["grasp", "pour", "place", "grasp", "pour", "place", "grasp", "mix"]


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(cases(constants=True), st.data(), st.sampled_from(["strict", "paper"]))
def test_matcher_equals_clingo(case, data, mode):
    library, scene, before, after = case
    inst = sorted(before.instances)
    more = [(data.draw(states(inst)), data.draw(states(inst))) for _ in range(data.draw(st.integers(0, 3)))]
    pairs = [(before, after), *more]
    m = Matcher.from_library(library, scene)
    assert ours(m, pairs, mode) == asp_matches(m.oacs, m.instance_classes, pairs, mode)
