"""The robust detector (mode ``robust``, step 4 of ``adaptive``): the windowed slope, n in seconds,
chunking and the per-frame reference, rate and jitter independence on hand-made scenes."""

from __future__ import annotations

import math

import numpy as np
import pytest
from _aas_helpers import path, recording, still, summary
from hypothesis import given, settings
from hypothesis import strategies as st
from segeval.reference import segment_reference
from test_adaptive import carry_scene

from oacdsl.errors import SegmentationError
from oacdsl.segmentation import AasParams, segment, slope
from oacdsl.segmentation.recording import Recording
from oacdsl.segmentation.slope import windowed_slope, windowed_slope_at


def test_slope_is_the_least_squares_line_and_skips_gaps():
    t = np.arange(11) * 0.01
    x = 0.2 + 0.3 * t  # 0.3 m/s
    x[[2, 7]] = np.nan
    s = windowed_slope(x[None, :].astype(np.float32), t, half=3)[0]
    assert np.allclose(s[3:8], 0.3, atol=1e-3)  # exact line: the fit is the line, gaps or not
    # too few visible samples (fewer than half + 1) → unknown
    y = np.full(11, np.nan, dtype=np.float32)
    y[5] = 0.1
    assert np.isnan(windowed_slope(y[None, :], t, half=3)).all()


@pytest.mark.parametrize("direct", [False, True])
def test_slope_at_some_columns_is_the_full_slope_there(monkeypatch, direct):
    """By prefix sums, bit for bit; by summing each window (few places asked for), to float32
    rounding, with the same unknown places."""
    monkeypatch.setattr(slope, "DIRECT_COST", 0.0 if direct else 1e9)
    rng = np.random.default_rng(7)
    for _ in range(40):
        a, r, half = int(rng.integers(1, 12)), int(rng.integers(1, 120)), int(rng.integers(1, 6))
        dist = (rng.random((a, r)) * 0.3).astype(np.float32)
        dist[rng.random((a, r)) < 0.2] = np.nan  # gaps: rows with their own weights
        t = np.cumsum(0.005 + 0.01 * rng.random(r)) + 50.0  # uneven frame times, seconds
        rows, cols = np.nonzero(rng.random((a, r)) < 0.3)
        full = windowed_slope(dist, t, half)[rows, cols]
        shuffled = rng.permutation(rows.size)  # any order of the requested places
        for got, want in ((windowed_slope_at(dist, t, half, rows, cols), full),
                          (windowed_slope_at(dist, t, half, rows[shuffled], cols[shuffled]), full[shuffled])):
            if direct:
                assert np.array_equal(np.isnan(got), np.isnan(want))
                assert np.allclose(got, want, rtol=1e-6, atol=1e-9, equal_nan=True)
            else:
                assert np.array_equal(got, want, equal_nan=True)
    assert windowed_slope_at(dist, t, 2, rows[:0], cols[:0]).shape == (0,)


def test_slope_noise_falls_with_the_rate_where_the_one_frame_difference_grows():
    rng = np.random.default_rng(0)
    sigma = 0.0005  # 0.5 mm white jitter on a still distance
    for rate in (50.0, 240.0):
        t = np.arange(int(rate * 4)) / rate
        x = (0.1 + sigma * rng.standard_normal(t.size)).astype(np.float32)
        half = AasParams().half_window(rate)
        slope = windowed_slope(x[None, :], t, half)[0, half:-half]
        diff = np.abs(np.diff(x)) * rate
        # prediction: σ √12 / (Δt N^1.5) for N = 2 half + 1 samples (docs/segmentation.md)
        predicted = sigma * math.sqrt(12) * rate / (2 * half + 1) ** 1.5
        assert np.std(slope) == pytest.approx(predicted, rel=0.25)
        assert np.percentile(np.abs(slope), 99.9) < 0.1 * 0.5  # far below v = 100 mm/s
    assert np.median(diff) > 0.1  # the one-frame difference at 240 Hz: above v half the time


def test_n_and_the_window_are_seconds():
    p = AasParams()
    assert [p.resolved(r).frames for r in (10.0, 50.0, 100.0, 240.0)] == [2, 5, 10, 24]
    assert [p.half_window(r) for r in (10.0, 50.0, 100.0, 240.0)] == [1, 3, 5, 12]
    assert AasParams(hold_s=0.2).resolved(50.0).frames == 10
    with pytest.raises(SegmentationError, match="change window must be a positive duration"):
        AasParams(change_window_s=0.0)
    with pytest.raises(SegmentationError, match="hold must be a positive duration"):
        AasParams(hold_s=-1.0)


def _resample(scene: dict[str, np.ndarray], rate_hz: float, jitter_m: float, seed: int) -> Recording:
    """A 100 Hz scene at another rate (linear interpolation) with white jitter, metres."""
    rng = np.random.default_rng(seed)
    n = next(iter(scene.values())).shape[0]
    t100 = np.arange(n) / 100.0
    t = np.arange(int((n - 1) / 100.0 * rate_hz) + 1) / rate_hz
    out = {}
    for name, pts in scene.items():
        flat = pts.reshape(n, -1)
        res = np.stack([np.interp(t, t100, flat[:, j]) for j in range(flat.shape[1])], axis=1)
        out[name] = res.reshape((t.size,) + pts.shape[1:]) + jitter_m * rng.standard_normal((t.size,)
                                                                                             + pts.shape[1:])
    return recording(out, rate_hz)


@pytest.mark.parametrize("mode", ["robust", "adaptive"])
def test_same_keyframes_at_50_to_240_hz_with_half_a_millimetre_of_jitter(mode):
    # the hand carries the cup 1.5-3 s, sets it down, leaves at 3.5 s (test_adaptive's scene)
    base = carry_scene()
    times = {}
    for rate in (50.0, 100.0, 200.0, 240.0):
        for seed, jitter in ((0, 0.0), (1, 0.0005), (2, 0.0005)):
            seg = segment(_resample(base, rate, jitter, seed), AasParams(mode=mode, distance_m=0.1))
            states = [k.state.sorted_relations() for k in seg.keyframes]
            assert states == [[], [("cup", "hand")], []], (rate, seed)
            times[(rate, seed)] = [k.time_s for k in seg.keyframes]
    for got in times.values():  # within 50 ms of each other
        assert np.allclose(got, times[(100.0, 0)], atol=0.05)


def test_paper_mode_is_the_one_frame_difference_and_fails_where_robust_holds():
    # a hand resting 5 cm from a cup for 2 s under 0.5 mm of jitter at 240 Hz: the one-frame
    # difference (2 σ × 240 Hz ≈ 240 mm/s) is above v on most frames; the fitted slope is not
    rng = np.random.default_rng(3)
    F = 960
    hand = path(F, [(0, (0.5, 0, 0)), (240, (0.05, 0, 0)), (720, (0.05, 0, 0)), (959, (0.5, 0, 0))])
    rec = recording({"hand": hand + 0.0005 * rng.standard_normal(hand.shape),
                     "cup": still(F, (0, 0, 0)) + 0.0005 * rng.standard_normal((F, 3))}, 240.0)
    assert [k[1] for k in summary(segment(rec, AasParams(mode="robust")))] == [[], [("cup", "hand")], []]
    paper = summary(segment(rec, AasParams(mode="paper")))
    assert paper == [(0, [])]


# -- the vectorised detector against the per-frame reference ---------------------------------------

def _steps(seed: int, frames: int = 150) -> Recording:
    """Clusters that rest and now and then step 1 cm (so pairs rest long enough to touch), with gaps."""
    rng = np.random.default_rng(seed)
    n_inst, markers = int(rng.integers(2, 4)), int(rng.integers(1, 3))
    c = rng.integers(0, 8, (n_inst, 3)).astype(float)
    cent = np.zeros((frames, n_inst, 3))
    for f in range(frames):
        move = rng.random(n_inst) < 0.04
        c = np.clip(c + move[:, None] * rng.integers(-1, 2, (n_inst, 3)), 0, 8)
        cent[f] = c
    off = rng.integers(-2, 3, (n_inst, markers, 3))
    pos = (cent[:, :, None, :] + off[None]) * 0.01
    pos[rng.random((frames, n_inst, markers)) < 0.03] = np.nan
    return recording({f"o{i}": pos[:, i] for i in range(n_inst)})


robust_params = st.builds(
    lambda n, merge, w: AasParams(mode="robust", distance_m=0.0555, speed_m_s=0.0371, frames=n,
                                  merge_s=merge, change_window_s=w),
    st.integers(1, 4), st.sampled_from([0.0, 0.3]), st.sampled_from([0.02, 0.05, 0.1]),
)


@settings(max_examples=25, deadline=None)
@given(st.integers(0, 2**32 - 1), robust_params, st.integers(1, 120))
def test_robust_chunked_equals_per_frame_reference(seed, p, chunk):
    rec = _steps(seed)
    fast = segment(rec, p, chunk_frames=chunk).keyframes
    assert fast == segment(rec, p, chunk_frames=10**6).keyframes
    assert fast == segment_reference(rec, p).keyframes


def test_adaptive_equals_per_frame_reference_on_a_carry():
    rec = _resample(carry_scene(), 100.0, 0.0003, 5)
    p = AasParams(mode="adaptive", merge_s=0.0)
    got = segment(rec, p)
    assert [k.state.sorted_relations() for k in got.keyframes] == [[], [("cup", "hand")], []]
    assert got.keyframes == segment_reference(rec, p).keyframes


# -- the command line ------------------------------------------------------------------------------

def test_hold_and_change_window_on_the_command_line(capsys, tmp_path):
    import json

    from oacdsl.cli import main
    from oacdsl.segmentation.readers import write_c3d

    c3d = write_c3d(_resample(carry_scene(), 200.0, 0.0003, 7), tmp_path / "carry.c3d")
    assert main(["segment", str(c3d), "--json", "--hold", "0.2s", "--change-window", "50ms"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["parameters"]["frames"] == 40 and doc["parameters"]["change_window_s"] == 0.05
    assert [k["relations"] for k in doc["keyframes"]] == [[], [["cup", "hand"]], []]
    for argv, needle in ((["--hold", "0.1s", "--frames", "3"], "--frames and --hold both set n"),
                         (["--change-window", "0s"], "change window must be a positive duration"),
                         (["--hold", "2"], "--hold: '2' has no unit"),
                         (["--hold", "1e9s"], "--hold 1e9s: longer than the recording"),
                         (["--change-window", "60s"], "--change-window 60s: longer than")):
        assert main(["segment", str(c3d), *argv]) == 2
        err = capsys.readouterr().err
        assert err.count("\n") == 1 and needle in err


def test_a_short_excursion_does_not_end_a_hold():
    # episodes.extend_episode: a hand marker hidden for 3 frames makes the closest distance jump to the
    # next marker's; the hold goes on (bridged up to tool_bridge_s), a longer one ends it
    from oacdsl.segmentation.episodes import extend_episode

    d = np.full(100, 0.06, dtype=np.float32)
    d[60:63] = 0.10
    assert extend_episode(d, 10, 20, 0.07) == (0, 60)
    assert extend_episode(d, 10, 20, 0.07, bridge=3) == (0, 100)
    d[60:70] = 0.10
    assert extend_episode(d, 10, 20, 0.07, bridge=3) == (0, 60)
