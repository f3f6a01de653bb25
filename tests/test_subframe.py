"""Event times below the frame (oacdsl/segmentation/subframe.py): a contact's distance crossing its
threshold between two frames, interpolated; on synthetic signals and a synthetic carry."""

from __future__ import annotations

import dataclasses
import json

import numpy as np
import pytest
from _aas_helpers import recording
from test_adaptive import carry_scene

from oacdsl.pipeline.inputs import read_segmentation_json
from oacdsl.segmentation import AasParams, segment
from oacdsl.segmentation.keyframes import keyframes_from_changes, merge_keyframes
from oacdsl.segmentation.recording import Recording
from oacdsl.segmentation.result import Keyframe
from oacdsl.segmentation.subframe import change_times_s, crossing, span_edges
from oacdsl.world import WorldState


def test_a_crossing_is_interpolated_between_the_two_frames():
    d = np.array([0.10, 0.08, 0.06, 0.04, 0.06], dtype=np.float32)
    assert crossing(d, 2, 0.07) == pytest.approx(1.5, abs=1e-5)  # approaching: 80 → 60 mm
    assert crossing(d, 4, 0.05) == pytest.approx(3.5, abs=1e-5)  # leaving: 40 → 60 mm
    assert crossing(d, 2, 0.09) is None  # crossed before frame 1
    assert crossing(d, 0, 0.07) is None and crossing(d, 5, 0.07) is None
    gap = d.copy()
    gap[1] = np.nan
    assert crossing(gap, 2, 0.07) is None  # unknown where it was crossed


def test_span_edges_and_change_times():
    d = np.array([0.10, 0.08, 0.06, 0.04, 0.06, 0.08], dtype=np.float32)
    edges: dict[int, float] = {}
    span_edges(d, [(2, 5, 0.07), (2, 4, 0.075)], edges)  # two episodes' thresholds: the earliest
    assert edges[2] == pytest.approx(1.25, abs=1e-5) and edges[5] == pytest.approx(4.5, abs=1e-5)
    assert 4 not in edges  # the second span ends at 4 without crossing its threshold (episode's end)
    times = np.arange(6) * 0.1
    got = change_times_s({7: edges}, np.array([7, 7, 7, 8]), np.array([2, 5, 4, 0]), times)
    assert got == pytest.approx([0.125, 0.45, 0.35, 0.0])  # a change without a crossing: halfway


def _phase(scene: dict[str, np.ndarray], offset: int) -> Recording:
    """The 100 Hz scene sampled at 10 Hz from frame ``offset`` on, at its true times."""
    rec = recording({k: v[offset::10] for k, v in scene.items()}, rate_hz=10.0)
    return dataclasses.replace(rec, times_s=rec.times_s + offset / 100)


def test_a_grasp_and_a_release_are_timed_alike_at_every_phase_of_a_10_hz_sampling():
    """Sampled at 10 Hz from ten different first frames, the hand's arrival at the cup falls anywhere
    within a frame: the keyframes' frame times spread over 0.1 s, their change times do not."""
    scene = carry_scene()
    params = AasParams(mode="adaptive", merge_s=0.0)
    grasps, releases, frame_times = [], [], []
    for offset in range(10):
        kfs = segment(_phase(scene, offset), params).keyframes
        assert len(kfs) == 3
        grasps.append(kfs[1].event_s)
        releases.append(kfs[2].event_s)
        frame_times.append(kfs[1].time_s)
    assert max(frame_times) - min(frame_times) > 0.08
    assert max(grasps) - min(grasps) < 0.03 and max(releases) - min(releases) < 0.03  # a third of a frame
    fine = segment(recording(scene), params).keyframes  # 100 Hz: the same moments
    assert np.median(grasps) == pytest.approx(fine[1].event_s, abs=0.02)
    assert np.median(releases) == pytest.approx(fine[2].event_s, abs=0.02)


def test_the_paper_mode_has_no_change_times():
    kfs = segment(recording(carry_scene()), AasParams(mode="paper")).keyframes
    assert all(k.change_s is None for k in kfs)


def test_keyframes_carry_their_earliest_change_through_merging_and_json(tmp_path):
    names = ("a", "c", "h")
    rels = [("a", "h"), ("a", "c")]
    kfs = keyframes_from_changes(names, rels, np.array([10, 10, 12]), np.array([0, 1, 1]),
                                 np.array([True, True, False]), np.arange(20) / 10,
                                 np.array([0.96, 0.93, 1.15]))
    assert [(k.frame, k.change_s) for k in kfs] == [(0, None), (10, 0.93), (12, 1.15)]
    assert kfs[1] == Keyframe(10, 1.0, kfs[1].state)  # the change time is not the keyframe's identity
    merged = merge_keyframes(kfs, 0.3, connected=True, agents=frozenset("h"))
    assert [(k.frame, k.change_s) for k in merged] == [(0, None), (10, 0.93)]
    seg = segment(recording(carry_scene()), AasParams(mode="adaptive"))
    path = tmp_path / "seg.json"
    path.write_text(json.dumps(seg.to_json()))
    back = read_segmentation_json(path)
    assert [k.change_s for k in back.keyframes] == pytest.approx([k.change_s for k in seg.keyframes])
    assert "change_s" not in seg.to_json()["keyframes"][0]  # frame 0: the initial state
    state = WorldState(frozenset(names), frozenset())
    assert Keyframe(3, 0.3, state).event_s == 0.3 and Keyframe(3, 0.3, state, 0.27).event_s == 0.27
