"""The demonstrated motion of each sub-action: features (synthetic), assignment (synthetic), KIT clips."""

import json
import math

import numpy as np
import pytest
from _mocap import mocap_file
from _motion_helpers import synthetic_stir

from oacdsl.segmentation import segment
from oacdsl.segmentation.grouping import group_recording
from oacdsl.segmentation.motion import sub_action_motions
from oacdsl.segmentation.motionfeatures import dominant_period, motion_features
from oacdsl.segmentation.readers import read_recording
from oacdsl.segmentation.recording import Recording


def path_transforms(xyz, tilt_rad=None):
    """(N, 4, 4) poses at positions ``xyz`` (N, 3), tilted about x by ``tilt_rad`` (N,)."""
    T = np.tile(np.eye(4), (len(xyz), 1, 1))
    T[:, :3, 3] = xyz
    if tilt_rad is not None:
        c, s = np.cos(tilt_rad), np.sin(tilt_rad)
        T[:, 1, 1], T[:, 1, 2], T[:, 2, 1], T[:, 2, 2] = c, -s, s, c
    return T


def circle(t, period_s, radius_m, rng, noise_m=0.001):
    w = 2 * np.pi * t / period_s
    xyz = np.stack([radius_m * np.cos(w), radius_m * np.sin(w), 0.08 + 0.0 * t], axis=1)
    return xyz + rng.normal(0.0, noise_m, xyz.shape)


@pytest.mark.parametrize("rate_hz, period_s, radius_m", [(10, 0.5, 0.02), (10, 0.8, 0.04), (100, 0.6, 0.03),
                                                         (240, 1.2, 0.05)])
def test_stirring_circle_gives_its_period_and_radius(rate_hz, period_s, radius_m):
    rng = np.random.default_rng(rate_hz)
    t = np.arange(0, 3.0, 1 / rate_hz)
    xyz = circle(t, period_s, radius_m, rng)
    T = path_transforms(xyz)
    T[len(t) // 3 : len(t) // 3 + max(1, len(t) // 30)] = np.nan  # a gap
    f = motion_features(t, T)
    assert f.period_s == pytest.approx(period_s, rel=0.05)
    assert f.radius_m == pytest.approx(radius_m, rel=0.1)
    assert f.cycles == pytest.approx(3.0 / period_s, rel=0.1)
    assert f.path_length_m == pytest.approx(2 * np.pi * radius_m * 3.0 / period_s, rel=0.15)


def test_entry_and_exit_do_not_hide_the_circles():
    """The spoon comes down into the cup, stirs, and leaves: the period is the circles'."""
    rng = np.random.default_rng(1)
    t = np.arange(0, 2.2, 0.1)  # 10 Hz, like the KIT clips
    xyz = circle(t, 0.5, 0.015, rng)
    xyz[:3] += np.array([[0, 0.15, 0.12], [0, 0.08, 0.06], [0, 0.04, 0.03]])
    xyz[-3:] += np.array([[0, 0.04, 0.03], [0, 0.09, 0.07], [0, 0.17, 0.12]])
    f = motion_features(t, path_transforms(xyz))
    assert f.period_s == pytest.approx(0.5, rel=0.1)
    assert f.radius_m == pytest.approx(0.015, rel=0.25)
    assert f.core_s[0] >= 0.1 and f.core_s[1] <= 2.0
    assert f.extent_m[0] > 0.15  # the extent is the whole path's


def test_wiping_strokes_give_their_period():
    t = np.arange(0, 4.0, 0.01)
    xyz = np.stack([0.1 * np.sin(2 * np.pi * t / 0.9), 0.01 * t, 0 * t], axis=1)  # strokes with a drift
    f = motion_features(t, path_transforms(xyz))
    assert f.period_s == pytest.approx(0.9, rel=0.03)
    assert f.extent_m[0] == pytest.approx(0.2, rel=0.05)


@pytest.mark.parametrize("xyz", [
    lambda t: np.stack([0.3 * t, 0.1 * t, 0 * t], axis=1),  # a straight carry
    lambda t: np.stack([np.random.default_rng(0).normal(0, 0.002, t.size), 0 * t, 0 * t], axis=1),  # noise
])
def test_no_oscillation_no_period(xyz):
    t = np.arange(0, 2.0, 0.01)
    f = motion_features(t, path_transforms(xyz(t)))
    assert f.period_s is None and f.cycles is None


def test_too_few_frames_for_a_period():
    t = np.arange(5) * 0.1
    assert dominant_period(t, np.sin(2 * np.pi * t / 0.2)) == (None, 0.0)


def test_a_tilt_gives_its_angle_and_time():
    """A pour: tilt up to 100° over 1 s, hold 1.5 s, back over 1 s (10 Hz)."""
    t = np.arange(0, 3.5, 0.1)
    tilt = np.radians(100) * np.clip(np.minimum(t, 3.5 - t), 0, 1.0)
    f = motion_features(t, path_transforms(np.zeros((t.size, 3)), tilt))
    assert math.degrees(f.tilt_max_rad) == pytest.approx(100, abs=0.5)
    assert f.tilt_time_s == pytest.approx(2.5, abs=0.15)  # above 50°: from 0.5 s to 3.0 s
    assert f.tilt_rise_s == pytest.approx(0.8, abs=0.01)  # 10 % at 0.1 s, 90 % at 0.9 s
    assert f.path_length_m == 0.0


def _turning(t, angle, wobble_rad=0.0):
    """(N, 4, 4): an object turning by ``angle`` (rad, per frame) about z, leaning ``wobble_rad``
    about x (a hand turning a lid is not exactly upright)."""
    T = np.tile(np.eye(4), (t.size, 1, 1))
    for k, (a, w) in enumerate(zip(angle, wobble_rad * np.sin(7 * t), strict=True)):
        rz = np.array([[math.cos(a), -math.sin(a), 0], [math.sin(a), math.cos(a), 0], [0, 0, 1]])
        rx = np.array([[1, 0, 0], [0, math.cos(w), -math.sin(w)], [0, math.sin(w), math.cos(w)]])
        T[k, :3, :3] = rx @ rz
    return T


def test_a_twist_adds_up_several_turns_with_their_sense():
    """A lid unscrewed in three strokes of 120° (still between them, as while the hand regrasps),
    at 10 Hz, a little wobbly, with a gap: 360° in all, counterclockwise seen from above."""
    t = np.arange(0, 4.5, 0.1)
    phase = np.clip(t % 1.5, 0, 1.0)  # each stroke: 1 s turning, 0.5 s still
    angle = np.radians(120) * (t // 1.5 + phase)
    T = _turning(t, angle, wobble_rad=math.radians(3))
    T[20:22] = np.nan
    f = motion_features(t, T)
    assert math.degrees(f.twist_rad) == pytest.approx(360, abs=6)
    screwed = motion_features(t, _turning(t, -angle))
    assert math.degrees(screwed.twist_rad) == pytest.approx(-360, abs=1)
    assert f.to_json()["twist_rad"] == pytest.approx(f.twist_rad, abs=1e-6)


def test_a_tilt_is_no_twist():
    t = np.arange(0, 3.5, 0.1)
    tilt = np.radians(100) * np.clip(np.minimum(t, 3.5 - t), 0, 1.0)
    f = motion_features(t, path_transforms(np.zeros((t.size, 3)), tilt))
    assert abs(f.twist_rad) < 1e-9


def test_no_tilt_no_rise():
    t = np.arange(0, 2.0, 0.1)
    f = motion_features(t, path_transforms(np.zeros((t.size, 3)), np.radians(2.0) * np.ones(t.size)))
    assert f.tilt_rise_s is None and f.tilt_time_s == 0.0




def test_moved_object_and_target_per_sub_action():
    rec, seg = synthetic_stir()
    motions = sub_action_motions(rec, seg)
    got = [(m.hand, m.moved, m.target, m.relation) for m in motions]
    assert got == [
        ("right_hand", "right_hand", "spoon", "made"),  # the hand reaches for the spoon
        ("right_hand", "spoon", "cup", "made"),  # carried into the cup (it travels farther than the cup)
        ("right_hand", "spoon", "cup", "kept"),  # stirs, and leaves it in the cup
    ]
    stir = motions[2]
    assert (stir.start_frame, stir.end_frame) == (40, 100) and stir.times_s[0] == 2.0
    assert stir.features.period_s == pytest.approx(0.6, rel=0.05)
    assert stir.features.radius_m == pytest.approx(0.02, rel=0.1)
    # the path is the spoon's in the cup's frame: the cup's slide is taken out
    offset = stir.T_target_object[:, :3, 3] - np.array([0.0, 0.0, 0.1])
    assert np.abs(offset[:, 2]).max() < 1e-9
    assert np.abs(np.linalg.norm(offset[1:-1, :2], axis=1) - 0.02).max() < 1e-9
    assert stir.residual_m < 1e-9


def test_motion_record_is_json():
    rec, seg = synthetic_stir()
    rec.positions_m[60, 4:8] = np.nan  # the spoon unseen in one frame: a gap in the trajectory
    doc = json.loads(json.dumps([m.to_json() for m in sub_action_motions(rec, seg)], allow_nan=False))
    stir = doc[2]
    assert stir["moved"] == "spoon" and stir["target"] == "cup" and stir["frame"] == "cup"
    assert len(stir["times_s"]) == len(stir["T_target_object"]) == 61
    assert stir["T_target_object"][20] is None and len(stir["T_target_object"][0]) == 4
    assert set(stir["features"]) >= {"path_length_m", "extent_m", "period_s", "tilt_max_rad", "tilt_time_s"}


def test_nothing_held_and_no_poses():
    rec, seg = synthetic_stir()
    flat = Recording(rec.source, rec.rate_hz, rec.times_s, rec.marker_names, rec.positions_m,
                     {name: idx[:2] for name, idx in rec.groups.items()})  # 2 markers each: no poses
    motions = sub_action_motions(flat, seg)
    assert [m.moved for m in motions] == [None, None, None]
    assert motions[0].to_json(trajectory=False)["features"] is None


# --- development clips (../shared/mocap); never the evaluation clips -------------------------

KIT = "kit_bimanual/{}.mmm.xml"


def kit_motions(clip):
    recording, _ = group_recording(read_recording(mocap_file(KIT.format(clip))), None)
    return sub_action_motions(recording, segment(recording))


def one(motions, moved, target):
    found = [m for m in motions if (m.moved, m.target) == (moved, target) and m.features.period_s is not None
             or (m.moved, m.target) == (moved, target) and m.relation != "made"]
    assert found, [(m.moved, m.target, m.relation) for m in motions]
    return max(found, key=lambda m: m.end_frame - m.start_frame)


def test_kit_stir_spoon_circles_in_the_cup():
    m = one(kit_motions("Stir_files_motions_2941_Stir1_bc_s_right_03"), "tablespoon", "cup_large")
    assert m.hand == "right_hand"
    assert 0.4 <= m.features.period_s <= 0.6  # measured 0.50 s (10 Hz clip)
    assert m.features.cycles >= 2.5  # measured 3.4
    assert 0.008 <= m.features.radius_m <= 0.03  # measured 16 mm


def test_kit_pour_milk_tilts_over_the_cup():
    m = one(kit_motions("Pour_files_motions_2967_Pour1_cs_ms_0_20l_04"), "milk_small", "cup_small")
    assert m.hand == "right_hand"
    assert math.degrees(m.features.tilt_max_rad) > 75  # measured 91°
    assert m.features.tilt_time_s >= 1.0  # measured 2.1 s


def test_kit_wipe_sponge_strokes_along_the_plate():
    m = one(kit_motions("Wipe_files_motions_3091_Wipe1_pl_sp_front_angle_03"), "sponge_small", "plate_dish")
    assert 0.5 <= m.features.period_s <= 0.85  # measured 0.67 s
    core = (m.times_s >= m.features.core_s[0]) & (m.times_s <= m.features.core_s[1])
    spread = np.nanstd(m.T_target_object[core, :3, 3], axis=0)
    assert spread[2] < 0.3 * min(spread[0], spread[1])  # in the plate's plane, not across it
