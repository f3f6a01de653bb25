"""C3D reading (real files of four writers), writing, round trip, corrupt files."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from _mocap import mocap_file

from oacdsl.errors import RecordingError, RecordingWarning, TruncatedRecording
from oacdsl.segmentation.readers import read_c3d, read_recording, write_c3d
from oacdsl.segmentation.recording import Recording

pytestmark = pytest.mark.mocap

BOX = "c3d/ezc3d/markers_analogs.c3d"


def gap_fraction(rec: Recording) -> float:
    return float(np.isnan(rec.positions_m).any(axis=-1).mean())


def test_vicon_box_with_subjects_as_groups():
    rec = read_recording(mocap_file(BOX))
    assert (rec.n_frames, rec.rate_hz, rec.first_frame, len(rec.marker_names)) == (580, 100.0, 0, 51)
    assert rec.instances == ("Daphnee", "boite")
    assert len(rec.groups["boite"]) == 8 and len(rec.groups["Daphnee"]) == 43
    assert rec.marker_names[rec.groups["boite"][0]] == "boite:gauche_ext"
    assert gap_fraction(rec) == pytest.approx(0.0103, abs=5e-4)
    assert rec.times_s[0] == 0.0 and rec.times_s[-1] == pytest.approx(5.79)
    # millimetres → metres: the box is lifted from z ≈ 0.72 m to ≈ 0.95 m (README)
    z = np.nanmean(rec.group_positions("boite")[:, :, 2], axis=1)
    assert 0.65 < z[0] < 0.75 and 0.9 < z[-1] < 1.0


def test_qualisys_first_frame_and_rate():
    rec = read_c3d(mocap_file("c3d/ezc3d/Qualisys.c3d"))
    assert (rec.n_frames, rec.rate_hz, rec.first_frame, len(rec.marker_names)) == (340, 200.0, 704, 55)
    assert gap_fraction(rec) == 0.0
    assert rec.times_s[1] == pytest.approx(0.005)
    assert 0.5 < np.nanmax(np.abs(rec.positions_m)) < 5.0  # metres, a person in a lab


def test_optotrak_declares_more_frames_than_it_holds():
    path = mocap_file("c3d/ezc3d/Optotrak.c3d")
    with pytest.raises(TruncatedRecording, match="it holds 29 of 1149 frames; frames 30..1149 lost") as err:
        read_c3d(path)
    assert (err.value.declared, err.value.complete, err.value.exit_code) == (1149, 29, 1)
    with pytest.warns(RecordingWarning, match="frames 30..1149 of 1149 lost; reading the 29 complete frames"):
        rec = read_c3d(path, allow_truncated=True)
    assert (rec.n_frames, rec.rate_hz, len(rec.marker_names)) == (29, 30.0, 54)
    assert rec.marker_names[0] == "Marker_1" and rec.marker_names[-1] == "Marker_54"
    assert gap_fraction(rec) == pytest.approx(0.0377, abs=5e-4)
    gaps = np.isnan(rec.positions_m)
    assert (gaps.all(axis=-1) == gaps.any(axis=-1)).all()  # a gap blanks all three coordinates


def test_integer_storage_and_labels_beyond_used():
    rec = read_c3d(mocap_file("c3d/py-c3d/my-motion.c3d"))
    assert (rec.n_frames, rec.rate_hz, len(rec.marker_names)) == (450, 50.0, 26)
    assert rec.marker_names[:3] == ("RFT1", "RFT2", "RFT3")
    assert gap_fraction(rec) == pytest.approx(0.0193, abs=5e-4)
    assert 0.5 < np.nanmax(np.abs(rec.positions_m)) < 5.0  # scale 0.0833 applied, then mm → m


def synthetic(frames: int = 50, first_frame: int = 0) -> Recording:
    rng = np.random.default_rng(3)
    pos = rng.uniform(-1.0, 1.0, size=(frames, 5, 3))
    pos[10:13, 1] = np.nan
    names = ("m1", "m2", "m3", "lid", "n")
    groups = {"cup": (0, 1, 2), "hand": (3,)}
    return Recording("synthetic", 100.0, np.arange(frames) / 100.0, names, pos, groups, first_frame)


def test_write_then_read_round_trip(tmp_path: Path):
    rec = synthetic(first_frame=12)
    out = write_c3d(rec, tmp_path / "demo.c3d")
    assert [p.name for p in tmp_path.iterdir()] == ["demo.c3d"]  # no temporary left behind
    back = read_recording(out)
    assert back.marker_names == ("cup:m1", "cup:m2", "cup:m3", "hand:lid", "n")
    assert {g: tuple(idx) for g, idx in back.groups.items()} == {"cup": (0, 1, 2), "hand": (3,)}
    assert (back.rate_hz, back.first_frame, back.n_frames) == (100.0, 12, 50)
    np.testing.assert_array_equal(np.isnan(back.positions_m), np.isnan(rec.positions_m))
    np.testing.assert_allclose(back.positions_m, rec.positions_m, atol=1e-6, equal_nan=True)  # float32 mm
    again = write_c3d(back, tmp_path / "again.c3d")  # prefixed labels are not prefixed twice
    assert read_c3d(again).marker_names == back.marker_names


def test_write_rejects_a_marker_in_two_groups(tmp_path: Path):
    rec = synthetic()
    both = Recording("x", 100.0, rec.times_s, rec.marker_names, rec.positions_m, {"a": (0, 1), "b": (1,)})
    with pytest.raises(RecordingError, match="'m2' is in groups 'a' and 'b'"):
        write_c3d(both, tmp_path / "x.c3d")
    assert not list(tmp_path.iterdir())


def corrupt(tmp_path: Path, name: str, edit) -> Path:
    data = bytearray(mocap_file(BOX).read_bytes())
    out = tmp_path / name
    out.write_bytes(bytes(edit(data)))
    return out


@pytest.mark.parametrize(
    ("name", "edit", "message"),
    [
        ("empty.c3d", lambda d: b"", "shorter than a header"),
        ("half.c3d", lambda d: d[: len(d) // 2],
         "truncated C3D file: it ends at byte 1125408, inside frame 289 of 580 frames; frames 289..580 lost"),
        ("params.c3d", lambda d: d[:3000], "truncated inside the parameter section"),
        ("key.c3d", lambda d: d[:1] + b"\x00" + d[2:], "header key byte"),
        ("text.c3d", lambda d: b"frame,x,y,z\n" * 200, "header key byte"),
        # ezc3d itself crashes the interpreter on these two:
        ("dims.c3d", lambda d: d[:7877] + b"\xd9" + d[7878:], "parameter 'USED' has 217 dimensions"),
        ("scale.c3d", lambda d: d[:7971] + b"Z" + d[7972:], "ANALOG:SCALE is missing"),
    ],
)
def test_corrupt_c3d_is_a_one_line_error(tmp_path: Path, name, edit, message):
    path = corrupt(tmp_path, name, edit)
    with pytest.raises(RecordingError) as err:
        read_recording(path)
    text = str(err.value)
    assert text.startswith(str(path)) and message in text and "\n" not in text


def test_no_frames_is_an_error(tmp_path: Path):
    one = write_c3d(synthetic(frames=1), tmp_path / "one.c3d")
    data = bytearray(one.read_bytes())
    data[8:10] = (0).to_bytes(2, "little")  # header word 5: last frame 0 < first frame 1
    at = data.index(b"FRAMES", 512) + 10  # POINT:FRAMES value (int16, no dimensions)
    data[at : at + 2] = (0).to_bytes(2, "little")
    data_start = (int.from_bytes(data[16:18], "little") - 1) * 512
    path = tmp_path / "noframes.c3d"
    path.write_bytes(bytes(data[:data_start]))
    with pytest.raises(RecordingError, match="noframes.c3d: the recording has no frames"):
        read_c3d(path)


def test_missing_file_and_unknown_format(tmp_path: Path):
    with pytest.raises(RecordingError, match="no such file"):
        read_recording(tmp_path / "nope.c3d")
    (tmp_path / "a.bvh").write_text("HIERARCHY\n")
    with pytest.raises(RecordingError, match="unknown recording format"):
        read_recording(tmp_path / "a.bvh")
    with pytest.raises(RecordingError, match="did you mean 'c3d'"):
        read_recording(tmp_path / "a.bvh", fmt="c3e")
