"""CPU time of ``segment()`` in two checkouts of the repository, interleaved in one process.

For a change that should make the segmentation faster and change nothing else: both versions
of the package are imported (each with its own modules, swapped in before each call), the same
``benchmarks/segmentation.py`` recording is segmented by each in turn, the keyframes are compared,
and the CPU seconds (``time.process_time``) are printed: medians over the repeats, the lowest, and
each repeat's own ratio (the two calls of a repeat run back to back, so a busy spell of the
machine hits both alike; which runs first alternates). In one process the two versions share the
allocator's state, which can favour either by some per cent: ``benchmarks/segmentation.py`` run in
separate processes, alternating, is the other check.

    python benchmarks/segment_ab.py --against ../main                # this checkout vs ../main
    python benchmarks/segment_ab.py --against ../main --minutes 10 --repeats 9 --scenario dense
"""

from __future__ import annotations

import argparse
import importlib
import statistics
import sys
import time
from pathlib import Path
from types import ModuleType

ROOT = Path(__file__).resolve().parents[1]


def load(root: Path) -> dict[str, ModuleType]:
    """The modules of the ``oacdsl`` package under ``root``, imported afresh."""
    for name in [k for k in sys.modules if k == "oacdsl" or k.startswith("oacdsl.")]:
        del sys.modules[name]
    sys.path.insert(0, str(root))
    try:
        package = importlib.import_module("oacdsl.segmentation")
        for name in ("adaptive", "robust", "paper"):  # the detectors, imported when first used
            importlib.import_module(f"oacdsl.segmentation.{name}")
    finally:
        sys.path.remove(str(root))
    if not str(package.__file__).startswith(str(root.resolve())):
        sys.exit(f"{root}: imported {package.__file__} instead")
    return {k: m for k, m in sys.modules.items() if k == "oacdsl" or k.startswith("oacdsl.")}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--against", required=True, help="the other checkout (its root folder)")
    parser.add_argument("--minutes", type=float, default=10.0)
    parser.add_argument("--scenario", default="table", choices=("table", "dense"))
    parser.add_argument("--mode", default="adaptive")
    parser.add_argument("--repeats", type=int, default=7)
    args = parser.parse_args(argv)
    versions = {"this": ROOT, "other": Path(args.against).resolve()}
    modules = {name: load(root) for name, root in versions.items()}
    sys.path.insert(0, str(ROOT / "benchmarks"))
    from segmentation import SCENARIOS, make_recording

    rec = make_recording(args.minutes, SCENARIOS[args.scenario], seed=0)

    def run(name: str) -> tuple[float, list[dict]]:  # type: ignore[type-arg]
        sys.modules.update(modules[name])
        seg = modules[name]["oacdsl.segmentation"]
        start = time.process_time()
        result = seg.segment(rec, seg.AasParams(mode=args.mode))
        return time.process_time() - start, result.to_json()["keyframes"]

    first = {name: run(name)[1] for name in versions}
    same = first["this"] == first["other"]
    print(f"{rec.n_frames} frames ({args.scenario}), mode {args.mode}: {len(first['this'])} keyframes,"
          f" the same in both: {same}")
    cpu: dict[str, list[float]] = {name: [] for name in versions}
    for k in range(args.repeats):  # ABBA: which version runs first alternates
        for name in (list(versions) if k % 2 == 0 else list(versions)[::-1]):
            cpu[name].append(run(name)[0])
    for name, root in versions.items():
        v = cpu[name]
        print(f"  {name:5} {root}: median {statistics.median(v):.3f} s CPU, lowest {min(v):.3f},"
              f" highest {max(v):.3f}")
    ratios = [a / b for a, b in zip(cpu["this"], cpu["other"], strict=True)]
    print(f"  this / other: median of the repeats' ratios {statistics.median(ratios):.3f}"
          f" [{min(ratios):.3f}–{max(ratios):.3f}],"
          f" lowest over lowest {min(cpu['this']) / min(cpu['other']):.3f}")
    return 0 if same else 1


if __name__ == "__main__":
    sys.exit(main())
