"""MMM XML, Qualisys TSV and plain CSV readers: real files and bad input."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from _mocap import mocap_file

from oacdsl.errors import RecordingError
from oacdsl.segmentation.readers import read_recording

KIT = "kit_bimanual"
POUR = f"{KIT}/Pour_files_motions_2967_Pour1_cs_ms_0_20l_04.mmm.xml"
DEVELOPMENT = {  # clip prefix: (frames, objects) from the data's README (development clips only)
    "Pour": (78, {"cup_small", "milk_small"}),
    "Stir": (79, {"cup_large", "tablespoon"}),
    "Mix": (79, {"mixing_bowl_green", "salad_fork", "salad_spoon"}),
    "Wipe": (75, {"draining_rack", "plate_dish", "sponge_small"}),
    "Scoop": (101, {"cup_small", "ladle", "mixing_bowl_green"}),
    "Cut": (107, {"cucumber_attachment", "cutting_board_small", "knife_black"}),
}
TSV = "tsv/hand_embodiment/recording.tsv"


def kit_clip(prefix: str) -> Path:
    folder = mocap_file(KIT)
    return next(folder.glob(f"{prefix}_*.mmm.xml"))


@pytest.mark.mocap
@pytest.mark.parametrize("clip", sorted(DEVELOPMENT))
def test_mmm_development_clips(clip):
    rec = read_recording(kit_clip(clip))
    frames, objects = DEVELOPMENT[clip]
    subject = "subject_1480" if clip == "Pour" else "subject_1723"
    assert (rec.n_frames, rec.rate_hz, rec.first_frame) == (frames, 10.0, 0)
    assert set(rec.instances) == objects | {subject}  # the sideboard has no marker data
    assert len(rec.groups[subject]) == 53 and all(len(rec.groups[o]) == 4 for o in objects)
    assert len(rec.marker_names) == 53 + 4 * len(objects)
    assert not np.isnan(rec.positions_m).any()
    assert rec.times_s[0] == 0.0 and rec.times_s[-1] == pytest.approx((frames - 1) / 10.0)


@pytest.mark.mocap
def test_mmm_values_are_metres_and_match_the_text():
    path = mocap_file(POUR)
    rec = read_recording(path)
    first = rec.marker_names.index("sc_01")
    np.testing.assert_allclose(rec.positions_m[0, first], [-0.239046, -0.156738, 0.943648])
    assert rec.marker_names.index("C7") in rec.groups["subject_1480"]


@pytest.mark.mocap
def test_qualisys_tsv():
    rec = read_recording(mocap_file(TSV))
    assert (rec.n_frames, rec.rate_hz, rec.first_frame, len(rec.marker_names)) == (6000, 100.0, 1, 21)
    assert rec.times_s[-1] == pytest.approx(59.99)
    gaps = dict(zip(rec.marker_names, np.isnan(rec.positions_m).any(axis=-1).mean(axis=0), strict=True))
    assert gaps["thumb_tip"] == pytest.approx(0.08, abs=0.005)
    assert gaps["middle_tip"] == pytest.approx(0.013, abs=0.001)
    assert gaps["ring_tip"] == pytest.approx(0.007, abs=0.001)
    assert sum(g > 0 for g in gaps.values()) == 3
    pillow = [rec.marker_names[i] for i in rec.groups["pillow"]]
    assert pillow == ["pillow_top", "pillow_left", "pillow_right"]
    assert len(rec.groups["hand"]) == 3
    pillow = rec.group_positions("pillow").mean(axis=1)
    assert np.ptp(pillow, axis=0).max() < 0.02  # metres: the pillow barely moves (< 8 mm in the README)


@pytest.mark.mocap
def test_tsv_units_override():
    rec = read_recording(mocap_file(TSV), units="cm")
    mm = read_recording(mocap_file(TSV))
    np.testing.assert_allclose(rec.positions_m, mm.positions_m * 10, equal_nan=True)


def write(tmp_path: Path, name: str, text: str) -> Path:
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


TSV_TEXT = (
    "NO_OF_FRAMES\t3\nNO_OF_MARKERS\t2\nFREQUENCY\t50\nMARKER_NAMES\tcup_a\thand\n"
    "Frame\tTime\tcup_a X\tcup_a Y\tcup_a Z\thand X\thand Y\thand Z\t\n"
    "7\t0.14\t1\t2\t3\t4\t5\t6\t\n"
    "8\t0.16\t0\t0\t0\t\tnan\t6\t\n"
    "9\t0.18\t1\t2\t3\t4\t5\t6\t\n"
)


def test_tsv_small_gaps_and_first_frame(tmp_path: Path):
    rec = read_recording(write(tmp_path, "s.tsv", TSV_TEXT))
    assert (rec.rate_hz, rec.first_frame, rec.n_frames) == (50.0, 7, 3)
    np.testing.assert_allclose(rec.times_s, [0, 0.02, 0.04])
    assert np.isnan(rec.positions_m[1]).all()  # 0 0 0 and an empty/nan field are gaps
    assert rec.positions_m[0, 1, 2] == pytest.approx(0.006)
    assert rec.groups == {"cup": (0,), "hand": (1,)}


CSV_TEXT = (
    "# units: mm\n"
    "frame,time,hand_x,hand_y,hand_z,cup_1_x,cup_1_y,cup_1_z\n"
    "5,0.00,412.0,18.5,903.1,500.2,20.0,880.0\n"
    "6,0.01,412.3,,,500.2,20.1,880.0\n"
    "7,0.02,412.3,1,1,500.2,20.1,880.0\n"
)


def test_csv_layout(tmp_path: Path):
    rec = read_recording(write(tmp_path, "a.csv", CSV_TEXT))
    assert rec.marker_names == ("hand", "cup_1") and rec.groups == {"hand": (0,), "cup": (1,)}
    assert (rec.rate_hz, rec.first_frame) == (100.0, 5)
    assert np.isnan(rec.positions_m[1, 0]).all() and rec.positions_m[0, 1, 2] == pytest.approx(0.88)
    metres = read_recording(write(tmp_path, "b.csv", CSV_TEXT), units="m")
    assert metres.positions_m[0, 1, 2] == pytest.approx(880.0)


def test_csv_rate_line_without_time_and_default_metres(tmp_path: Path):
    text = "# rate_hz: 25\ncup X,cup Y,cup Z\n0.1,0.2,0.3\n0.1,0.2,0.4\n"
    rec = read_recording(write(tmp_path, "c.csv", text))
    assert rec.rate_hz == 25.0 and rec.times_s[1] == pytest.approx(0.04) and rec.first_frame == 0
    assert rec.positions_m[1, 0, 2] == pytest.approx(0.4)


@pytest.mark.parametrize(
    ("name", "text", "message"),
    [
        ("ragged.tsv", TSV_TEXT.replace("9\t0.18\t1\t2\t3\t4\t5\t6", "9\t0.18\t1\t2\t3\t4"),
         "line 8: 6 fields, expected 8"),
        ("short.tsv", TSV_TEXT.replace("NO_OF_FRAMES\t3", "NO_OF_FRAMES\t4"),
         "NO_OF_FRAMES is 4 but the file holds 3 data rows"),
        ("word.tsv", TSV_TEXT.replace("0.14\t1\t2", "0.14\tone\t2"), "line 6: value 'one' is not a number"),
        ("nomarkers.tsv", "NO_OF_FRAMES\t3\nFREQUENCY\t50\n1\t2\t3\n", "no MARKER_NAMES line"),
        ("empty.tsv", TSV_TEXT.split("7\t")[0].replace("NO_OF_FRAMES\t3\n", ""), "no frames"),
        ("ragged.csv", CSV_TEXT.replace("7,0.02,412.3,1,1,", "7,0.02,412.3,1,"),
         "line 5: 7 fields, expected 8"),
        ("col.csv", CSV_TEXT.replace("cup_1_z", "cup_1_w"), "column 'cup_1_w' is not frame, time"),
        ("norate.csv", "cup_x,cup_y,cup_z\n1,2,3\n", "the frame rate is unknown"),
        ("empty.csv", "# units: mm\nframe,time,a_x,a_y,a_z\n", "no frames"),
        ("unit.csv", CSV_TEXT.replace("units: mm", "units: inch"), "unknown unit 'inch'"),
        ("notmmm.xml", "<?xml version='1.0'?>\n<svg><g/></svg>\n",
         "not an MMM motion file: the root element is <svg>"),
        ("broken.xml", "<MMM><Motion name='a'>\n<Sensors></Motion>", "not well-formed XML at line 2"),
        ("nodata.xml", "<MMM><Motion name='true_x'><Sensors/></Motion></MMM>", "no MoCapMarker measurements"),
        ("badpos.xml",
         "<MMM><Motion name='true_x'><Sensors><Sensor type='MoCapMarker'><Data>"
         "<Measurement timestep='0'><MarkerPosition name='a'>1 2</MarkerPosition></Measurement>"
         "</Data></Sensor></Sensors></Motion></MMM>",
         "motion 'true_x', timestep 0: MarkerPosition 'a' is '1 2', expected three numbers"),
    ],
)
def test_bad_text_recordings(tmp_path: Path, name, text, message):
    path = write(tmp_path, name, text)
    with pytest.raises(RecordingError) as err:
        read_recording(path)
    assert str(err.value).startswith(str(path)) and message in str(err.value) and "\n" not in str(err.value)


@pytest.mark.mocap
def test_truncated_and_garbled_mmm(tmp_path: Path):
    data = mocap_file(POUR).read_bytes()
    cut = tmp_path / "cut.mmm.xml"
    cut.write_bytes(data[: len(data) // 3])
    with pytest.raises(RecordingError, match="not well-formed XML at line"):
        read_recording(cut)
    garbled = tmp_path / "garbled.mmm.xml"
    garbled.write_bytes(data.replace(b"-239.046 -156.738", b"-239.046 abc", 1))
    with pytest.raises(RecordingError, match="MarkerPosition 'sc_01' is '-239.046 abc 943.648'"):
        read_recording(garbled)


@pytest.mark.mocap
def test_fmt_overrides_extension(tmp_path: Path):
    copy = tmp_path / "pour.txt"
    copy.write_bytes(mocap_file(POUR).read_bytes())
    assert read_recording(copy, fmt="mmm").n_frames == 78
    with pytest.raises(RecordingError, match="declare their own units"):
        read_recording(copy, fmt="mmm", units="mm")
