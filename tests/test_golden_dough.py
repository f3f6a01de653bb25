"""The golden test: the bundled dough demonstration composes into exactly the paper's new OAC."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest

from oacdsl.cli import main
from oacdsl.compiler import compile_paths, load_library
from tests.kitchen import PAPER_EFFECT, PAPER_PRE

ROOT = Path(__file__).resolve().parents[1]
DOUGH = ROOT / "data" / "dough.c3d"


@pytest.fixture
def lib_dir(tmp_path: Path) -> Path:
    # the developer's own learned/ and drafts/ (from oacc reproduce runs) are not the standard library
    skip = shutil.ignore_patterns("learned", "drafts")
    shutil.copytree(ROOT / "library", tmp_path / "library", ignore=skip)
    return tmp_path / "library"


def test_compose_dough_gives_the_papers_oac(capsys, lib_dir):
    code = main(["compose", str(DOUGH), "--library", str(lib_dir), "--name", "dough", "--json"])
    out, err = capsys.readouterr()
    assert code == 0, err
    doc = json.loads(out)
    # Wächter et al. 2013, IV-B: the new OAC's preconditions and effects
    assert doc["pre"] == PAPER_PRE
    assert doc["effect"] == PAPER_EFFECT
    assert doc["ended"] == [["green_cup", "liquid_two"], ["liquid_one", "red_cup"]]
    truth = json.loads((ROOT / "data" / "dough.truth.json").read_text())
    assert [s["oac"] for s in doc["steps"]] == [s["oac"] for s in truth["sub_actions"]]
    assert [s["binding"] for s in doc["steps"]] == [s["binding"] for s in truth["sub_actions"]]
    assert {s["oac"] for s in doc["steps"]} == {"grasp", "pour", "place", "mix"}
    # written into the library, compiling cleanly with it
    assert doc["file"] == str(lib_dir / "learned" / "dough.oac")
    assert compile_paths([lib_dir]).diagnostics == []
    learned = load_library([lib_dir]).oacs["dough"]
    assert [c.oac for c in learned.steps] == [s["oac"] for s in doc["steps"]]
    assert {p.default for p in learned.params} == set(truth["instances"])


def test_match_dough_one_oac_per_sub_action(capsys, lib_dir):
    # The truth's frames are where the paper's Eq. 1/2 fire: compare them in paper mode.
    code = main(["match", str(DOUGH), "--library", str(lib_dir), "--json", "--mode", "paper"])
    doc = json.loads(capsys.readouterr().out)
    assert code == 0
    truth = json.loads((ROOT / "data" / "dough.truth.json").read_text())
    got = [(s["from_frame"], s["to_frame"], s["matches"][s["chosen"]]) for s in doc["sub_actions"]]
    assert got == [(t["from_frame"], t["to_frame"], {"oac": t["oac"], "binding": t["binding"]})
                   for t in truth["sub_actions"]]
    assert all(len(s["matches"]) == 1 for s in doc["sub_actions"])


def test_match_dough_default_mode_same_oacs_and_bindings(capsys, lib_dir):
    # The default (adaptive) detector moves keyframes (by up to 0.33 s) but must find the
    # same sub-actions, each matching the same OAC with the same binding.
    code = main(["match", str(DOUGH), "--library", str(lib_dir), "--json"])
    doc = json.loads(capsys.readouterr().out)
    assert code == 0
    truth = json.loads((ROOT / "data" / "dough.truth.json").read_text())
    got = [s["matches"][s["chosen"]] for s in doc["sub_actions"]]
    assert got == [{"oac": t["oac"], "binding": t["binding"]} for t in truth["sub_actions"]]
    assert all(len(s["matches"]) == 1 for s in doc["sub_actions"])


def test_the_papers_plain_steps_with_no_demo_params(capsys, lib_dir):
    # The paper's OAC names its steps only; by default oacc compose also writes the skill
    # parameters of the demonstrated motion on the steps (the pours' tilt and duration).
    code = main(["compose", str(DOUGH), "--library", str(lib_dir), "--name", "dough", "--no-demo-params"])
    assert code == 0, capsys.readouterr().err
    learned = load_library([lib_dir]).oacs["dough"]
    steps = ["grasp", "pour", "place", "grasp", "pour", "place", "grasp", "mix"]
    assert [c.oac for c in learned.steps] == steps
    assert all(c.skill_params == () for c in learned.steps)
    assert "demonstrated" not in (lib_dir / "learned" / "dough.oac").read_text()
