"""``oacc inspect``: summary of a recording, JSON form, presets, one-line errors."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
from _mocap import mocap_file

from oacdsl.cli import main
from oacdsl.segmentation.readers import write_c3d
from oacdsl.segmentation.recording import Recording


def demo(tmp_path: Path) -> Path:
    pos = np.zeros((200, 3, 3)) + [0.1, 0.2, 0.3]
    pos[:50, 2] = np.nan  # a quarter of the lid marker is occluded
    rec = Recording("demo", 100.0, np.arange(200) / 100.0, ("a", "b", "lid"), pos,
                    {"cup": (0, 1), "hand": (2,)}, first_frame=30)
    return write_c3d(rec, tmp_path / "demo.c3d")


def test_inspect_text(tmp_path: Path, capsys):
    assert main(["inspect", str(demo(tmp_path))]) == 0
    out = capsys.readouterr().out
    assert "100 Hz, 200 frames, 1.99 s (first frame 30)" in out
    assert "x 0.100..0.100 m" in out
    assert "cup     2 markers  gaps     0 %  cup:a cup:b" in out
    assert "hand    1 markers  gaps  25.0 %  hand:lid(25.0 %)" in out


def test_inspect_json(tmp_path: Path, capsys):
    assert main(["inspect", str(demo(tmp_path)), "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert (doc["frames"], doc["rate_hz"], doc["first_frame"], doc["format"]) == (200, 100.0, 30, "c3d")
    assert [g["name"] for g in doc["groups"]] == ["cup", "hand"]
    assert doc["groups"][1]["markers"] == [{"name": "hand:lid", "gap_fraction": 0.25}]
    assert doc["gap_fraction"] == pytest.approx(50 / 600)


def test_inspect_bad_file_is_one_line_exit_1(tmp_path: Path, capsys):
    bad = tmp_path / "bad.c3d"
    bad.write_bytes(b"\x02\x50" + bytes(1200))
    assert main(["inspect", str(bad)]) == 1
    err = capsys.readouterr().err
    assert err.startswith(f"oacc: error: {bad}: not a valid C3D file") and err.count("\n") == 1


@pytest.mark.mocap
def test_inspect_kit_preset_and_warning(capsys):
    clip = next(mocap_file("kit_bimanual").glob("Wipe_*.mmm.xml"))
    assert main(["inspect", str(clip), "--preset", "kit", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert [g["name"] for g in doc["groups"]] == [
        "draining_rack", "left_hand", "plate_dish", "right_hand", "sponge_small"]
    assert len(doc["ungrouped"]) == 43
    optotrak = str(mocap_file("c3d/ezc3d/Optotrak.c3d"))
    assert main(["inspect", optotrak]) == 1
    err = capsys.readouterr().err
    assert "frames 30..1149 lost; --allow-truncated reads the 29 complete frames" in err
    assert err.count("\n") == 1
    assert main(["inspect", optotrak, "--allow-truncated"]) == 0
    assert "oacc: warning:" in capsys.readouterr().err


def test_inspect_and_segment_give_the_same_duration(tmp_path: Path, capsys):
    # 85 frames at 10 Hz span 8.40 s from the first frame to the last: both commands say so
    pos = np.zeros((85, 2, 3)) + [0.1, 0.2, 0.3]
    pos[:, 1, 0] += 0.5
    rec = Recording("short", 10.0, np.arange(85) / 10.0, ("a", "b"), pos, {"cup": (0,), "hand": (1,)})
    path = write_c3d(rec, tmp_path / "short.c3d")
    assert main(["inspect", str(path)]) == 0
    assert "10 Hz, 85 frames, 8.40 s" in capsys.readouterr().out
    assert main(["segment", str(path)]) == 0
    assert "85 frames at 10 Hz (8.40 s)" in capsys.readouterr().out
