"""The bundled dough on seed 2's places: the pours keep the cups off the bowl's rim as their
tilt begins (each step raised by what the arm's measured lag needs), and the reproduction is
faithful (the measured tilts are the demonstrated ones)."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

pytest.importorskip("mujoco", reason="the robot runtime needs the 'robot' extra (mujoco)")
pytest.importorskip("placo", reason="the robot runtime needs the 'robot' extra (placo)")

ROOT = Path(__file__).resolve().parents[1]


@pytest.mark.slow
def test_dough_on_seed_2_tilts_as_demonstrated(tmp_path: Path) -> None:
    # tilted at the demonstrated pace (125 deg in 0.8 s) the arm lagged its goal 1.5-2 cm and
    # the red cup came down on the bowl's rim for 0.3 s as its tilt began; that touch (a + and
    # a - merged into nothing) ended the span aligned with the pour before it, so the tilt was
    # measured from 53 deg on: 74 deg against the demonstrated 109 (motion.2.tilt failed)
    from oacdsl.pipeline import load_inputs, reproduce
    from oacdsl.segmentation import AasParams

    library = tmp_path / "library"
    shutil.copytree(ROOT / "library", library, ignore=shutil.ignore_patterns("learned", "drafts"))
    inputs = load_inputs(None, library, None, AasParams())
    outcome = reproduce(inputs, name="dough", out=tmp_path / "out", db=None, seed=2, render=False,
                        quiet=True, force=True)
    verdict = outcome.result["verdict"]
    # the tilts alone: whether the mixer's contact with the bowl's floor flickers long enough to
    # read as a lost contact varies from run to run (docs/kit.md)
    tilts = [c for c in verdict.get("failed_checks", []) if c.endswith(".tilt")]
    assert verdict["success"] or verdict.get("failed_checks") == ["relations"], verdict.get("failed_checks")
    assert not tilts, verdict.get("summary")
