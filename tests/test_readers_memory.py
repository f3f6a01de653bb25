"""Issue 21, memory: a TSV or CSV is read in bounded memory (the result plus one block, not
14 times the file as Python strings), measured with tracemalloc on files of a few MB; a
segmentation's distance and scratch buffers stay within a budget (chunks of fewer frames,
or a refusal before anything is allocated)."""

from __future__ import annotations

import re
import tracemalloc
from pathlib import Path

import numpy as np
import pytest

from oacdsl.cli import main
from oacdsl.errors import SegmentationError
from oacdsl.segmentation import geometry, segment
from oacdsl.segmentation.geometry import ChunkGeometry
from oacdsl.segmentation.pairs import PairTable
from oacdsl.segmentation.params import AasParams
from oacdsl.segmentation.readers import read_recording
from oacdsl.segmentation.recording import Recording

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


# --- segmentation: the distances of a chunk are bounded, not frames × marker pairs ---------------

def two_big_groups(markers_each: int, frames: int) -> Recording:
    rng = np.random.default_rng(5)
    pos = rng.uniform(0.0, 0.3, (frames, 2 * markers_each, 3))
    names = tuple(f"m{i}" for i in range(2 * markers_each))
    groups = {"a": tuple(range(markers_each)), "b": tuple(range(markers_each, 2 * markers_each))}
    return Recording("big", 100.0, np.arange(frames) / 100.0, names, pos, groups)


def test_too_many_marker_pairs_are_refused_before_any_buffer(capsys):
    """The fuzzed case: 2 groups × 5,000 markers × 25 frames asked for 2.3 GiB of scratch at once."""
    rec = two_big_groups(5000, 25)
    tracemalloc.start()
    try:
        with pytest.raises(SegmentationError) as err:
            segment(rec)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert re.search(r"25000000 marker pairs × \d+ frames at once \(\d+ before each chunk\) need \d+ MiB of"
                     " distances, more than the 128 MiB a segmentation holds", str(err.value))
    assert peak < 16 * 2**20  # bytes: refused before the pair table (600 MB) or a buffer is made


@pytest.mark.parametrize("mode", ["paper", "robust"])
def test_chunks_shrink_to_hold_the_distance_budget(mode: str, monkeypatch):
    rec = two_big_groups(40, 300)  # 1,600 marker pairs
    whole = segment(rec, AasParams(mode=mode))
    budget = 1600 * 2 * 4 * 40  # bytes: distances and scratch of 40 frames
    monkeypatch.setattr(geometry, "MAX_CHUNK_DISTANCE_BYTES", budget)
    sizes: list[int] = []
    distances, scratch, near = ChunkGeometry.distances, ChunkGeometry.scratch, ChunkGeometry.near_distances

    def watched_distances(self, x, blocks):
        pairs, dist = distances(self, x, blocks)
        sizes.append(dist.nbytes)
        return pairs, dist

    def watched_near(self, x, blocks, *args):  # the paper's detector: only the pairs within reach
        pairs, dist = near(self, x, blocks, *args)
        sizes.append(dist.nbytes)
        return pairs, dist

    def watched_scratch(self, n_rows):
        buffer = scratch(self, n_rows)
        sizes.append(buffer.nbytes)
        return buffer

    monkeypatch.setattr(ChunkGeometry, "distances", watched_distances)
    monkeypatch.setattr(ChunkGeometry, "near_distances", watched_near)
    monkeypatch.setattr(ChunkGeometry, "scratch", watched_scratch)
    bounded = segment(rec, AasParams(mode=mode))
    assert sizes and max(sizes) <= budget // 2  # each of the two buffers within its half
    assert bounded.keyframes == whole.keyframes  # chunking changes nothing
    monkeypatch.setattr(geometry, "MAX_CHUNK_DISTANCE_BYTES", budget // 4)
    with pytest.raises(SegmentationError, match=r"1600 marker pairs × \d+ frames at once"):
        segment(rec, AasParams(mode=mode))


def test_a_scratch_buffer_is_the_largest_instance_pair_not_the_largest_instance_squared():
    rec = Recording("r", 100.0, np.arange(4) / 100.0, tuple(f"m{i}" for i in range(1001)),
                    np.zeros((4, 1001, 3)), {"big": tuple(range(1000)), "one": (1000,)})
    geo = ChunkGeometry(rec, PairTable.of(rec))
    assert geo.scratch(10).size == 1000 * 10  # was 1000 × 1000 × 10


# --- an input value of megabytes is clipped in the one-line error, not echoed whole ---------------

BIG = "x" * 1_000_000
MMM_ONE = ('<MMM><Motion name="{motion}"><Sensors><Sensor type="MoCapMarker"><Data>'
           '<Measurement timestep="{t}"><MarkerPosition name="m">{xyz}</MarkerPosition></Measurement>'
           "</Data></Sensor></Sensors></Motion></MMM>")
ECHOES = {
    "name.tsv": f"NO_OF_FRAMES\t1\nNO_OF_MARKERS\t1\nFREQUENCY\t100\nMARKER_NAMES\t{BIG}\n1e9\t2\t3\n",
    "count.tsv": f"NO_OF_FRAMES\t{BIG}\nNO_OF_MARKERS\t1\nFREQUENCY\t100\nMARKER_NAMES\tcup\n1\t2\t3\n",
    "column.csv": f"frame,time,{BIG}\n1,2,3\n",
    "unit.csv": f"# units: {BIG}\nframe,time,a_x,a_y,a_z\n1,2,3,4,5\n",
    "value.csv": f"# rate_hz: 10\na_x,a_y,a_z\n3,4,{BIG}\n",
    "position.xml": MMM_ONE.format(motion="a", t="0", xyz=BIG),
    "timestep.xml": MMM_ONE.format(motion="a", t=BIG, xyz="1 2 3"),
    "motion.xml": MMM_ONE.format(motion=BIG, t="0", xyz="1 2 x"),
    "root.xml": f"<{BIG}/>",
}


@pytest.mark.parametrize("name", sorted(ECHOES))
def test_a_huge_value_is_clipped_in_the_error(name: str, tmp_path: Path, capsys):
    path = tmp_path / name
    path.write_text(ECHOES[name])
    code = main(["inspect", str(path)])
    out, err = capsys.readouterr()
    assert (code, out) == (1, "") and err.count("\n") == 1
    assert len(err) < 300 + len(str(path)) and "(1000000 characters)" in err
