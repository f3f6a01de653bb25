"""``oacc draft RECORDING``: a draft .oac scene whose geometry comes from the markers.

Synthetic recordings with known objects check the sizes (a box and a cylinder of known
size: within 2 mm; the dough demonstration's cups and bowl: within 2 cm, the table being
estimated from markers that sit up to 18 mm above it); every draft compiles and is in
canonical form.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

from oacdsl.cli import main
from oacdsl.segmentation.readers.c3d import write_c3d
from oacdsl.segmentation.recording import Recording
from oacdsl.segmentation.synth.scene import BOWL_RIM_RADIUS_M, TABLE_Z_M, hand_markers
from tests._draft_helpers import LIBRARY, check_draft, dims, run

ROOT = Path(__file__).resolve().parents[1]
DOUGH = ROOT / "data" / "dough.c3d"
TABLE_M = 0.80  # table top of the hand-made recording, metres
BOX_M = (0.24, 0.12, 0.08)  # length, width, height, metres
BOX_YAW_RAD = np.deg2rad(30.0)
CYLINDER_M = (0.04, 0.10)  # radius, height, metres


def hand_made(path: Path, *, objects: bool = True, hands: bool = True) -> Path:
    """A still scene on a table at 0.80 m: two hands, a box 24 x 12 x 8 cm turned 30° (three top
    corners and one bottom corner marked), a cylinder r 4 cm h 10 cm (four rim markers), a
    group of two markers, and a group whose label is no name ('my box')."""
    c, s = np.cos(BOX_YAW_RAD), np.sin(BOX_YAW_RAD)
    yaw = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
    length, width, height = BOX_M
    corners = np.array([[length / 2, width / 2, height], [-length / 2, width / 2, height],
                        [-length / 2, -width / 2, height], [length / 2, -width / 2, 0.0]])
    box = corners @ yaw.T + [0.10, 0.30, TABLE_M]
    radius, tall = CYLINDER_M
    angles = np.deg2rad([10.0, 95.0, 170.0, 260.0])
    cylinder = np.column_stack([radius * np.cos(angles), radius * np.sin(angles), np.full(4, tall)])
    cylinder += [-0.25, 0.35, TABLE_M]
    groups: dict[str, np.ndarray] = {
        "left_hand": hand_markers("left") + [-0.5, -0.3, TABLE_M + 0.3],
        "right_hand": hand_markers("right") + [0.5, -0.3, TABLE_M + 0.3],
    }
    if not hands:
        groups = {}
    if objects:
        tag = np.array([[0.4, 0.5, TABLE_M + 0.05], [0.42, 0.5, 0.85]])
        flaky = cylinder + [0.0, -0.6, 0.0]
        groups |= {"tray": box, "can": cylinder, "tag": tag, "my box": box + [0.0, 0.5, 0.0],
                   "flaky": flaky[:3]}
    names, points, index = [], [], {}
    for g, pts in groups.items():
        index[g] = tuple(range(len(names), len(names) + len(pts)))
        names += [f"{g}_{i}" for i in range(len(pts))]
        points.append(pts)
    frames = 30
    positions = np.repeat(np.concatenate(points)[None], frames, axis=0)
    if objects:  # 'flaky': its first two markers take turns, so never three are seen at once
        first = index["flaky"][0]
        positions[0::2, first] = np.nan
        positions[1::2, first + 1] = np.nan
    rec = Recording("hand-made", 100.0, np.arange(frames) / 100.0, tuple(names), positions, index)
    return write_c3d(rec, path)


def test_draft_sizes_a_box_and_a_cylinder_from_their_markers(capsys, tmp_path):
    code, text, err = run(capsys, "draft", str(hand_made(tmp_path / "still.c3d")))
    assert code == 0, err
    classes, scene = check_draft(text)
    written = tmp_path / "still.oac"
    assert run(capsys, "draft", str(tmp_path / "still.c3d"), "-o", str(written))[0] == 0
    assert written.read_text(encoding="utf-8") == text.replace("DRAFT.oac", str(written))
    assert run(capsys, "compile", str(written))[0] == 0
    assert run(capsys, "fmt", "--check", str(written))[0] == 0
    assert scene.name == "still" and scene.layout == "demonstrated"
    got = {i.name: (i.classes, i.markers, i.environment) for i in scene.instances}
    assert got == {
        "can": (("Can",), (), False), "tag": (("Tag",), (), False), "tray": (("Tray",), (), False),
        "my_box": (("MyBox",), tuple(f"my box:my box_{i}" for i in range(4)), False),
        "flaky": (("Flaky",), (), False),
        "left_hand": (("Hand",), (), False), "right_hand": (("Hand",), (), False),
        "table": (("Table",), (), True),
    }
    assert {"Hand", "Graspable", "Table", "Surface", "Container", "Tool"} <= set(classes)  # no library: bases
    tray = dims(classes["Tray"])
    assert classes["Tray"].geometry.shapes[0].primitive == "box"
    # x along the box's length; the hands stand along x (left at -x): the demonstrator faces +y,
    # the box's length lies 30° from +x, 60° from forward towards the right: turned -60deg
    assert [tray["length"], tray["width"], tray["height"]] == pytest.approx(BOX_M, abs=0.002)
    assert "#   tray at (x, y) turned -60deg" in text and "#   my_box at (x, y) turned -60deg" in text
    assert "can at (x, y) turned" not in text  # a cylinder is alike however turned
    can = dims(classes["Can"])
    assert classes["Can"].geometry.shapes[0].primitive == "cylinder"
    assert [can["radius"], can["height"]] == pytest.approx(CYLINDER_M, abs=0.002)
    # the markers in the object frame: origin at the base centre, x along the box's length, z up
    from oacdsl.geometry import point_si

    marks = np.array([point_si(p) for p in classes["Tray"].geometry.markers])
    l2, w2, h = BOX_M[0] / 2, BOX_M[1] / 2, BOX_M[2]
    np.testing.assert_allclose(np.abs(marks), [[l2, w2, h], [l2, w2, h], [l2, w2, h], [l2, w2, 0.0]],
                               atol=0.002)
    # mass from the volume at the stated density (300 kg/m³): 24 x 12 x 8 cm → 691 g
    assert classes["Tray"].geometry.mass.value == pytest.approx(0.24 * 0.12 * 0.08 * 300 * 1000, abs=1)
    # two markers: a class without geometry, and a comment saying why
    assert classes["Tag"].geometry is None and classes["Flaky"].geometry is None
    assert "tag: 2 marker(s); a shape needs at least 3" in text
    assert "flaky: 3 markers, but never more than 2 seen at once" in text
    assert "mass 691g = volume 2304 cm3 x 300 kg/m3" in text
    assert "table top stands at 800 mm" in text
    assert "(no sub-action found" in text and "Container" in text and "Tool" in text


def test_draft_of_the_dough_demonstration(capsys, tmp_path):
    code, text, err = run(capsys, "draft", str(DOUGH))
    assert code == 0, err
    classes, scene = check_draft(text)
    assert scene.name == "dough"
    by_instance = {i.name: i.classes[0] for i in scene.instances}
    assert by_instance == {"green_cup": "GreenCup", "red_cup": "RedCup", "orange_bowl": "OrangeBowl",
                           "mixer": "Mixer", "liquid_one": "LiquidOne", "liquid_two": "LiquidTwo",
                           "left_hand": "Hand", "right_hand": "Hand", "table": "Table"}
    # the synthetic objects' sizes (oacdsl/segmentation/synth/scene.py): cups and bowl 12 cm high,
    # the bowl's rim 33 cm across; the table is estimated 18 mm high (the bowl's low markers)
    assert "table top stands at 768 mm" in text and TABLE_Z_M == 0.75
    for cls in ("RedCup", "GreenCup", "OrangeBowl"):
        assert dims(classes[cls])["height"] == pytest.approx(0.12, abs=0.02), cls
    assert dims(classes["OrangeBowl"])["length"] == pytest.approx(2 * BOWL_RIM_RADIUS_M, abs=0.02)
    # rim to handle: its length (x), across the demonstrator (the handle to the side): turned
    assert dims(classes["RedCup"])["length"] == pytest.approx(0.048 + 0.095, abs=0.02)
    assert re.search(r"#   red_cup at \(x, y\) turned -8\ddeg", text)
    assert classes["LiquidOne"].geometry is None  # one marker
    subs = re.findall(r"^# sub-action (\d+) \(frames (\d+)-(\d+)\): (.*)$", text, re.M)
    assert [int(s[0]) for s in subs] == list(range(1, len(subs) + 1)) and len(subs) >= 6
    assert "+ left_hand <-> red_cup" in subs[0][3]
    assert "oacc compose" in text and "--propose" in text


def test_draft_with_a_library_writes_only_the_missing_classes(capsys, tmp_path):
    out = tmp_path / "dough_scene.oac"
    code, _, err = run(capsys, "draft", str(DOUGH), "--library", str(LIBRARY), "--out", str(out),
                       "--name", "dough2")
    assert code == 0, err
    assert "scene kitchen of the library has the same instances" in err
    assert f"wrote {out}: scene dough2, 8 instances (2 hands, 6 objects), 2 classes drafted" in err
    text = out.read_text(encoding="utf-8")
    classes, scene = check_draft(text, LIBRARY)
    assert set(classes) == {"LiquidOne", "LiquidTwo"}  # the library has no buildable liquid class
    # the library's classes whose name's words are in the group's name: Mixer, Cup, Bowl
    assert {i.name: i.classes[0] for i in scene.instances if i.name not in ("liquid_one", "liquid_two")} == {
        "mixer": "Mixer", "red_cup": "Cup", "green_cup": "Cup", "orange_bowl": "Bowl",
        "left_hand": "Hand", "right_hand": "Hand", "table": "Table"}
    assert "# class Cup comes from the library (its name's words are in the group's name)" in text
    assert f"--library {out} --library {LIBRARY} --scene dough2 --name NAME --propose" in text
    # without --force an existing file is kept; with it, replaced
    out.write_text("# mine\n", encoding="utf-8")
    code, _, err = run(capsys, "draft", str(DOUGH), "--library", str(LIBRARY), "-o", str(out), "--name", "d")
    assert code == 2 and "the file exists; give --force to replace it" in err
    assert out.read_text(encoding="utf-8") == "# mine\n"
    code, _, err = run(capsys, "draft", str(DOUGH), "--library", str(LIBRARY), "-o", str(out), "--force",
                       "--name", "d")
    assert code == 0 and "scene d {" in out.read_text(encoding="utf-8")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["dough_scene.oac"]  # no temporary file left
    # the scene's name must be free in the library
    code, _, err = run(capsys, "draft", str(DOUGH), "--library", str(LIBRARY), "--name", "kitchen")
    assert code == 2 and "the library already has a scene 'kitchen'" in err


@pytest.mark.parametrize(("argv", "code", "message"), [
    (["nowhere.c3d"], 2, "nowhere.c3d: no such recording file"),
    (["garbage.c3d"], 1, "garbage.c3d"),
    (["hands.c3d"], 1, "no object with markers: the marker groups are left_hand, right_hand"),
    (["hands.c3d", "--name", "scene"], 2, "--name 'scene': a scene name is letters"),
    (["hands.c3d", "--distance", "5g"], 2, "--distance"),
    (["hands.c3d", "--library", "nolib"], 2, "nolib: no such library folder or file"),
    (["hands.c3d", "-o", "hands.c3d", "--force"], 2, "--out names the recording itself"),
])
def test_draft_errors_are_one_line(capsys, tmp_path, monkeypatch, argv, code, message):
    monkeypatch.chdir(tmp_path)
    hand_made(tmp_path / "hands.c3d", objects=False)
    (tmp_path / "garbage.c3d").write_bytes(b"not a c3d file at all" * 20)
    got, out, err = run(capsys, "draft", *argv)
    assert got == code and out == ""
    assert err.startswith("oacc: error: ") and message in err and "Traceback" not in err
    assert len(err.strip().splitlines()) == 1


def test_draft_lists_the_sub_actions_as_match_counts_them(tmp_path):
    """A liquid briefly in flight (touching nothing for 0.5 s between cup and bowl) splits no sub-action."""
    from oacdsl.draft import draft_scene
    from oacdsl.segmentation.readers import read_recording
    from oacdsl.segmentation.result import Keyframe, Segmentation
    from oacdsl.world import WorldState

    rec = read_recording(hand_made(tmp_path / "still.c3d"))
    names = rec.instances
    states = [(0, [("tag", "tray")]), (100, []), (150, [("can", "tag")]),
              (500, [("can", "tag"), ("can", "left_hand")])]
    keyframes = tuple(Keyframe(f, f / 100.0, WorldState.of(names, pairs)) for f, pairs in states)
    seg = Segmentation("still", 100.0, 600, names, keyframes, {})
    draft = draft_scene(rec, seg, "still", hands=("left_hand", "right_hand"))
    assert re.findall(r"^# sub-action .*$", draft.text, re.M) == [
        "# sub-action 1 (frames 0-150): + can <-> tag, - tag <-> tray",
        "# sub-action 2 (frames 150-500): + can <-> left_hand",
    ]


def test_draft_default_name_is_never_a_keyword(capsys, tmp_path):
    code, text, err = run(capsys, "draft", str(hand_made(tmp_path / "scene.c3d")))
    assert code == 0, err
    assert check_draft(text)[1].name == "scene_scene"


def test_draft_without_hands_says_so(capsys, tmp_path):
    code, text, err = run(capsys, "draft", str(hand_made(tmp_path / "objects.c3d", hands=False)))
    assert code == 0 and "no marker group is a hand" in err
    _, scene = check_draft(text)
    assert "Hand" not in {c for i in scene.instances for c in i.classes}


def test_draft_help_has_examples(capsys):
    with pytest.raises(SystemExit):
        main(["draft", "--help"])
    text = capsys.readouterr().out
    assert "examples:" in text and "oacc draft Stir.mmm.xml --library library -o stir.oac" in text
    assert "--force" in text and "--preset" in text and "--allow-truncated" in text


def test_an_edited_draft_composes_the_dough_demonstration(capsys, tmp_path):
    """The workflow the draft is for: draft, choose the parents its comments offer, compose."""
    draft = tmp_path / "dough_scene.oac"
    code, _, err = run(capsys, "draft", str(DOUGH), "--library", str(LIBRARY), "-o", str(draft), "--name=d2")
    assert code == 0, err
    text = draft.read_text(encoding="utf-8")
    for cls, parents in (("LiquidOne", "Liquid"), ("LiquidTwo", "Liquid")):
        text = text.replace(f"class {cls} : Graspable", f"class {cls} : {parents}")
    draft.write_text(text, encoding="utf-8")
    assert run(capsys, "compile", str(draft), str(LIBRARY))[0] == 0
    code, out, err = run(capsys, "compose", str(DOUGH), "--library", str(draft), "--library", str(LIBRARY),
                         "--scene", "d2", "--name", "dough_again", "--dry-run")
    assert code == 0, err
    steps = re.findall(r"^        (\w+)\(", out, re.M)
    assert steps == ["grasp", "pour", "place", "grasp", "pour", "place", "grasp", "mix"]
    assert "Cup = red_cup" in out and "LiquidOne = liquid_one" in out  # the library's and the draft's classes


def test_names_of_instances_and_classes():
    from oacdsl.draft.names import camel_case, instance_name, unique

    assert instance_name("cup_small", set()) == ("cup_small", False)
    assert instance_name("table", {"table"}) == ("table2", True)  # the environment is 'table'
    assert instance_name("in", set()) == ("object_in", True)  # a keyword
    assert instance_name("3d box:", set()) == ("object_3d_box", True)
    assert instance_name("Tasse à café", set()) == ("tasse_caf", True)
    assert [camel_case(n) for n in ("cup_small", "mixing_bowl_green", "box2", "a__b")] == [
        "CupSmall", "MixingBowlGreen", "Box2", "AB"]
    assert unique("Cup", {"Cup", "Cup2"}) == "Cup3"


def test_draft_stands_a_lid_on_its_bottle_and_reuses_library_classes_by_name(capsys, tmp_path):
    """A lid on a bottle is drafted from the bottle's top, not as one tall box from the table;
    groups named like a library class with more words (``knife_black``) take that class."""
    table = 0.80
    bottle = np.array([[0.03, 0.0, 0.20], [-0.03, 0.0, 0.20], [0.0, 0.03, 0.20], [0.0, -0.03, 0.02]])
    bottle += [0.40, 0.10, table]
    lid = np.array([[0.015, 0.0, 0.025], [-0.015, 0.0, 0.025], [0.0, 0.015, 0.025], [0.0, -0.015, 0.005]])
    lid += [0.40, 0.10, table + 0.20]
    knife = np.array([[0.0, 0.0, 0.0], [0.10, 0.0, 0.01], [0.20, 0.01, 0.02]]) + [0.0, -0.2, table]
    groups = {"bottle": bottle, "lid": lid, "knife_black": knife,
              "left_hand": hand_markers("left") + [-0.5, -0.3, table + 0.3],
              "right_hand": hand_markers("right") + [0.5, -0.3, table + 0.3]}
    names, points, index = [], [], {}
    for g, pts in groups.items():
        index[g] = tuple(range(len(names), len(names) + len(pts)))
        names += [f"{g}_{i}" for i in range(len(pts))]
        points.append(pts)
    positions = np.repeat(np.concatenate(points)[None], 20, axis=0)
    rec = Recording("lid", 100.0, np.arange(20) / 100.0, tuple(names), positions, index)
    path = write_c3d(rec, tmp_path / "lid.c3d")
    kit = ROOT / "library" / "kit"
    code, text, err = run(capsys, "draft", str(path), "--library", str(kit))
    assert code == 0, err
    classes, scene = check_draft(text, kit)
    assert "# it stands on bottle at frame 0" in text
    lid_size = dims(classes["Lid"])
    assert lid_size["height"] == pytest.approx(0.025 - 0.0, abs=0.002)  # from the bottle's top, not the table
    assert dims(classes["Bottle"])["height"] == pytest.approx(0.20, abs=0.002)
    assert {i.name: i.classes[0] for i in scene.instances}["knife_black"] == "Knife"
    assert "Knife" not in classes  # the library's, not drafted again


def test_library_class_for_a_group_name():
    from oacdsl.draft.names import library_class_for

    options = ["Cup", "SmallCup", "CuttingBoard", "Knife", "SaladFork", "SaladSpoon"]
    assert library_class_for("cutting_board_small", options) == ("CuttingBoard", [])
    assert library_class_for("cup_small", options) == ("SmallCup", [])  # the most words
    assert library_class_for("salad_fork_spoon", options) == (None, ["SaladFork", "SaladSpoon"])
    assert library_class_for("bowl", options) == (None, [])


def test_a_drafted_box_lies_along_its_length_and_is_said_turned_from_the_demonstrators_forward(
        capsys, tmp_path):
    """x is the principal axis of the larger spread (its length); the scene says how far it is
    turned from the demonstrator's forward (from the hands), as 'turned' (before: x was the axis
    nearer forward, since objects could not be turned; estimate_shape still does that when given
    a forward direction); without a left and a right hand there is no forward to say it from."""
    from oacdsl.draft.estimate import estimate_shape
    from oacdsl.segmentation.readers import read_recording

    rec = read_recording(hand_made(tmp_path / "still.c3d"))
    plain = estimate_shape(rec, "tray", TABLE_M)
    facing = estimate_shape(rec, "tray", TABLE_M, np.array([0.0, 1.0]))
    assert (plain.length_m, plain.width_m) == pytest.approx(BOX_M[:2], abs=0.002) and not plain.facing
    assert (facing.length_m, facing.width_m) == pytest.approx(BOX_M[1::-1], abs=0.002) and facing.facing
    joined = re.sub(r"\n    #   (?!\w+ at)", " ", run(capsys, "draft", str(tmp_path / "still.c3d"))[1])
    said = "tray lies turned -60deg (its x, its length, from the demonstrator's forward towards the left)"
    assert said in joined
    assert "x the one nearer the demonstrator's forward" not in joined
    code, text, err = run(capsys, "draft", str(hand_made(tmp_path / "alone.c3d", hands=False)))
    assert code == 0, err
    tray = dims(check_draft(text)[0]["Tray"])
    assert [tray["length"], tray["width"]] == pytest.approx(BOX_M[:2], abs=0.002)
    assert "nearer the demonstrator" not in re.sub(r"\n#   ", " ", text) and "turned" not in text
