"""Issue 13, the readers' items: each bad recording is one line and exit 1 (its content) or
exit 2 (not a file, a window that does not fit), in ``inspect`` as in ``segment``, ``match``
and ``reproduce``; truncated C3D files; special files; entity bombs; bounded sizes and work."""

from __future__ import annotations

import json
import os
import shutil
import struct
import threading
import tracemalloc
from pathlib import Path

import numpy as np
import pytest
from _mocap import mocap_file

from oacdsl.cli import main
from oacdsl.errors import InvalidRecording, SegmentationError
from oacdsl.segmentation import aas as aas_module
from oacdsl.segmentation import segment
from oacdsl.segmentation.params import AasParams
from oacdsl.segmentation.readers import limits, read_recording, write_c3d
from oacdsl.segmentation.readers.c3d_check import check_c3d_structure
from oacdsl.segmentation.recording import Recording

ROOT = Path(__file__).resolve().parents[1]
DOUGH = ROOT / "data" / "dough.c3d"
DOUGH_FRAMES = 2688


def run(capsys, *argv: object) -> tuple[int, str, str]:
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err


def one_line_error(capsys, code_wanted: int, *argv: object) -> str:
    code, out, err = run(capsys, *argv)
    assert (code, out) == (code_wanted, ""), (argv, code, err)
    assert err.startswith("oacc: error: ") and err.count("\n") == 1 and "Traceback" not in err
    return err


ROWS = ("1\t0.00", "2\t0.01", "3\t0.02")


def tsv(frequency: str = "FREQUENCY\t100\n", rows: tuple[str, ...] = ROWS) -> str:
    head = f"NO_OF_FRAMES\t{len(rows)}\nNO_OF_MARKERS\t2\n{frequency}MARKER_NAMES\thand\tcup\n"
    return head + "".join(f"{r}\t10\t20\t30\t110\t20\t30\t\n" for r in rows)


TSV_CASES = {
    "empty-frame-first-row": (tsv(rows=("\t0.00", "2\t0.01", "3\t0.02")), "line 5: frame number NaN"),
    "nan-frame-first-row": (tsv(rows=("nan\t0.00", "2\t0.01", "3\t0.02")), "line 5: frame number NaN"),
    "empty-time-first-row": (tsv(rows=("1\t", "2\t0.01", "3\t0.02")), "line 5: time NaN is not a number"),
    "nan-time-mid-file": (tsv(rows=("1\t0.00", "2\tnan", "3\t0.02")), "line 6: time NaN is not a number"),
    "time-backwards": (tsv(rows=("1\t0.00", "2\t0.03", "3\t0.02")), "line 7: time 0.02 s does not follow"),
    "frequency-inf": (tsv("FREQUENCY\tinf\n"), "line 3: FREQUENCY is inf Hz; a recording's rate must lie"),
    "frequency-1e9": (tsv("FREQUENCY\t1e9\n"), "line 3: FREQUENCY is 1e+09 Hz"),
    "frequency-huge": (tsv("FREQUENCY\t1e300\n"), "line 3: FREQUENCY is 1e+300 Hz"),
    "frequency-nan": (tsv("FREQUENCY\tnan\n"), "line 3: FREQUENCY is nan Hz"),
    "frequency-bare": (tsv("FREQUENCY\n"), "line 3: FREQUENCY has no value"),
    "coordinate-inf": (tsv().replace("110\t20", "inf\t20", 1), "line 5: marker 'cup' has x = inf m"),
    "coordinate-huge": (tsv().replace("110\t20", "1e300\t20", 1), "line 5: marker 'cup' has x = 1e+297 m"),
}


@pytest.mark.parametrize("case", sorted(TSV_CASES))
def test_bad_tsv_is_exit_1_in_inspect_and_segment(case: str, tmp_path: Path, capsys):
    text, message = TSV_CASES[case]
    path = tmp_path / "r.tsv"
    path.write_text(text)
    for command in ("inspect", "segment"):
        assert message in one_line_error(capsys, 1, command, path)


def test_nan_coordinate_stays_a_gap(tmp_path: Path):
    path = tmp_path / "r.tsv"
    path.write_text(tsv().replace("110\t20", "nan\t20", 1))
    rec = read_recording(path)
    assert np.isnan(rec.positions_m[0, 1]).all() and np.isfinite(rec.positions_m[1]).all()


@pytest.mark.parametrize(("rate", "shown"),
                         [("inf", "inf"), ("1e30", "1e+30"), ("0.2", "0.2"), ("nan", "nan")])
def test_csv_rate_line_out_of_range(rate: str, shown: str, tmp_path: Path, capsys):
    path = tmp_path / "r.csv"
    path.write_text(f"# rate_hz: {rate}\nhand_x,hand_y,hand_z,cup_x,cup_y,cup_z\n0,0,0,1,1,1\n0,0,0,1,1,1\n")
    for command in ("inspect", "segment"):
        err = one_line_error(capsys, 1, command, path)
        assert f"r.csv: line 1: rate_hz is {shown} Hz; a recording's rate must lie within 1..10000 Hz" in err


def c3d_with_rate(tmp_path: Path, rate: float) -> Path:
    """The bundled demonstration's first 300 frames with the header rate and POINT:RATE set to ``rate``."""
    rec = read_recording(DOUGH)
    short = Recording(rec.source, rec.rate_hz, rec.times_s[:300], rec.marker_names, rec.positions_m[:300],
                      rec.groups, rec.first_frame)
    data = bytearray(write_c3d(short, tmp_path / "short.c3d").read_bytes())
    at = data.index(b"RATE", 512) + 4 + 4 + data[data.index(b"RATE", 512) + 7]  # POINT:RATE's value
    data[20:24] = data[at:at + 4] = struct.pack("<f", rate)
    path = tmp_path / "rate.c3d"
    path.write_bytes(bytes(data))
    return path


@pytest.mark.parametrize("rate", [1e9, float("inf"), 3e38])
def test_c3d_rate_out_of_range_in_every_command(rate: float, tmp_path: Path, capsys):
    path = c3d_with_rate(tmp_path, rate)
    out = tmp_path / "out"
    library = ROOT / "library"
    for argv in (["inspect", path], ["segment", path], ["match", path, "--library", library],
                 ["reproduce", path, "--library", library, "--out", out, "--no-record", "--no-render"]):
        err = one_line_error(capsys, 1, *argv)
        assert "rate.c3d: the frame rate (POINT:RATE) is" in err and "within 1..10000 Hz" in err
    assert not out.exists()


def test_c3d_with_a_sane_rate_is_read(tmp_path: Path):
    assert read_recording(c3d_with_rate(tmp_path, 250.0)).rate_hz == 250.0


def dough_layout() -> tuple[bytes, int, int]:
    data = DOUGH.read_bytes()
    layout = check_c3d_structure(DOUGH, data)
    frame_bytes = 4 * (4 * layout.points + layout.analog_per_frame)
    return data, (layout.data_start_block - 1) * 512, frame_bytes


@pytest.mark.parametrize("lost_bytes", [1, 17, 415, 416, 417, 416 * 5, 416 * 5 + 300])
def test_truncated_c3d_names_the_frames_lost(lost_bytes: int, tmp_path: Path, capsys):
    data, start, frame_bytes = dough_layout()
    end = start + DOUGH_FRAMES * frame_bytes
    path = tmp_path / "cut.c3d"
    path.write_bytes(data[: end - lost_bytes])
    complete = DOUGH_FRAMES - -(-lost_bytes // frame_bytes)
    lost = "frame 2688" if complete == DOUGH_FRAMES - 1 else f"frames {complete + 1}..2688"
    for command in ("inspect", "segment"):
        err = one_line_error(capsys, 1, command, path)
        assert "cut.c3d: truncated C3D file: " in err and f"of 2688 frames; {lost} lost" in err
        assert f"--allow-truncated reads the {complete} complete frames" in err
    code, out, err = run(capsys, "inspect", path, "--allow-truncated", "--json")
    assert code == 0 and json.loads(out)["frames"] == complete
    assert err == f"oacc: warning: {path}: truncated C3D file: {lost} of 2688 lost; reading the {complete}" \
        " complete frames\n"


def test_padding_after_the_last_frame_may_be_cut(tmp_path: Path):
    data, start, frame_bytes = dough_layout()
    path = tmp_path / "padding.c3d"
    path.write_bytes(data[: start + DOUGH_FRAMES * frame_bytes])  # the block's padding removed
    assert read_recording(path).n_frames == DOUGH_FRAMES


@pytest.mark.mocap
@pytest.mark.parametrize(("sample", "frames"),
                         [("c3d/py-c3d/my-motion.c3d", 450), ("c3d/ezc3d/Qualisys.c3d", 340)])
def test_truncated_third_party_c3d(sample: str, frames: int, tmp_path: Path, capsys):
    data = mocap_file(sample).read_bytes()
    path = tmp_path / "cut.c3d"
    path.write_bytes(data[: len(data) - 4000])
    err = one_line_error(capsys, 1, "segment", path)
    assert f"of {frames} frames;" in err and "lost; --allow-truncated reads the" in err


@pytest.mark.parametrize("device", ["/dev/zero", "/dev/urandom"])
def test_devices_are_refused_before_reading(device: str, capsys):
    if not Path(device).exists():
        pytest.skip(f"no {device} here")
    for fmt in ("c3d", "csv", "mmm", "tsv"):
        err = one_line_error(capsys, 2, "inspect", device, "--format", fmt)
        assert err == f"oacc: error: {device}: is a character device, not a recording file\n"


def test_a_fifo_is_refused_without_waiting_for_a_writer(tmp_path: Path, capsys):
    fifo = tmp_path / "live.tsv"
    os.mkfifo(fifo)
    result: list[int] = []
    worker = threading.Thread(target=lambda: result.append(main(["segment", str(fifo)])), daemon=True)
    worker.start()
    worker.join(timeout=30)
    if worker.is_alive():  # unblock the reader so that the test run can end, then fail
        with open(fifo, "wb"):
            pass
        pytest.fail("oacc segment waited on a FIFO")
    assert result == [2]
    assert "live.tsv: is a FIFO (named pipe), not a recording file" in capsys.readouterr().err


def test_a_file_beyond_the_size_limit_is_refused_unread(tmp_path: Path, capsys):
    path = tmp_path / "huge.csv"
    with open(path, "wb") as fh:
        fh.truncate(limits.MAX_FILE_BYTES + 1)  # sparse: no disk space used
    err = one_line_error(capsys, 1, "inspect", path)
    assert "huge.csv: the file is 1.0 GiB, more than the limit of 1 GiB" in err


def test_positions_are_bounded_before_allocation(tmp_path: Path):
    """6000 timesteps of one motion × 9001 markers of another: 1.2 GiB from a 1 MB file."""
    stamps = "".join(f'<Measurement timestep="{t / 100:.2f}"><MarkerPosition name="a">1 2 3</MarkerPosition>'
                     "</Measurement>" for t in range(6000))
    many = "".join(f'<MarkerPosition name="m{k}">1 2 3</MarkerPosition>' for k in range(9000))
    motion = ('<Motion name="{}"><Sensors><Sensor type="MoCapMarker"><Data>{}</Data></Sensor></Sensors>'
              "</Motion>")
    path = tmp_path / "wide.xml"
    path.write_text("<MMM>" + motion.format("one", stamps)
                    + motion.format("two", f'<Measurement timestep="0">{many}</Measurement>') + "</MMM>")
    with pytest.raises(InvalidRecording, match=r"6000 frames × 9001 markers need 1\.2 GiB, more than"):
        read_recording(path)


def test_c3d_size_is_checked_before_ezc3d_reads_it(tmp_path: Path, monkeypatch):
    import ezc3d

    def refuse(*_: object) -> None:
        raise AssertionError("ezc3d was called")

    monkeypatch.setattr(limits, "MAX_POSITION_BYTES", 1 << 20)  # 1 MiB: the dough file needs 1.6 MB
    monkeypatch.setattr(ezc3d, "c3d", refuse)
    with pytest.raises(InvalidRecording, match="2688 frames × 26 markers need"):
        read_recording(DOUGH)


XML_BOMB = ('<?xml version="1.0"?>\n<!DOCTYPE MMM [\n <!ENTITY a "aaaaaaaaaa">\n'
            + "".join(f' <!ENTITY {chr(98 + i)} "{("&" + chr(97 + i) + ";") * 10}">\n' for i in range(9))
            + ']>\n<MMM><Motion name="&j;"/></MMM>\n')


@pytest.mark.parametrize(("name", "text"), [
    ("bomb.xml", XML_BOMB),
    ("external.xml", '<!DOCTYPE MMM [<!ENTITY x SYSTEM "file:///etc/passwd">]>\n<MMM>&x;</MMM>\n'),
    ("parameter.xml", '<!DOCTYPE MMM [<!ENTITY % p SYSTEM "http://example.invalid/x.dtd"> %p;]>\n<MMM/>\n'),
])
def test_xml_entities_are_refused_in_bounded_memory(name: str, text: str, tmp_path: Path, capsys):
    path = tmp_path / name
    path.write_text(text)
    tracemalloc.start()
    try:
        err = one_line_error(capsys, 1, "inspect", path)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert "a document type declaration (DTD, entities) is not allowed in an MMM file" in err
    assert peak < 20 * 2**20  # bytes: the billion laughs would expand to 1 GB


def mmm(positions: str = "1 2 3", stamps: tuple[str, ...] = ("0", "0.1", "0.2")) -> str:
    rows = "".join(f'<Measurement timestep="{t}"><MarkerPosition name="a">{positions if k == 1 else "1 2 3"}'
                   '</MarkerPosition><MarkerPosition name="b">4 5 6</MarkerPosition></Measurement>'
                   for k, t in enumerate(stamps))
    return f'<MMM><Motion name="true_cup"><Sensors><Sensor type="MoCapMarker"><Data>{rows}</Data></Sensor>' \
           "</Sensors></Motion></MMM>"


@pytest.mark.parametrize(("text", "message"), [
    (mmm("inf 2 3"), "line 1: motion 'true_cup', timestep 0.1: MarkerPosition 'a' has x = inf mm"),
    (mmm("1 1e300 3"), "MarkerPosition 'a' has y = 1e+300 mm"),
    (mmm(stamps=("0", "0.1", "1e300")), "the recording spans 1e+300 s, more than the limit of 1e+06 s"),
    (mmm(stamps=("0", "1e-5", "2e-5")), "is 100000 Hz; a recording's rate must lie within"),
])
def test_mmm_values_out_of_range(text: str, message: str, tmp_path: Path, capsys):
    path = tmp_path / "m.xml"
    path.write_text(text)
    for command in ("inspect", "segment"):
        assert message in one_line_error(capsys, 1, command, path)


@pytest.mark.parametrize("argv", [["--frames", "1e8"], ["--frames", "1e12"], ["--frames", "2689"],
                                  ["--merge", "1e9s"], ["--merge", "27s"]])
def test_windows_longer_than_the_recording(argv: list[str], tmp_path: Path, capsys):
    library = ROOT / "library"
    for command in (["segment", DOUGH], ["match", DOUGH, "--library", library]):
        err = one_line_error(capsys, 2, *command, *argv)
        assert f"dough.c3d: {argv[0]} {argv[1]}: " in err
        assert "more than the recording's 2688 frames" in err or "longer than the recording (26.87 s)" in err


def test_segment_refuses_a_window_longer_than_the_recording():
    rec = Recording("r", 100.0, np.arange(20) / 100.0, ("a", "b"), np.zeros((20, 2, 3)),
                    {"x": (0,), "y": (1,)})
    with pytest.raises(SegmentationError, match="frames n = 1000000000000 is more than the recording's 20"):
        segment(rec, AasParams(frames=10**12))


def test_a_csv_of_thousands_of_single_marker_groups(tmp_path: Path, capsys):
    names = [f"m{i}" for i in range(3000)]
    path = tmp_path / "wide.csv"
    path.write_text("# rate_hz: 100\n" + ",".join(f"{n}_{a}" for n in names for a in "xyz") + "\n"
                    + ("0.5," * 9000)[:-1] + "\n" + ("0.6," * 9000)[:-1] + "\n")
    code, out, _ = run(capsys, "inspect", path, "--json")
    assert code == 0 and json.loads(out)["markers"] == 3000  # readable: inspect shows it
    err = one_line_error(capsys, 2, "segment", path)
    assert "3000 marker groups (instances), more than the 100 a segmentation takes" in err


def test_segmentation_work_is_bounded(monkeypatch):
    rec = Recording("r", 100.0, np.arange(50) / 100.0, ("a", "b", "c"), np.zeros((50, 3, 3)),
                    {"x": (0, 1), "y": (2,)})
    monkeypatch.setattr(aas_module, "MAX_PAIR_FRAMES", 99)
    with pytest.raises(SegmentationError, match=r"2 marker pairs × 50 frames is more than the 1e\+02 pair"):
        segment(rec)


def test_no_file_is_written_for_a_bad_recording(tmp_path: Path, capsys, monkeypatch):
    library = tmp_path / "library"
    shutil.copytree(ROOT / "library", library, ignore=shutil.ignore_patterns("learned", "drafts"))
    before = sorted(p.relative_to(tmp_path) for p in tmp_path.rglob("*"))
    monkeypatch.chdir(tmp_path)
    path = c3d_with_rate(tmp_path, float("inf"))
    one_line_error(capsys, 1, "compose", path, "--name", "bad", "--library", library)
    assert sorted(p.relative_to(tmp_path) for p in tmp_path.rglob("*")) == sorted(
        before + [Path("rate.c3d"), Path("short.c3d")])


def test_a_quote_in_a_csv_row_does_not_swallow_the_next_rows(tmp_path: Path, capsys):
    path = tmp_path / "q.csv"
    path.write_text('# rate_hz: 50\nframe,time,a_x,a_y,a_z\n0,0,1,"2,3\n1,0.02,1,2,3\n')
    for command in ("inspect", "segment"):
        assert "q.csv: line 3: 4 fields, expected 5" in one_line_error(capsys, 1, command, path)


def test_c3d_frame_size_follows_point_used_as_ezc3d_does(tmp_path: Path, capsys):
    """The header says 0 points, POINT:USED 26 (what ezc3d reads): a cut file is still caught."""
    data, start, frame_bytes = dough_layout()
    data = bytearray(data)
    data[2:4] = struct.pack("<H", 0)  # header word 2: points per frame
    path = tmp_path / "used.c3d"
    path.write_bytes(bytes(data[: start + DOUGH_FRAMES * frame_bytes - 3000]))
    err = one_line_error(capsys, 1, "inspect", path)
    assert "inside frame 2681 of 2688 frames; frames 2681..2688 lost" in err
