"""Scoring tool–target contacts during the main action, cross-hand frames; the KIT development clips."""

from __future__ import annotations

import numpy as np
import pytest
from _mocap import mocap_file
from segeval.evaluate import Score, contact_from_labels, nearest_object, read_labels, score_clip
from segeval.toolscore import KIT_TOOL_TARGETS, cross_hand_frames, score_tools

from oacdsl.segmentation import segment
from oacdsl.segmentation.grouping import recognise_preset
from oacdsl.segmentation.readers import read_recording
from oacdsl.segmentation.recording import Recording
from oacdsl.segmentation.result import Keyframe, Segmentation
from oacdsl.world import WorldState

INSTANCES = ("board", "cup", "left_hand", "right_hand", "spoon")
DEVELOPMENT = ("Pour", "Stir", "Mix", "Wipe", "Scoop", "Cut")


def seg(frames: int, changes: list[tuple[int, list[tuple[str, str]]]]) -> Segmentation:
    kfs = tuple(Keyframe(f, f / 10.0, WorldState.of(INSTANCES, rel)) for f, rel in changes)
    return Segmentation("clip", 10.0, frames, INSTANCES, kfs)


def test_tool_contacts_in_the_widened_main_action_window():
    held = [("cup", "left_hand"), ("right_hand", "spoon")]
    s = seg(40, [(0, [("board", "cup")]),
                 (5, [("board", "cup"), *held]),
                 (8, [("board", "cup"), ("cup", "spoon"), *held]),        # 2 frames before Stir: in window
                 (20, [("board", "cup"), ("board", "spoon"), *held]),     # 2 frames: a flicker
                 (22, [("board", "cup"), *held, ("cup", "right_hand")]),  # cross-hand, 6 frames
                 (28, [("board", "cup")])])
    labels = {"left_hand": ["Idle"] * 5 + ["Hold"] * 23 + ["Idle"] * 12,
              "right_hand": ["Idle"] * 5 + ["Move"] * 5 + ["Stir"] * 10 + ["Place"] * 8 + ["Idle"] * 12}
    result = score_tools("Stir", s, labels, [("spoon", "cup")], tolerance=3, min_s=0.3)
    assert result.window == (7, 23)
    assert result.predicted == [("spoon", "cup")] and result.other == [("board", "cup")]
    assert (result.score.matched, result.score.predicted, result.score.labelled) == (1, 1, 1)
    assert result.coverage == {("spoon", "cup"): 1.0}
    # a flicker shorter than min_s is no contact; a longer one of the tool elsewhere is a false one
    longer = score_tools("Stir", s, labels, [("spoon", "cup")], tolerance=3, min_s=0.2)
    assert longer.predicted == [("spoon", "board"), ("spoon", "cup")] and longer.score.precision == 0.5
    assert score_tools("Cut", s, labels, [("knife", "cup")]).score.recall == 0.0  # no Cut frames
    assert cross_hand_frames(s, {"left_hand": "cup", "right_hand": "spoon"}) == {"left_hand": 0,
                                                                                 "right_hand": 6}


def kit(action: str):
    xml = next(mocap_file("kit_bimanual").glob(f"{action}_*.mmm.xml"))
    labels = read_labels(xml.with_name(xml.name[: -len(".mmm.xml")] + ".labels.csv"))
    recording, preset = recognise_preset(read_recording(xml))
    assert preset == "kit"
    return recording, labels


@pytest.mark.mocap
def test_development_clips_hands_tools_and_no_cross_hand_contacts():
    hands = Score()
    for action in DEVELOPMENT:
        rec, labels = kit(action)
        s = segment(rec)  # default parameters, one set for all clips
        hands += score_clip(action, s, labels).score
        tools = score_tools(action, s, labels, KIT_TOOL_TARGETS[action])
        assert tools.score.recall == 1.0, (action, tools.predicted)  # every tool–target pair found
        objects = {g: rec.group_positions(g) for g in rec.instances if g not in labels}
        held = {h: nearest_object(rec.group_positions(h), objects, contact_from_labels(lab))
                for h, lab in labels.items()}
        assert cross_hand_frames(s, held) == {"left_hand": 0, "right_hand": 0}, action
    assert hands.f1 >= 0.95


@pytest.mark.mocap
@pytest.mark.parametrize("action", ["Stir", "Cut"])
def test_tool_contacts_alike_at_100_hz(action):
    # the 10 Hz clip interpolated to 100 Hz: the tool rule counts seconds, not frames
    rec, labels = kit(action)
    times = np.arange((rec.n_frames - 1) * 10 + 1) / 100.0
    flat = rec.positions_m.reshape(rec.n_frames, -1)
    pos = np.stack([np.interp(times, rec.times_s, flat[:, c]) for c in range(flat.shape[1])], axis=1)
    fast = Recording(rec.source, 100.0, times, rec.marker_names, pos.reshape(len(times), -1, 3), rec.groups)
    s = segment(fast)
    up = {hand: [lab for lab in hand_labels for _ in range(10)][: len(times)]
          for hand, hand_labels in labels.items()}
    tools = score_tools(action, s, up, KIT_TOOL_TARGETS[action], tolerance=30)
    assert tools.score.recall == 1.0 and all(c > 0.9 for c in tools.coverage.values())
    objects = {g: fast.group_positions(g) for g in fast.instances if g not in labels}
    held = {h: nearest_object(fast.group_positions(h), objects, contact_from_labels(lab))
            for h, lab in up.items()}
    assert cross_hand_frames(s, held) == {"left_hand": 0, "right_hand": 0}
