"""Skill parameters of composed steps from the demonstrated motion (oacdsl/matching/demoparams.py),
and the runtime passing a step's parameters to its skill (oacdsl/runtime/binding.py)."""

from __future__ import annotations

import json
import math
import shutil
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).parent))

from runtime_lib import STANDARD  # noqa: E402

from oacdsl.cli import main  # noqa: E402
from oacdsl.compiler import compile_sources, load_library, parse_text  # noqa: E402
from oacdsl.errors import RuntimeFailure  # noqa: E402
from oacdsl.library import Library  # noqa: E402
from oacdsl.matching.demoparams import CLEARANCE_M, room_m, step_params  # noqa: E402
from oacdsl.runtime.binding import expand  # noqa: E402
from oacdsl.segmentation.motion import SubActionMotion  # noqa: E402
from oacdsl.segmentation.motionfeatures import MotionFeatures  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
DOUGH = ROOT / "data" / "dough.c3d"


def motion(moved: str = "cup", target: str | None = None, **features: object) -> SubActionMotion:
    base = dict(duration_s=3.0, path_length_m=0.4, extent_m=(0.3, 0.1, 0.05), core_s=(0.0, 3.0),
                period_s=None, cycles=None, radius_m=0.1, tilt_max_rad=0.0, tilt_time_s=0.0, tilt_rise_s=None)
    base.update(features)
    t = np.arange(3) * 0.1
    return SubActionMotion(1, 10, 12, "left_hand", moved, target, None, t, np.full((3, 4, 4), np.nan),
                           MotionFeatures(**base), 0.0)  # type: ignore[arg-type]


@pytest.fixture(scope="module")
def lib():
    return load_library(list(STANDARD))


def values(found) -> dict[str, tuple[float, str]]:
    return {p.name: (p.value.value, p.value.unit) for p in found.params}


def test_a_pour_takes_the_demonstrated_tilt_and_a_scaled_duration(lib):
    m = motion(tilt_max_rad=math.radians(104.4), tilt_rise_s=0.8)
    found = step_params("pour", m, ("left_hand", "red_cup", "liquid_one", "orange_bowl"), lib,
                        lib.scenes["kitchen"])
    assert values(found) == {"tilt": (104.0, "deg"), "duration": (1.0, "s")}
    assert found.comment == ("demonstrated (cup relative to world): tilt 104deg as demonstrated;"
                             " duration 1s from tilt rise 0.80s, x1.25")
    assert [r["how"] for r in found.rows] == ["as demonstrated", "scaled x1.25"]


def test_values_outside_the_skills_range_are_clamped_and_said_so(lib):
    m = motion(tilt_max_rad=math.radians(20.0), tilt_rise_s=9.0)
    found = step_params("pour", m, ("left_hand", "red_cup", "liquid_one", "orange_bowl"), lib,
                        lib.scenes["kitchen"])
    assert values(found) == {"tilt": (30.0, "deg"), "duration": (10.0, "s")}
    assert "tilt 30deg from tilt 20deg, clamped to the skill's range" in found.comment
    assert "duration 10s from tilt rise 9.00s, x1.25, clamped to the skill's range" in found.comment


def test_a_stir_radius_is_clamped_to_the_room_in_the_container(lib):
    scene = lib.scenes["kitchen"]
    room = room_m(lib, scene, "orange_bowl", "mixer")  # bowl 11.5cm - wall 7mm, mixer base 36mm
    assert room == pytest.approx(0.115 - 0.007 - 0.036 - CLEARANCE_M)
    m = motion(moved="mixer", target="orange_bowl", radius_m=0.116, period_s=0.88, cycles=3.4)
    found = step_params("mix", m, ("right_hand", "mixer", "orange_bowl"), lib, scene)
    assert values(found) == {"radius": (67.0, "mm"), "period": (0.88, "s"), "turns": (3.0, "")}
    assert "radius 67mm from radius 116mm, clamped to the room on the target (67mm)" in found.comment
    assert "turns 3 = cycles 3.4" in found.comment


def test_without_an_oscillation_or_a_motion_the_skill_keeps_its_defaults(lib):
    scene = lib.scenes["kitchen"]
    args = ("right_hand", "mixer", "orange_bowl")
    found = step_params("mix", motion(moved="mixer", radius_m=0.116), args, lib, scene)
    assert found.params == ()
    assert found.comment == "skill defaults: the motion has no cycles; the motion has no period_s"
    found = step_params("mix", None, args, lib, scene)
    assert found.params == () and "fewer than 3 markers" in str(found.comment)
    assert step_params("reach_and_grasp", motion(), ("left_hand", "red_cup"), lib, scene).comment is None


def test_a_wipe_stroke_is_half_the_demonstrated_extent(lib):
    m = motion(moved="sponge", target="tray", extent_m=(0.1, 0.02, 0.01), period_s=0.67, cycles=2.5)
    found = step_params("wipe", m, ("left_hand", "sponge", "tray"), lib, lib.scenes["wiping"])
    assert values(found) == {"strokes": (2.0, ""), "length": (50.0, "mm")}


@pytest.fixture
def lib_dir(tmp_path: Path) -> Path:
    ignore = shutil.ignore_patterns("learned", "drafts")
    shutil.copytree(ROOT / "library", tmp_path / "library", ignore=ignore)
    return tmp_path / "library"


def test_compose_writes_the_demonstrated_pours_and_no_demo_params_does_not(capsys, lib_dir, tmp_path):
    assert main(["compose", str(DOUGH), "--library", str(lib_dir), "--name", "dough", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    params = [s.get("params") for s in doc["steps"]]
    pours = [p for s, p in zip(doc["steps"], params, strict=True) if s["oac"] == "pour"]
    # the dough's cups tilt 110deg and 109deg, rising (10-90 %) in 0.65 s and 0.60 s
    assert [round(math.degrees(p["tilt"])) for p in pours] == [110, 109]
    assert [p["duration"] for p in pours] == [0.81, 0.75]
    assert all(p is None for s, p in zip(doc["steps"], params, strict=True) if s["oac"] != "pour")
    text = (lib_dir / "learned" / "dough.oac").read_text()
    assert "pour(hand1, cup1, liquid1, bowl) { duration 0.81s  tilt 110deg }" in text
    assert "# demonstrated (red_cup relative to world): tilt 110deg as demonstrated;" in text
    assert "# skill defaults: the motion has no cycles" in text  # the mix: no oscillation before its keyframe
    learned = load_library([lib_dir]).oacs["dough"]
    plain_path = tmp_path / "plain.oac"
    assert main(["compose", str(DOUGH), "--library", str(lib_dir), "--name", "plain", "-o", str(plain_path),
                 "--no-demo-params"]) == 0
    plain = parse_text(plain_path.read_text(), str(plain_path)).decls[0]
    assert all(not c.skill_params for c in plain.steps) and "demonstrated" not in plain_path.read_text()
    # the only difference: the pours' parameters
    assert (plain.pre, plain.effect, plain.params) == (learned.pre, learned.effect, learned.params)
    assert [c.model_copy(update={"skill_params": ()}) for c in learned.steps] == list(plain.steps)


def test_the_executor_passes_a_steps_parameters_over_the_oacs(lib):
    text = """oac p2(h: Hand = left_hand, c: Cup = red_cup, l: Liquid = liquid_one, b: Bowl = orange_bowl) {
    pre h <-> nothing, c <-> l
    effect l <-> b
    steps {
        grasp(h, c)
        pour(h, c, l, b) { tilt 100deg }
        pourq(h, c, l, b) { duration 3s }
    }
}
oac pourq(h: Hand, c: Container, l: Liquid, b: Container) {
    pre h <-> c, c <-> l
    effect l <-> b, not c <-> l
    execute pour { duration 1s  height 6cm }
}
oac outer(h: Hand = left_hand, c: Cup = red_cup, l: Liquid = liquid_one, b: Bowl = orange_bowl) {
    pre h <-> nothing, c <-> l
    effect l <-> b
    steps { p2(h, c, l, b) { tilt 90deg } }
}
"""
    sources = {str(p): p.read_text() for p in STANDARD}
    result = compile_sources({**sources, "t.oac": text})
    assert [d.code for d in result.errors] == ["E047"]
    library = Library(result.modules)
    steps, _ = expand(library, library.oacs["p2"], {"h": "left_hand", "c": "red_cup", "l": "liquid_one",
                                                    "b": "orange_bowl"})
    pour, pourq = steps[1], steps[2]
    assert pour.params["tilt"] == pytest.approx(math.radians(100)) and pour.params["duration"] == 1.8
    assert pour.given == pytest.approx({"tilt": math.radians(100)})
    # the step's duration over the OAC's, the OAC's height kept
    assert pourq.params["duration"] == 3.0 and pourq.params["height"] == pytest.approx(0.06)
    assert steps[0].given == {}
    with pytest.raises(RuntimeFailure, match="p2 is composed: a step calling it takes no skill parameters"):
        expand(library, library.oacs["outer"], {"h": "left_hand", "c": "red_cup", "l": "liquid_one",
                                                "b": "orange_bowl"})
