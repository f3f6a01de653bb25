"""Mining throughput: ``oacc mine`` on Dask with 1 and 2 workers against an in-process loop.

N takes of the bundled dough demonstration (moved and turned, written as C3D files into a
temporary folder) are segmented and matched against ``library/`` three ways in the same
process: a plain loop calling the same task function (:func:`oacdsl.mining.task.analyse`), and
:func:`oacdsl.mining.mine` with an embedded LocalCluster of 1 and of 2 worker processes (a fresh
table each time; cluster start-up included, as a user waits for it). Printed: the wall time of
each (median of --repeat runs), the speed-up of 2 workers over the loop, and the overhead per
recording of the 1-worker job over the loop.

    python benchmarks/mining.py                   # 200 recordings
    python benchmarks/mining.py --recordings 40   # quicker

Targets (issue 23): 2 workers ≥ 1.8× the loop on 2 cores; overhead < 50 ms per recording.
"""

from __future__ import annotations

import argparse
import shutil
import statistics
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from oacdsl.mining import mine  # noqa: E402
from oacdsl.mining.inputs import expand_recordings  # noqa: E402
from oacdsl.mining.task import JobSpec, analyse  # noqa: E402
from oacdsl.segmentation.params import AasParams  # noqa: E402
from oacdsl.segmentation.readers import read_recording, write_c3d  # noqa: E402
from oacdsl.segmentation.recording import Recording  # noqa: E402


def takes(folder: Path, n: int) -> None:
    rec = read_recording(ROOT / "data" / "dough.c3d")
    for k in range(n):
        a = np.deg2rad(7.0 * k)
        rot = np.array([[np.cos(a), -np.sin(a), 0.0], [np.sin(a), np.cos(a), 0.0], [0.0, 0.0, 1.0]])
        pos = rec.positions_m @ rot.T + [0.01 * k, 0.0, 0.0]
        write_c3d(
            Recording(f"take{k}", rec.rate_hz, rec.times_s, rec.marker_names, pos, dict(rec.groups)),
            folder / f"take_{k:03d}.c3d",
        )


def loop(folder: Path) -> float:
    from dataclasses import asdict

    spec = JobSpec([str(ROOT / "library")], None, asdict(AasParams()), False)
    t0 = time.perf_counter()
    for f in expand_recordings([str(folder)]):
        row = analyse(f.path, f.id, spec)
        if row["status"] != "ok":
            raise SystemExit(f"{f.path}: {row['error']}")
    return time.perf_counter() - t0


def job(folder: Path, workers: int) -> float:
    out = Path(tempfile.mkdtemp(prefix="mine-bench-"))
    try:
        t0 = time.perf_counter()
        result = mine([str(folder)], [ROOT / "library"], out=out, workers=workers, progress=None)
        wall = time.perf_counter() - t0
        if result.errors:
            raise SystemExit(f"{result.errors} recordings failed")
        return wall
    finally:
        shutil.rmtree(out, ignore_errors=True)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--recordings", type=int, default=200)
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    folder = Path(tempfile.mkdtemp(prefix="mine-takes-"))
    try:
        takes(folder, args.recordings)
        times: dict[str, list[float]] = {"loop": [], "1 worker": [], "2 workers": []}
        for _ in range(args.repeat):  # interleaved, so that load drifts hit all three alike
            times["loop"].append(loop(folder))
            times["1 worker"].append(job(folder, 1))
            times["2 workers"].append(job(folder, 2))
        med = {k: statistics.median(v) for k, v in times.items()}
        n = args.recordings
        for k, v in med.items():
            print(
                f"{k:>10}: {v:7.2f} s  ({1000 * v / n:.1f} ms per recording; runs: "
                + ", ".join(f"{t:.2f}" for t in times[k])
                + ")"
            )
        speedup = med["loop"] / med["2 workers"]
        overhead_ms = 1000 * (med["1 worker"] - med["loop"]) / n
        print(f"2 workers vs loop: {speedup:.2f}x (target >= 1.8x) {'met' if speedup >= 1.8 else 'NOT met'}")
        print(
            f"overhead of the 1-worker job over the loop: {overhead_ms:.1f} ms per recording (target < 50 ms)"
            " "
            f"{'met' if overhead_ms < 50 else 'NOT met'}"
        )
    finally:
        shutil.rmtree(folder, ignore_errors=True)


if __name__ == "__main__":
    main()
