"""The hand-written examples of actions no KIT development clip has (``library/examples/``):
verdict per seed and time per run.

    python benchmarks/kit_examples.py [--seeds 0,1,2,3,4,5] [--examples peel_cucumber,transfer_to_bowl]

Each example OAC (``close_and_open``: twist; ``open_bottle``: twist from a lid that starts on
its bottle, with the synthetic first frame of ``tests/test_kit_general.py``;
``peel_cucumber``, ``transfer_to_bowl``: stroke; ``roll_the_pin``: roll; and those written from
the docs alone: ``stack_block``, ``hand_over``, ``cover_pot``) runs on ARMAR-III in
this process as ``oacc run NAME --library library/kit --library library/examples --seed N``
does (no pictures, no run store). Printed per example: the verdict per seed (0: the scene's
own places), the median wall seconds over the seeds, and the ratio against the baseline
measured in the same process: laying out and building the scene alone (``prepare``), median
over the same seeds. Accuracy more than speed: no target; the test runs one seed of each.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT), str(ROOT / "tests")]

from test_kit_general import FIRST_FRAME, library  # noqa: E402

from oacdsl.errors import OacError  # noqa: E402
from oacdsl.runtime.executor import prepare, run_prepared  # noqa: E402

EXAMPLES = ("close_and_open", "open_bottle", "peel_cucumber", "transfer_to_bowl", "roll_the_pin",
            "stack_block", "hand_over", "cover_pot")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--seeds", default="0,1,2,3,4,5", help="seeds (0: the scene's places)")
    parser.add_argument("--examples", default=",".join(EXAMPLES), help="which (default: all eight)")
    args = parser.parse_args()
    seeds = [int(s) for s in args.seeds.split(",")]
    names = [n.strip() for n in args.examples.split(",") if n.strip()]
    unknown = [n for n in names if n not in EXAMPLES]
    if unknown:
        parser.error(f"not an example: {', '.join(unknown)} (valid: {', '.join(EXAMPLES)})")
    for name in names:
        kw = {"layout": "demonstrated", "demonstrated": FIRST_FRAME} if name == "open_bottle" else {}
        verdicts, walls, builds = [], [], []
        for seed in seeds:
            t0 = time.perf_counter()
            try:
                run = prepare(library(), name, seed=seed or None, **kw)
                builds.append(time.perf_counter() - t0)
                result = run_prepared(run)
                ok, why = result.success, result.error or ""
            except OacError as error:
                ok, why = False, str(error)
            walls.append(time.perf_counter() - t0)
            verdicts.append(f"{seed}: ok" if ok else f"{seed}: FAILED ({why[:90]})")
        base = statistics.median(builds) if builds else float("nan")
        wall = statistics.median(walls)
        print(f"{name}: median wall {wall:.1f} s, scene build {base:.2f} s, ratio {wall / base:.0f}")
        for v in verdicts:
            print(f"    seed {v}")


if __name__ == "__main__":
    main()
