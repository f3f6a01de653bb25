"""The adaptive detector's invariances (issue 20): rigid gap filling, the demonstration's own pace
(``AdaptiveSettings.rescale``) and merging of connected changes only (``AdaptiveSettings.merge``).

Fast cases on hand-made recordings; mocap-guarded ones on the KIT development clips.
"""

from __future__ import annotations

import numpy as np
import pytest
from _aas_helpers import path, recording, still, summary
from _mocap import mocap_file
from segeval.reference import segment_reference

from oacdsl.errors import SegmentationError
from oacdsl.segmentation import AasParams, segment
from oacdsl.segmentation.adaptive import AdaptiveDetector, AdaptiveSettings
from oacdsl.segmentation.grouping import recognise_preset
from oacdsl.segmentation.keyframes import merge_keyframes
from oacdsl.segmentation.poses import fill_rigid_gaps
from oacdsl.segmentation.readers import read_recording
from oacdsl.segmentation.result import Keyframe
from oacdsl.segmentation.scales import (
    MIN_REACH_FACTOR,
    SUBJECT_BAND,
    DemoScale,
    measure,
    scale_params,
    tool_reach_m,
)
from oacdsl.segmentation.takes import scaled, stretched, with_gap
from oacdsl.world import WorldState

F = 500
CUP = np.array([[0.03, 0.03, 0.0], [-0.03, 0.03, 0.0], [0.03, -0.03, 0.05], [-0.03, -0.03, 0.05]])
# a KIT-like hand: wrist to finger tip, 16 cm
HAND = np.array([[0.0, 0.0, 0.0], [0.04, 0.0, 0.0], [0.0, 0.03, 0.01], [0.12, 0.05, 0.0], [0.15, 0.04, 0.02]])
GRIP = np.array([0.0, 0.0, 0.14])


def cluster(centre: np.ndarray, layout: np.ndarray) -> np.ndarray:
    return centre[:, None, :] + layout[None, :, :]


def carry() -> dict[str, np.ndarray]:
    """A hand reaches a cup (100), carries it (150-300), sets it down and leaves (350-450)."""
    start, goal = (0.5, 0.0, 0.0), (0.9, 0.2, 0.0)
    cup = path(F, [(0, start), (150, start), (300, goal)])
    held, placed = tuple(np.add(start, GRIP)), tuple(np.add(goal, GRIP))
    hand = path(F, [(0, (0.2, -0.3, 0.4)), (100, held), (150, held), (300, placed), (350, placed),
                    (450, (1.0, 0.4, 0.5))])
    return {"cup": cluster(cup, CUP), "right_hand": cluster(hand, HAND)}


def run(rec, settings: AdaptiveSettings | None = None, **kwargs) -> list:
    params = AasParams(**kwargs)
    detector = AdaptiveDetector(params.resolved(rec.rate_hz), settings)
    return summary(segment(rec, params, detector=detector))


# --- rigid gap filling -------------------------------------------------------------------------

def test_a_rigid_objects_hidden_marker_is_put_where_its_fit_says():
    rec = recording(carry())
    gap = with_gap(rec, "cup.0", 2.0, 0.5)  # while the cup is carried
    hidden = np.isnan(gap.positions_m[:, 0, 0])
    assert hidden.sum() == 50
    filled = fill_rigid_gaps(gap, ["cup", "right_hand"])
    assert np.allclose(filled.positions_m, rec.positions_m, atol=1e-9)
    # nothing to fill: the same recording; an instance of three markers has no spare marker
    assert fill_rigid_gaps(rec, ["cup"]) is rec
    three = recording({"cup": cluster(still(10, (0, 0, 0)), CUP[:3])})
    three.positions_m[2, 0] = np.nan
    assert np.isnan(fill_rigid_gaps(three, ["cup"]).positions_m[2, 0]).all()


def test_the_default_detector_fills_object_gaps_but_not_hands():
    rec = recording(carry())
    gap = with_gap(rec, "cup.0", 2.0, 0.5)
    det = AdaptiveDetector(AasParams().resolved(rec.rate_hz))
    mended = det.prepare(with_gap(gap, "right_hand.0", 2.0, 0.5))
    assert np.isfinite(mended.positions_m[:, :4]).all()  # the cup's markers
    assert np.isnan(mended.positions_m[200:250, 4]).all()  # the hand's: a hand is not rigid
    assert AdaptiveDetector(AasParams().resolved(100), AdaptiveSettings(fill_gaps=False)).prepare(gap) is gap


@pytest.mark.mocap
def test_a_half_second_gap_in_a_cup_marker_leaves_the_stir_clip_as_it_was():
    xml = next(mocap_file("kit_bimanual").glob("Stir_*.mmm.xml"))
    raw = read_recording(xml)
    original, _ = recognise_preset(raw)
    marker = original.marker_names[original.groups["cup_large"][0]]
    gap, _ = recognise_preset(with_gap(raw, marker, 0.4 * float(raw.times_s[-1]), 0.5))
    assert run(gap) == run(original)
    # without the fill the closest distance jumps to the next marker's: the tablespoon touches
    # the left hand holding the cup for 1.6 s
    assert run(gap, AdaptiveSettings(fill_gaps=False)) != run(original)


# --- the demonstration's pace -----------------------------------------------------------------

def test_the_pace_halves_on_a_take_twice_as_slow_and_grows_with_the_scale():
    rec = recording(carry())
    base = measure(rec, ("right_hand",))
    slow = measure(stretched(rec, 2.0), ("right_hand",))
    large = measure(scaled(rec, 1.15), ("right_hand",))
    assert slow.speed == pytest.approx(base.speed / 2, rel=0.02)
    assert slow.length == pytest.approx(base.length, rel=1e-6)
    assert slow.time == pytest.approx(2 * base.time, rel=0.02)
    assert large.length == pytest.approx(1.15 * base.length, rel=1e-6)
    assert large.time == pytest.approx(base.time, rel=0.02)  # 15 % larger is 15 % faster, not quicker
    assert measure(rec, ()) == DemoScale()  # no hands: the constants stay


def test_rescaled_parameters_grow_d_only_and_keep_an_explicit_frame_count():
    p = scale_params(AasParams(frames=3), DemoScale(length=1.2, speed=0.5))
    assert p.distance_m == pytest.approx(0.18) and p.frames == 3  # a larger demonstrator: a longer reach
    assert scale_params(AasParams(), DemoScale(length=0.9, speed=0.5)).distance_m == 0.15  # never shorter
    assert p.speed_m_s == pytest.approx(0.05) and p.merge_s == pytest.approx(0.3 * 2.4)
    assert p.hold_s == pytest.approx(0.24) and p.change_window_s == pytest.approx(0.24)


def test_a_take_twice_as_slow_keeps_its_keyframes_when_rescaled():
    rec = recording(carry())
    slow = stretched(rec, 2.0)
    on = AdaptiveSettings(rescale=True)
    base, got = run(rec, on), run(slow, on)
    assert [r for _, r in base] == [r for _, r in got]
    assert all(abs(f2 / 2 - f1) <= 1 for (f1, _), (f2, _) in zip(base, got, strict=True))
    seg = segment(slow, AasParams(), detector=AdaptiveDetector(AasParams().resolved(100), on))
    assert seg.parameters["scale"]["time"] == pytest.approx(2 * measure(rec, ("right_hand",)).time, rel=0.02)


@pytest.mark.mocap
@pytest.mark.parametrize("clip", ["Pour", "Scoop", "Cut"])
def test_a_kit_clip_twice_as_slow_keeps_its_keyframes_when_rescaled(clip):
    raw = read_recording(next(mocap_file("kit_bimanual").glob(f"{clip}_*.mmm.xml")))
    original, _ = recognise_preset(raw)
    slow, _ = recognise_preset(stretched(raw, 2.0))

    def same(settings: AdaptiveSettings) -> bool:
        base, got = run(original, settings), run(slow, settings)
        return [r for _, r in base] == [r for _, r in got] and all(
            abs(f2 / 2 - f1) <= 1 for (f1, _), (f2, _) in zip(base, got, strict=True))

    assert same(AdaptiveSettings(rescale=True))
    assert not same(AdaptiveSettings(rescale=False))  # fixed speeds and durations: other keyframes


# --- merging connected changes only -----------------------------------------------------------

def _kf(frame: int, *rels: tuple[str, str]) -> Keyframe:
    return Keyframe(frame, frame / 10, WorldState(frozenset("abcdhk"), frozenset(rels)))


def test_connected_merge_keeps_independent_changes_and_joins_one_objects():
    ah, ac, bk = ("a", "h"), ("a", "c"), ("b", "k")
    kfs = [_kf(0), _kf(10, ah), _kf(11, ah, ac), _kf(12, ah, ac, bk)]
    # the paper's: one chain, at its last frame
    assert [k.frame for k in merge_keyframes(kfs, 0.3)] == [0, 12]
    got = merge_keyframes(kfs, 0.3, at_onset=True, connected=True)
    # h grasps a (10) and a reaches c (11): one event at its first frame; k grasps b (12) on its own
    assert [(k.frame, len(k.state.relations)) for k in got] == [(0, 0), (10, 2), (12, 3)]
    assert got[1].state.relations == {("a", "h"), ("a", "c")}


def test_connected_merge_drops_a_bounce_and_folds_early_flicker():
    kfs = [_kf(0), _kf(1, ("a", "b")), _kf(2), _kf(20, ("c", "d")), _kf(21), _kf(40, ("c", "d"))]
    got = merge_keyframes(kfs, 0.3, at_onset=True, connected=True)
    assert [(k.frame, sorted(k.state.relations)) for k in got] == [(0, []), (40, [("c", "d")])]


def test_the_options_agree_with_the_per_frame_reference():
    rec = with_gap(recording(carry()), "cup.1", 1.0, 0.3)
    params = AasParams(merge_s=0.3)
    for settings in (AdaptiveSettings(), AdaptiveSettings(rescale=False, merge="paper")):
        det = AdaptiveDetector(params.resolved(rec.rate_hz), settings)
        fast = segment(rec, params, detector=det)
        assert fast.keyframes == segment_reference(rec, params, settings).keyframes


def test_bad_merge_option():
    with pytest.raises(SegmentationError, match="merge must be"):
        AdaptiveSettings(merge="last")


# --- holding still ----------------------------------------------------------------------------

BOTTLE = np.array([[0.04, 0.0, 0.0], [-0.04, 0.0, 0.05], [0.0, 0.04, 0.15], [0.0, -0.04, 0.2]])  # 21 cm


def bottle_scene() -> dict[str, np.ndarray]:
    """The left hand comes to the bottle (1 s) and holds it still, its nearest marker 9 cm from the
    bottle's (beyond the 8 cm of the static rule), while the right hand turns the lid (1.5-4 s);
    both hands leave (4.5-5 s)."""
    n, base = 600, np.array([0.5, 0.0, 0.0])
    bottle = cluster(still(n, tuple(base)), BOTTLE)
    at = tuple(base + (-0.13, 0.0, 0.05))
    left = path(n, [(0, (0.2, -0.3, 0.3)), (100, at), (450, at), (500, (0.2, -0.3, 0.3))])
    top = base + (0.0, 0.0, 0.22)
    ang = np.interp(np.arange(n), [150, 400], [0.0, 3 * np.pi])
    lid_layout = np.array([[0.02, 0.0, 0.0], [-0.02, 0.0, 0.0], [0.0, 0.02, 0.01]])
    rot = np.stack([np.cos(ang), -np.sin(ang), np.sin(ang), np.cos(ang)], axis=1).reshape(n, 2, 2)
    lid = np.repeat(lid_layout[None], n, axis=0)
    lid[:, :, :2] = np.einsum("fij,kj->fki", rot, lid_layout[:, :2])
    lid += top
    grip = np.array([0.0, 0.0, 0.06])
    right_at = path(n, [(0, (0.8, 0.3, 0.4)), (140, tuple(top + grip)), (410, tuple(top + grip)),
                        (480, (0.8, 0.3, 0.4))])
    right = np.repeat(right_at[:, None, :], 5, axis=1) + HAND[None] * 0.5
    right[:, :, :2] = right_at[:, None, :2] + np.einsum("fij,kj->fki", rot, HAND[:, :2] * 0.5)
    back = HAND * (-1.0, 1.0, 1.0)  # the fingers point away from the bottle: markers on the back
    return {"bottle": bottle, "lid": lid, "left_hand": cluster(left, back), "right_hand": right}


def test_a_hand_holding_a_still_bottle_touches_it_by_default():
    rec = recording(bottle_scene())
    without = {r for _, rs in run(rec, AdaptiveSettings(hold_still=False)) for r in rs}
    assert ("bottle", "left_hand") not in without  # nothing moves with it: co-motion cannot see it
    with_hold = run(rec)
    on = [f for f, rs in with_hold if ("bottle", "left_hand") in rs]
    off = [f for f, rs in with_hold if on and f > on[0] and ("bottle", "left_hand") not in rs]
    assert on and 100 <= on[0] <= 160 and off and 440 <= off[0] <= 470, with_hold


def test_holding_still_agrees_with_the_per_frame_reference():
    rec = recording(bottle_scene())
    params = AasParams()
    for settings in (AdaptiveSettings(), AdaptiveSettings(hold_still=False)):
        fast = segment(rec, params, detector=AdaptiveDetector(params.resolved(rec.rate_hz), settings))
        assert fast.keyframes == segment_reference(rec, params, settings).keyframes
    assert segment(rec).keyframes == segment_reference(rec, params).keyframes  # the defaults: with it
    assert AdaptiveSettings().hold_still


# --- the tool rule's reach in the scene's length ------------------------------------------------

SPOON = np.array([[0.0, 0.0, 0.0], [0.0, 0.0, 0.04], [0.01, 0.0, 0.08]])


def hover_then_stir() -> dict[str, np.ndarray]:
    """A cup stands still; a hand takes a spoon (50-100), holds it 165 mm from the cup's nearest
    marker (150-250: beyond the 150 mm reach), stirs in the cup (300-400) and takes it away (450)."""
    frames = 560
    cup_at = np.array([0.9, 0.0, 0.0])
    spoon_start = (0.5, 0.0, 0.0)
    hover = (0.9 - 0.03 - 0.175, -0.03, 0.0)  # its nearest marker 165 mm from the cup's
    stir = [(300 + 20 * i, (0.9 + (0.01 if i % 2 else -0.01), 0.0, 0.02)) for i in range(6)]
    keys = [(0, spoon_start), (100, spoon_start), (150, hover), (250, hover), *stir, (450, (0.5, 0.3, 0.0))]
    spoon = path(frames, keys)
    hand = spoon + GRIP
    hand[:100] = path(frames, [(0, (0.3, -0.3, 0.3)), (50, tuple(np.add(spoon_start, GRIP)))])[:100]
    return {"cup": cluster(still(frames, tuple(cup_at)), CUP), "right_hand": cluster(hand, HAND),
            "spoon": cluster(spoon, SPOON)}


def test_a_smaller_take_keeps_a_tool_out_of_reach_where_the_original_did():
    rec = recording(hover_then_stir())
    base, small = run(rec), run(scaled(rec, 0.85))
    assert ("cup", "spoon") in base[-2][1]  # the stir is a tool contact
    assert [r for _, r in small] == [r for _, r in base]
    assert all(abs(f1 - f2) <= 1 for (f1, _), (f2, _) in zip(base, small, strict=True))


def test_the_tool_reach_shrinks_with_a_smaller_scene_not_with_a_subjects_hands():
    assert tool_reach_m(AasParams(), DemoScale(length=1.2)) == pytest.approx(0.18)  # as d grows
    assert tool_reach_m(AasParams(), DemoScale(length=0.95)) == 0.15  # a subject with smaller hands
    assert tool_reach_m(AasParams(), DemoScale(length=0.85)) == pytest.approx(0.15 * 0.85 / SUBJECT_BAND)
    assert tool_reach_m(AasParams(), DemoScale(length=0.34)) == pytest.approx(0.15 * MIN_REACH_FACTOR)
    rec = scaled(recording(hover_then_stir()), 0.85)
    det = AdaptiveDetector(AasParams().resolved(rec.rate_hz))
    det.effective_params(rec, AasParams())
    assert det.scale is not None and det.scale.length < SUBJECT_BAND
    assert det.tool_reach_m == pytest.approx(0.15 * det.scale.length / SUBJECT_BAND)
    assert det.params.distance_m == 0.15  # d itself, a cap on learned distances, never shrinks
