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
    tracked = ["green_cup", "left_hand", "liquid_one", "liquid_two", "mixer", "orange_bowl", "red_cup",
               "right_hand"]
    doc = {"recording": "x.c3d", "rate_hz": 100.0, "frames": 10, "instances": tracked,
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


def test_a_recognised_marker_set_groups_the_recording_and_is_noted(tmp_path: Path):
    from oacdsl.segmentation.grouping import KIT_HANDS

    markers = [m for hand in KIT_HANDS.values() for m in hand] + ["LKNE", "cup_1", "cup_2"]
    header = "frame,time," + ",".join(f"{m}_{a}" for m in markers for a in "xyz")
    rows = [f"{f},{f / 10:.1f}," + ",".join(f"{0.01 * i + 0.001 * f:.4f}" for i in range(3 * len(markers)))
            for f in range(10)]
    csv = tmp_path / "kit.csv"
    csv.write_text("# rate_hz: 10\n" + header + "\n" + "\n".join(rows) + "\n", encoding="utf-8")
    scene = tmp_path / "kit_scene.oac"
    scene.write_text("scene kit_demo {\n  left_hand, right_hand : Hand\n  cup : Cup\n  LKNE : Table\n}\n",
                     encoding="utf-8")
    notes: list[str] = []
    inputs = load_inputs(csv, LIBRARY, str(scene), AasParams(), note=notes.append)
    assert inputs.outside_scene == scene and inputs.scene.name == "kit_demo"
    assert inputs.recording is not None and sorted(inputs.recording.instances) == [
        "LKNE", "cup", "left_hand", "right_hand"]
    assert len(notes) == 1 and notes[0].startswith(f"{csv}: marker set 'kit' recognised (left_hand = ")
    with pytest.raises(InputError, match="are not tracked instances of scene 'kit_demo'"):
        load_inputs(csv, LIBRARY, str(scene), AasParams(), preset="none", note=notes.append)
    assert len(notes) == 1
