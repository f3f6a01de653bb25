"""The dough demonstration at other rates, with more jitter and with a liquid in flight: default
parameters still compose exactly the paper's OAC (issue 9). The full grid is
``benchmarks/robustness.py``; this is a small slice of it."""

from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest

from oacdsl.cli import main
from oacdsl.compiler import load_library
from oacdsl.matching.demonstration import compose_demonstration, find_scene, match_segmentation
from oacdsl.matching.emit import library_files
from oacdsl.matching.matcher import Matcher
from oacdsl.segmentation import AasParams, segment
from oacdsl.segmentation.synth import dough_demonstration
from oacdsl.segmentation.synth.realism import NoiseModel
from tests.kitchen import DOUGH_STEPS as STEPS
from tests.kitchen import PAPER_EFFECT, PAPER_PRE

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def library():
    return load_library(library_files(ROOT / "library"))


def composed(library, recording, mode: str | None = None, **match: float) -> dict:
    seg = segment(recording, AasParams() if mode is None else AasParams(mode=mode))  # the defaults
    scene = find_scene(library, seg.instances)
    matches = match_segmentation(seg, Matcher.from_library(library, scene), **match)
    return compose_demonstration("dough", matches, library, scene).composition.to_json(None)


@pytest.mark.parametrize(("rate", "seed"), [(50.0, 11), (100.0, 12), (200.0, 13), (240.0, 14)])
def test_half_a_millimetre_of_jitter_at_50_to_240_hz_gives_the_papers_oac(library, rate, seed):
    demo = dough_demonstration(seed, rate_hz=rate, noise=NoiseModel(white_m=0.0005))  # 0.5 mm
    doc = composed(library, demo.recording)
    assert doc["pre"] == PAPER_PRE and doc["effect"] == PAPER_EFFECT
    assert [s["oac"] for s in doc["steps"]] == STEPS


def test_the_papers_one_frame_difference_fails_there(library):
    # the failure of issue 9 that the default detector removes: paper mode at 200 Hz, 0.5 mm
    demo = dough_demonstration(13, rate_hz=200.0, noise=NoiseModel(white_m=0.0005))
    seg = segment(demo.recording, AasParams(mode="paper"))
    truth = [sorted(map(tuple, k["relations"])) for k in demo.truth["keyframes"]]
    assert [k.state.sorted_relations() for k in seg.keyframes] != truth


def test_a_second_of_flight_composes_as_the_papers_pour(library):
    demo = dough_demonstration(4, flight_s=1.0)
    truth = demo.truth
    # the liquids leave their cups a second before they reach the bowl: a transient state each
    assert [t["in_flight"] for t in truth["transient"]] == [["liquid_one"], ["liquid_two"]]
    assert truth["realism"]["flight_s"] == 1.0 and [s["oac"] for s in truth["sub_actions"]] == STEPS
    # the default detector composes the paper's OAC (its tool rule keeps the liquid touching
    # the held cup it flies away from until it lands: no transient state shows)
    doc = composed(library, demo.recording)
    assert doc["pre"] == PAPER_PRE and doc["effect"] == PAPER_EFFECT
    assert [s["oac"] for s in doc["steps"]] == STEPS
    # the robust detector at one distance sees the flight: two transient states, joined by matching
    seg = segment(demo.recording, AasParams(mode="robust"))
    assert len(seg.keyframes) == 11
    doc = composed(library, demo.recording, mode="robust")
    assert doc["pre"] == PAPER_PRE and doc["effect"] == PAPER_EFFECT
    assert [s["oac"] for s in doc["steps"]] == STEPS
    with pytest.raises(Exception, match="matches no OAC"):  # without the rule: two halves, no pour
        composed(library, demo.recording, mode="robust", transient_s=0.0)


def run(capsys, *argv) -> tuple[int, str, str]:
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


def test_synth_rate_jitter_flight_from_the_command_line(capsys, tmp_path):
    lib = tmp_path / "library"
    shutil.copytree(ROOT / "library", lib, ignore=shutil.ignore_patterns("learned", "drafts"))
    c3d = tmp_path / "fly.c3d"
    code, _, err = run(capsys, "synth", "dough", "-o", c3d, "--seed", 5, "--rate", 240, "--jitter", 0.5,
                       "--flight", "1s")
    assert code == 0, err
    assert "at 240 Hz" in err
    truth = json.loads((tmp_path / "fly.truth.json").read_text())
    assert truth["rate_hz"] == 240.0 and truth["realism"]["noise"]["white_m"] == pytest.approx(0.0005)
    assert len(truth["transient"]) == 2
    code, out, err = run(capsys, "compose", c3d, "--library", lib, "--name", "dough", "--json")
    assert code == 0, err  # the default detector
    doc = json.loads(out)
    assert doc["pre"] == PAPER_PRE and doc["effect"] == PAPER_EFFECT
    code, out, err = run(capsys, "match", c3d, "--library", lib, "--mode", "robust")
    assert code == 0, err
    assert out.count("through a transient state") == 2
    code, out, err = run(capsys, "match", c3d, "--library", lib, "--mode", "robust", "--transient", "0s",
                         "--json")
    assert code == 1 and "transient" not in out


@pytest.mark.parametrize(
    ("argv", "needle"),
    [
        (["--rate", "5"], "--rate must be between 10 and 1000 Hz, got 5"),
        (["--jitter", "-1"], "--jitter must be between 0 and 5 mm, got -1"),
        (["--flight", "3s"], "--flight must be between 0.05s and 1.5s, got 3s"),
        (["--flight", "1"], "--flight: '1' has no unit"),
    ],
)
def test_synth_bad_options_are_one_line_exit_2(capsys, tmp_path, argv, needle):
    code, _, err = run(capsys, "synth", "dough", "-o", tmp_path / "x.c3d", *argv)
    assert code == 2 and err.count("\n") == 1 and needle in err
    assert not list(tmp_path.iterdir())


def test_bad_transient_is_one_line_exit_2(capsys, tmp_path):
    code, _, err = run(capsys, "match", ROOT / "data" / "dough.c3d", "--transient", "1")
    assert code == 2 and err.count("\n") == 1 and "--transient: '1' has no unit" in err
