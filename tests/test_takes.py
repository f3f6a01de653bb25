"""Other takes of a recording (oacdsl.segmentation.takes, .mirror), their files and ``oacc take``."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from _mocap import mocap_file

from oacdsl.cli import main
from oacdsl.compiler import load_library
from oacdsl.errors import RecordingError
from oacdsl.segmentation.mirror import mirror_label, sagittal_plane
from oacdsl.segmentation.readers import read_recording, write_recording
from oacdsl.segmentation.recording import Recording
from oacdsl.segmentation.takes import (
    IDENTITY,
    STANDARD_TAKES,
    gap_marker,
    mirrored,
    resampled,
    rotated,
    scaled,
    stretched,
    translated,
    with_gap,
)

ROOT = Path(__file__).resolve().parents[1]
KIT = ROOT / "library" / "kit"
DOUGH = ROOT / "data" / "dough.c3d"

#: A subject standing at x = 0.3 m facing +x (left is +y), turned by _TURN about the vertical.
_TURN = 0.4
_TORSO = {
    "CLAV": (0.1, 0.0, 1.4),
    "STRN": (0.12, 0.0, 1.3),
    "C7": (-0.05, 0.0, 1.5),
    "T10": (-0.1, 0.0, 1.2),
    "LSHO": (0.0, 0.18, 1.45),
    "RSHO": (0.0, -0.18, 1.45),
    "LASI": (0.08, 0.12, 1.0),
    "RASI": (0.08, -0.12, 1.0),
}


def _turn(xyz: np.ndarray) -> np.ndarray:
    c, s = np.cos(_TURN), np.sin(_TURN)
    out = xyz.copy()
    out[..., 0], out[..., 1] = c * xyz[..., 0] - s * xyz[..., 1], s * xyz[..., 0] + c * xyz[..., 1]
    return out + np.array([0.3, 0.0, 0.0])


def synthetic(frames: int = 60, rate_hz: float = 20.0, torso: bool = True, seed: int = 1) -> Recording:
    """Two hands (KIT labels, one group each), a cup moving from 1 s to 2 s, a board; the subject's
    torso (ungrouped, like after the KIT preset) when ``torso``; a gap in the cup's second marker."""
    rng = np.random.default_rng(seed)
    t = np.arange(frames) / rate_hz
    names: list[str] = []
    tracks: list[np.ndarray] = []
    groups: dict[str, tuple[int, ...]] = {}

    def add(group: str | None, label: str, path: np.ndarray) -> None:
        if group is not None:
            groups[group] = (*groups.get(group, ()), len(names))
        names.append(label)
        tracks.append(path)

    wobble = 0.01 * np.sin(t)[:, None] * np.array([1.0, 0.5, 0.2])
    for side, y in (("left", 0.25), ("right", -0.2)):
        base = np.array([0.45, y, 0.95])
        for k, m in enumerate(("HPS", "HTS", "IFD", "WPS", "WTS")):
            local = base + 0.02 * np.array([k % 2, k // 2, k % 3])
            add(
                f"{side}_hand", f"{side[0].upper()}{m}", _turn(local + wobble * (2 if side == "right" else 1))
            )
    motion = np.clip(t - 1.0, 0.0, 1.0)[:, None] * np.array([0.0, 0.2, 0.1])
    for k in range(3):
        add("cup", f"cup_{k + 1}", _turn(np.array([0.55, 0.0 + 0.03 * k, 0.9 + 0.01 * k]) + motion))
    for k in range(3):
        add("board", f"board_{k + 1}", _turn(np.array([0.6 + 0.1 * k, -0.1, 0.85 + 0.0 * k]) + 0 * wobble))
    if torso:
        for label, xyz in _TORSO.items():
            add(None, label, _turn(np.array(xyz) + 0.002 * rng.standard_normal((frames, 3))))
    positions = np.stack(tracks, axis=1)
    positions[10:14, names.index("cup_2")] = np.nan
    return Recording("synthetic", rate_hz, t, tuple(names), positions, groups)


def _distances(p: np.ndarray) -> np.ndarray:
    return np.linalg.norm(p[:, :, None] - p[:, None, :], axis=-1)


def test_rotation_and_translation_preserve_distances_and_heights():
    rec = synthetic()
    take = translated(rotated(rec, 1.1), (2.0, -1.0))
    assert np.allclose(_distances(take.positions_m), _distances(rec.positions_m), equal_nan=True)
    assert np.allclose(take.positions_m[..., 2], rec.positions_m[..., 2], equal_nan=True)
    assert not np.allclose(take.positions_m, rec.positions_m, equal_nan=True)
    back = rotated(translated(take, (-2.0, 1.0, 0.0)), -1.1, about_xy_m=_mean_xy(rec))
    assert np.allclose(back.positions_m, rec.positions_m, atol=1e-12, equal_nan=True)
    assert take.marker_names == rec.marker_names and dict(take.groups) == dict(rec.groups)


def _mean_xy(rec: Recording) -> np.ndarray:
    xy = rec.positions_m[..., :2].reshape(-1, 2)
    return xy[np.isfinite(xy).all(axis=1)].mean(axis=0)


def test_scale_multiplies_distances_about_the_floor():
    rec = synthetic()
    take = scaled(rec, 1.15)
    assert np.allclose(_distances(take.positions_m), 1.15 * _distances(rec.positions_m), equal_nan=True)
    assert np.allclose(take.positions_m[..., 2], 1.15 * rec.positions_m[..., 2], equal_nan=True)
    with pytest.raises(RecordingError, match="positive"):
        scaled(rec, 0.0)


def test_stretch_doubles_the_duration_at_the_same_rate():
    rec = synthetic()
    slow = stretched(rec, 2.0)
    assert slow.rate_hz == rec.rate_hz
    assert slow.times_s[-1] == pytest.approx(2 * rec.times_s[-1])
    assert np.allclose(np.diff(slow.times_s), 1 / rec.rate_hz)
    assert np.allclose(
        slow.positions_m[::2], rec.positions_m, equal_nan=True
    )  # every other frame: the original
    between = slow.positions_m[1::2]
    assert np.allclose(between, (rec.positions_m[:-1] + rec.positions_m[1:]) / 2, equal_nan=True)
    fast = stretched(rec, 0.5)
    assert fast.times_s[-1] == pytest.approx(rec.times_s[-1] / 2, abs=1 / rec.rate_hz)
    assert np.allclose(fast.positions_m, rec.positions_m[::2], equal_nan=True)
    assert np.array_equal(stretched(rec, 1.0).positions_m, rec.positions_m, equal_nan=True)


def test_resampling_keeps_gaps_and_never_interpolates_across_them():
    rec = synthetic()
    gap = rec.marker_names.index("cup_2")
    take = resampled(rec, 100.0)
    assert take.rate_hz == 100.0 and np.allclose(np.diff(take.times_s), 0.01)
    missing = np.isnan(take.positions_m[:, gap, 0])
    t = take.times_s
    # the original gap is frames 10..13 (0.5 s to 0.65 s); neighbours at 0.45 s and 0.7 s are finite
    assert missing[(t > 0.45 + 1e-9) & (t < 0.7 - 1e-9)].all()
    assert not missing[(t <= 0.45 + 1e-9) | (t >= 0.7 - 1e-9)].any()
    on_frames = np.isclose((t * rec.rate_hz) % 1, 0) | np.isclose((t * rec.rate_hz) % 1, 1)
    assert np.allclose(
        take.positions_m[on_frames],
        rec.positions_m[np.round(t[on_frames] * rec.rate_hz).astype(int)],
        equal_nan=True,
    )


def test_jitter_has_the_given_spread_and_follows_the_seed():
    rec = synthetic(frames=400)
    a = resampled(rec, rec.rate_hz, jitter_m=0.0002, seed=3)
    noise = (a.positions_m - rec.positions_m)[np.isfinite(rec.positions_m)]
    assert noise.std() == pytest.approx(0.0002, rel=0.05) and abs(noise.mean()) < 2e-5
    assert np.array_equal(
        a.positions_m, resampled(rec, rec.rate_hz, 0.0002, seed=3).positions_m, equal_nan=True
    )
    assert not np.allclose(
        a.positions_m, resampled(rec, rec.rate_hz, 0.0002, seed=4).positions_m, equal_nan=True
    )


def test_a_gap_removes_exactly_its_window():
    rec = synthetic()
    take = with_gap(rec, "board_2", 1.0, 0.5)
    i = rec.marker_names.index("board_2")
    changed = np.isnan(take.positions_m[:, i, 0]) & ~np.isnan(rec.positions_m[:, i, 0])
    assert np.flatnonzero(changed).tolist() == list(range(20, 30))
    others = np.delete(np.arange(len(rec.marker_names)), i)
    assert np.array_equal(take.positions_m[:, others], rec.positions_m[:, others], equal_nan=True)
    with pytest.raises(RecordingError, match="did you mean 'board_2'"):
        with_gap(rec, "bord_2", 1.0, 0.5)
    with pytest.raises(RecordingError, match="holds no frame"):
        with_gap(rec, "board_2", 10.0, 0.5)


def test_the_standard_gap_falls_on_the_moving_object_while_it_moves():
    rec = synthetic()
    marker, start = gap_marker(rec, 0.5)
    assert marker == "cup_1"  # the cup moves, the board does not; cup_2 has a gap already
    assert 0.5 <= start <= 1.5  # the window lies in the motion (1 s to 2 s)


def test_the_sagittal_plane_comes_from_the_torso():
    rec = synthetic()
    point, normal, how = sagittal_plane(rec)
    assert how == "torso"
    expected = np.array([-np.sin(_TURN), np.cos(_TURN), 0.0])  # the subject's left, turned
    assert abs(float(normal @ expected)) == pytest.approx(1.0, abs=1e-3)
    assert float((point - np.array([0.3, 0.0, 0.0])) @ normal) == pytest.approx(0.0, abs=2e-3)


def test_mirror_is_an_involution_and_exchanges_the_hands():
    rec = synthetic()
    take, hands = mirrored(rec)
    assert hands["left_hand"] == "right_hand" and hands["right_hand"] == "left_hand"
    assert take.marker_names == rec.marker_names and dict(take.groups) == dict(rec.groups)
    again, _ = mirrored(take)
    assert np.allclose(again.positions_m, rec.positions_m, atol=1e-9, equal_nan=True)
    # the take's left hand is the original right hand, reflected: the same distances to the cup
    point, normal, _ = sagittal_plane(rec)
    right = rec.group_positions("right_hand")
    reflected = right - 2 * ((right - point) @ normal)[..., None] * normal
    assert np.allclose(take.group_positions("left_hand"), reflected)
    order = [
        rec.marker_names.index(mirror_label(n)) if mirror_label(n) in rec.marker_names else i
        for i, n in enumerate(rec.marker_names)
    ]
    assert np.allclose(_distances(take.positions_m), _distances(rec.positions_m[:, order]), equal_nan=True)
    assert np.allclose(take.positions_m[..., 2], rec.positions_m[:, order, 2], equal_nan=True)


def test_mirror_without_torso_uses_the_hands_or_a_given_plane():
    rec = synthetic(torso=False)
    assert sagittal_plane(rec)[2] == "hands"
    take, _ = mirrored(rec, plane=((0.0, 0.0, 0.0), (0.0, 2.0, 0.0)))
    left = rec.group_positions("left_hand") * np.array([1.0, -1.0, 1.0])
    assert np.allclose(take.group_positions("right_hand"), left)
    objects = rec.with_groups({"cup": ["cup_1", "cup_2", "cup_3"]})
    objects = Recording(
        "objects",
        objects.rate_hz,
        objects.times_s,
        objects.marker_names[10:16],
        objects.positions_m[:, 10:16],
        {"cup": (0, 1, 2), "board": (3, 4, 5)},
    )
    with pytest.raises(RecordingError, match="cannot mirror: no sagittal plane"):
        mirrored(objects)
    with pytest.raises(RecordingError, match="non-zero normal"):
        mirrored(rec, plane=((0.0, 0.0, 0.0), (0.0, 0.0, 0.0)))


def test_mirror_exchanges_side_groups_whose_markers_have_no_partner():
    rec = synthetic(torso=False)
    names = tuple(n.lower() + "_x" for n in rec.marker_names)  # no L/R partners by label
    odd = Recording("odd", rec.rate_hz, rec.times_s, names, rec.positions_m, dict(rec.groups))
    take, hands = mirrored(odd)
    assert take.groups["left_hand"] == rec.groups["right_hand"]
    assert take.groups["right_hand"] == rec.groups["left_hand"]


def test_mirror_labels():
    assert mirror_label("LSHO") == "RSHO" and mirror_label("RIFD") == "LIFD"
    assert mirror_label("left_hand:LHTS") == "right_hand:RHTS"
    assert mirror_label("C7") == "C7" and mirror_label("ladle_01") == "ladle_01"
    assert mirror_label("Left_cup:a") == "Right_cup:a"


def test_the_standard_takes():
    rec = synthetic()
    assert list(STANDARD_TAKES) == [
        "mirrored",
        "rotated_translated",
        "half_speed",
        "double_speed",
        "resampled_100hz",
        "marker_gap",
        "scaled",
    ]
    for name, take in STANDARD_TAKES.items():
        out, hands = take(rec)
        assert isinstance(out, Recording) and out.marker_names == rec.marker_names, name
        assert hands == (
            {"left_hand": "right_hand", "right_hand": "left_hand"} if name == "mirrored" else dict(IDENTITY)
        ), name
    assert STANDARD_TAKES["half_speed"](rec)[0].n_frames == 2 * rec.n_frames - 1
    assert STANDARD_TAKES["resampled_100hz"](rec)[0].rate_hz == 100.0
    assert (
        np.isnan(STANDARD_TAKES["marker_gap"](rec)[0].positions_m).sum()
        == np.isnan(rec.positions_m).sum() + 30
    )


@pytest.mark.parametrize("suffix", [".mmm.xml", ".c3d"])
def test_a_written_take_reads_back(tmp_path, suffix):
    rec = synthetic(torso=False)
    rec = with_gap(rec, "LHPS", 0.0, 3.0)  # a marker missing in every frame
    path = write_recording(rec, tmp_path / f"take{suffix}")
    back = read_recording(path)
    assert back.rate_hz == pytest.approx(rec.rate_hz)
    assert np.allclose(back.times_s, rec.times_s)
    assert {g: [back.marker_names[i].split(":")[-1] for i in idx] for g, idx in back.groups.items()} == {
        g: [rec.marker_names[i] for i in idx] for g, idx in rec.groups.items()
    }
    order = [
        next(j for j, n in enumerate(back.marker_names) if n.split(":")[-1] == m) for m in rec.marker_names
    ]
    assert np.allclose(back.positions_m[:, order], rec.positions_m, atol=1e-7, equal_nan=True)
    assert [p.name for p in tmp_path.iterdir()] == [f"take{suffix}"]  # no temporary left


def test_mmm_refuses_markers_outside_any_group(tmp_path):
    with pytest.raises(RecordingError, match="belong to no group"):
        write_recording(synthetic(), tmp_path / "t.mmm.xml")


def test_the_command_writes_the_take_it_names(tmp_path, capsys):
    out = tmp_path / "d.c3d"
    assert (
        main(
            [
                "take",
                str(DOUGH),
                "-o",
                str(out),
                "--rotate",
                "90deg",
                "--translate",
                "2m,0m",
                "--speed",
                "2",
                "--gap",
                "red_cup:RC1@1s+0.5s",
            ]
        )
        == 0
    )
    assert "frames at 100 Hz" in capsys.readouterr().out
    rec = read_recording(DOUGH)
    expected = with_gap(
        stretched(translated(rotated(rec, np.pi / 2), (2.0, 0.0)), 0.5), "red_cup:RC1", 1.0, 0.5
    )
    back = read_recording(out)
    assert back.marker_names == expected.marker_names and dict(back.groups) == dict(expected.groups)
    assert np.allclose(back.positions_m, expected.positions_m, atol=1e-6, equal_nan=True)


def test_the_command_writes_a_standard_take(tmp_path, capsys):
    out = tmp_path / "m.c3d"
    assert main(["take", str(DOUGH), "-o", str(out), "--standard", "mirrored"]) == 0
    assert "hands exchanged: left_hand -> right_hand" in capsys.readouterr().out
    expected, _ = mirrored(read_recording(DOUGH))
    assert np.allclose(read_recording(out).positions_m, expected.positions_m, atol=1e-6, equal_nan=True)


@pytest.mark.parametrize(
    ("args", "message"),
    [
        ([], "nothing to change"),
        (["--standard", "mirrored", "--mirror"], "--standard mirrored is one take; drop --mirror"),
        (["--rotate", "90"], "--rotate: '90' has no unit"),
        (["--translate", "2m"], "expected X,Y or X,Y,Z"),
        (["--speed", "0"], "--speed must be a positive factor"),
        (["--rate", "100mm"], "unknown unit 'mm'"),
        (["--gap", "RC1+1s"], "expected MARKER@START+DURATION"),
        (["--gap", "nope@1s+0.5s"], "marker 'nope' is not in the recording"),
        (["--jitter", "1m"], "--jitter 1m: from 0mm to 100mm"),
    ],
)
def test_bad_options_are_one_line_errors(tmp_path, capsys, args, message):
    out = tmp_path / "t.c3d"
    assert main(["take", str(DOUGH), "-o", str(out), *args]) == 2
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1 and not out.exists()


def test_an_unwritable_format_and_a_missing_file(tmp_path, capsys):
    assert main(["take", str(DOUGH), "-o", str(tmp_path / "t.tsv"), "--mirror"]) == 2
    assert "written as .c3d or .mmm.xml" in capsys.readouterr().err
    assert main(["take", str(tmp_path / "none.c3d"), "-o", str(tmp_path / "t.c3d"), "--mirror"]) == 2
    assert capsys.readouterr().err.count("\n") == 1


def test_a_mirrored_kit_clip_composes_with_the_hands_exchanged(tmp_path, capsys):
    """The command of docs/segmentation.md: the take of Pour resolves the same scene and steps."""
    xml = next(mocap_file("kit_bimanual").glob("Pour_*.mmm.xml"))
    take = tmp_path / "p.mmm.xml"
    assert main(["take", str(xml), "--standard", "mirrored", "-o", str(take)]) == 0
    steps = []
    for source in (xml, take):
        out = tmp_path / f"{len(steps)}.oac"
        assert main(["compose", str(source), "--library", str(KIT), "--name", "p", "-o", str(out)]) == 0, (
            capsys.readouterr().err
        )
        composed = load_library([KIT, out]).oacs["p"]
        defaults = {p.name: p.default for p in composed.params}
        steps.append([(s.oac, [defaults.get(a, a) for a in s.args]) for s in composed.steps])
    capsys.readouterr()
    swap = {"left_hand": "right_hand", "right_hand": "left_hand"}
    assert "scene kit_pour" in (tmp_path / "1.oac").read_text()
    assert steps[1] == [(oac, [swap.get(a, a) for a in args]) for oac, args in steps[0]]
    assert {"left_hand", "right_hand"} <= {a for _, args in steps[0] for a in args}


def test_the_standard_gap_skips_the_subjects_body():
    rec = synthetic()
    torso = [i for i, n in enumerate(rec.marker_names) if n in _TORSO]
    knee = rec.positions_m.copy()
    knee[:, torso[0]] += np.linspace(0.0, 3.0, rec.n_frames)[:, None]  # the subject walks far
    body = Recording(
        "body", rec.rate_hz, rec.times_s, rec.marker_names, knee, {**rec.groups, "subject_1723": tuple(torso)}
    )
    assert gap_marker(body, 0.5)[0] == "cup_1"


@pytest.mark.parametrize("clip", ["dough", "Pour"])
def test_mirroring_a_real_recording_twice_gives_it_back(clip):
    path = DOUGH if clip == "dough" else next(mocap_file("kit_bimanual").glob(f"{clip}_*.mmm.xml"))
    rec = read_recording(path)
    take, _ = mirrored(rec)
    assert sagittal_plane(rec)[2] == ("hands" if clip == "dough" else "torso")
    assert np.allclose(mirrored(take)[0].positions_m, rec.positions_m, atol=1e-9, equal_nan=True)
    assert np.array_equal(np.isnan(take.positions_m), np.isnan(rec.positions_m[:, _partners(rec)]))


def _partners(rec: Recording) -> list[int]:
    index = {n: i for i, n in enumerate(rec.marker_names)}
    return [index.get(mirror_label(n), i) for i, n in enumerate(rec.marker_names)]
