"""Benchmark: ``oacc compile`` on pathological libraries stays linear in time and memory.

Three generated files, each at N = 10,000 (the baseline) and 100,000 declarations:

- ``chain``: ``class C1 : C0``, ``class C2 : C1``, … and a scene whose instance is of the
  deepest class (its ancestors are the whole chain);
- ``duplicates``: the same ``class A`` N times (N − 1 E006 errors, each rendered with its
  source line and a note);
- ``nested``: N opening braces (fails at the first, E001).

Each case runs ``oacc compile`` in its own process (``--repeat`` times); the figures are the
median CPU time of that process and its peak resident memory. The ratio is the time per
declaration at 100,000 over the time per declaration at 10,000: 1.0 is linear, 10 would be
quadratic. (Before issue 13: ``chain`` at 100,000 was killed at 24 GB, ``duplicates`` took
352 s.)

    python benchmarks/pathological.py
    python benchmarks/pathological.py --sizes 10000 50000 --repeat 1
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

_CHILD = """
import json, resource, sys, time
from oacdsl.cli import main
start = time.process_time()
status = main(["compile", "--format", "json", sys.argv[1]])
cpu = time.process_time() - start
peak_kib = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
print(json.dumps({"status": status, "cpu_s": cpu, "peak_mib": peak_kib / 1024}), file=sys.stderr)
"""


def text(case: str, n: int) -> str:
    if case == "chain":
        return "class C0\n" + "".join(f"class C{i} : C{i - 1}\n" for i in range(1, n)) + (
            f"scene s {{ x : C{n - 1} }}\n"
        )
    if case == "duplicates":
        return "class A\n" * n
    return "{" * n


def measure(path: Path) -> dict[str, float]:
    proc = subprocess.run(
        [sys.executable, "-c", _CHILD, str(path)], capture_output=True, text=True, cwd=ROOT, check=False
    )
    return json.loads(proc.stderr.strip().splitlines()[-1])


def main() -> None:
    parser = argparse.ArgumentParser(
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    parser.add_argument("--sizes", type=int, nargs=2, default=[10_000, 100_000], metavar="N")
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    small, large = args.sizes
    print(f"{'case':<11} {'N':>8} {'CPU s':>8} {'peak MiB':>9} {'per-decl ratio':>15}")
    with tempfile.TemporaryDirectory() as tmp:
        for case in ("chain", "duplicates", "nested"):
            per_decl = {}
            for n in (small, large):
                path = Path(tmp) / f"{case}{n}.oac"
                path.write_text(text(case, n), encoding="utf-8")
                runs = [measure(path) for _ in range(args.repeat)]
                cpu = statistics.median(r["cpu_s"] for r in runs)
                peak = statistics.median(r["peak_mib"] for r in runs)
                per_decl[n] = cpu / n
                ratio = f"{per_decl[n] / per_decl[small]:.2f}" if n == large else "(baseline)"
                print(f"{case:<11} {n:>8} {cpu:>8.2f} {peak:>9.0f} {ratio:>15}")


if __name__ == "__main__":
    main()
