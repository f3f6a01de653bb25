"""Marker groups: prefixes, explicit mappings, scenes, the KIT preset."""

from __future__ import annotations

import re

import numpy as np
import pytest
from _mocap import mocap_file

from oacdsl.errors import RecordingError
from oacdsl.model import Instance, Scene
from oacdsl.segmentation.grouping import (
    KIT_HANDS,
    apply_preset,
    apply_scene_groups,
    prefix_groups,
    with_mapping,
)
from oacdsl.segmentation.readers import read_recording
from oacdsl.segmentation.recording import Recording


def rec(names: tuple[str, ...], groups=None) -> Recording:
    pos = np.arange(4 * len(names) * 3, dtype=float).reshape(4, len(names), 3)
    return Recording("demo.c3d", 100.0, np.arange(4) / 100.0, names, pos, groups or {})


def test_prefix_groups_colon_then_underscore():
    assert prefix_groups(["boite:a", "boite:b", "Daphnee:WRIST", "loose"]) == {
        "boite": ["boite:a", "boite:b"], "Daphnee": ["Daphnee:WRIST"]}
    assert prefix_groups(["pillow_top", "pillow_left", "hand", "thumb_tip"]) == {
        "pillow": ["pillow_top", "pillow_left"], "hand": ["hand"], "thumb": ["thumb_tip"]}


def test_mapping_by_label_bare_name_and_glob():
    r = rec(("boite:a", "boite:b", "hand:x", "cup_1", "cup_2"))
    out = with_mapping(r, {"box": ["a", "boite:b"], "cup": ["cup_*"], "hand": ["x"]})
    assert out.groups == {"box": (0, 1), "cup": (3, 4), "hand": (2,)}
    np.testing.assert_array_equal(out.positions_m, r.positions_m)


def test_mapping_errors_name_the_file_instance_and_marker():
    r = rec(("boite:a", "hand:a", "cup_1"))
    expected = "demo.c3d: instance 'cup': marker 'cup_9' is not in the recording (did you mean 'cup_1'?)"
    with pytest.raises(RecordingError, match=re.escape(expected)):
        with_mapping(r, {"cup": ["cup_9"]})
    with pytest.raises(RecordingError, match="marker 'a' is ambiguous"):
        with_mapping(r, {"x": ["a"]})
    with pytest.raises(RecordingError, match=re.escape("marker 'lid_*' is not in the recording")):
        with_mapping(r, {"lid": ["lid_*"]})


def scene(*instances: Instance) -> Scene:
    return Scene(name="kitchen", instances=instances)


def test_scene_groups_markers_names_and_environment():
    r = rec(("cup_1", "cup_2", "hand_a", "table_1"), {"cup": (0, 1), "hand": (2,), "table": (3,)})
    s = scene(
        Instance(name="red_cup", classes=("Cup",), markers=("cup_1", "cup_2")),
        Instance(name="hand", classes=("Hand",)),
        Instance(name="table", classes=("Table",), environment=True),
    )
    out = apply_scene_groups(r, s)
    assert out.groups == {"hand": (2,), "red_cup": (0, 1)}  # table dropped, unnamed groups dropped


def test_scene_instance_without_markers_is_an_error_listing_groups():
    r = rec(("cup_1", "hand_a"), {"cup": (0,), "hand": (1,)})
    with pytest.raises(RecordingError) as err:
        apply_scene_groups(r, scene(Instance(name="green_cup", classes=("Cup",))))
    assert str(err.value) == (
        "demo.c3d: scene 'kitchen': instance 'green_cup' has no marker group in the recording and lists"
        " no markers (groups in the recording: cup, hand)"
    )
    with pytest.raises(RecordingError, match="instance 'red_cup': marker 'cup_7'"):
        apply_scene_groups(r, scene(Instance(name="red_cup", classes=("Cup",), markers=("cup_7",))))


def test_kit_preset_on_synthetic_names():
    body = ("C7", *KIT_HANDS["left_hand"], *KIT_HANDS["right_hand"], "LKNE")
    r = rec((*body, "sc_01", "sc_02"), {"subject_1": tuple(range(len(body))), "cup_small": (12, 13)})
    out = apply_preset(r, "kit")
    assert out.groups == {"cup_small": (12, 13), "left_hand": (1, 2, 3, 4, 5), "right_hand": (6, 7, 8, 9, 10)}
    with pytest.raises(RecordingError, match="unknown marker preset 'kti' \\(did you mean 'kit'\\?\\)"):
        apply_preset(r, "kti")
    with pytest.raises(RecordingError, match="preset 'kit': instance 'left_hand': marker 'LHPS'"):
        apply_preset(rec(("C7", "sc_01")), "kit")


@pytest.mark.mocap
def test_kit_preset_on_a_real_clip():
    path = next(mocap_file("kit_bimanual").glob("Stir_*.mmm.xml"))
    out = apply_preset(read_recording(path), "kit")
    assert out.instances == ("cup_large", "left_hand", "right_hand", "tablespoon")
    assert [out.marker_names[i] for i in out.groups["right_hand"]] == list(KIT_HANDS["right_hand"])


def test_kit_marker_set_is_recognised_unasked():
    from oacdsl.segmentation.grouping import group_recording, recognise_preset

    body = tuple(m for hand in KIT_HANDS.values() for m in hand) + ("C7", "LKNE")
    names = (*body, "cup_01", "cup_02")
    subject = {"subject_7": tuple(range(len(body))), "cup": (len(body), len(body) + 1)}
    found, preset = recognise_preset(rec(names, subject))
    assert preset == "kit" and set(found.groups) == {"cup", "left_hand", "right_hand"}
    assert [found.marker_names[i] for i in found.groups["left_hand"]] == list(KIT_HANDS["left_hand"])
    # one hand's markers missing: nothing recognised, the file's groups stay
    partial = tuple(n for n in names if n != "RWTS")
    same, preset = recognise_preset(rec(partial, {"cup": (len(partial) - 2, len(partial) - 1)}))
    assert preset is None and set(same.groups) == {"cup"}
    # a recording that names its hands already keeps them
    named = {"left_hand": (0,), "cup": (len(body), len(body) + 1)}
    assert recognise_preset(rec(names, named))[1] is None
    # the command line: a named preset, none (the file's groups), or unset (recognised)
    assert set(group_recording(rec(names, subject), "none")[0].groups) == {"subject_7", "cup"}
    assert group_recording(rec(names, subject), "kit")[1] is None
    assert group_recording(rec(names, subject), None)[1] == "kit"
    with pytest.raises(RecordingError, match=r"unknown marker preset 'nones' \(did you mean 'none'\?\)"):
        group_recording(rec(names, subject), "nones")
