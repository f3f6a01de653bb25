"""How long `oacc verify` takes, and what the verify stage adds to `oacc reproduce`.

    python benchmarks/verify.py [--clip Cut] [--repeats 3] [--runs 2]

1. `oacc verify D E` (in this process, as the command line runs it) of a KIT development clip
   D and a take E of it (rotated 90° about the vertical, translated 2 m, written as C3D), median
   wall and CPU seconds over ``--repeats``, against the baseline `oacc segment D` in the same
   process (reading and the AAS). Target: < 2 s for a 10 s pair.
2. `oacc reproduce` of the bundled demonstration (``--runs`` times, no pictures, no run store):
   the verify stage's seconds over the rest of the run's, wall (the run's own stage timings)
   and CPU (this process's CPU time in the stage against the whole run's: on a shared machine
   the wall clock measures the load), medians. Target: < 15 %.
"""

from __future__ import annotations

import argparse
import contextlib
import io
import math
import statistics
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT), str(ROOT / "tests")]

from _mocap import MOCAP  # noqa: E402
from kit_reproduce import DEV  # noqa: E402


def timed(fn):  # type: ignore[no-untyped-def]
    wall, cpu = time.perf_counter(), time.process_time()
    out = fn()
    return out, time.perf_counter() - wall, time.process_time() - cpu


def quiet(argv: list[str]) -> int:
    from oacdsl.cli import main

    with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
        return main(argv)


def verify_pair(clip: str, repeats: int) -> None:
    from oacdsl.segmentation import takes
    from oacdsl.segmentation.grouping import group_recording
    from oacdsl.segmentation.readers import read_recording
    from oacdsl.segmentation.readers.c3d import write_c3d

    demo = MOCAP / "kit_bimanual" / DEV[clip]
    library = str(ROOT / "library" / "kit")
    rec, _ = group_recording(read_recording(demo), None)
    with tempfile.TemporaryDirectory() as tmp:
        take = Path(tmp) / "take.c3d"
        write_c3d(takes.translated(takes.rotated(rec, math.pi / 2), (2.0, 0.0, 0.0)), take)
        quiet(["verify", str(demo), str(take), "--library", library])  # imports, caches
        base = [timed(lambda: quiet(["segment", str(demo)])) for _ in range(repeats)]
        runs = [timed(lambda: quiet(["verify", str(demo), str(take), "--library", library]))
                for _ in range(repeats)]
    codes = {r[0] for r in runs}
    wall, cpu = statistics.median(r[1] for r in runs), statistics.median(r[2] for r in runs)
    bwall = statistics.median(b[1] for b in base)
    print(f"oacc verify {clip} ({rec.times_s[-1]:.1f} s at {rec.rate_hz:g} Hz) vs its rotated take:"
          f" {wall:.2f} s wall, {cpu:.2f} s CPU (exit {sorted(codes)}); oacc segment {bwall:.2f} s;"
          f" ratio {wall / bwall:.1f}; target < 2 s")


def reproduce_share(runs: int) -> None:
    from oacdsl.pipeline import load_inputs, reproduce, robot
    from oacdsl.segmentation import AasParams

    stage = robot.verify_stage
    spent: list[float] = []

    def timed_stage(*args, **kwargs):  # type: ignore[no-untyped-def]
        cpu = time.process_time()
        try:
            return stage(*args, **kwargs)
        finally:
            spent.append(time.process_time() - cpu)

    robot.verify_stage = timed_stage  # type: ignore[assignment]
    shares, cpu_shares, totals = [], [], []
    with tempfile.TemporaryDirectory() as tmp:
        for k in range(runs):
            spent.clear()
            inputs = load_inputs(None, None, None, AasParams())
            out = Path(tmp) / f"out{k}"
            outcome, _, cpu = timed(lambda i=inputs, o=out: reproduce(i, name="dough", out=o, db=None,
                                                                      render=False, quiet=True, force=True))
            stages = {s["name"]: s.get("duration_s") or 0.0 for s in outcome.result["stages"]}
            verify = stages.get("verify", 0.0)
            rest = sum(stages.values()) - verify
            shares.append(verify / rest)
            cpu_shares.append(sum(spent) / (cpu - sum(spent)))
            totals.append(rest + verify)
            print(f"  run {k}: verify {verify:.1f} s of {rest + verify:.1f} s wall, {sum(spent):.1f} s of"
                  f" {cpu:.1f} s CPU (faithful: {outcome.result['verdict'].get('faithful')})", flush=True)
    robot.verify_stage = stage  # type: ignore[assignment]
    wall, cpu_share = statistics.median(shares), statistics.median(cpu_shares)
    print(f"oacc reproduce (dough, {runs} runs): median total {statistics.median(totals):.1f} s wall; the"
          f" verify stage adds {wall:.0%} (wall), {cpu_share:.0%} (CPU) to the other stages; target < 15 %")


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--clip", default="Cut", help="the KIT development clip (default: Cut)")
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--runs", type=int, default=2, help="oacc reproduce runs (0: none)")
    args = parser.parse_args()
    if MOCAP is None or args.clip not in DEV:
        print("shared/mocap is absent or the clip is not a development clip", file=sys.stderr)
        return 2
    verify_pair(args.clip, args.repeats)
    if args.runs:
        reproduce_share(args.runs)
    return 0


if __name__ == "__main__":
    sys.exit(main())
