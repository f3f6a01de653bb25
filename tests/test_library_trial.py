"""Issue 21, items 1-3 of the `.oac`-only trial: several --library for every command, a learned
folder that never breaks composing, and ties between matching OACs broken by specificity."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest

from oacdsl.cli import main
from oacdsl.matching import Matcher
from oacdsl.model import Param
from oacdsl.segmentation.result import Keyframe, Segmentation
from tests.kitchen import DOUGH_STATES, GRASP, KITCHEN, OACS, TRACKED, atom, kitchen_library, state

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture
def lib_dir(tmp_path: Path) -> Path:
    skip = shutil.ignore_patterns("learned", "drafts")
    shutil.copytree(ROOT / "library", tmp_path / "library", ignore=skip)
    return tmp_path / "library"


def one_grasp(tmp_path: Path) -> Path:
    """A demonstration of one sub-action: the left hand grasps the red cup."""
    kfs = (Keyframe(0, 0.0, DOUGH_STATES[0]), Keyframe(100, 1.0, DOUGH_STATES[1]))
    path = tmp_path / "grasp.json"
    path.write_text(json.dumps(Segmentation("grasp", 100.0, 200, tuple(TRACKED), kfs, {}).to_json()))
    return path


# ------------------------------------------------------------------ 1: --library given twice


def test_reproduce_takes_every_library_given(tmp_path, lib_dir, monkeypatch, capsys):
    """The scene in one file, the OACs and classes in the library: reproduce loads both (it kept the
    last --library only, and then blamed the scene's classes)."""
    import oacdsl.pipeline

    scene_file = tmp_path / "scene.oac"
    kitchen = lib_dir / "kitchen.oac"
    scene_file.write_text(kitchen.read_text())
    kitchen.unlink()
    seen = {}

    class Stop(Exception):
        pass

    def fake_reproduce(inputs, **_):
        seen["paths"] = inputs.library_paths
        seen["scene"] = inputs.scene.name
        raise Stop

    monkeypatch.setattr(oacdsl.pipeline, "reproduce", fake_reproduce)
    with pytest.raises(Stop):
        main(["reproduce", "--library", str(lib_dir), "--library", str(scene_file), "--no-record",
              "--out", str(tmp_path / "out"), "--no-render", "--quiet"])
    assert seen == {"paths": (lib_dir, scene_file), "scene": "kitchen"}
    capsys.readouterr()


# ------------------------------------------------------------------ 2: the learned folder


def test_composing_again_never_matches_the_earlier_composition(tmp_path, lib_dir, capsys):
    """The learned OAC of a one-step demonstration is more specific (Cup) than grasp: it used to be
    matched as the step of its own recomposition (E019, every second run)."""
    demo = one_grasp(tmp_path)
    for _ in range(2):
        code = main(["compose", str(demo), "--library", str(lib_dir), "--name", "take_cup"])
        out, err = capsys.readouterr()
        assert code == 0, err
    assert "steps   grasp" in out and "unchanged" in out
    # and an OAC that calls it is no step of it either (it would call itself through that one)
    (lib_dir / "learned" / "again.oac").write_text(
        "oac again(hand: Hand = left_hand, cup: Cup = red_cup) {\n"
        "    pre     hand <-> nothing\n    effect  hand <-> cup\n"
        "    steps {\n        take_cup(hand, cup)\n    }\n}\n")
    code = main(["compose", str(demo), "--library", str(lib_dir), "--name", "take_cup"])
    out, err = capsys.readouterr()
    assert code == 0 and "E019" not in err and "unchanged" in out


def test_a_stale_learned_file_is_left_out_with_a_warning(tmp_path, lib_dir, capsys):
    """A learned OAC whose step became a composed OAC (E047) no longer compiles: matching and
    composing go on without it and say so; the files of the library proper still stop them."""
    learned = lib_dir / "learned"
    learned.mkdir()
    (lib_dir / "fetch.oac").write_text(
        "oac fetch(h: Hand, o: Graspable) {\n    pre     h <-> nothing\n    effect  h <-> o\n"
        "    steps {\n        grasp(h, o)\n    }\n}\n")
    (learned / "old.oac").write_text(
        "oac old(hand: Hand = left_hand, cup: Cup = red_cup) {\n    pre     hand <-> nothing\n"
        "    effect  hand <-> cup\n    steps {\n        fetch(hand, cup) { duration 2s }\n    }\n}\n")
    (learned / "older.oac").write_text(  # calls the stale one: goes with it
        "oac older(hand: Hand = left_hand, cup: Cup = red_cup) {\n    pre     hand <-> nothing\n"
        "    effect  hand <-> cup\n    steps {\n        old(hand, cup)\n    }\n}\n")
    demo = one_grasp(tmp_path)
    code = main(["compose", str(demo), "--library", str(lib_dir), "--name", "take_cup"])
    out, err = capsys.readouterr()
    assert code == 0, err
    assert "old.oac left out: it no longer compiles" in err and "E047" in err
    assert "older.oac left out" in err
    assert (learned / "take_cup.oac").is_file()
    code = main(["match", str(demo), "--library", str(lib_dir)])
    assert code == 0
    capsys.readouterr()
    (lib_dir / "broken.oac").write_text(
        "oac broken(h: Hand) { pre h <-> nothing effect h <-> x execute place }\n")
    code = main(["match", str(demo), "--library", str(lib_dir)])
    _, err = capsys.readouterr()
    assert code == 1 and "broken.oac" in err


# ------------------------------------------------------------------ 3: ties


def test_more_conditions_win_a_tie_of_classes():
    """grasp_free states one more precondition than grasp with the same classes: it was chosen by
    name (grasp < grasp_free), now by being more specific."""
    lib = kitchen_library()
    free = GRASP.model_copy(update={"name": "grasp_free", "pre": (atom("h"), atom("o", "orange_bowl", True))})
    m = Matcher([*OACS, free], lib.instance_classes(KITCHEN), ancestors=lib.ancestors)
    result = m.match(state(), state(("left_hand", "red_cup")))
    assert result.chosen.text() == "grasp_free(h=left_hand, o=red_cup)"
    assert "it states more conditions (3 preconditions and effects" in result.reason
    assert not result.ambiguous


def test_a_remaining_tie_says_how_to_break_it(tmp_path, lib_dir, capsys):
    (lib_dir / "take.oac").write_text(
        "oac take(h: Hand, o: Graspable) {\n    pre     h <-> nothing\n    effect  h <-> o\n"
        "    execute reach_and_grasp\n}\n")
    code = main(["match", str(one_grasp(tmp_path)), "--library", str(lib_dir)])
    out, _ = capsys.readouterr()
    assert code == 0
    assert "ambiguous: it ties with take(h=left_hand, o=red_cup)" in out
    assert "give the OAC you mean a more specific parameter class or a precondition the other lacks" in out
    assert out.rstrip().endswith("1 matched, 0 unmatched, 1 ambiguous")


def test_a_symmetric_oac_bound_both_ways_is_no_tie():
    lib = kitchen_library()
    both = GRASP.model_copy(update={
        "name": "grasp_both",
        "params": (Param(name="h1", cls="Hand"), Param(name="o1", cls="Graspable"),
                   Param(name="h2", cls="Hand"), Param(name="o2", cls="Graspable")),
        "pre": (atom("h1"), atom("h2")), "effect": (atom("h1", "o1"), atom("h2", "o2"))})
    m = Matcher([both], lib.instance_classes(KITCHEN), ancestors=lib.ancestors)
    result = m.match(state(), state(("left_hand", "red_cup"), ("right_hand", "green_cup")))
    assert len(result.matches) == 2 and not result.ambiguous
    assert "the OAC is symmetric" in result.reason
