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


POUR = ("left_hand", "red_cup", "liquid_one", "orange_bowl")


def test_a_pour_takes_the_demonstrated_tilt_and_a_scaled_duration(lib):
    m = motion(tilt_max_rad=math.radians(140.4), tilt_rise_s=0.8)
    found = step_params("pour", m, POUR, lib, lib.scenes["kitchen"])
    assert values(found) == {"tilt": (140.0, "deg"), "duration": (1.0, "s")}
    assert found.comment == ("demonstrated (cup relative to world, frames 10-12): tilt 140deg as"
                             " demonstrated; duration 1s from tilt rise 0.80s, x1.25")
    assert [r["how"] for r in found.rows] == ["as demonstrated", "scaled x1.25"]


def test_a_tilt_below_what_empties_the_robots_cup_is_raised(lib):
    # people pour liquids at 90-110 deg; the robot's balls leave its cup reliably from 125 deg on
    found = step_params("pour", motion(tilt_max_rad=math.radians(110.2), tilt_rise_s=0.65), POUR, lib,
                        lib.scenes["kitchen"])
    assert values(found) == {"tilt": (125.0, "deg"), "duration": (0.81, "s")}
    assert "tilt 125deg from tilt 110deg, raised to the robot's least (125deg)" in found.comment
    assert found.rows[0]["how"] == "raised to the robot's least"
    assert found.rows[0]["demonstrated"] == pytest.approx(math.radians(110.2))


def test_values_outside_the_skills_range_are_clamped_and_said_so(lib):
    m = motion(tilt_max_rad=math.radians(179.9), tilt_rise_s=9.0)
    found = step_params("pour", m, POUR, lib, lib.scenes["kitchen"])
    assert values(found) == {"tilt": (180.0, "deg"), "duration": (10.0, "s")}
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


def test_a_wipe_stroke_goes_sqrt2_times_the_median_radius(lib):
    m = motion(moved="sponge", target="tray", radius_m=0.035, period_s=0.67, cycles=2.6)
    found = step_params("wipe", m, ("left_hand", "sponge", "tray"), lib, lib.scenes["wiping"])
    assert values(found) == {"strokes": (3.0, ""), "length": (49.0, "mm")}  # 1.41 x 35mm


def test_a_saw_stroke_goes_along_the_blade_not_clamped_to_the_targets_room(lib):
    # a knife's strokes pass over the target (a cucumber 4.5 cm wide): only the blade bounds
    # them (the skill does), where a wipe's stroke is clamped to the room on the target
    scene = lib.scenes["kitchen"]
    m = motion(moved="mixer", target="orange_bowl", radius_m=0.06, period_s=1.28, cycles=3.3)
    found = step_params("saw", m, ("right_hand", "mixer", "orange_bowl"), lib, scene)
    assert values(found) == {"strokes": (3.0, ""), "length": (85.0, "mm"), "period": (1.28, "s")}
    assert "clamped" not in str(found.comment)
    wipe = step_params("wipe", m, ("right_hand", "mixer", "orange_bowl"), lib, scene)
    assert values(wipe)["length"] == (67.0, "mm")  # the room in the bowl


def test_a_tip_out_takes_the_demonstrated_tilt_relative_to_the_container(lib):
    # KIT Scoop: the ladle tipped 125 deg relative to the cup it scooped into, its rise in 0.69 s
    scene = lib.scenes["kitchen"]
    args = ("right_hand", "mixer", "red_cup", "orange_bowl")
    m = motion(moved="mixer", target="red_cup", tilt_max_rad=math.radians(124.6), tilt_rise_s=0.69)
    found = step_params("tip_out", m, args, lib, scene)
    assert values(found) == {"tilt": (125.0, "deg"), "duration": (0.86, "s")}
    # no tilt demonstrated (no rise found): the skill's defaults
    assert step_params("tip_out", motion(moved="mixer", target="red_cup"), args, lib, scene).params == ()


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
    # the dough's cups tilt 110deg and 109deg (raised to the robot's 125deg), rising (10-90 %)
    # in 0.65 s and 0.60 s
    assert [round(math.degrees(p["tilt"])) for p in pours] == [125, 125]
    tilts = [r["demonstrated"] for d in doc["demo_params"] for r in d["params"] if r["name"] == "tilt"]
    assert [round(math.degrees(t)) for t in tilts] == [110, 109]
    assert [p["duration"] for p in pours] == [0.81, 0.75]
    assert all(p is None for s, p in zip(doc["steps"], params, strict=True) if s["oac"] != "pour")
    text = (lib_dir / "learned" / "dough.oac").read_text()
    assert "pour(hand1, cup1, liquid1, bowl) { duration 0.81s  tilt 125deg }" in text
    assert ("# demonstrated (red_cup relative to world, frames 207-505): tilt 125deg from tilt 110deg,"
            " raised to the robot's least (125deg); duration 0.81s from tilt rise 0.64s, x1.25") in text
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
    with pytest.raises(RuntimeFailure, match="p2 is composed: .* 2 steps take .tilt."):
        expand(library, library.oacs["outer"], {"h": "left_hand", "c": "red_cup", "l": "liquid_one",
                                                "b": "orange_bowl"})


def test_a_made_relation_takes_the_motion_while_it_lasts():
    # a spoon enters the cup (made), circles in it (kept), leaves (broken): the step that
    # makes the relation executes the stir, so its motion spans all three sub-actions
    from types import SimpleNamespace

    from oacdsl.matching.demoparams import dwelling

    t = np.arange(0, 6.0, 0.1)
    T_spoon = np.tile(np.eye(4), (len(t), 1, 1))
    circling = (t >= 1.0) & (t < 5.0)
    T_spoon[:, 0, 3] = np.where(circling, 0.016 * np.cos(2 * np.pi * t / 0.5), 0.2)
    T_spoon[:, 1, 3] = np.where(circling, 0.016 * np.sin(2 * np.pi * t / 0.5), 0.0)
    # only the frame times and the poses are read
    cup = SimpleNamespace(T_world_object=np.tile(np.eye(4), (len(t), 1, 1)))
    spoon = SimpleNamespace(T_world_object=T_spoon)
    rec = SimpleNamespace(times_s=t)

    def m(a: int, b: int, relation: str) -> SubActionMotion:
        return SubActionMotion(0, a, b, "right_hand", "spoon", "cup", relation, t[a:b + 1],
                               T_spoon[a:b + 1], None, 0.0)

    motions = [m(0, 12, "made"), m(12, 48, "kept"), m(48, 55, "broken")]
    longer = dwelling(rec, motions, 0, {"cup": cup, "spoon": spoon})
    assert (longer.start_frame, longer.end_frame) == (0, 55)
    assert longer.features.period_s == pytest.approx(0.5, abs=0.03)
    assert longer.features.radius_m == pytest.approx(0.016, abs=0.002)
    assert dwelling(rec, motions, 1, {"cup": cup, "spoon": spoon}) is motions[1]  # kept: unchanged
    # nothing breaks it: to the recording's end
    assert dwelling(rec, motions[:2], 0, {"cup": cup, "spoon": spoon}).end_frame == len(t) - 1


def test_two_tools_made_together_take_the_motion_of_either():
    # a fork and a spoon go into the bowl at once (made, the fork moved most); then the
    # spoon circles in it (kept, the spoon moved most): the step that put both in mixes,
    # so it takes the circling that follows although the moved object differs
    from types import SimpleNamespace

    from oacdsl.matching.demoparams import dwelling
    from oacdsl.segmentation.motionfeatures import motion_features

    t = np.arange(0, 6.0, 0.1)
    still = np.tile(np.eye(4), (len(t), 1, 1))
    T_spoon = still.copy()
    circling = t >= 1.2
    T_spoon[:, 0, 3] = np.where(circling, 0.04 * np.cos(2 * np.pi * t / 0.9), 0.2)
    T_spoon[:, 1, 3] = np.where(circling, 0.04 * np.sin(2 * np.pi * t / 0.9), 0.0)
    posed = {n: SimpleNamespace(T_world_object=T) for n, T in
             (("bowl", still), ("fork", still.copy()), ("spoon", T_spoon))}
    rec = SimpleNamespace(times_s=t)
    made = SubActionMotion(1, 0, 12, "left_hand", "fork", "bowl", "made", t[:13], still[:13], None, 0.0)
    kept = SubActionMotion(2, 12, 58, "right_hand", "spoon", "bowl", "kept", t[12:59], T_spoon[12:59],
                           motion_features(t[12:59], T_spoon[12:59]), 0.0)
    # alone, the fork's sub-action is not followed by one of the fork: unchanged
    assert dwelling(rec, [made, kept], 0, posed) is made
    both = dwelling(rec, [made, kept], 0, posed, frozenset({"fork", "spoon"}))
    assert both.moved == "spoon" and both.features is not None
    assert both.features.period_s == pytest.approx(0.9, abs=0.05)
    assert both.features.radius_m == pytest.approx(0.04, abs=0.005)


def test_a_parameter_on_a_step_calling_a_composed_oac_goes_to_the_one_step_inside_that_takes_it(lib):
    """``outer``'s ``{ tilt 90deg }`` reaches the pour inside ``twice`` (over the step's own
    ``tilt 100deg``: the caller decides); ``duration``, which both pours inside take, is E047."""
    params = "h: Hand = left_hand, c: Cup = red_cup, l: Liquid = liquid_one, b: Bowl = orange_bowl"
    text = """oac twice(PARAMS) {
    pre h <-> nothing, c <-> l
    effect l <-> b
    steps {
        grasp(h, c)
        pour(h, c, l, b) { tilt 100deg }
    }
}
oac outer(PARAMS) {
    pre h <-> nothing, c <-> l
    effect l <-> b
    steps { twice(h, c, l, b) { tilt 90deg } }
}
oac nested(PARAMS) {
    pre h <-> nothing, c <-> l
    effect l <-> b
    steps { outer(h, c, l, b) { lift 3cm } }
}
""".replace("PARAMS", params)
    sources = {str(p): p.read_text() for p in STANDARD}
    result = compile_sources({**sources, "t.oac": text})
    assert result.errors == []
    library = Library(result.modules)
    binding = {"h": "left_hand", "c": "red_cup", "l": "liquid_one", "b": "orange_bowl"}
    grasp, pour = expand(library, library.oacs["nested"], binding)[0]
    assert pour.given == pytest.approx({"tilt": math.radians(90)})
    assert grasp.given == pytest.approx({"lift": 0.03})
    bad = text.replace("{ tilt 90deg }", "{ tilt 90deg  strokes 3 }") + """oac two(PARAMS) {
    pre h <-> nothing, c <-> l
    effect l <-> b
    steps {
        twice(h, c, l, b)
        twice(h, c, l, b)
    }
}
oac three(PARAMS) {
    pre h <-> nothing, c <-> l
    effect l <-> b
    steps { two(h, c, l, b) { tilt 5deg } }
}
""".replace("PARAMS", params)
    errors = compile_sources({**sources, "t.oac": bad}).errors
    messages = sorted(e.message for e in errors if e.code == "E047")
    assert any("no step inside it executes a skill that takes 'strokes'" in m for m in messages)
    assert any("more than one step inside it executes a skill that takes 'tilt'" in m for m in messages)
    with pytest.raises(RuntimeFailure, match="2 steps take 'tilt'"):
        bad_library = Library(compile_sources({**sources, "t.oac": bad}).modules)
        expand(bad_library, bad_library.oacs["three"], binding)


@pytest.mark.mocap
def test_a_parameter_is_measured_on_the_steps_own_pair_of_objects(tmp_path):
    """KIT Wipe at twice the speed (10 Hz): the sponge leaving the plate and the plate reaching
    the rack are one keyframe, so ``lift_sponge`` and ``set_into_rack`` share a sub-action whose
    motion (the object that travels farthest) is the sponge's against the plate. The tilt of
    ``set_into_rack(h, plate, rack)`` is the plate's in the rack, by the skill's roles (held
    object relative to target), as in the original: 97°, not the sponge's 68° against the plate."""
    from _mocap import mocap_file

    from oacdsl import api
    from oacdsl.segmentation import AasParams
    from oacdsl.segmentation.readers import read_recording, write_recording
    from oacdsl.segmentation.takes import STANDARD_TAKES

    path = mocap_file("kit_bimanual/Wipe_files_motions_3091_Wipe1_pl_sp_front_angle_03.mmm.xml")
    fast = write_recording(STANDARD_TAKES["double_speed"](read_recording(path))[0], tmp_path / "w.mmm.xml")
    tilts = {}
    # the original as recorded; at twice the speed; with a merge window longer than the 0.3 s
    # between the sponge's leaving and the plate's arrival (one keyframe, whatever the take)
    for name, source, params in (("original", path, None), ("fast", fast, None),
                                 ("merged", path, AasParams(merge_s=0.5))):
        demo = api.load_demonstration(source, ROOT / "library" / "kit", params=params)
        composed = api.compose(demo, "w")
        names = [s.oac.name for s in composed.composition.steps]
        k = names.index("set_into_rack")
        shared = composed.composition.steps[k].start_frame == composed.composition.steps[k - 1].start_frame
        assert names[k - 1] == "lift_sponge" and shared == (name != "original"), name
        call = (composed.oac.steps or ())[k]
        assert "plate_dish relative to draining_rack" in call.comments[-1], call.comments
        tilts[name] = {p.name: p.value.value for p in call.skill_params}["tilt"]
    assert tilts["fast"] == tilts["original"] == 97.0 and 80.0 <= tilts["merged"] <= 110.0, tilts


def test_a_skill_names_the_pair_its_parameters_are_measured_on():
    from oacdsl.skills import SIGNATURES

    assert SIGNATURES["touch"].measured_pair(("h", "plate", "rack")) == ("plate", "rack")
    # a ladle tipped out over the cup, then brought into the bowl: its tilt is over the cup
    assert SIGNATURES["tip_out"].measured_pair(("h", "ladle", "cup", "bowl")) == ("ladle", "cup")
    assert SIGNATURES["touch"].measured_pair(("h", "plate")) is None
