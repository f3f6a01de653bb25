"""Hand-contact scoring of another take against the original's labels (benchmarks/segeval/takelabels.py)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from segeval.takelabels import labels_for_take, on_original_grid, stated_factor, take_factor

from oacdsl.segmentation.result import Keyframe, Segmentation
from oacdsl.world import WorldState

INSTANCES = ("left_hand", "right_hand", "cup")


def _seg(times: np.ndarray, frames: list[int], touching: list[bool]) -> Segmentation:
    kfs = tuple(Keyframe(f, float(times[f]), WorldState.of(INSTANCES, [("left_hand", "cup")] if on else []))
                for f, on in zip(frames, touching, strict=True))
    rate = (times.size - 1) / (times[-1] - times[0])
    return Segmentation("take", float(rate), int(times.size), INSTANCES, kfs)


def test_the_original_itself_is_unchanged():
    t = np.arange(50) / 10.0
    seg = _seg(t, [0, 14, 40], [False, True, False])
    assert on_original_grid(seg, t, t).keyframes == seg.keyframes
    assert take_factor(t, t) == 1.0


def test_a_slower_take_maps_back_to_the_original_frames():
    t = np.arange(50) / 10.0
    slow = np.arange(99) / 10.0  # ×2: frame 28 shows the original's 1.4 s
    assert take_factor(t, slow) == pytest.approx(2.0)
    grid = on_original_grid(_seg(slow, [0, 28, 80], [False, True, False]), t, slow)
    assert [k.frame for k in grid.keyframes] == [0, 14, 40] and grid.frames == 50


def test_a_finer_take_lands_on_the_first_original_frame_that_shows_the_change():
    t = np.arange(50) / 10.0
    fine = np.arange(491) / 100.0
    grid = on_original_grid(_seg(fine, [0, 133, 401], [False, True, False]), t, fine)
    assert [k.frame for k in grid.keyframes] == [0, 14, 41]  # 1.325-1.33 s: seen at 1.4 s


def test_keyframes_on_one_original_frame_leave_the_last_state():
    t = np.arange(50) / 10.0
    fine = np.arange(491) / 100.0
    grid = on_original_grid(_seg(fine, [0, 131, 135, 139], [False, True, False, True]), t, fine)
    assert [(k.frame, bool(k.state.relations)) for k in grid.keyframes] == [(0, False), (14, True)]


def test_a_keyframe_goes_to_the_first_original_frame_after_its_change():
    """A take ×0.8 (frames 0.125 s of the original's): a let-go at 5.78 s of the original, seen at the
    take's frame 47 (5.875 s), goes to 5.8 s as the original sees it; by the middle of the take's
    two frames (5.8125 s) it went to 5.9 s."""
    t = np.arange(81) / 10.0
    fast = np.arange(65) / 10.0  # 6.4 s for the original's 8 s: factor 0.8
    seg = _seg(fast, [0, 47], [True, False])
    assert [k.frame for k in on_original_grid(seg, t, fast).keyframes] == [0, 59]
    kfs = seg.keyframes
    timed = replace(seg, keyframes=(kfs[0], replace(kfs[1], change_s=5.78 * 0.8)))
    assert [k.frame for k in on_original_grid(timed, t, fast).keyframes] == [0, 58]


def test_a_stretched_take_states_its_factor_where_its_duration_falls_short():
    """A take ×0.8 of 7.2 s ends on its last whole frame, 5.7 s (not 5.76 s): by the durations its
    factor is 0.792, and a let-go at 5.78 s of the original (4.624 s of the take) lands a frame late."""
    assert stated_factor("Mix.mmm.xml (time x0.7) (scaled x0.9) (60 Hz) (time x2)") == pytest.approx(1.4)
    assert stated_factor("Mix.mmm.xml (rotated 30 deg)") is None
    t = np.arange(73) / 10.0
    take = np.arange(58) / 10.0
    kfs = _seg(take, [0, 47], [True, False]).keyframes
    seg = _seg(take, [0, 47], [True, False])
    timed = replace(seg, keyframes=(kfs[0], replace(kfs[1], change_s=4.624)))
    assert take_factor(t, take) == pytest.approx(0.7917, abs=1e-4)
    assert [k.frame for k in on_original_grid(timed, t, take).keyframes] == [0, 59]
    assert [k.frame for k in on_original_grid(timed, t, take, factor=0.8).keyframes] == [0, 58]


def test_a_mirrored_take_scores_each_hand_against_the_other_hands_labels():
    labels = {"left_hand": ["Idle", "Hold"], "right_hand": ["Idle", "Idle"]}
    swapped = labels_for_take(labels, {"left_hand": "right_hand", "right_hand": "left_hand"})
    assert swapped == {"right_hand": ["Idle", "Hold"], "left_hand": ["Idle", "Idle"]}
    assert labels_for_take(labels) == labels


@pytest.mark.mocap
@pytest.mark.parametrize("take", ["mirrored", "double_speed", "resampled_100hz"])
def test_kit_pour_takes_score_as_the_original(take):
    """``benchmarks/kit_bimanual.py --take``: Pour's takes find every labelled contact event."""
    import kit_bimanual
    from _mocap import mocap_file

    from oacdsl.segmentation import AasParams
    from oacdsl.segmentation.takes import STANDARD_TAKES

    folder = mocap_file("kit_bimanual")
    result, reference, tools, cross = kit_bimanual.run_clip(folder, "Pour", AasParams(mode="adaptive"), 3,
                                                            take=STANDARD_TAKES[take])
    assert result.score.f1 == 1.0 and tools.score.f1 == 1.0
    assert set(reference) == {"left_hand", "right_hand"} and cross == {"left_hand": 0, "right_hand": 0}
