"""Emission: canonical text, compiles with the library, no duplicates, atomic writes, drafts."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest
from hypothesis import HealthCheck, assume, given, settings

from oacdsl.compiler import compile_paths, load_library, parse_text
from oacdsl.errors import LanguageError, MatchingError
from oacdsl.matching import Matcher
from oacdsl.matching.composer import Step, compose
from oacdsl.matching.drafts import PLACEHOLDER_SKILL, propose_draft
from oacdsl.matching.emit import FINGERPRINT, differences, emit, library_files, render, unedited
from oacdsl.model import Call, Oac
from tests.kitchen import DOUGH_STATES, state
from tests.random_cases import demonstrations

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture
def lib_dir(tmp_path: Path) -> Path:
    # learned/ and drafts/ hold what earlier runs wrote (oacc reproduce, oacc compose): not the test's
    skip = shutil.ignore_patterns("learned", "drafts")
    shutil.copytree(ROOT / "library", tmp_path / "library", ignore=skip)
    return tmp_path / "library"


def dough(library_dir: Path) -> Oac:
    lib = load_library([library_dir])
    scene = lib.scenes["kitchen"]
    m = Matcher.from_library(lib, scene)
    steps = []
    for k, (before, after) in enumerate(zip(DOUGH_STATES, DOUGH_STATES[1:], strict=False)):
        c = m.match(before, after).chosen
        steps.append(Step(c.oac, c.binding, before, after, k, 150 * k, 150 * k + 150))
    return compose("dough", steps, lib, scene).oac


def test_emit_writes_canonical_text_that_compiles_and_parses_back(lib_dir):
    oac = dough(lib_dir)
    target = lib_dir / "learned" / "dough.oac"
    e = emit([oac], target, library=lib_dir, header=["Composed from the dough demonstration."])
    assert e.status == "written" and target.read_text() == e.text
    fingerprint, rest = e.text.split("\n", 1)
    assert fingerprint.startswith(FINGERPRINT)
    assert rest.startswith("# Composed from the dough demonstration.\noac dough(\n")
    assert "cup1 <-> liquid1,  # step 2 pour, keyframe 1, frame 150" in e.text
    lib = load_library([lib_dir])
    assert lib.oacs["dough"] == oac and lib.oacs["dough"].pre[0].note is not None
    assert compile_paths([lib_dir]).diagnostics == []
    assert [p.name for p in target.parent.iterdir()] == ["dough.oac"]  # no temporary file left


def test_same_demonstration_again_changes_nothing(lib_dir):
    oac = dough(lib_dir)
    target = lib_dir / "learned" / "dough.oac"
    emit([oac], target, library=lib_dir)
    before = target.stat().st_mtime_ns
    e = emit([oac], target, library=lib_dir, header=["another header"])  # comments are not meaning
    assert e.status == "unchanged" and target.stat().st_mtime_ns == before
    assert load_library([lib_dir]).oacs["dough"] == oac


def test_a_composed_file_nobody_edited_is_replaced_without_force(lib_dir):
    oac = dough(lib_dir)
    target = lib_dir / "learned" / "dough.oac"
    header = ["Composed by oacc compose from dough.c3d."]
    emit([oac], target, library=lib_dir, header=header)
    assert target.read_text().startswith(FINGERPRINT) and unedited(target)
    assert compile_paths([lib_dir]).ok  # the fingerprint is a comment
    shorter = oac.model_copy(update={"pre": oac.pre[1:]})
    e = emit([shorter], target, library=lib_dir, header=header)  # e.g. the library changed since
    assert e.status == "replaced" and e.changes == "pre -cup1 <-> liquid1"
    assert load_library([lib_dir]).oacs["dough"] == shorter and unedited(target)


@pytest.mark.parametrize("edit", [
    lambda text: text.replace("Composed by", "Reviewed; composed by"),  # a comment is an edit too
    lambda text: text + "# checked by hand\n",
    lambda text: text.split("\n", 1)[1],  # the fingerprint line removed
])
def test_an_edited_composed_file_is_kept(lib_dir, edit):
    oac = dough(lib_dir)
    target = lib_dir / "learned" / "dough.oac"
    header = ["Composed by oacc compose from dough.c3d."]
    emit([oac], target, library=lib_dir, header=header)
    target.write_text(edit(target.read_text()))
    assert not unedited(target)
    shorter = oac.model_copy(update={"pre": oac.pre[1:]})
    with pytest.raises(MatchingError, match="already holds a different 'dough'.*pass --force"):
        emit([shorter], target, library=lib_dir, header=header)
    assert load_library([lib_dir]).oacs["dough"] == oac


def test_different_content_of_the_same_name_needs_force(lib_dir):
    oac = dough(lib_dir)
    target = lib_dir / "learned" / "dough.oac"
    emit([oac], target, library=lib_dir)
    shorter = oac.model_copy(update={"pre": oac.pre[1:]})
    with pytest.raises(MatchingError, match=r"already holds a different 'dough' \(pre -cup1 <-> liquid1\);"
                                            " pass --force"):
        emit([shorter], target, library=lib_dir)
    assert load_library([lib_dir]).oacs["dough"] == oac
    e = emit([shorter], target, library=lib_dir, force=True)
    assert e.status == "replaced" and e.changes == "pre -cup1 <-> liquid1"
    assert load_library([lib_dir]).oacs["dough"] == shorter
    assert differences(oac, oac) == "same meaning"


def test_a_name_the_library_already_uses_is_refused(lib_dir):
    oac = dough(lib_dir).model_copy(update={"name": "grasp"})
    with pytest.raises(MatchingError, match="an OAC named 'grasp' is already defined in .*actions.oac"):
        emit([oac], lib_dir / "learned" / "grasp.oac", library=lib_dir)
    assert not (lib_dir / "learned" / "grasp.oac").exists()


def test_nothing_is_written_when_the_result_does_not_compile(lib_dir):
    bad = dough(lib_dir).model_copy(update={"steps": (Call(oac="grap", args=("hand1", "cup1")),)})
    with pytest.raises(LanguageError, match=r"error\[E013\]: unknown OAC 'grap'.*nothing was written"):
        emit([bad], lib_dir / "learned" / "dough.oac", library=lib_dir)
    assert not (lib_dir / "learned").exists() or not any((lib_dir / "learned").iterdir())


def test_drafts_are_parseable_flagged_by_the_compiler_and_left_out_of_the_library(lib_dir):
    lib = load_library([lib_dir])
    classes = lib.instance_classes(lib.scenes["kitchen"])
    before = state(("left_hand", "red_cup"), ("liquid_one", "red_cup"))
    after = state(("left_hand", "red_cup"), ("liquid_one", "red_cup"), ("orange_bowl", "red_cup"))
    draft, binding = propose_draft("stack", before, after, classes, lib.ancestors, comments=("DRAFT",))
    assert binding == {"bowl": "orange_bowl", "cup": "red_cup", "hand": "left_hand", "liquid": "liquid_one"}
    assert draft.skill == PLACEHOLDER_SKILL
    # the draft matches its own sub-action under the strict rule
    m = Matcher([draft], classes, ancestors=lib.ancestors).match(before, after)
    assert [x.mapping for x in m.matches] == [binding]
    target = lib_dir / "drafts" / "stack.oac"
    emit([draft], target, library=lib_dir, drafts=True)
    codes = [d.code for d in compile_paths([lib_dir]).errors]
    assert codes == ["E016"]
    assert target not in library_files(lib_dir) and lib_dir / "actions.oac" in library_files(lib_dir)
    assert parse_text(target.read_text()).decls == (draft,)


@settings(max_examples=30, deadline=None,
          suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])
@given(demonstrations())
def test_emit_then_parse_gives_the_same_model(demo):
    library, scene, steps = demo
    assume(steps)
    try:
        oac = compose("learned", steps, library, scene).oac
    except MatchingError:
        assume(False)
        return
    text = render([oac], "x.oac", ["header"])
    assert parse_text(text).decls == (oac,)
