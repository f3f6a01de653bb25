"""Other takes beyond the standard seven: do they compose to the original's OAC steps?

``benchmarks/takes.py`` measures the seven takes of issue 20. The claim is wider: the same
keyframes under ×0.5–×2 time, 10–240 Hz, ±15 % scale, gaps up to 0.5 s, mirrored hands and any
rotation about the vertical. This script composes variations inside that range that no constant
was set on (:data:`SWEEP`: other speeds, frame rates with jitter and other seeds, smaller and
larger scenes, other angles, gaps in other markers and at other times, and combinations) for the
six development clips and the dough, exactly as ``benchmarks/takes.py`` does (written to a file,
read back, segmented, matched, composed, compared with the original's steps, the hands exchanged
for the mirror), and prints one row per clip and a count.

    python benchmarks/takesweep.py                          # every clip, every variation
    python benchmarks/takesweep.py --clip Stir --take rate_240hz --take speed_x0.6
    python benchmarks/takesweep.py --markdown               # the table for docs/segmentation.md
"""

from __future__ import annotations

import argparse
import sys
import tempfile
from collections.abc import Callable
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks"))

import takes as bench  # noqa: E402

from oacdsl.segmentation.readers import read_recording, write_recording  # noqa: E402
from oacdsl.segmentation.recording import Recording  # noqa: E402
from oacdsl.segmentation.takes import (  # noqa: E402
    IDENTITY,
    gap_marker,
    mirrored,
    resampled,
    rotated,
    scaled,
    stretched,
    translated,
    with_gap,
)

Variation = Callable[[Recording], tuple[Recording, dict[str, str]]]


def _same(fn: Callable[[Recording], Recording]) -> Variation:
    return lambda r: (fn(r), dict(IDENTITY))


def _gap_at(fraction: float, which: int = 0) -> Variation:
    """A 0.5 s gap in the moving object's ``which``-th marker (of its group), starting at
    ``fraction`` of the recording's duration."""

    def take(rec: Recording) -> tuple[Recording, dict[str, str]]:
        marker, _ = gap_marker(rec, 0.5)
        group = next(idx for idx in rec.groups.values() if rec.marker_names.index(marker) in idx)
        label = rec.marker_names[group[min(which, len(group) - 1)]]
        start = float(rec.times_s[0] + fraction * (rec.times_s[-1] - rec.times_s[0]))
        return with_gap(rec, label, start, 0.5), dict(IDENTITY)

    return take


def _combined(rec: Recording) -> tuple[Recording, dict[str, str]]:
    take, hands = mirrored(rec)
    return translated(rotated(stretched(take, 1.5), np.radians(135)), (-1.0, 0.5, 0.0)), hands


def _combined_fast(rec: Recording) -> tuple[Recording, dict[str, str]]:
    take = resampled(scaled(stretched(rec, 0.7), 0.9), 60.0, jitter_m=0.0002, seed=3)
    return rotated(take, np.radians(-60)), dict(IDENTITY)


#: Variations inside issue 20's range, none of them a standard take.
SWEEP: dict[str, Variation] = {
    "speed_x0.6": _same(lambda r: stretched(r, 0.6)),
    "speed_x0.8": _same(lambda r: stretched(r, 0.8)),
    "speed_x1.25": _same(lambda r: stretched(r, 1.25)),
    "speed_x1.6": _same(lambda r: stretched(r, 1.6)),
    "rate_30hz": _same(lambda r: resampled(r, 30.0, jitter_m=0.0002, seed=1)),
    "rate_60hz": _same(lambda r: resampled(r, 60.0, jitter_m=0.0002, seed=2)),
    "rate_120hz": _same(lambda r: resampled(r, 120.0, jitter_m=0.0002, seed=3)),
    "rate_240hz": _same(lambda r: resampled(r, 240.0, jitter_m=0.0002, seed=4)),
    "rate_100hz_seed1": _same(lambda r: resampled(r, 100.0, jitter_m=0.0002, seed=1)),
    "scale_0.85": _same(lambda r: scaled(r, 0.85)),
    "scale_0.9": _same(lambda r: scaled(r, 0.9)),
    "scale_1.1": _same(lambda r: scaled(r, 1.1)),
    "rotate_30": _same(lambda r: rotated(r, np.radians(30))),
    "rotate_180": _same(lambda r: rotated(r, np.pi)),
    "gap_early": _gap_at(0.2),
    "gap_late_marker2": _gap_at(0.6, which=1),
    "mirror_x1.5_rot135": _combined,
    "x0.7_scale0.9_60hz_rot-60": _combined_fast,
}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--data", help="the kit_bimanual folder (default: ../shared/mocap/kit_bimanual)")
    parser.add_argument("--clip", action="append", choices=[*bench.DEVELOPMENT, "dough"],
                        help="a clip (repeatable; default: the six development clips and dough)")
    parser.add_argument("--take", action="append", choices=list(SWEEP),
                        help="a variation (repeatable; default: all)")
    parser.add_argument("--markdown", action="store_true", help="print a Markdown table")
    args = parser.parse_args(argv)
    wanted = args.clip or [*bench.DEVELOPMENT, "dough"]
    names = args.take or list(SWEEP)
    rows: list[tuple[str, list[bench.Outcome]]] = []
    with tempfile.TemporaryDirectory(prefix="oac-sweep-") as tmp:
        for clip, path, library in bench.clips(bench.data_folder(args.data), wanted):
            folder = Path(tmp) / clip
            folder.mkdir()
            suffix = ".c3d" if path.suffix == ".c3d" else ".mmm.xml"
            rec = read_recording(path)
            base = bench.compose_file(path, library)
            cells = []
            for name in names:
                if base.steps is None:
                    cells.append(bench.Outcome("-", "original fails", None, 0.0))
                    continue
                take, hands = SWEEP[name](rec)
                out = bench.compose_file(write_recording(take, folder / f"{name}{suffix}"), library)
                if out.steps is not None:
                    out.status, out.detail = bench.compare(base, out, hands)
                cells.append(out)
                print(f"{clip:6} {name:26} {out.status:8} kf {out.keyframes} (original {base.keyframes})"
                      f" {out.seconds:5.1f}s {out.detail}", file=sys.stderr, flush=True)
            rows.append((clip, cells))
    ok = sum(c.status in ("same", "same*") for _, cells in rows for c in cells)
    total = sum(len(cells) for _, cells in rows)
    if args.markdown:
        print("| variation | " + " | ".join(clip for clip, _ in rows) + " |")
        print("|---" * (len(rows) + 1) + "|")
        for i, name in enumerate(names):
            print(f"| {name} | " + " | ".join(cells[i].status for _, cells in rows) + " |")
    else:
        for clip, cells in rows:
            bad = [f"{n}: {c.status} {c.detail}" for n, c in zip(names, cells, strict=True)
                   if c.status not in ("same", "same*")]
            listed = "".join(f"\n  {b}" for b in bad)
            print(f"{clip}: {len(cells) - len(bad)} of {len(cells)} the same{listed}")
    print(f"{ok} of {total} variations compose to the original's steps (same or same*)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
