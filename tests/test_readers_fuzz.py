"""Fuzzing the four readers through the command line, in process (issue 13).

A seeded corpus is generated here: small valid recordings written by the test
(C3D, MMM XML, Qualisys TSV, CSV) and their mutations — truncations, byte flips,
header edits (rate → inf, 1e9, NaN, empty, …), NaN/inf cells, huge column counts.
Each case runs ``oacc inspect`` or ``oacc segment`` through ``oacdsl.cli.main`` and
must end with no exception escaping, exit 0 (a mutant that is still a valid
recording) or exit 1/2 with exactly one ``oacc: error:`` line on stderr, and no file
written. Mutations that make a recording invalid by construction must fail, in
``inspect`` as in ``segment``.
"""

from __future__ import annotations

import contextlib
import io
import random
import struct
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest

from oacdsl.cli import main
from oacdsl.segmentation.readers import write_c3d
from oacdsl.segmentation.readers.c3d_check import check_c3d_structure
from oacdsl.segmentation.recording import Recording

SEED = 13
FRAMES = 40
RATE_HZ = 50.0
BAD_NUMBERS = ["inf", "-inf", "nan", "NaN", "", "1e9", "1e300", "1e400", "0", "-50", "x", "0x10"]
BAD_RATES = BAD_NUMBERS + ["0.5", "20000", "1e-300"]
BAD_COORDINATES = ["inf", "-inf", "1e300", "1e400", "-2e7"]  # mm: -2e7 is 20 km from the origin


def motion() -> np.ndarray:
    """(F, 5, 3) metres: a hand (2 markers) reaches a cup (2 markers) and lifts it; a bowl (1)."""
    t = np.linspace(0.0, 1.0, FRAMES)[:, None]
    hand = np.array([0.0, 0.0, 0.3]) + np.clip(t * 2, 0, 1) * [0.5, 0.0, -0.2]
    cup = np.array([0.52, 0.0, 0.1]) + np.clip(t * 2 - 1, 0, 1) * [0.0, 0.0, 0.2]
    bowl = np.broadcast_to([1.0, 0.5, 0.05], (FRAMES, 3))
    return np.stack([hand, hand + 0.02, cup, cup + [0.03, 0, 0], bowl], axis=1)


NAMES = ("hand_a", "hand_b", "cup_a", "cup_b", "bowl")


def c3d_bytes(folder: Path) -> bytes:
    rec = Recording("fuzz", RATE_HZ, np.arange(FRAMES) / RATE_HZ, NAMES, motion(),
                    {"hand": (0, 1), "cup": (2, 3), "bowl": (4,)})
    return write_c3d(rec, folder / "base.c3d").read_bytes()


def tsv_text() -> str:
    mm = motion() * 1000.0
    head = (f"NO_OF_FRAMES\t{FRAMES}\nNO_OF_CAMERAS\t8\nNO_OF_MARKERS\t{len(NAMES)}\nFREQUENCY\t{RATE_HZ:g}\n"
            "DATA_INCLUDED\t3D\nMARKER_NAMES\t" + "\t".join(NAMES) + "\n"
            "Frame\tTime\t" + "\t".join(f"{n} {a}" for n in NAMES for a in "XYZ") + "\t\n")
    rows = [f"{f + 1}\t{f / RATE_HZ:.3f}\t" + "\t".join(f"{v:.3f}" for v in mm[f].ravel()) + "\t"
            for f in range(FRAMES)]
    return head + "\n".join(rows) + "\n"


def csv_text() -> str:
    mm = motion() * 1000.0
    head = f"# units: mm\n# rate_hz: {RATE_HZ:g}\nframe,time," + ",".join(
        f"{n}_{a}" for n in NAMES for a in "xyz") + "\n"
    rows = [f"{f},{f / RATE_HZ:.3f}," + ",".join(f"{v:.3f}" for v in mm[f].ravel()) for f in range(FRAMES)]
    return head + "\n".join(rows) + "\n"


def mmm_text() -> str:
    mm = motion() * 1000.0
    parts = ['<?xml version="1.0" encoding="UTF-8"?>\n<MMM>\n']
    for name, cols in (("true_hand", (0, 1)), ("true_cup", (2, 3)), ("bowl", (4,))):
        parts.append(f'<Motion name="{name}">\n<Sensors>\n<Sensor type="MoCapMarker">\n<Data>\n')
        for f in range(FRAMES):
            parts.append(f'<Measurement timestep="{f / RATE_HZ:.3f}">')
            parts += [f'<MarkerPosition name="{NAMES[c]}">{" ".join(f"{v:.3f}" for v in mm[f, c])}'
                      "</MarkerPosition>" for c in cols]
            parts.append("</Measurement>\n")
        parts.append("</Data>\n</Sensor>\n</Sensors>\n</Motion>\n")
    parts.append("</MMM>\n")
    return "".join(parts)


@dataclass(frozen=True)
class Case:
    name: str
    suffix: str
    data: bytes
    invalid: bool  # invalid by construction: every command must fail


# -- mutations ---------------------------------------------------------------------------------


def flips(rng: random.Random, data: bytes) -> bytes:
    out = bytearray(data)
    for _ in range(rng.randint(1, 4)):
        out[rng.randrange(len(out))] = rng.randrange(256)
    return bytes(out)


def replace_field(text: str, line_index: int, sep: str, column: int, value: str) -> str:
    lines = text.split("\n")
    fields = lines[line_index].split(sep)
    fields[column] = value
    lines[line_index] = sep.join(fields)
    return "\n".join(lines)


def column_is_valid(texts: list[str], *, frames: bool) -> bool:
    """The rule of docs/readers.md for a frame column (whole numbers within ±2**31 - 1) or a time
    column (span at most 1e6 s): numbers, finite, strictly increasing."""
    try:
        values = np.array([float(t) if t.strip() else np.nan for t in texts])
    except ValueError:
        return False
    if not np.isfinite(values).all() or not (np.diff(values) > 0).all():
        return False
    if frames:
        return bool((values == np.round(values)).all() and (np.abs(values) <= 2**31 - 1).all())
    return bool(values[-1] - values[0] <= 1e6)


def text_cases(rng: random.Random, fmt: str, text: str, n: int) -> list[Case]:
    sep = "\t" if fmt == "tsv" else ","
    lines = text.split("\n")
    first_row = next(i for i, line in enumerate(lines) if line[:1].isdigit())
    last_row = max(i for i, line in enumerate(lines) if line[:1].isdigit())
    rate_line = next(i for i, line in enumerate(lines) if "FREQUENCY" in line or "rate_hz" in line)
    cases: list[Case] = []
    for k in range(n):
        kind = k % 7
        row = rng.randint(first_row, last_row)
        if kind == 0:  # truncation: TSV before its last row (NO_OF_FRAMES), CSV inside a row
            if fmt == "tsv":
                cut = rng.randrange(sum(len(line) + 1 for line in lines[:last_row]))
            else:
                start = sum(len(line) + 1 for line in lines[:row])
                cut = start + rng.randrange(1, lines[row].rindex(","))
            cases.append(Case(f"{fmt}-truncate-{cut}", fmt, text[:cut].encode(), True))
        elif kind == 1:
            cases.append(Case(f"{fmt}-flip-{k}", fmt, flips(rng, text.encode()), False))
        elif kind == 2:  # the rate line
            value = rng.choice(BAD_RATES)
            edited = "\n".join(
                (f"FREQUENCY\t{value}" if fmt == "tsv" else f"# rate_hz: {value}") if i == rate_line else line
                for i, line in enumerate(lines))
            # an empty '# rate_hz:' is no rate line; the time column gives the rate then
            invalid = not (fmt == "csv" and value == "")
            cases.append(Case(f"{fmt}-rate-{value!r}", fmt, edited.encode(), invalid))
        elif kind == 3:  # frame or time column
            column, value = rng.choice([0, 1]), rng.choice(BAD_NUMBERS + ["2.5"])
            edited = replace_field(text, row, sep, column, value)
            values = [line.split(sep)[column] for line in edited.split("\n")[first_row : last_row + 1]]
            valid = column_is_valid(values, frames=column == 0)
            cases.append(Case(f"{fmt}-col{column}-{row}-{value!r}", fmt, edited.encode(), not valid))
        elif kind == 4:  # a coordinate: NaN or empty is a gap (valid), inf or huge is an error
            value = rng.choice(BAD_COORDINATES + ["nan", ""])
            edited = replace_field(text, row, sep, rng.randrange(2, 2 + 3 * len(NAMES)), value)
            cases.append(Case(f"{fmt}-cell-{row}-{value!r}", fmt, edited.encode(), value not in ("nan", "")))
        elif kind == 5:  # a header edit: marker names or frame count
            key = rng.choice(["NO_OF_FRAMES", "NO_OF_MARKERS", "MARKER_NAMES"]) if fmt == "tsv" else "units"
            value = rng.choice(["", "1e12", "-1", "abc", "inf"])
            if fmt == "tsv":
                edited = "\n".join(f"{key}\t{value}" if line.startswith(key) else line for line in lines)
            else:
                edited = "\n".join(f"# units: {value}" if line.startswith("# units") else line
                                   for line in lines)
            cases.append(Case(f"{fmt}-header-{key}-{value!r}", fmt, edited.encode(), fmt == "tsv"))
        else:  # random bytes inserted into the text
            at = rng.randrange(len(text))
            junk = bytes(rng.randrange(256) for _ in range(rng.randint(1, 8)))
            data = text.encode()
            cases.append(Case(f"{fmt}-insert-{at}", fmt, data[:at] + junk + data[at:], False))
    return cases


def wide_csv(markers: int, rows_too: bool) -> Case:
    """A CSV of ``markers`` markers (one group each); without ``rows_too`` its rows are too short."""
    names = [f"m{i}" for i in range(markers)]
    head = f"# rate_hz: {RATE_HZ:g}\n" + ",".join(f"{n}_{a}" for n in names for a in "xyz") + "\n"
    width = 3 * markers if rows_too else 3
    body = "\n".join(",".join(["0.5"] * width) for _ in range(3)) + "\n"
    return Case(f"csv-wide-{markers}-{rows_too}", "csv", (head + body).encode(),
                not rows_too or markers > 10_000)


def c3d_rate_offsets(data: bytes) -> tuple[int, int]:
    """Byte offsets of the header's frame rate and of POINT:RATE's value (Intel floats)."""
    at = data.index(b"RATE", 512)
    n_dims = data[at + 4 + 3]
    return 20, at + 4 + 4 + n_dims


def c3d_cases(rng: random.Random, data: bytes, n: int) -> list[Case]:
    layout = check_c3d_structure(Path("base.c3d"), data)
    frame_bytes = 4 * (4 * layout.points + layout.analog_per_frame)
    data_end = (layout.data_start_block - 1) * 512 + layout.n_frames * frame_bytes
    header_rate, param_rate = c3d_rate_offsets(data)
    cases: list[Case] = []
    for k in range(n):
        kind = k % 5
        if kind == 0:
            cut = rng.randrange(data_end)
            cases.append(Case(f"c3d-truncate-{cut}", "c3d", data[:cut], True))
        elif kind == 1:
            cases.append(Case(f"c3d-flip-{k}", "c3d", flips(rng, data), False))
        elif kind == 2:  # the rate in the header and in POINT:RATE
            value = rng.choice([float("inf"), float("nan"), 1e9, 1e30, -100.0, 0.0, 0.25, 2e4, 3.4e38])
            out = bytearray(data)
            out[header_rate:header_rate + 4] = struct.pack("<f", value)
            out[param_rate:param_rate + 4] = struct.pack("<f", value)
            cases.append(Case(f"c3d-rate-{value:g}", "c3d", bytes(out), True))
        elif kind == 3:  # a coordinate (float storage): infinite or beyond 10 km
            frame, marker, axis = rng.randrange(FRAMES), rng.randrange(len(NAMES)), rng.randrange(3)
            value = rng.choice([float("inf"), float("-inf"), 1e30, -3e7])
            at = (layout.data_start_block - 1) * 512 + frame * frame_bytes + (4 * marker + axis) * 4
            out = bytearray(data)
            out[at:at + 4] = struct.pack("<f", value)
            cases.append(Case(f"c3d-coordinate-{frame}-{marker}-{value:g}", "c3d", bytes(out), True))
        else:  # a header word: points, frames, data start
            word = rng.choice([1, 2, 3, 4, 8])
            out = bytearray(data)
            out[2 * word:2 * word + 2] = struct.pack("<H", rng.randrange(65536))
            cases.append(Case(f"c3d-header-word{word}-{k}", "c3d", bytes(out), False))
    return cases


def mmm_cases(rng: random.Random, text: str, n: int) -> list[Case]:
    stamps = [f'timestep="{f / RATE_HZ:.3f}"' for f in range(FRAMES)]
    bomb = ('<!DOCTYPE MMM [<!ENTITY a "aaaaaaaaaa">' + "".join(
        f'<!ENTITY {chr(98 + i)} "{("&" + chr(97 + i) + ";") * 10}">' for i in range(9)) + "]>\n")
    cases: list[Case] = []
    for k in range(n):
        kind = k % 6
        if kind == 0:
            cut = rng.randrange(text.rindex("</MMM>"))
            cases.append(Case(f"mmm-truncate-{cut}", "xml", text[:cut].encode(), True))
        elif kind == 1:
            cases.append(Case(f"mmm-flip-{k}", "xml", flips(rng, text.encode()), False))
        elif kind == 2:  # a timestep
            stamp, value = rng.choice(stamps[1:]), rng.choice(["nan", "inf", "", "x", "1e300", "-1e300"])
            cases.append(Case(f"mmm-timestep-{value!r}", "xml",
                              text.replace(stamp, f'timestep="{value}"').encode(), True))
        elif kind == 3:  # every timestep scaled: a rate of 1e9 Hz or 0.5 Hz
            scale = rng.choice([1e-8, 100.0])
            edited = text
            for f, stamp in enumerate(stamps):
                edited = edited.replace(stamp, f'timestep="{f / RATE_HZ * scale!r}"')
            cases.append(Case(f"mmm-rate-x{scale:g}", "xml", edited.encode(), True))
        elif kind == 4:  # a coordinate
            value = rng.choice(BAD_COORDINATES)
            at = rng.randrange(text.count("</MarkerPosition>"))
            pieces = text.split("</MarkerPosition>")
            head, _, numbers = pieces[at].rpartition(">")
            pieces[at] = f"{head}>{numbers.split()[0]} {value} {numbers.split()[2]}"
            edited = "</MarkerPosition>".join(pieces)
            cases.append(Case(f"mmm-cell-{at}-{value}", "xml", edited.encode(), True))
        else:  # entities: a bomb or an external entity
            doctype = bomb if rng.random() < 0.5 else '<!DOCTYPE MMM [<!ENTITY x SYSTEM "/etc/passwd">]>\n'
            body = text.replace("<MMM>", doctype + "<MMM>", 1).replace("bowl", "&x;" if "SYSTEM" in doctype
                                                                        else "&j;", 1)
            cases.append(Case(f"mmm-entity-{k}", "xml", body.encode(), True))
    return cases


# -- running ----------------------------------------------------------------------------------------


def run_cli(argv: list[str]) -> tuple[int, str, str]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            code = main(argv)
        except BaseException as exc:  # the point of the test: nothing escapes
            raise AssertionError(f"{argv}: {type(exc).__name__} escaped: {exc}") from exc
    return code, out.getvalue(), err.getvalue()


def check(case: Case, command: str, path: Path, workdir: Path) -> int:
    code, out, err = run_cli([command, str(path)])
    where = f"{case.name} ({command})"
    if code == 0:
        assert not case.invalid, f"{where}: an invalid recording was accepted"
        assert out and all(line.startswith("oacc: warning: ") for line in err.splitlines()), where
    else:
        assert code in (1, 2), f"{where}: exit {code}"
        assert err.count("\n") == 1 and err.startswith("oacc: error: "), f"{where}: stderr {err!r}"
        assert "Traceback" not in err and not out, where
    assert not any(workdir.iterdir()), f"{where}: wrote {sorted(workdir.iterdir())}"
    assert sorted(p.name for p in path.parent.iterdir()) == [path.name], f"{where}: a file was left behind"
    return code


@pytest.fixture(scope="module")
def corpus(tmp_path_factory) -> list[Case]:
    rng = random.Random(SEED)
    base = tmp_path_factory.mktemp("base")
    cases = (c3d_cases(rng, c3d_bytes(base), 900) + mmm_cases(rng, mmm_text(), 600)
             + text_cases(rng, "tsv", tsv_text(), 700) + text_cases(rng, "csv", csv_text(), 700))
    cases += [wide_csv(3000, True), wide_csv(20_000, False), wide_csv(12_000, True)]
    return cases


def test_the_unmutated_recordings_are_read(tmp_path: Path):
    texts: dict[str, Callable[[], str]] = {"tsv": tsv_text, "csv": csv_text, "xml": mmm_text}
    files = [tmp_path / "base.c3d"]
    c3d_bytes(tmp_path)
    for suffix, make in texts.items():
        files.append(tmp_path / f"base.{suffix}")
        files[-1].write_text(make(), encoding="utf-8")
    for path in files:
        code, out, err = run_cli(["segment", str(path), "--json"])
        assert code == 0 and err == "", (path, err)
        assert '"frames": 40' in out and "cup" in out


def test_fuzz_readers_through_the_cli(corpus, tmp_path: Path, monkeypatch):
    workdir = tmp_path / "work"
    workdir.mkdir()
    monkeypatch.chdir(workdir)
    rng = random.Random(SEED)
    counts = {0: 0, 1: 0, 2: 0}
    for i, case in enumerate(corpus):
        folder = tmp_path / f"c{i}"
        folder.mkdir()
        path = folder / f"rec.{case.suffix}"
        path.write_bytes(case.data)
        both = case.invalid or case.name.startswith("csv-wide")
        commands = ["inspect", "segment"] if both else [rng.choice(["inspect", "inspect", "segment"])]
        for command in commands:
            counts[check(case, command, path, workdir)] += 1
        path.unlink()
        folder.rmdir()
    assert len(corpus) > 2500
    assert counts[1] > 1500 and counts[0] > 100, counts  # mostly errors, some still-valid mutants
