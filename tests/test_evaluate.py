"""Scoring contact keyframes against hand labels; the KIT development clips in both modes."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from _mocap import mocap_file
from segeval.evaluate import (
    Event,
    Score,
    contact_from_labels,
    contact_from_segmentation,
    events,
    match_events,
    read_labels,
    score_clip,
)

from oacdsl.errors import RecordingError
from oacdsl.segmentation import AasParams, segment
from oacdsl.segmentation.grouping import apply_preset
from oacdsl.segmentation.readers import read_recording
from oacdsl.segmentation.result import Keyframe, Segmentation
from oacdsl.world import WorldState

HANDS = ("left_hand", "right_hand")
INSTANCES = ("cup", "jug", *HANDS)
DEVELOPMENT = ("Pour", "Stir", "Mix", "Wipe", "Scoop", "Cut")


def seg(frames: int, changes: list[tuple[int, list[tuple[str, str]]]]) -> Segmentation:
    kfs = tuple(Keyframe(f, f / 10.0, WorldState.of(INSTANCES, rel)) for f, rel in changes)
    return Segmentation("clip", 10.0, frames, INSTANCES, kfs)


def test_events_of_a_contact_array():
    c = np.array([1, 1, 0, 0, 1, 1, 1, 0, 1], dtype=bool)
    assert events(c, "h") == [Event(0, "h", "start"), Event(2, "h", "end"), Event(4, "h", "start"),
                              Event(7, "h", "end"), Event(8, "h", "start")]
    assert events(np.zeros(5, dtype=bool), "h") == []


def test_matching_is_one_to_one_within_tolerance_and_same_kind():
    truth = [Event(10, "l", "start"), Event(12, "l", "start"), Event(30, "l", "end"), Event(10, "r", "start")]
    pred = [Event(11, "l", "start"), Event(14, "l", "end"), Event(34, "l", "end"), Event(13, "r", "start")]
    m = match_events(pred, truth, tolerance=3)
    assert m == [(Event(11, "l", "start"), Event(10, "l", "start")),
                 (Event(13, "r", "start"), Event(10, "r", "start"))]
    assert len(match_events(pred, truth, tolerance=4)) == 3  # 34 ↔ 30 now


def test_score_measures():
    s = Score(matched=3, predicted=4, labelled=6)
    assert (s.precision, s.recall) == (0.75, 0.5) and s.f1 == pytest.approx(0.6)
    assert Score().f1 == 1.0 and Score(0, 2, 0).f1 == 0.0
    s += Score(1, 1, 1)
    assert (s.matched, s.predicted, s.labelled) == (4, 5, 7)


def test_contact_ignores_the_other_hand_and_scores_a_clip():
    s = seg(20, [(0, []), (4, [("cup", "left_hand")]),
                 (6, [("cup", "left_hand"), ("left_hand", "right_hand")]),
                 (9, [("left_hand", "right_hand"), ("jug", "right_hand")]), (15, [])])
    left = contact_from_segmentation(s, "left_hand", HANDS)
    assert np.flatnonzero(left).tolist() == list(range(4, 9))  # hand–hand contact is not contact
    labels = {"left_hand": ["Idle"] * 3 + ["Move"] * 6 + ["Retreat"] * 11,
              "right_hand": ["Idle"] * 20}
    result = score_clip("clip", s, labels, tolerance=1)
    # left: start 3 vs 4 ✓, end 9 vs 9 ✓; right: predicted start 9 and end 15, none labelled
    assert (result.score.matched, result.score.predicted, result.score.labelled) == (2, 4, 2)
    assert result.touched == {"left_hand": {"cup": 5}, "right_hand": {"jug": 6}}
    assert result.frame_agreement["right_hand"] == pytest.approx(14 / 20)


def test_score_clip_checks_lengths_and_hands():
    with pytest.raises(RecordingError, match="3 labelled frames for a recording of 20 frames"):
        score_clip("clip", seg(20, [(0, [])]), {"left_hand": ["Idle"] * 3})
    with pytest.raises(RecordingError, match="no instance 'lefthand'"):
        score_clip("clip", seg(20, [(0, [])]), {"lefthand": ["Idle"] * 20})


def write(tmp_path: Path, text: str) -> Path:
    p = tmp_path / "x.labels.csv"
    p.write_text(text, encoding="utf-8")
    return p


HEADER = "frame,time_s,lhand_action,rhand_action\n"


@pytest.mark.parametrize(("text", "message"), [
    ("frame,time_s,lhand_action\n0,0,Idle\n", "no column 'rhand_action'"),
    (HEADER + "0,0,Idle,Hodl\n", "line 2: unknown label 'Hodl' (did you mean 'Hold'?)"),
    (HEADER + "0,0,Idle,Idle\n2,0.2,Idle,Idle\n", "line 3: frame '2' is out of order"),
    (HEADER + "0,0,Idle\n", "line 2: 3 fields, expected 4"),
    (HEADER, "no frames"),
])
def test_bad_label_files(tmp_path: Path, text, message):
    with pytest.raises(RecordingError) as err:
        read_labels(write(tmp_path, text))
    assert message in str(err.value) and str(err.value).startswith(str(tmp_path))


def kit(action: str):
    xml = next(mocap_file("kit_bimanual").glob(f"{action}_*.mmm.xml"))
    labels = read_labels(xml.with_name(xml.name[: -len(".mmm.xml")] + ".labels.csv"))
    return apply_preset(read_recording(xml), "kit"), labels


@pytest.mark.mocap
def test_real_labels():
    _, labels = kit("Pour")
    assert len(labels["left_hand"]) == 78 and labels["left_hand"][12] == "Move"
    contact = contact_from_labels(labels["left_hand"])
    assert np.flatnonzero(contact)[[0, -1]].tolist() == [12, 54]  # README: Move 12-26 … Place 44-54


@pytest.mark.mocap
def test_development_clips_adaptive_beats_paper():
    totals = {"paper": Score(), "adaptive": Score()}
    for action in DEVELOPMENT:
        rec, labels = kit(action)
        for mode, total in totals.items():
            total += score_clip(action, segment(rec, AasParams(mode=mode)), labels).score
    assert totals["adaptive"].f1 >= 0.95  # the target, one parameter set for all clips
    assert totals["paper"].f1 < totals["adaptive"].f1
