"""One input loader for reproduce, match and compose: the same checks and messages."""

from __future__ import annotations

import json
from dataclasses import replace
from pathlib import Path

import pytest

from oacdsl.cli import main
from oacdsl.errors import InputError, MatchingError, UsageError
from oacdsl.pipeline.inputs import Inputs, load_inputs
from oacdsl.segmentation.params import AasParams
from oacdsl.segmentation.readers import read_recording
from oacdsl.segmentation.readers.c3d import write_c3d

ROOT = Path(__file__).resolve().parents[1]
LIBRARY = ROOT / "library"


@pytest.fixture(scope="module")
def whisk(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The bundled demonstration's first 50 frames, the mixer's markers renamed 'whisk'."""
    rec = read_recording(ROOT / "data" / "dough.c3d")
    names = tuple(n.replace("mixer:", "whisk:") for n in rec.marker_names)
    short = replace(rec, marker_names=names, groups={}, times_s=rec.times_s[:50],
                    positions_m=rec.positions_m[:50])
    return write_c3d(short, tmp_path_factory.mktemp("inputs") / "whisk.c3d")


def test_the_tracked_instance_check_is_one_for_every_command(whisk: Path, capsys):
    for segmentations in (False, True):
        with pytest.raises(InputError, match="marker groups whisk are not tracked instances of scene 'k"):
            load_inputs(whisk, LIBRARY, "kitchen", AasParams(), segmentations=segmentations)
    with pytest.raises(MatchingError, match="no scene"):  # no scene has a whisk
        load_inputs(whisk, LIBRARY, None, AasParams())
    assert main(["match", str(whisk), "--library", str(LIBRARY), "--scene", "kitchen"]) == 2
    assert "marker groups whisk are not tracked" in capsys.readouterr().err


def test_a_segmentation_is_an_input_of_match_not_of_reproduce(tmp_path: Path):
    doc = {"recording": "x.c3d", "rate_hz": 100.0, "frames": 10, "instances": ["left_hand", "red_cup"],
           "keyframes": [{"frame": 0, "time_s": 0.0, "relations": []},
                         {"frame": 5, "time_s": 0.05, "relations": [["left_hand", "red_cup"]]}]}
    path = tmp_path / "seg.json"
    path.write_text(json.dumps(doc), encoding="utf-8")
    inputs = load_inputs(path, LIBRARY, "kitchen", AasParams(), segmentations=True)
    assert inputs.recording is None and inputs.segmented() is inputs.segmentation
    assert len(inputs.segmented().keyframes) == 2
    with pytest.raises(UsageError, match="needs the motion capture"):
        inputs.motion_capture()
    with pytest.raises(UsageError, match="is a segmentation already"):
        load_inputs(path, LIBRARY, "kitchen", AasParams(), preset="kit", segmentations=True)
    with pytest.raises(TypeError, match="exactly one"):
        Inputs(inputs.library, inputs.library_path, inputs.scene, inputs.source, inputs.params)
