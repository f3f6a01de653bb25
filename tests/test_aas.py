"""The AAS on hand-made trajectories: the paper's rules, index conventions, gaps, merging."""

import math

import numpy as np
import pytest
from _aas_helpers import path, recording, still, summary

from oacdsl.errors import RecordingError, SegmentationError
from oacdsl.segmentation import AasParams, segment
from oacdsl.segmentation.adaptive import AdaptiveDetector, AdaptiveSettings
from oacdsl.segmentation.recording import Recording

# These tests check the paper's Eq. 1 and Eq. 2 as printed, so they name mode="paper";
# the default mode (adaptive) is tested in test_adaptive.py.

F = 400
CUP = (0.0, 0.0, 0.0)


def approach_hold_leave(rate_hz: float = 100.0) -> Recording:
    # the hand comes in at 0.45 m/s, rests 5 cm from the cup from frame 100 to 200, leaves
    hand = path(F, [(0, (0.5, 0, 0)), (100, (0.05, 0, 0)), (200, (0.05, 0, 0)), (300, (0.5, 0, 0))])
    return recording({"hand": hand, "cup": still(F, CUP)}, rate_hz)


@pytest.mark.parametrize("n", [1, 2, 3, 5, 10])
def test_touch_is_labelled_at_the_first_frame_of_its_run(n):
    # frame 100 still has the approach's distance change (from 99); 101 is the first still frame.
    # Leaving: frame 201 is the first with a large change. Neither depends on n.
    seg = segment(approach_hold_leave(), AasParams(mode="paper", frames=n, merge_s=0))
    assert summary(seg) == [(0, []), (101, [("cup", "hand")]), (201, [])]
    assert seg.keyframes[1].time_s == pytest.approx(1.01)


def test_distance_and_speed_thresholds_both_matter():
    rec = approach_hold_leave()
    # resting at 5 cm is not "close" under a 4 cm threshold
    assert summary(segment(rec, AasParams(distance_m=0.04, mode="paper"))) == [(0, [])]
    # with no speed condition the touch starts as soon as the hand is within 15 cm
    seg = segment(rec, AasParams(speed_m_s=math.inf, frames=3, merge_s=0, mode="paper"))
    # distance 0.5 - 0.0045 f < 0.15 from f = 78 (0.149 m) to the mirror frame on the way out
    assert [k.frame for k in seg.keyframes] == [0, 78, 223]


def test_pass_by_is_no_touch():
    # 1 m/s straight past the cup at 5 cm: |dist'| < v only for a frame or two around the
    # closest point, fewer than the 10 frames that 100 Hz asks for by default
    hand = path(F, [(0, (-2.0, 0.05, 0)), (F - 1, (-2.0 + 0.01 * (F - 1), 0.05, 0))])
    rec = recording({"hand": hand, "cup": still(F, CUP)})
    assert summary(segment(rec)) == [(0, [])]
    # the same path, but the hand stops next to the cup: that is a touch. By the paper's
    # one-frame difference from frame 200, whose step is tangential (the distance changes by
    # 0.99 mm, under v Δt = 1 mm); by the default detector's slope over ±5 frames two frames
    # later, when the window no longer holds enough of the approach. The default detector rescales
    # its windows by the demonstration's pace (1 m/s, twice the reference: ±2 frames), and sees
    # the rest at frame 200 too.
    stop = recording({"hand": path(F, [(0, (-2.0, 0.05, 0)), (200, (0.0, 0.05, 0))]), "cup": still(F, CUP)})
    assert summary(segment(stop, AasParams(mode="paper"))) == [(0, []), (200, [("cup", "hand")])]
    # (the default detector puts a hand and an object that never move together at the static
    # distance only with static_agents: by default a hand touches by moving, holding or a tool)
    fixed = AdaptiveDetector(AasParams().resolved(stop.rate_hz),
                             AdaptiveSettings(rescale=False, static_agents=True))
    assert summary(segment(stop, detector=fixed)) == [(0, []), (202, [("cup", "hand")])]
    assert summary(segment(stop, detector=_static_hands(stop))) == [(0, []), (200, [("cup", "hand")])]
    assert summary(segment(stop)) == [(0, [])]


def _static_hands(rec: Recording) -> AdaptiveDetector:
    """The default detector, but with the static distance for pairs with a hand too."""
    return AdaptiveDetector(AasParams().resolved(rec.rate_hz), AdaptiveSettings(static_agents=True))


def test_slow_pass_by_touches_when_n_is_too_small():
    # the reason n is counted in time: a 0.4 m/s pass-by at 5 cm has |dist'| < v for
    # |t| < v b / u² = 31 ms, about 6 frames at 100 Hz
    hand = path(F, [(0, (-0.8, 0.05, 0)), (F - 1, (-0.8 + 0.004 * (F - 1), 0.05, 0))])
    rec = recording({"hand": hand, "cup": still(F, CUP)})
    assert len(segment(rec, AasParams(mode="paper", frames=3, merge_s=0)).keyframes) == 3
    assert len(segment(rec, AasParams(mode="paper", frames=10, merge_s=0)).keyframes) == 1


def test_auto_frames_follow_the_rate():
    assert AasParams().resolved(100.0).frames == 10
    assert AasParams().resolved(10.0).frames == 2
    assert AasParams().resolved(30.0).frames == 3
    assert AasParams(frames=4).resolved(100.0).frames == 4
    assert segment(approach_hold_leave()).parameters["frames"] == 10


def hold_with_noise(spikes: list[int], width: int) -> Recording:
    hand = still(F, (0.05, 0, 0))
    for s in spikes:  # the hand marker jumps by 2 cm for `width` frames and back
        hand[s : s + width, 0] += 0.02
    return recording({"hand": hand, "cup": still(F, CUP)})


def test_noise_does_not_break_a_touch():
    # one-frame jumps: the change is large on the jump and on the way back, 2 far frames each
    seg = segment(hold_with_noise([100, 150, 250], width=1), AasParams(mode="paper", frames=3, merge_s=0))
    assert summary(seg) == [(0, [("cup", "hand")])]


def test_a_real_separation_breaks_the_touch():
    # a jump that stays: far for 1 frame then still but outside d -> separation
    hand = still(F, (0.05, 0, 0))
    hand[200:, 0] = 0.3
    seg = segment(
        recording({"hand": hand, "cup": still(F, CUP)}), AasParams(mode="paper", frames=3, merge_s=0)
    )
    assert summary(seg) == [(0, [("cup", "hand")]), (200, [])]


def test_initial_state_is_frame_zero():
    liquid = still(F, (0.0, 0.0, 0.02))
    seg = segment(recording({"liquid": liquid, "cup": still(F, CUP), "hand": still(F, (1, 0, 0))}))
    assert summary(seg) == [(0, [("cup", "liquid")])]
    assert seg.keyframes[0].time_s == 0.0
    assert seg.keyframes[0].state.touches_nothing("hand")


def bounce(merge_s: float) -> list:
    # a cup set down on a tray bounces: resting 101-104, in the air 105-110, resting from 111
    cup = path(
        F,
        [
            (0, (0, 0, 0.5)),
            (100, (0, 0, 0.05)),
            (104, (0, 0, 0.05)),
            (106, (0, 0, 0.2)),
            (108, (0, 0, 0.2)),
            (110, (0, 0, 0.05)),
        ],
    )
    return summary(
        segment(
            recording({"cup": cup, "tray": still(F, CUP)}), AasParams(mode="paper", frames=1, merge_s=merge_s)
        )
    )


def test_bounce_is_merged():
    unmerged = bounce(0.0)
    assert [f for f, _ in unmerged] == [0, 101, 105, 111]
    assert bounce(0.3) == [(0, []), (111, [("cup", "tray")])]


def test_merge_drops_a_flicker_that_returns_to_the_previous_state():
    # hand touches the cup for 10 frames (0.1 s) only: merged away entirely
    hand = path(F, [(0, (0.5, 0, 0)), (100, (0.05, 0, 0)), (110, (0.05, 0, 0)), (111, (0.5, 0, 0))])
    rec = recording({"hand": hand, "cup": still(F, CUP)})
    assert len(segment(rec, AasParams(mode="paper", frames=2, merge_s=0)).keyframes) == 3
    assert summary(segment(rec, AasParams(mode="paper", frames=2, merge_s=0.3))) == [(0, [])]


def test_instances_touch_while_any_marker_pair_touches():
    # a two-marker tray; the hand rests at marker 0, slides over to marker 1 (20 cm away),
    # so marker pair (hand, tray.0) ends while (hand, tray.1) begins: the instances keep touching
    tray = np.stack([still(F, (0, 0, 0)), still(F, (0.2, 0, 0))], axis=1)
    hand = path(F, [(0, (0.0, 0.05, 0)), (150, (0.0, 0.05, 0)), (250, (0.2, 0.05, 0))])
    rec = recording({"hand": hand, "tray": tray})
    for chunk in (7, 64, 1000):
        assert summary(
            segment(rec, AasParams(mode="paper", speed_m_s=math.inf, frames=3), chunk_frames=chunk)
        ) == [(0, [("hand", "tray")])]


def test_gap_keeps_a_touch():
    hand = still(F, (0.05, 0, 0))
    hand[100:180] = np.nan  # occluded while holding
    rec = recording({"hand": hand, "cup": still(F, CUP)})
    assert summary(segment(rec, detector=_static_hands(rec))) == [(0, [("cup", "hand")])]


def test_gap_does_not_make_a_touch():
    hand = still(F, (0.5, 0, 0))
    hand[100:180] = np.nan
    rec = recording({"hand": hand, "cup": still(F, CUP)})
    assert summary(segment(rec)) == [(0, [])]


def test_touch_that_starts_in_a_gap_is_found_after_it():
    # the hand vanishes far away and reappears resting at the cup: frame 180 has no known
    # distance change (179 is a gap), so the first close frame is 181
    hand = still(F, (0.5, 0, 0))
    hand[100:180] = np.nan
    hand[180:] = (0.05, 0, 0)
    rec = recording({"hand": hand, "cup": still(F, CUP)})
    assert summary(segment(rec, AasParams(mode="paper", frames=3, merge_s=0))) == [
        (0, []),
        (181, [("cup", "hand")]),
    ]


def test_touch_that_ends_in_a_gap_ends_after_it():
    # the hand vanishes while touching and reappears far: frame 180 is far (distance known)
    hand = still(F, (0.05, 0, 0))
    hand[100:180] = np.nan
    hand[180:] = (0.5, 0, 0)
    rec = recording({"hand": hand, "cup": still(F, CUP)})
    assert summary(segment(rec, AasParams(mode="paper", frames=3, merge_s=0))) == [
        (0, [("cup", "hand")]),
        (180, []),
    ]


def test_to_json_has_the_documented_schema():
    doc = segment(approach_hold_leave(), AasParams(frames=3, mode="paper")).to_json()
    assert list(doc) == ["recording", "rate_hz", "frames", "parameters", "instances", "keyframes"]
    assert doc["frames"] == F and doc["rate_hz"] == 100.0 and doc["instances"] == ["cup", "hand"]
    assert doc["parameters"] == {
        "distance_m": 0.15,
        "speed_m_s": 0.1,
        "frames": 3,
        "merge_s": 0.3,
        "mode": "paper",
        "hold_s": 0.1,
        "change_window_s": 0.1,
    }
    assert doc["keyframes"][0] == {"frame": 0, "time_s": 0.0, "relations": []}
    assert doc["keyframes"][1]["relations"] == [["cup", "hand"]]


def test_no_speed_condition_is_null_in_json():
    assert (
        segment(approach_hold_leave(), AasParams(mode="paper", speed_m_s=math.inf)).to_json()["parameters"][
            "speed_m_s"
        ]
        is None
    )


def test_degenerate_recordings():
    one = recording({"hand": still(1, (0.05, 0, 0)), "cup": still(1, CUP)})
    assert summary(segment(one)) == [(0, [])]  # no distance change known in a single frame
    alone = recording({"hand": still(10, (0, 0, 0))})
    assert summary(segment(alone)) == [(0, [])]


@pytest.mark.parametrize(
    ("kwargs", "needle"),
    [
        ({"distance_m": 0.0}, "distance must be a positive length"),
        ({"distance_m": math.nan}, "distance must be a positive length"),
        ({"speed_m_s": -1.0}, "speed must be a positive speed"),
        ({"frames": 0}, "frames must be a whole number"),
        ({"frames": 2.5}, "frames must be a whole number"),
        ({"merge_s": -0.1}, "merge window must be a duration"),
    ],
)
def test_bad_parameters(kwargs, needle):
    with pytest.raises(SegmentationError, match=needle):
        AasParams(**kwargs)


def test_unknown_mode_suggests_the_known_ones():
    with pytest.raises(SegmentationError, match="unknown segmentation mode 'papr'.*did you mean 'paper'"):
        segment(approach_hold_leave(), AasParams(mode="papr"))


def test_times_must_increase():
    rec = approach_hold_leave()
    times = rec.times_s.copy()
    times[5] = times[4]
    bad = Recording("bad.c3d", 100.0, times, rec.marker_names, rec.positions_m, rec.groups)
    with pytest.raises(SegmentationError, match="^bad.c3d: frame times must increase; frame 5"):
        segment(bad)


def test_a_marker_in_two_instances_is_an_error():
    rec = approach_hold_leave()
    with pytest.raises(SegmentationError, match="marker 'hand.0' belongs to both"):
        segment(rec.with_groups({"cup": ["cup.0", "hand.0"], "hand": ["hand.0"]}))
    with pytest.raises(RecordingError):
        rec.with_groups({"cup": ["nope"]})


def _kf(frame, *rels):
    from oacdsl.segmentation.result import Keyframe
    from oacdsl.world import WorldState

    return Keyframe(frame, frame / 100, WorldState.of(["a", "b", "c"], rels))


def test_merge_groups_chain_and_keep_the_last_state():
    from oacdsl.segmentation.keyframes import merge_keyframes

    kfs = [
        _kf(0),
        _kf(100, ("a", "b")),
        _kf(120, ("a", "b"), ("b", "c")),
        _kf(140, ("b", "c")),
        _kf(300, ("b", "c"), ("a", "c")),
    ]
    # 100-120-140 chain (each 0.2 s apart, window 0.3 s) although 100 and 140 are 0.4 s apart
    assert [(k.frame, k.state.sorted_relations()) for k in merge_keyframes(kfs, 0.3)] == [
        (0, []),
        (140, [("b", "c")]),
        (300, [("a", "c"), ("b", "c")]),
    ]
    assert merge_keyframes(kfs, 0.0) == kfs
    # exactly one window apart is not "closer than the window"
    assert len(merge_keyframes(kfs, 0.2)) == 5


def test_merge_keeps_frame_zero_with_the_state_after_its_group():
    from oacdsl.segmentation.keyframes import merge_keyframes

    kfs = [_kf(0), _kf(10, ("a", "b")), _kf(200, ("a", "b"), ("a", "c"))]
    merged = merge_keyframes(kfs, 0.3)
    assert [(k.frame, k.time_s, k.state.sorted_relations()) for k in merged] == [
        (0, 0.0, [("a", "b")]),
        (200, 2.0, [("a", "b"), ("a", "c")]),
    ]


class ThresholdDetector:
    """A plug-in for the test: touching exactly while closer than d (dense, no hysteresis)."""

    history_frames = 0
    delay_frames = 0
    reach_m = None

    def __init__(self, params):
        self.d = params.distance_m

    def begin(self, recording, table):
        self.state = np.zeros(table.n_pairs, dtype=bool)

    def step(self, chunk):
        from oacdsl.segmentation.detectors import PairChanges

        states = chunk.dist_m[:, chunk.history :] < self.d
        changes = PairChanges.from_states(chunk.pairs, states, self.state[chunk.pairs], chunk.start)
        self.state[chunk.pairs] = states[:, -1]
        return changes


def test_a_detector_plugs_in_by_mode_name(monkeypatch):
    from _aas_helpers import grid_scene

    from oacdsl.segmentation import detectors

    monkeypatch.setitem(detectors.DETECTORS, "threshold", f"{__name__}:ThresholdDetector")
    rec = grid_scene(np.random.default_rng(3), 150, n_inst=3, markers=2, gap_rate=0.0)
    plugged = segment(rec, AasParams(mode="threshold", distance_m=0.155, merge_s=0), chunk_frames=17)
    paper = segment(rec, AasParams(distance_m=0.155, speed_m_s=math.inf, frames=1, merge_s=0, mode="paper"))
    assert plugged.parameters["mode"] == "threshold"
    assert len(plugged.keyframes) > 3
    assert plugged.keyframes == paper.keyframes
