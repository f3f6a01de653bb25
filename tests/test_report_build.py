"""Helpers that assemble parts of the result dict."""

from oacdsl.model import Atom, Oac, Param
from oacdsl.report.build import bound_conditions, reliability_doc
from oacdsl.report.schema import MatchDoc
from oacdsl.stats import Outcome, RunStore

POUR = Oac(
    name="pour",
    params=(Param(name="h", cls="Hand"), Param(name="c", cls="Container"), Param(name="l", cls="Liquid"),
            Param(name="b", cls="Container")),
    pre=(Atom(left="h", right="c"), Atom(left="l", right="c")),
    effect=(Atom(left="l", right="b"), Atom(left="l", right="c", negated=True)),
    skill="pour",
)


def test_bound_conditions_replace_variables_and_sort_pairs():
    binding = {"h": "left_hand", "c": "red_cup", "l": "liquid_one", "b": "orange_bowl"}
    got = bound_conditions(POUR, binding)
    assert got == {
        "pre": [["left_hand", "red_cup"], ["liquid_one", "red_cup"]],
        "pre_not": [],
        "effect": [["liquid_one", "orange_bowl"]],
        "effect_not": [["liquid_one", "red_cup"]],
    }
    MatchDoc(oac="pour", binding=binding, **got)  # fits the schema


def test_bound_conditions_keep_nothing_on_the_right():
    grasp = Oac(name="grasp", params=(Param(name="h", cls="Hand"), Param(name="o", cls="Graspable")),
                pre=(Atom(left="h", right="nothing"),), effect=(Atom(left="h", right="o"),),
                skill="reach_and_grasp")
    got = bound_conditions(grasp, {"h": "right_hand", "o": "green_cup"})
    assert got["pre"] == [["right_hand", "nothing"]] and got["effect"] == [["green_cup", "right_hand"]]


def test_reliability_doc_reads_the_store(tmp_path):
    assert reliability_doc(tmp_path / "none.db") is None
    with RunStore(tmp_path / "r.db") as store:
        store.record(Outcome("grasp", {}, True, 1.0), [Outcome("pour", {}, False, 2.0, "spilled")])
    doc = reliability_doc(tmp_path / "r.db")
    assert doc is not None and doc["db"] == str(tmp_path / "r.db")
    assert [(o["oac"], o["runs"], o["successes"], o["last_failure"]) for o in doc["oacs"]] == [
        ("grasp", 1, 1, None), ("pour", 1, 0, "spilled")]
