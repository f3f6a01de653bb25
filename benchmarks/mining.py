"""Mining throughput: ``oacc mine`` on Dask with 1 and 2 workers against an in-process loop;
``oacc run NAME --seeds 0:K --workers 2`` against the same K runs one after the other.

**Mining.** N takes of the bundled dough demonstration (moved and turned, written as C3D files
into a temporary folder) are segmented and matched against ``library/`` three ways in the same
process: a plain loop calling the same task function (:func:`oacdsl.mining.task.analyse`, the
library parsed once per loop as a job parses it once), and :func:`oacdsl.mining.mine` with an
embedded cluster of 1 and of 2 worker processes (a fresh table each time; the cluster's start
and shutdown included, as a user waits for them). Every numerical library runs one thread here
as in the workers (``OMP/MKL/OPENBLAS_NUM_THREADS=1``, set before numpy loads), so that the
loop is one core's work, as a worker's is. The three alternate (--repeat rounds), so that a
drift in the machine's load hits them alike.

**Runs.** For each OAC of --run-oacs: K runs one after the other in this process
(:func:`oacdsl.mining.runs.run_one`, after one warm-up run: imports and caches are not the
loop's to pay K times) against :func:`oacdsl.mining.runs.run_many` on 2 workers (cluster start
and shutdown included); their outcomes must be identical (every step's relations and verdicts,
the simulated durations). ``grasp`` (0.3 s of CPU a run) shows the fixed cost of a job; ``dough``
(the paper's composed task, tests/data/runtime_tasks.oac: pour, pour, mix, ~3 s a run) is what
a user's success measure over seeds looks like.

Printed, per measurement: the median wall time and every round's, the CPU seconds of this
process and of its workers (reaped children), the median CPU per recording or run; then
the ratios with their targets. On a loaded machine the wall times measure the load; the CPU
times still say what a job costs over the loop.

    python benchmarks/mining.py                                   # all (about 8 min, quiet 2 cores)
    python benchmarks/mining.py --recordings 40 --runs 0 --repeat 1   # quick

Targets (issue 23): 2 workers ≥ 1.8× the loop on 2 cores; overhead < 50 ms per recording;
``--seeds 0:20 --workers 2`` ≥ 1.7× the 20 runs one after the other.
"""

from __future__ import annotations

import argparse
import os
import shutil
import statistics
import sys
import tempfile
import time
from collections.abc import Callable
from dataclasses import asdict
from pathlib import Path
from typing import Any

for _name in ("OMP_NUM_THREADS", "MKL_NUM_THREADS", "OPENBLAS_NUM_THREADS"):
    os.environ[_name] = "1"  # before numpy loads: one core's loop, as in the workers

import numpy as np  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from oacdsl.mining import mine  # noqa: E402
from oacdsl.mining.inputs import expand_recordings  # noqa: E402
from oacdsl.mining.task import JobSpec, analyse  # noqa: E402
from oacdsl.pipeline.inputs import open_library  # noqa: E402
from oacdsl.segmentation.params import AasParams  # noqa: E402
from oacdsl.segmentation.readers import read_recording, write_c3d  # noqa: E402
from oacdsl.segmentation.recording import Recording  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent))
from mining_reference import cores_alone_and_together, plain_processes  # noqa: E402

#: The OACs --runs measures: name → (libraries, bindings).
RUN_OACS: dict[str, tuple[list[Path], dict[str, str]]] = {
    "grasp": ([ROOT / "library"], {"h": "right_hand", "o": "green_cup"}),
    "dough": ([ROOT / "library", ROOT / "tests" / "data" / "runtime_tasks.oac"], {}),
}


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


class Measure:
    """Wall and CPU seconds of repeated calls: this process's and its reaped children's."""

    def __init__(self, name: str):
        self.name = name
        self.wall: list[float] = []
        self.own_cpu: list[float] = []
        self.child_cpu: list[float] = []
        self.unit_cpu: list[float] = []  # CPU per recording or run, all rounds
        self.stage_cpu: dict[str, list[float]] = {}  # a task thread's CPU per stage, all rounds

    def rows(self, rows: list[dict[str, Any]]) -> None:
        """The CPU of each recording's task: the process's, and its thread's per stage."""
        for row in rows:
            self.unit_cpu.append(row["cpu_s"])
            for stage, cpu in row.get("stage_cpu_s", {}).items():
                self.stage_cpu.setdefault(stage, []).append(cpu)

    def __call__(self, fn: Callable[[], Any]) -> Any:
        before, t0 = os.times(), time.perf_counter()
        out = fn()
        wall, after = time.perf_counter() - t0, os.times()
        self.wall.append(wall)
        self.own_cpu.append(after[0] + after[1] - before[0] - before[1])
        self.child_cpu.append(max(0.0, after[2] + after[3] - before[2] - before[3]))
        return out

    def median(self) -> float:
        return statistics.median(self.wall)

    def line(self, n: int, what: str) -> str:
        cpu = statistics.median(self.own_cpu) + statistics.median(self.child_cpu)
        unit = f", {1000 * statistics.median(self.unit_cpu):.0f} ms CPU per {what}" if self.unit_cpu else ""
        return (
            f"  {self.name:>22}: {self.median():7.2f} s wall median (rounds: "
            + ", ".join(f"{t:.2f}" for t in self.wall)
            + f"); CPU {cpu:.2f} s = {statistics.median(self.own_cpu):.2f} here"
            f" + {statistics.median(self.child_cpu):.2f} workers{unit};"
            f" {1000 * self.median() / n:.1f} ms wall per {what}"
            + ("; stages (ms CPU, median): " + ", ".join(
                f"{k} {1000 * statistics.median(v):.1f}" for k, v in self.stage_cpu.items())
               if self.stage_cpu else "")
        )


def verdict(ratio: float, target: float) -> str:
    return f"{ratio:.2f}x (target >= {target}x: {'met' if ratio >= target else 'NOT met'})"


def mining(n: int, repeat: int) -> list[str]:
    folder = Path(tempfile.mkdtemp(prefix="mine-takes-"))
    try:
        takes(folder, n)
        library = [str(ROOT / "library")]
        open_library([Path(library[0])])  # the grammar's parser is built once per process: in no figure
        loop, one, two = Measure("loop"), Measure("1 worker"), Measure("2 workers")
        plain = Measure("2 plain processes")

        def run_loop() -> None:
            spec = JobSpec(library, None, asdict(AasParams()), False, open_library([Path(library[0])]))
            rows = [analyse(f.path, f.id, spec) for f in expand_recordings([str(folder)])]
            for row in rows:
                if row["status"] != "ok":
                    raise SystemExit(f"{row['path']}: {row['error']}")
            loop.rows(rows)

        def run_plain() -> None:
            spec = JobSpec(library, None, asdict(AasParams()), False, open_library([Path(library[0])]))
            rows = plain_processes(expand_recordings([str(folder)]), spec)
            if len(rows) != n or any(row["status"] != "ok" for row in rows):
                raise SystemExit("a plain process's recording failed")
            plain.rows(rows)

        def run_job(measure: Measure, workers: int) -> None:
            out = Path(tempfile.mkdtemp(prefix="mine-bench-"))
            try:
                result = mine([str(folder)], library, out=out, workers=workers, progress=None)
                if result.errors or result.analysed != n:
                    raise SystemExit(f"{result.errors} of {result.analysed} recordings failed")
                measure.rows(result.rows)
            finally:
                shutil.rmtree(out, ignore_errors=True)

        for _ in range(repeat):  # interleaved
            loop(run_loop)
            one(lambda: run_job(one, 1))
            two(lambda: run_job(two, 2))
            plain(run_plain)
        print(f"oacc mine, {n} recordings ({repeat} rounds):")
        for m in (loop, one, two, plain):
            print(m.line(n, "recording"))
        print(f"  the machine: {cores_alone_and_together()}")
        speedup = loop.median() / two.median()
        ceiling = loop.median() / plain.median()
        overhead_ms = 1000 * (one.median() - loop.median()) / n
        extra_cpu_ms = 1000 * (statistics.median(two.own_cpu) + statistics.median(two.child_cpu)
                               - statistics.median(loop.own_cpu)) / n
        return [
            f"oacc mine {n} recordings, 2 workers vs the loop: {verdict(speedup, 1.8)}; two plain"
            f" processes (no Dask) vs the loop: {ceiling:.2f}x, the 2-worker job reaches"
            f" {100 * speedup / ceiling:.0f} % of that",
            f"oacc mine {n} recordings, overhead of the 1-worker job over the loop: {overhead_ms:.1f} ms per"
            f" recording (target < 50 ms: {'met' if overhead_ms < 50 else 'NOT met'}); the 2-worker job's"
            f" CPU over the loop's: {extra_cpu_ms:.1f} ms per recording",
        ]
    finally:
        shutil.rmtree(folder, ignore_errors=True)


def _outcome(doc: dict[str, Any]) -> Any:
    """A run's document without what differs from process to process (its wall time)."""
    return {k: v for k, v in doc.items() if k != "metrics"}, {
        k: v for k, v in doc.get("metrics", {}).items() if "wall" not in k
    }


def runs(name: str, k: int, repeat: int) -> str:
    """``oacc run NAME --seeds 0:k --workers 2`` against the k runs one after the other."""
    from oacdsl.mining.runs import RunSpec, _library, run_many, run_one

    paths, binding = RUN_OACS[name]
    spec = RunSpec([str(p) for p in paths], name, binding, None)
    spec.parsed = _library(spec.library)  # parsed once, for both (not part of either's time)
    run_one(spec, 0, 0)  # imports and the simulator's first model: not the loop's to pay k times
    seq, par = Measure("one after the other"), Measure("2 workers")

    def sequential() -> list[dict[str, Any]]:
        docs = []
        for s in range(k):
            c0 = time.process_time()
            docs.append(run_one(spec, s, 0))
            seq.unit_cpu.append(time.process_time() - c0)
        return docs

    wins = 0
    for _ in range(repeat):
        one_by_one = seq(sequential)
        on_cluster = par(lambda: run_many(spec, list(range(k)), 1, workers=2))
        if [_outcome(d) for d in one_by_one] != [_outcome(d) for d in on_cluster]:
            raise SystemExit(f"{name}: the runs on 2 workers differ from the runs one after the other")
        wins = sum(1 for d in on_cluster if d["success"])
    print(f"oacc run {name} --seeds 0:{k} ({repeat} rounds; {wins}/{k} succeeded, identical outcomes):")
    for m in (seq, par):
        print(m.line(k, "run"))
    ratio = seq.median() / par.median()
    return f"oacc run {name} --seeds 0:{k} --workers 2 vs one after the other: {verdict(ratio, 1.7)}"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--recordings", type=int, default=200, help="0: no mining")
    ap.add_argument("--repeat", type=int, default=3, help="rounds of each measurement (medians)")
    ap.add_argument("--runs", type=int, default=20, help="oacc run --seeds 0:RUNS (0: none)")
    ap.add_argument("--run-oacs", default="grasp,dough", help=f"of {', '.join(RUN_OACS)} (default: both)")
    args = ap.parse_args()
    c0 = time.process_time()
    import dask.distributed  # noqa: F401  # once per process, as the first job of a session imports it

    print(f"(importing dask.distributed: {time.process_time() - c0:.2f} s CPU, once per process, in no"
          " figure)")
    names = [n for n in args.run_oacs.split(",") if n]
    unknown = [n for n in names if n not in RUN_OACS]
    if unknown:
        ap.error(f"--run-oacs: unknown {', '.join(unknown)} (known: {', '.join(RUN_OACS)})")
    results = []
    if args.recordings:
        results += mining(args.recordings, args.repeat)
    if args.runs:
        results += [runs(name, args.runs, args.repeat) for name in names]
    print("\n".join(["", "RESULTS (medians of wall time):", *(f"  {r}" for r in results)]))


if __name__ == "__main__":
    main()
