"""Throughput and memory of the AAS against (a) a per-frame Python loop and (b) the brute-force floor.

Data: a synthetic recording (random walks, generated here) of 12 objects with 4
markers and two hands with 5 markers, at 100 Hz, one hour by default: 1,561
cross-instance marker pairs × 360,000 frames = 562 M marker-pair-frames.

- ours: ``oacdsl.segmentation.segment`` with default parameters, per detector: ``paper``
  (Eq. 1/2 as printed) and the default ``adaptive`` (co-motion, and the rule with the
  distance change fitted over a window);
- (a) ``segment_reference`` in the *same* mode: the same equations, one frame and one pair at
  a time in Python (for ``adaptive``, its co-motion pre-scan is the shared vectorised
  ``comotion()``), timed on a slice and extrapolated linearly; agreement of the keyframes
  on the slice is checked;
- (b) the floor: one vectorised numpy pass (in chunks, float32) computing every
  cross-instance marker distance of the same data, and nothing else.

Targets (issues 3, 9), for the default detector: ours ≥ 100× (a); ours no slower than 1.5×
(b); peak memory < 1 GiB; the keyframes agree with (a). The memory is the resident set's peak
while ``segment()`` runs, the recording's own positions included (on Linux the peak is reset
before the call, ``/proc/self/clear_refs``; elsewhere it is the process's peak so far); the
process's peak at the end (the floor's and the generator's working arrays too) is printed
beside it.
Times are CPU seconds of this process (wall seconds in brackets), medians of ``--repeats``
interleaved repeats with the lowest and highest; in each repeat the reference runs on its slice
right before and right after ours, and the ratio printed is the median of the repeats' own ratios
(a: the mean of the two, extrapolated, over ours), with their range and how many repeats met the
target (benchmarks/README.md: how to read it). Run on a quiet machine:

    python benchmarks/segmentation.py            # one hour, both detectors, ~10 minutes
    python benchmarks/segmentation.py --minutes 5 --scenario both

Last measured (2026-11-26 19:11 UTC, branch segperf2; docs/segmentation.md, Performance):
``python benchmarks/segmentation.py --mode adaptive``, one hour, 3 repeats on a busy 2-core
machine (load 7-10): the default detector 6.33 s CPU [5.46-6.85], 112x (a) [106-135] (reference
738 s extrapolated, stretched by the load), 0.20x (b), peak 0.77 GiB RSS while segment() runs (the
process's whole peak 0.93 GiB: the floor's pass), agreement on the slice.
"""

from __future__ import annotations

import argparse
import gc
import resource
import statistics
import sys
import time
import tracemalloc
from collections.abc import Callable
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from segeval.reference import pair_frames, segment_reference  # noqa: E402

from oacdsl.segmentation import AasParams, segment  # noqa: E402
from oacdsl.segmentation.aas import DEFAULT_CHUNK_FRAMES  # noqa: E402
from oacdsl.segmentation.pairs import PairTable  # noqa: E402
from oacdsl.segmentation.params import DEFAULT_MODE  # noqa: E402
from oacdsl.segmentation.recording import Recording  # noqa: E402

OBJECTS, OBJECT_MARKERS, HANDS, HAND_MARKERS = 12, 4, 2, 5
RATE_HZ = 100.0
#: workspace boxes (metres): a kitchen table top, or everything crammed together
SCENARIOS = {
    "table": ((0.0, 0.0, 0.75), (1.2, 0.8, 1.15)),
    "dense": ((0.0, 0.0, 0.75), (0.25, 0.25, 0.9)),
}


Box = tuple[tuple[float, ...], tuple[float, ...]]


def make_recording(minutes: float, box: Box, seed: int = 0) -> Recording:
    """Random-walk marker clusters (hands fast, objects slow) with noise and occlusion gaps."""
    rng = np.random.default_rng(seed)
    n_frames = int(round(minutes * 60 * RATE_HZ))
    sizes = [HAND_MARKERS] * HANDS + [OBJECT_MARKERS] * OBJECTS
    names = [f"hand{i}" for i in range(HANDS)] + [f"object{i:02d}" for i in range(OBJECTS)]
    speeds = [0.4] * HANDS + [0.03] * OBJECTS  # m/s, typical
    lo, hi = np.array(box[0]), np.array(box[1])
    pos = np.empty((n_frames, sum(sizes), 3), dtype=np.float64)
    groups: dict[str, tuple[int, ...]] = {}
    col = 0
    dt = 1.0 / RATE_HZ
    for name, k, speed in zip(names, sizes, speeds, strict=True):
        # velocity: white noise smoothed over 0.5 s; position: its integral, folded into the box
        noise = rng.normal(size=(n_frames + 50, 3))
        c = np.cumsum(noise, axis=0)
        vel = (c[50:] - c[:-50]) / np.sqrt(50.0) * speed
        walk = np.cumsum(vel, axis=0) * dt + rng.random(3) * (hi - lo)
        span = hi - lo
        folded = np.mod(walk, 2 * span)
        centre = lo + span - np.abs(folded - span)
        yaw = np.cumsum(rng.normal(scale=0.01, size=n_frames))
        offsets = rng.normal(scale=0.03, size=(k, 3))
        cos, sin = np.cos(yaw)[:, None], np.sin(yaw)[:, None]
        block = pos[:, col:col + k, :]
        block[..., 0] = centre[:, None, 0] + cos * offsets[:, 0] - sin * offsets[:, 1]
        block[..., 1] = centre[:, None, 1] + sin * offsets[:, 0] + cos * offsets[:, 1]
        block[..., 2] = centre[:, None, 2] + offsets[:, 2]
        block += rng.normal(scale=1e-4, size=block.shape)  # 0.1 mm marker noise
        for m in range(k):  # occlusions: ~20 gaps of up to 0.5 s per marker and hour
            for start in rng.integers(0, n_frames, size=max(1, int(20 * minutes / 60))):
                block[start:start + int(rng.integers(1, 50)), m] = np.nan
        groups[name] = tuple(range(col, col + k))
        col += k
    marker_names = tuple(f"{n}_{j}" for n, k in zip(names, sizes, strict=True) for j in range(k))
    times = np.arange(n_frames) * dt
    return Recording(f"synthetic {minutes:g} min", RATE_HZ, times, marker_names, pos, groups)


def floor_pass(recording: Recording, chunk: int = 4096) -> float:
    """(b) all cross-instance marker distances, vectorised, chunked; returns a checksum."""
    table = PairTable.of(recording)
    first, second = table.first, table.second
    total = 0.0
    for lo in range(0, recording.n_frames, chunk):
        x = recording.positions_m[lo:lo + chunk].astype(np.float32)
        diff = x[:, first] - x[:, second]
        dist = np.sqrt(np.einsum("fpk,fpk->fp", diff, diff))
        total += float(np.nansum(dist[-1]))
    return total


def timed(fn: Callable[[], object]) -> tuple[float, float]:
    """(wall, CPU) seconds of one call. CPU time is what the ratios use: other processes on
    a busy machine stretch wall time but not the process's own CPU time."""
    w0, c0 = time.perf_counter(), time.process_time()
    fn()
    return time.perf_counter() - w0, time.process_time() - c0


def run_scenario(name: str, args: argparse.Namespace) -> bool:
    t0 = time.perf_counter()
    rec = make_recording(args.minutes, SCENARIOS[name], seed=args.seed)
    pf = pair_frames(rec)
    gen = time.perf_counter() - t0
    print(f"\n== scenario {name!r}: {rec.n_frames} frames at {RATE_HZ:g} Hz, "
          f"{pf // rec.n_frames} marker pairs, {pf / 1e6:.0f} M marker-pair-frames "
          f"(data {rec.positions_m.nbytes / 2**20:.0f} MiB, generated in {gen:.1f} s)")
    sl = Recording(rec.source, rec.rate_hz, rec.times_s[:args.slice], rec.marker_names,
                   rec.positions_m[:args.slice], rec.groups)
    modes = args.mode or ["paper", DEFAULT_MODE]
    peaks: dict[str, int] = {}
    counts: dict[str, int] = {}
    rss: dict[str, int] = {}
    for mode in modes:
        reset = reset_rss_peak()
        tracemalloc.start()
        counts[mode] = len(segment(rec, AasParams(mode=mode), chunk_frames=args.chunk).keyframes)
        peaks[mode] = tracemalloc.get_traced_memory()[1]
        tracemalloc.stop()
        rss[mode] = rss_peak_bytes(reset)
    # Interleaved, so that a busy spell hits all alike; per repeat the reference runs right before
    # and right after ours, and each repeat gives its own ratios: the machine's state (other
    # processes on the same core, its clock) changes the CPU seconds of all three alike.
    runs: dict[str, list[tuple[float, float]]] = {"floor": []}
    ratios: dict[str, list[float]] = {}  # per repeat: (a) / ours
    floors: dict[str, list[float]] = {}  # per repeat: ours / (b)
    scale = rec.n_frames / args.slice
    for _ in range(args.repeats):
        gc.collect()
        floor = timed(lambda: floor_pass(rec))
        runs["floor"].append(floor)
        for mode in modes:
            p = AasParams(mode=mode)
            before = timed(lambda p=p: segment_reference(sl, p))
            ours = timed(lambda p=p: segment(rec, p, chunk_frames=args.chunk))
            after = timed(lambda p=p: segment_reference(sl, p))
            ref = ((before[0] + after[0]) / 2 * scale, (before[1] + after[1]) / 2 * scale)
            runs.setdefault(f"ours {mode}", []).append(ours)
            runs.setdefault(f"ref {mode}", []).append(ref)
            ratios.setdefault(mode, []).append(ref[1] / ours[1])
            floors.setdefault(mode, []).append(ours[1] / floor[1])
    wall = {k: statistics.median(w for w, _ in v) for k, v in runs.items()}
    cpu = {k: [c for _, c in v] for k, v in runs.items()}

    def row(label: str, seconds: list[float], wall_s: float) -> str:
        mid = statistics.median(seconds)
        return (f"  {label:<60} {mid:8.2f} s CPU {spread(seconds, '.2f'):>15}"
                f" {pf / mid / 1e6:7.1f} M pair-frames/s  ({wall_s:.2f} s wall)")

    print(f"  CPU seconds: the median of {args.repeats} repeats [lowest–highest]; a ratio: the median of the"
          " repeats' own ratios [lowest–highest]")
    print(row("(b) floor: all distances, one numpy pass", cpu["floor"], wall["floor"]))
    data_mib = rec.positions_m.nbytes / 2**20
    ok_all = True
    for mode in modes:
        p = AasParams(mode=mode)
        agree = segment(sl, p).keyframes == segment_reference(sl, p).keyframes
        default = " (default)" if mode == DEFAULT_MODE else ""
        print(f"  -- mode {mode}{default}: {counts[mode]} keyframes; vectorised and per-frame agree on the"
              f" slice: {agree}; segment() allocates {peaks[mode] / 2**20:.0f} MiB at most (tracemalloc),"
              f" peak RSS while it runs {rss[mode] / 2**20:.0f} MiB incl. the {data_mib:.0f} MiB data")
        print(row(f"ours: segment(mode={mode})", cpu[f"ours {mode}"], wall[f"ours {mode}"]))
        print(row(f"(a) per-frame Python, same equations ({args.slice} frames, extr.)", cpu[f"ref {mode}"],
                  wall[f"ref {mode}"]))
        speedup, vs_floor = statistics.median(ratios[mode]), statistics.median(floors[mode])
        ok_a, ok_b = speedup >= 100, vs_floor <= 1.5
        held = sum(r >= 100 for r in ratios[mode])
        print(f"  ours vs (a): {speedup:7.0f}x faster {spread(ratios[mode], '.0f'):>12}  target >= 100x"
              f"   {'PASS' if ok_a else 'FAIL'} ({held} of {len(ratios[mode])} repeats >= 100x)")
        print(f"  ours / (b):  {vs_floor:7.2f}x the time {spread(floors[mode], '.2f'):>10}  target <= 1.5x"
              f"   {'PASS' if ok_b else 'FAIL'}")
        ok_m = rss[mode] < 2**30
        verdict = "PASS" if ok_m else "FAIL"
        print(f"  peak RSS:    {rss[mode] / 2**30:7.2f} GiB         target < 1 GiB   {verdict}")
        if mode == DEFAULT_MODE:  # the targets are the default detector's
            ok_all = ok_all and ok_a and ok_b and ok_m
        ok_all = ok_all and agree
    whole = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024  # Linux: KiB
    print(f"  the process's peak RSS: {whole / 2**30:.2f} GiB (generating the data, the floor's pass and"
          f" the reference included)")
    return ok_all


def spread(values: list[float], fmt: str) -> str:
    """``[lowest–highest]`` of ``values``."""
    return f"[{min(values):{fmt}}–{max(values):{fmt}}]"


def reset_rss_peak() -> bool:
    """Reset the process's resident-set peak (Linux: ``/proc/self/clear_refs``); False where it
    cannot be, and the peak read after is the process's so far."""
    try:
        with open("/proc/self/clear_refs", "w") as f:
            f.write("5")
    except OSError:
        return False
    return True


def rss_peak_bytes(reset: bool) -> int:
    """The resident set's peak (bytes) since :func:`reset_rss_peak` (``VmHWM``), else since the start."""
    if reset:
        with open("/proc/self/status") as f:
            for line in f:
                if line.startswith("VmHWM:"):
                    return int(line.split()[1]) * 1024
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024  # Linux: KiB


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--minutes", type=float, default=60.0, help="recording length (default 60)")
    parser.add_argument("--scenario", choices=[*SCENARIOS, "both"], default="table")
    parser.add_argument("--repeats", type=int, default=3, help="runs per measurement; medians (default 3)")
    parser.add_argument("--slice", type=int, default=300, help="frames timed for (a) (default 300)")
    parser.add_argument("--chunk", type=int, default=DEFAULT_CHUNK_FRAMES, help="frames per chunk")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--mode", action="append",
                        help=f"detector(s) to measure (default: paper and {DEFAULT_MODE}, the default)")
    args = parser.parse_args(argv)
    names = list(SCENARIOS) if args.scenario == "both" else [args.scenario]
    ok = all([run_scenario(name, args) for name in names])
    return 0 if ok else 1


if __name__ == "__main__":
    raise SystemExit(main())
