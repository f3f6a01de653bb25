"""``oacc synth`` and the bundled demonstration data/dough.c3d."""

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from oacdsl.cli import main
from oacdsl.segmentation import AasParams, segment
from oacdsl.segmentation.readers import read_recording
from oacdsl.segmentation.synth import DEFAULT_SEED, dough_demonstration

ROOT = Path(__file__).resolve().parents[1]
BUNDLED = ROOT / "data" / "dough.c3d"


def oacc(*args):
    return subprocess.run([sys.executable, "-m", "oacdsl", *args], capture_output=True, text=True, cwd=ROOT)


def test_synth_writes_c3d_and_truth_that_segment_back(tmp_path):
    out = tmp_path / "runs" / "d7.c3d"
    assert main(["synth", "dough", "-o", str(out), "--seed", "7"]) == 0
    truth = json.loads((tmp_path / "runs" / "d7.truth.json").read_text(encoding="utf-8"))
    assert truth["seed"] == 7 and truth["recording"] == "d7.c3d" and truth["clean"] is False
    rec = read_recording(out)
    demo = dough_demonstration(7)
    assert rec.instances == demo.recording.instances and rec.rate_hz == 100.0
    for inst in rec.instances:
        np.testing.assert_allclose(rec.group_positions(inst), demo.recording.group_positions(inst), atol=1e-6)
    # the truth's frames are where the paper's Eq. 1/2 fire
    seg = segment(rec, AasParams(mode="paper"))
    assert [[list(r) for r in k.state.sorted_relations()] for k in seg.keyframes] == [
        k["relations"] for k in truth["keyframes"]]
    assert [k.frame for k in seg.keyframes] == pytest.approx([k["frame"] for k in truth["keyframes"]], abs=2)
    # the default (adaptive) detector sees the same sequence of world states
    default = segment(rec, AasParams())
    assert [[list(r) for r in k.state.sorted_relations()] for k in default.keyframes] == [
        k["relations"] for k in truth["keyframes"]]
    # nothing else left behind (no temporary files)
    assert sorted(p.name for p in (tmp_path / "runs").iterdir()) == ["d7.c3d", "d7.truth.json"]


def test_synth_truth_path_and_clean_option(tmp_path):
    out, truth = tmp_path / "c.c3d", tmp_path / "elsewhere" / "t.json"
    assert main(["synth", "dough", "-o", str(out), "--truth", str(truth), "--clean"]) == 0
    assert json.loads(truth.read_text(encoding="utf-8"))["clean"] is True
    assert not np.isnan(read_recording(out).positions_m).any()
    assert not (tmp_path / "c.truth.json").exists()


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["synth", "dough", "-o", "x.txt"], "the output must be a .c3d file"),
        (["synth", "dough", "-o", "x.c3d", "--seed", "-1"], "--seed must be a whole number"),
        (["synth", "dugh", "-o", "x.c3d"], "invalid choice: 'dugh' (choose from 'dough')"),
        (["synth", "dough", "-o", "README.md/x.c3d"], "cannot write"),
        (["synth", "dough"], "required: -o"),
    ],
)
def test_synth_bad_usage_is_one_line_exit_2(args, message, capsys, monkeypatch):
    monkeypatch.chdir(ROOT)
    try:
        status = main(args)
    except SystemExit as stop:  # argparse's own usage errors
        status = stop.code
    err = capsys.readouterr().err
    assert status == 2, err
    assert message in err.strip().splitlines()[-1]  # one error line (argparse prints its usage above it)
    assert not (ROOT / "x.c3d").exists() and not (ROOT / "x.truth.json").exists()


def test_synth_error_from_the_shell_has_no_traceback():
    result = oacc("synth", "dough", "-o", "README.md/x.c3d")
    assert result.returncode == 2 and result.stderr.startswith("oacc: error: ")
    assert "Traceback" not in result.stderr and len(result.stderr.strip().splitlines()) == 1


def test_synth_help_explains_the_scene():
    result = oacc("synth", "--help")
    assert result.returncode == 0 and "dough" in result.stdout and "--seed" in result.stdout


def test_bundled_demonstration_is_the_default_seed():
    """data/dough.c3d + data/dough.truth.json are exactly what the generator makes for the default seed.

    If this fails after a deliberate change of the generator or of the AAS defaults, regenerate with
    ``python -m oacdsl synth dough -o data/dough.c3d`` (see docs/demonstration.md).
    """
    demo = dough_demonstration(DEFAULT_SEED)
    rec = read_recording(BUNDLED)
    assert rec.marker_names == demo.recording.marker_names and rec.n_frames == demo.recording.n_frames
    np.testing.assert_array_equal(np.isnan(rec.positions_m), np.isnan(demo.recording.positions_m))
    np.testing.assert_allclose(rec.positions_m, demo.recording.positions_m, atol=1e-6)  # float32 in mm
    truth = json.loads(BUNDLED.with_name("dough.truth.json").read_text(encoding="utf-8"))
    assert truth == json.loads(json.dumps(dict(demo.truth, recording="dough.c3d", clean=False)))
    assert BUNDLED.stat().st_size < 2_000_000
