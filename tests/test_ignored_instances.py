"""A marker group nobody uses (a rack) marked ``ignored``: the recording's group is dropped before
segmenting, the scene is still found by its instances, and matching sees only the tracked ones."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from oacdsl.cli import main
from oacdsl.compiler import load_library, parse_text
from oacdsl.library import Library
from oacdsl.matching.demonstration import find_scene
from oacdsl.segmentation.readers import read_recording

ROOT = Path(__file__).resolve().parents[1]
STANDARD = sorted((ROOT / "library").glob("*.oac"))

RACK_SCENE = """\
class Rack

scene kitchen_with_rack {
    green_cup, red_cup     : Cup
    left_hand, right_hand  : Hand
    liquid_one, liquid_two : Liquid
    mixer                  : Mixer
    orange_bowl            : Bowl
    rack                   : Rack ignored
    table                  : Table environment
}
"""


def _dough_with_a_rack(path: Path) -> None:
    """The bundled demonstration as CSV (``group:marker`` columns, metres) plus a still rack."""
    rec = read_recording(ROOT / "data" / "dough.c3d")
    names = [*rec.marker_names, "rack:R1", "rack:R2", "rack:R3"]
    rack = np.array([[0.9, 0.6, 0.8], [0.95, 0.6, 0.8], [0.9, 0.65, 0.8]])
    pos = np.concatenate([rec.positions_m, np.broadcast_to(rack, (rec.n_frames, 3, 3))], axis=1)
    header = ["time"] + [f"{n}_{a}" for n in names for a in "xyz"]
    rows = [",".join(header)]
    for f in range(rec.n_frames):
        values = ["" if not np.isfinite(v) else f"{v:.5f}" for v in pos[f].ravel()]
        rows.append(f"{rec.times_s[f]:.4f}," + ",".join(values))
    path.write_text("# units: m\n# rate_hz: 100\n" + "\n".join(rows) + "\n", encoding="utf-8")


def test_the_scene_is_found_by_its_tracked_instances_plus_its_ignored_groups():
    lib = Library([*load_library(STANDARD).modules, parse_text(RACK_SCENE, "rack.oac")])
    groups = [*(i.name for i in lib.scenes["kitchen"].tracked()), "rack"]
    assert find_scene(lib, groups).name == "kitchen_with_rack"
    assert find_scene(lib, groups[:-1]).name == "kitchen"


def test_match_drops_the_ignored_marker_group(tmp_path, capsys):
    demo, scene = tmp_path / "dough_rack.csv", tmp_path / "rack.oac"
    _dough_with_a_rack(demo)
    scene.write_text(RACK_SCENE, encoding="utf-8")
    lib = tmp_path / "library"
    lib.mkdir()
    for p in STANDARD:
        (lib / p.name).write_text(p.read_text(encoding="utf-8"), encoding="utf-8")
    code = main(["match", str(demo), "--library", str(lib), "--scene", str(scene)])
    out = capsys.readouterr()
    assert code == 0, out.err
    assert "scene kitchen_with_rack): 8 matched, 0 unmatched" in out.out
    assert "rack" not in out.out.split("sub-actions")[0]  # no relation of the rack anywhere
