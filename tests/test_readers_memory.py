"""Issue 21, memory: a TSV or CSV is read in bounded memory (the result plus one block, not
14 times the file as Python strings); measured with tracemalloc on files of a few MB."""

from __future__ import annotations

import tracemalloc
from pathlib import Path

import numpy as np
import pytest

from oacdsl.segmentation.readers import read_recording

MARKERS = 10


def big_text(path: Path, rows: int) -> None:
    """``rows`` frames of ``MARKERS`` markers, some fields empty (gaps), as TSV or CSV."""
    rng = np.random.default_rng(0)
    values = rng.uniform(100.0, 900.0, (1000, 3 * MARKERS))
    tsv = path.suffix == ".tsv"
    sep = "\t" if tsv else ","
    lines = [sep.join(f"{v:.3f}" for v in row) for row in values]
    lines[7] = sep.join(["", "", ""] + lines[7].split(sep)[3:])  # a gap: empty fields
    names = [f"m{i}" for i in range(MARKERS)]
    with path.open("w") as out:
        if tsv:
            out.write(f"NO_OF_FRAMES\t{rows}\nNO_OF_MARKERS\t{MARKERS}\nFREQUENCY\t100\n"
                      f"MARKER_NAMES\t{chr(9).join(names)}\nFrame\tTime\t"
                      + "\t".join(f"{n} {a}" for n in names for a in "XYZ") + "\n")
        else:
            out.write("# units: mm\nframe,time," + ",".join(f"{n}_{a}" for n in names for a in "xyz") + "\n")
        out.writelines(f"{r + 1}{sep}{r / 100:.2f}{sep}{lines[r % 1000]}\n" for r in range(rows))


@pytest.mark.parametrize("suffix", [".tsv", ".csv"])
def test_text_recordings_are_read_in_bounded_memory(suffix: str, tmp_path: Path):
    path = tmp_path / f"big{suffix}"
    rows = 40_000
    big_text(path, rows)
    size = path.stat().st_size  # about 10 MB
    result = rows * MARKERS * 3 * 8  # bytes of the positions
    tracemalloc.start()
    try:
        rec = read_recording(path)
        peak = tracemalloc.get_traced_memory()[1]
        print(f"peak {peak / 2**20:.1f} MiB, file {size / 2**20:.1f} MiB, positions {result / 2**20:.1f} MiB")
    finally:
        tracemalloc.stop()
    assert rec.n_frames == rows and np.isnan(rec.positions_m[7, 0]).all()
    assert not np.isnan(rec.positions_m[8]).any() and 0.1 <= np.nanmin(rec.positions_m) <= 0.9
    # the whole file as Python strings took 14 times its size; now the result and one block
    assert peak < result + 20 * 2**20, (peak / 2**20, size / 2**20, result / 2**20)
