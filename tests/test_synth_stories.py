"""Other takes of the dough task (``oacc synth dough --story``): a hand-over of the red cup and
the two hands at work at once. Their ground truth holds under the paper's rule (the truth is
refused otherwise), the default segmentation composes them to the scripted sub-actions, and
the robot reproduces them (slow)."""

from __future__ import annotations

import json
import shutil
import sys
from pathlib import Path

import pytest

from oacdsl.cli import main
from oacdsl.cli.synth_cmd import _STORIES
from oacdsl.errors import SegmentationError
from oacdsl.segmentation.synth import STORIES, dough_demonstration

ROOT = Path(__file__).resolve().parents[1]
LIBRARY = ROOT / "library"

HANDOVER = [
    "grasp(left_hand, red_cup)",
    "pour(left_hand, red_cup, liquid_one, orange_bowl)",
    "grasp(right_hand, red_cup)",
    "place(left_hand, red_cup)",
    "place(right_hand, red_cup)",
    "grasp(right_hand, green_cup)",
    "pour(right_hand, green_cup, liquid_two, orange_bowl)",
    "place(right_hand, green_cup)",
    "grasp(right_hand, mixer)",
    "mix(right_hand, mixer, orange_bowl)",
]
OVERLAP = [
    "grasp(left_hand, red_cup)",
    "grasp(right_hand, green_cup)",
    "pour(left_hand, red_cup, liquid_one, orange_bowl)",
    "pour(right_hand, green_cup, liquid_two, orange_bowl)",
    "place(left_hand, red_cup)",
    "place(right_hand, green_cup)",
    "grasp(right_hand, mixer)",
    "mix(right_hand, mixer, orange_bowl)",
]


def test_the_cli_offers_every_story():
    assert tuple(_STORIES) == STORIES == ("paper", "handover", "overlap")


@pytest.mark.parametrize("seed", [2013, 1, 2, 3, 4, 5])
@pytest.mark.parametrize(("story", "sequence"), [("handover", HANDOVER), ("overlap", OVERLAP)])
def test_story_truth_holds_for_seeds(story, sequence, seed):
    demo = dough_demonstration(seed, story=story)  # raises unless the rule sees exactly the script
    assert demo.truth["oac_sequence"] == sequence
    assert demo.truth["realism"]["bounce"]["hand"] == ("right_hand" if story == "handover" else "left_hand")


def test_the_paper_story_is_the_default_and_unknown_stories_are_refused():
    assert dough_demonstration(2013).truth == dough_demonstration(2013, story="paper").truth
    known = "the stories are paper, handover, overlap"
    with pytest.raises(SegmentationError, match=f"unknown story 'juggle'; {known}"):
        dough_demonstration(2013, story="juggle")


def _steps(oac_file: Path) -> list[str]:
    text = oac_file.read_text()
    body = text[text.index("steps {") + len("steps {") :]
    return [line.strip() for line in body.splitlines() if line.strip() and not line.strip().startswith("#")]


@pytest.mark.parametrize(("story", "sequence"), [("handover", HANDOVER), ("overlap", OVERLAP)])
def test_story_composes_to_its_scripted_sub_actions(tmp_path, capsys, story, sequence):
    rec = tmp_path / f"{story}.c3d"
    assert main(["synth", "dough", "-o", str(rec), "--story", story, "--seed", "3"]) == 0
    truth = json.loads(rec.with_name(f"{story}.truth.json").read_text())
    assert truth["oac_sequence"] == sequence
    out = tmp_path / f"{story}.oac"
    assert main(["compose", str(rec), "--library", str(LIBRARY), "--name", story, "-o", str(out)]) == 0
    capsys.readouterr()
    steps = [s.split(" {")[0].split("(")[0] for s in _steps(out) if "(" in s]
    assert steps == [s.split("(")[0] for s in sequence]


@pytest.mark.slow
@pytest.mark.parametrize("story", ["overlap", "handover"])
def test_story_is_reproduced_on_the_robot_and_verified(tmp_path, capsys, story):
    pytest.importorskip("mujoco")
    rec = tmp_path / f"{story}.c3d"
    assert main(["synth", "dough", "-o", str(rec), "--story", story]) == 0
    out, library = tmp_path / "out", tmp_path / "library"
    shutil.copytree(LIBRARY, library)  # reproduce writes the composed OAC into the library's learned/
    status = main(["reproduce", str(rec), "--library", str(library), "--out", str(out), "--no-render"])
    text = capsys.readouterr().out
    assert status == 0, text
    result = json.loads((out / "result.json").read_text())
    assert result["verdict"]["verified"] is True, result["verdict"]
    assert result["run"]["metrics"]["balls_in_bowl"] == result["run"]["metrics"]["balls_total"] == 20


if __name__ == "__main__":  # pragma: no cover
    sys.exit(pytest.main([__file__, "-q"]))
