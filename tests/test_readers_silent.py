"""Issue 21, silent wrong reads (exit 0 with wrong data): a C3D file whose parameters contradict
its header, a TSV or CSV cut inside its last number, a CSV naming a column twice, an MMM motion
with a repeated timestep. Each is now one line naming the parameter or line, exit 1."""

from __future__ import annotations

import struct
from pathlib import Path

import numpy as np
import pytest

from oacdsl.cli import main
from oacdsl.errors import RecordingWarning
from oacdsl.segmentation.readers import read_recording, write_c3d
from oacdsl.segmentation.recording import Recording

FRAMES = 40


def c3d_file(tmp_path: Path, *, analogs: bool = False) -> Path:
    """40 frames of 3 markers at 100 Hz (float storage, mm); with 2 analog channels at 1 kHz."""
    if not analogs:
        pos = np.random.default_rng(0).uniform(-1.0, 1.0, (FRAMES, 3, 3))
        rec = Recording("s", 100.0, np.arange(FRAMES) / 100.0, ("a", "b", "c"), pos, {"g": (0, 1, 2)})
        return write_c3d(rec, tmp_path / "ok.c3d")
    import ezc3d

    c3d = ezc3d.c3d()
    c3d["parameters"]["POINT"]["RATE"]["value"] = [100]
    c3d["parameters"]["POINT"]["LABELS"]["value"] = ("a", "b")
    c3d["parameters"]["POINT"]["UNITS"]["value"] = ["mm"]
    c3d["parameters"]["ANALOG"]["RATE"]["value"] = [1000]
    c3d["parameters"]["ANALOG"]["LABELS"]["value"] = ("c1", "c2")
    points = np.ones((4, 2, FRAMES))
    points[:3] = np.random.default_rng(1).uniform(100.0, 900.0, (3, 2, FRAMES))
    c3d["data"]["points"] = points
    c3d["data"]["analogs"] = np.zeros((1, 2, FRAMES * 10))
    path = tmp_path / "analog.c3d"
    c3d.write(str(path))
    return path


def value_offset(data: bytes, group: str, name: str) -> int:
    """Byte offset of parameter GROUP:NAME's value (Intel file, scalar parameter)."""
    pos = (data[0] - 1) * 512 + 4
    groups: dict[int, str] = {}
    while True:
        n_chars, ident = struct.unpack("bb", data[pos : pos + 2])
        label = data[pos + 2 : pos + 2 + abs(n_chars)].decode()
        (offset,) = struct.unpack("<h", data[pos + 2 + abs(n_chars) : pos + 4 + abs(n_chars)])
        value = pos + 4 + abs(n_chars)
        if ident < 0:
            groups[-ident] = label
        elif (groups.get(ident), label) == (group, name):
            return value + 2 + data[value + 1]
        pos += 2 + abs(n_chars) + offset


def edited(tmp_path: Path, source: Path, edits: dict[tuple[str, str] | int, bytes]) -> Path:
    """``source`` with parameter values (GROUP, NAME) or header bytes (an offset) replaced."""
    data = bytearray(source.read_bytes())
    for where, value in edits.items():
        at = where if isinstance(where, int) else value_offset(bytes(data), *where)
        data[at : at + len(value)] = value
    path = tmp_path / "edited.c3d"
    path.write_bytes(bytes(data))
    return path


U16 = struct.Struct("<H").pack
F32 = struct.Struct("<f").pack

CASES = {
    "point-frames-1": ({("POINT", "FRAMES"): U16(1)},
                       "header and parameters disagree: POINT:FRAMES is 1 but the header says frames 1..40"),
    "data-start-0": ({16: U16(0)}, "the header (word 9) puts the data at block 0, inside the header or the"),
    "point-data-start": ({("POINT", "DATA_START"): U16(9)},
                         "POINT:DATA_START is 9 but the header (word 9) says block 4"),
    "point-used-1": ({("POINT", "USED"): U16(1)},
                     "POINT:USED is 1 but the header (word 2) says 3 points per frame"),
    "point-scale-nan": ({("POINT", "SCALE"): F32(float("nan"))},
                        "POINT:SCALE is nan; it must be a finite number"),
    "point-scale-0": ({("POINT", "SCALE"): F32(0.0), 12: F32(0.0)},
                      "POINT:SCALE is 0: integer coordinates scaled by 0 would all read as 0"),
}


@pytest.mark.parametrize("case", sorted(CASES))
def test_c3d_parameters_that_contradict_the_header(case: str, tmp_path: Path, capsys):
    edits, message = CASES[case]
    path = edited(tmp_path, c3d_file(tmp_path), edits)
    code = main(["inspect", str(path)])
    out, err = capsys.readouterr()
    assert (code, out) == (1, ""), err
    assert err.startswith(f"oacc: error: {path}: ") and message in err
    assert err.count("\n") == 1 and "Traceback" not in err


def test_analog_rate_that_contradicts_the_header(tmp_path: Path, capsys):
    source = c3d_file(tmp_path, analogs=True)
    assert read_recording(source).n_frames == FRAMES  # the unedited file reads
    path = edited(tmp_path, source, {("ANALOG", "RATE"): F32(0.0)})
    code = main(["inspect", str(path)])
    err = capsys.readouterr().err
    assert code == 1 and err.count("\n") == 1
    assert ("ANALOG:RATE is 0 Hz: ANALOG:USED = 2 channels at that rate and POINT:RATE 100 Hz make 0 analog"
            " values per frame, the header (word 3) says 20") in err


def test_agreeing_files_still_read(tmp_path: Path):
    rec = read_recording(c3d_file(tmp_path))
    assert (rec.n_frames, len(rec.marker_names), rec.rate_hz) == (FRAMES, 3, 100.0)
    assert not np.isnan(rec.positions_m).any()
    # a header that counts 0 points leaves the count to POINT:USED (what ezc3d reads)
    zero = edited(tmp_path, c3d_file(tmp_path), {2: U16(0)})
    assert len(read_recording(zero).marker_names) == 3


def one_line_error(capsys, path: Path) -> str:
    code = main(["inspect", str(path)])
    out, err = capsys.readouterr()
    assert (code, out) == (1, ""), err
    assert err.startswith(f"oacc: error: {path}: ") and err.count("\n") == 1 and "Traceback" not in err
    return err


def mmm(*measurements: tuple[str, str]) -> str:
    """An MMM file of one motion; ``measurements``: (timestep, MarkerPosition elements), one per line."""
    rows = "".join(f'<Measurement timestep="{t}">{markers}</Measurement>\n' for t, markers in measurements)
    return (f'<MMM>\n<Motion name="true_cup"><Sensors><Sensor type="MoCapMarker"><Data>\n{rows}</Data>'
            "</Sensor></Sensors></Motion></MMM>\n")


A = '<MarkerPosition name="a">1 2 3</MarkerPosition>'
B = '<MarkerPosition name="b">4 5 6</MarkerPosition>'


@pytest.mark.parametrize(("text", "message"), [
    (mmm(("0", A + B), ("0.1", A + B), ("0.1", A)),
     "line 5: motion 'true_cup': Measurement timestep 0.1 repeats the one at line 4"),
    (mmm(("0", A + B), ("0.1000001", A + B), ("0.1", B)), "timestep 0.1 repeats the one at line 4"),
    (mmm(("0", A + B), ("0.1", A + B + A)), "line 4: motion 'true_cup', timestep 0.1: MarkerPosition 'a' tw"),
])
def test_mmm_repeated_measurements_are_refused(text: str, message: str, tmp_path: Path, capsys):
    path = tmp_path / "m.xml"
    path.write_text(text)
    assert message in one_line_error(capsys, path)


def test_mmm_motions_share_timesteps(tmp_path: Path):
    """Two motions measured at the same timesteps are one recording (no repeat)."""
    one = mmm(("0", A), ("0.1", A), ("0.2", A))
    lid = "".join(f'<Measurement timestep="{t}">{B}</Measurement>' for t in ("0", "0.1", "0.2"))
    two = one.replace("</Motion>", '</Motion><Motion name="true_lid"><Sensors><Sensor type="MoCapMarker">'
                      f"<Data>{lid}</Data></Sensor></Sensors></Motion>")
    path = tmp_path / "m.xml"
    path.write_text(two)
    rec = read_recording(path)
    assert rec.n_frames == 3 and rec.instances == ("cup", "lid") and not np.isnan(rec.positions_m).any()


TSV = ("NO_OF_FRAMES\t3\nNO_OF_MARKERS\t1\nFREQUENCY\t50\nMARKER_NAMES\tcup\n"
       "Frame\tTime\tcup X\tcup Y\tcup Z\t\n"
       "1\t0.00\t100.0\t200.0\t903.1\t\n2\t0.02\t100.0\t200.0\t903.1\t\n3\t0.04\t100.0\t200.0\t903.1\t\n")
CSV = ("frame,time,cup_x,cup_y,cup_z\n"
       "0,0.00,0.1,0.2,0.9031\n1,0.01,0.1,0.2,0.9031\n2,0.02,0.1,0.2,0.9031\n")


@pytest.mark.parametrize(("name", "text", "cut"), [
    ("cut.tsv", TSV, "903.1\t\n"),  # the last row ends "…\t90": every field there, one number short
    ("cut.csv", CSV, "031\n"),  # the last row ends "…,0.9": a number cut short
    ("crlf.csv", CSV.replace("\n", "\r\n"), "031\r\n"),
])
def test_text_cut_inside_its_last_number(name: str, text: str, cut: str, tmp_path: Path, capsys):
    path = tmp_path / name
    path.write_bytes(text[: len(text) - len(cut)].encode())
    err = one_line_error(capsys, path)
    last = text.count("\n")
    assert (f"line {last}: the file ends inside this line (no line end after it): cut short, perhaps inside a"
            " number; --allow-truncated reads the lines before it") in err
    with pytest.warns(RecordingWarning, match=f"line {last}: the file ends inside this line"):
        rec = read_recording(path, allow_truncated=True)
    assert rec.n_frames == 2  # the complete rows only
    whole = tmp_path / f"whole{path.suffix}"
    whole.write_bytes(text.encode())
    assert read_recording(whole).n_frames == 3


def test_a_file_without_its_last_line_end_is_named_even_when_its_numbers_look_whole(tmp_path: Path, capsys):
    path = tmp_path / "r.csv"
    path.write_text(CSV.rstrip("\n"))
    assert "line 4: the file ends inside this line" in one_line_error(capsys, path)


@pytest.mark.parametrize(("header", "message"), [
    ("frame,time,cup_x,cup_y,cup_z,cup_x", "line 1: columns 3 and 6 ('cup_x', 'cup_x') both hold marker"),
    ("frame,time,cup_x,cup_y,cup_z,cup.X", "columns 3 and 6 ('cup_x', 'cup.X') both hold marker 'cup''s x"),
    ("frame,time,cup_x,cup_y,cup_z,time", "columns 2 and 6 ('time', 'time') both hold the time"),
    ("frame,time_s,cup_x,cup_y,cup_z,Time", "columns 2 and 6 ('time_s', 'Time') both hold the time"),
    ("frame,time,cup_x,cup_y,cup_z,Frame", "columns 1 and 6 ('frame', 'Frame') both hold the frame"),
])
def test_csv_column_named_twice(header: str, message: str, tmp_path: Path, capsys):
    path = tmp_path / "twice.csv"
    path.write_text(header + "\n" + "".join(f"{r},{r / 100},0.1,0.2,0.3,0.4\n" for r in range(3)))
    assert message in one_line_error(capsys, path)
