"""``oacc reproduce`` of the KIT development clips Mix, Wipe, Scoop and Cut on ARMAR-III.

Each test runs the main job as a new user would (``oacc reproduce CLIP.mmm.xml --library
library/kit``, no other flag but where to write) on a copy of library/kit, and checks the
closed loop: the robot's own recording shows the demonstration's world-state changes
(a change the robot makes in several steps counts once, see oacdsl/verify.py). Clips whose
robot run does not verify yet are listed in docs/kit.md, not tested here.
"""

from __future__ import annotations

import json
import os
import shutil
from pathlib import Path

import pytest
from _mocap import mocap_file

from oacdsl.cli import main

ROOT = Path(__file__).resolve().parents[1]

#: clip → the robot's OAC of each sub-action (what the closed loop matches).
VERIFIED = {
    "Scoop": ["grasp", "take_and_dip", "scoop_into", "back_into", "put_down_and_leave"],
}


@pytest.fixture
def kit(tmp_path: Path) -> Path:
    lib = tmp_path / "kit"
    shutil.copytree(ROOT / "library" / "kit", lib, ignore=shutil.ignore_patterns("learned", "drafts"))
    return lib


@pytest.mark.slow
@pytest.mark.parametrize("clip", sorted(VERIFIED))
def test_clip_is_reproduced_and_verified(clip: str, kit: Path, tmp_path: Path, monkeypatch,
                                         capsys: pytest.CaptureFixture[str]) -> None:
    monkeypatch.setenv("MUJOCO_GL", os.environ.get("MUJOCO_GL", "egl"))
    xml = next(mocap_file("kit_bimanual").glob(f"{clip}_*.mmm.xml"))
    out = tmp_path / "out"
    code = main(["reproduce", str(xml), "--library", str(kit), "--out", str(out), "--quiet", "--no-render"])
    printed = capsys.readouterr().out
    assert code == 0, printed
    doc = json.loads((out / "result.json").read_text())
    assert doc["verification"]["verified"] is True
    assert [s["matches"][s["chosen"]]["oac"] for s in doc["match"]["sub_actions"]] == VERIFIED[clip]
