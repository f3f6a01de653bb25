"""Rate and jitter robustness of the segmentation: the dough demonstration over a grid (issue 9).

For every seed × frame rate × white jitter, ``oacc synth dough`` (in process:
``dough_demonstration``) makes a demonstration; it is segmented with the given
parameters (default: the project's defaults), matched and composed against the
standard library. A cell passes when the composition is exactly the paper's new OAC
(pre, effect and the eight steps). Printed per detector mode: passes per cell, the
smallest jitter at which some seed fails (per rate), and the keyframe timing error against
the ground truth (median |Δt| of the keyframes, where the world states are the truth's).

    python benchmarks/robustness.py                          # default detector, full grid, ~5 min
    python benchmarks/robustness.py --mode paper --mode adaptive --seeds 4
    python benchmarks/robustness.py --windows 0.02,0.05,0.1,0.2,0.3 --rates 50,240 \\
        --jitters 0.5,1,2 --seeds 4                          # the sweep that chose the window
    python benchmarks/robustness.py --flight 1 --seeds 8     # liquids a second in the air
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from oacdsl.compiler import load_library  # noqa: E402
from oacdsl.errors import OacError  # noqa: E402
from oacdsl.matching.demonstration import compose_demonstration, find_scene, match_segmentation  # noqa: E402
from oacdsl.matching.emit import library_files  # noqa: E402
from oacdsl.matching.matcher import Matcher  # noqa: E402
from oacdsl.segmentation import AasParams, segment  # noqa: E402
from oacdsl.segmentation.synth import FLIGHT_S, dough_demonstration  # noqa: E402
from oacdsl.segmentation.synth.realism import NoiseModel  # noqa: E402
from tests.kitchen import DOUGH_STEPS as STEPS  # noqa: E402
from tests.kitchen import PAPER_EFFECT, PAPER_PRE  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]


def one(library, seed: int, rate: float, jitter_mm: float, params: AasParams,
        flight_s: float) -> tuple[bool, list[float]]:
    """(composes the paper's OAC, |Δt| of each keyframe against the truth when the states agree)."""
    noise = NoiseModel(white_m=jitter_mm * 1e-3)  # mm → m
    demo = dough_demonstration(seed, rate_hz=rate, noise=noise, flight_s=flight_s)
    seg = segment(demo.recording, params)
    scene = find_scene(library, seg.instances)
    matches = match_segmentation(seg, Matcher.from_library(library, scene))
    stable = [m.sub_action for m in matches]
    truth_kfs = demo.truth["keyframes"]
    errors: list[float] = []
    if len(stable) + 1 == len(truth_kfs):
        ours = [stable[0].start] + [s.end for s in stable]
        if all(k.state.sorted_relations() == sorted(map(tuple, t["relations"]))
               for k, t in zip(ours, truth_kfs, strict=True)):
            errors = [abs(k.time_s - t["time_s"]) for k, t in zip(ours[1:], truth_kfs[1:], strict=True)]
    try:
        doc = compose_demonstration("dough", matches, library, scene).composition.to_json(None)
    except OacError:
        return False, errors
    steps = [s["oac"] for s in doc["steps"]]
    return doc["pre"] == PAPER_PRE and doc["effect"] == PAPER_EFFECT and steps == STEPS, errors


def grid(library, params: AasParams, rates: list[float], jitters: list[float], seeds: int,
         flight_s: float) -> None:
    print(f"\n== mode {params.mode}, change window {params.change_window_s:g} s, hold {params.hold_s:g} s,"
          f" flight {flight_s:g} s, {seeds} seeds per cell (seed = 1000·k + cell)")
    print("  jitter [mm] " + "".join(f"{r:>9g} Hz" for r in rates))
    first_fail: dict[float, float | None] = {r: None for r in rates}
    all_errors: dict[float, list[float]] = {r: [] for r in rates}
    for j in jitters:
        row = []
        for r in rates:
            passed = 0
            for k in range(seeds):
                ok, errors = one(library, 1000 * k + int(r) + int(j * 1000), r, j, params, flight_s)
                passed += ok
                if j <= 0.5:
                    all_errors[r] += errors
            row.append(f"{passed:>6d}/{seeds:<5d}")
            if passed < seeds and first_fail[r] is None:
                first_fail[r] = j
        print(f"  {j:>10g}  " + "".join(row), flush=True)
    print("  first failing jitter: " + ", ".join(
        f"{r:g} Hz: {'none up to ' + format(max(jitters), 'g') if f is None else format(f, 'g')} mm"
        for r, f in first_fail.items()))
    print("  keyframe |Δt| vs truth, median over jitters ≤ 0.5 mm: " + ", ".join(
        f"{r:g} Hz: {1000 * statistics.median(e):.0f} ms" if e else f"{r:g} Hz: n/a"
        for r, e in all_errors.items()))


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--mode", action="append", help="detector mode(s) (default: the default mode)")
    parser.add_argument("--rates", default="50,100,200,240", help="frame rates, Hz (default 50,100,200,240)")
    parser.add_argument("--jitters", default="0,0.1,0.2,0.3,0.4,0.5,0.75,1,1.5,2,3",
                        help="white jitter, mm (default 0 … 3)")
    parser.add_argument("--seeds", type=int, default=8, help="seeds per cell (default 8)")
    parser.add_argument("--windows", default=None, help="change windows to sweep, s (default: the default)")
    parser.add_argument("--flight", type=float, default=FLIGHT_S, help="liquid flight, s (default 0.16)")
    args = parser.parse_args(argv)
    library = load_library(library_files(ROOT / "library"))
    rates = [float(x) for x in args.rates.split(",")]
    jitters = [float(x) for x in args.jitters.split(",")]
    windows = [float(x) for x in args.windows.split(",")] if args.windows else [AasParams().change_window_s]
    t0 = time.perf_counter()
    for mode in args.mode or [AasParams().mode]:
        for w in windows:
            grid(library, AasParams(mode=mode, change_window_s=w), rates, jitters, args.seeds, args.flight)
    print(f"\n({time.perf_counter() - t0:.0f} s)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
