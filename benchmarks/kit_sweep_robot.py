"""Variations beyond the standard takes, on the robot: the segmentation's sweep and random
combined takes of the development clips, each reproduced and verified.

    python benchmarks/kit_sweep_robot.py --takes sweep [--clips Stir,dough] [--seeds 0]
    python benchmarks/kit_sweep_robot.py --variation speed_x0.6 --variation rate_30hz --clips Cut
    python benchmarks/kit_sweep_robot.py --random 12 --random-seed 0 [--random-first 4] [--clips …]
    python benchmarks/kit_sweep_robot.py --clips Mix --variation 'mirror=1 speed=1.2 rate_hz=31.5
        scale=0.93 rotation_deg=211.4 gap_at=0.42 jitter_seed=77'

``--takes sweep``: every variation of ``benchmarks/takesweep.py`` (:data:`takesweep.SWEEP`:
speeds ×0.6–×1.6 in time, 30–240 Hz with jitter, scales ×0.85–×1.1, rotations, gaps,
combinations). ``--variation NAME`` (repeatable): one of those, a standard take
(``oacc take --standard NAME``) or a random take's parameter line. ``--random N``: N random
combined takes per clip (``benchmarks/random_takes.py``: mirror, speed ×0.6–×1.8, 10–120 Hz
with 0.2 mm jitter, scale ×0.85–×1.15, rotation, a 0.3 s gap), the i-th of a clip drawn from
(``--random-seed``, the clip's name, i), so each clip gets takes of its own and a run repeats
(``--random-first K``: only the i ≥ K of them).

Each take is written to a file and reproduced as ``benchmarks/kit_takes_robot.py`` does
(``oacc reproduce TAKE --library library/kit --no-render --seed N``; a take with the hands
exchanged is judged with ``--any-hands`` when it is not V). One line per run:
``CLIP VARIATION seed N: V|v|x  [failed checks]`` and, for a random take, its parameter line;
a count at the end. Only the development clips and the dough are offered.
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
import zlib
from collections.abc import Callable
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT), str(ROOT / "tests"), str(ROOT / "benchmarks")]

import random_takes  # noqa: E402
from kit_reproduce import DEV, reproduce_once  # noqa: E402
from kit_takes_robot import rejudged_with_any_hands, source_of  # noqa: E402

from oacdsl.segmentation.recording import Recording  # noqa: E402

Variation = Callable[[Recording], tuple[Recording, dict[str, str]]]


def named_variation(name: str) -> Variation:
    """A sweep variation, a standard take or a random take's parameter line (``ValueError``)."""
    from takesweep import SWEEP

    from oacdsl.segmentation.takes import STANDARD_TAKES

    if name in SWEEP:
        return SWEEP[name]
    if name in STANDARD_TAKES:
        return STANDARD_TAKES[name]
    if "=" in name:
        return random_takes.parse(name).apply
    raise ValueError(f"{name!r}: not a variation of the sweep ({', '.join(SWEEP)}), a standard take"
                     f" ({', '.join(STANDARD_TAKES)}) or a random take's parameters")


def random_for(clip: str, seed: int, count: int) -> list[random_takes.RandomTake]:
    """The ``count`` random takes of ``clip`` under ``seed``."""
    key = zlib.crc32(clip.encode())
    return [random_takes.draw(seed, i, key) for i in range(count)]


def file_name(name: str) -> str:
    """``name`` (a variation, or a random take's parameter line) as a short file name."""
    return "".join(c if c.isalnum() or c in "._-" else "_" for c in name)[:60]


def write_variation(clip: str, name: str, variation: Variation, folder: Path) -> tuple[Path, bool]:
    """(the variation of ``clip`` written into ``folder``, whether it exchanges the hands)."""
    from oacdsl.segmentation.readers import read_recording, write_recording

    recording, _ = source_of(clip)
    rec, hands = variation(read_recording(recording))
    suffix = ".c3d" if recording.suffix == ".c3d" else ".mmm.xml"
    path = Path(write_recording(rec, folder / f"{clip}_{file_name(name)}{suffix}"))
    return path, any(k != v for k, v in hands.items())


def run_variation(clip: str, path: Path, exchanged: bool, seed: int, work: Path,
                  out: Path) -> tuple[str, str]:
    """(V/v/x, why not V) of one reproduction of the written variation at ``path``."""
    _, library = source_of(clip)
    mark, summary, *_shares = reproduce_once(path, seed, work, out, library)
    if exchanged and mark != "V" and (out / "execution.c3d").is_file():
        mark, summary = rejudged_with_any_hands(path, work / ("dough" if clip == "dough" else "kit"), out)
    return mark, summary


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--clips", default=",".join([*DEV, "dough"]),
                        help="development clips and dough, comma-separated (default: all seven)")
    parser.add_argument("--takes", choices=["sweep"], help="every variation of benchmarks/takesweep.py")
    parser.add_argument("--variation", action="append", default=[], metavar="NAME",
                        help="a sweep variation, standard take or random take's line (repeatable)")
    parser.add_argument("--random", type=int, default=0, metavar="N", help="N random takes per clip")
    parser.add_argument("--random-seed", type=int, default=0, metavar="S")
    parser.add_argument("--random-first", type=int, default=0, metavar="K",
                        help="skip the first K random takes of each clip (run K to N-1)")
    parser.add_argument("--seeds", default="0", help="robot seeds (0 = the scene's own places)")
    parser.add_argument("--keep", metavar="DIR", help="keep each run's folder in DIR/CLIP-NAME-SEED")
    args = parser.parse_args(argv)
    from takesweep import SWEEP

    clips = [c.strip() for c in args.clips.split(",") if c.strip()]
    bad = [c for c in clips if c not in DEV and c != "dough"]
    if bad:
        print(f"not a development clip: {', '.join(bad)} (valid: {', '.join(DEV)}, dough)", file=sys.stderr)
        return 2
    names = [*(SWEEP if args.takes == "sweep" else ()), *args.variation]
    try:
        fixed = [(n, named_variation(n)) for n in names]
    except ValueError as err:
        print(f"--variation {err}", file=sys.stderr)
        return 2
    if not fixed and args.random <= 0:
        print("nothing to run: give --takes sweep, --variation NAME or --random N", file=sys.stderr)
        return 2
    seeds = [int(s) for s in args.seeds.split(",")]
    keep = Path(args.keep) if args.keep else None
    tally: dict[str, int] = {"V": 0, "v": 0, "x": 0, "error": 0}
    with tempfile.TemporaryDirectory(prefix="oac-sweep-robot-") as tmp:
        for clip in clips:
            jobs: list[tuple[str, Variation, str]] = [(n, v, "") for n, v in fixed]
            for i, take in enumerate(random_for(clip, args.random_seed, args.random)):
                if i < args.random_first:
                    continue
                jobs.append((f"random{args.random_seed}.{i}", take.apply, take.spec()))
            for k, (name, variation, spec) in enumerate(jobs):
                work = Path(tmp) / f"{clip}-{k}"
                work.mkdir()
                try:
                    path, exchanged = write_variation(clip, name, variation, work)
                except Exception as err:  # a take that cannot be made is reported, not fatal
                    tally["error"] += 1
                    print(f"{clip} {name}: take not made: {err} {spec}", flush=True)
                    continue
                for seed in seeds:
                    out = (keep if keep is not None else work) / f"{clip}-{file_name(name)}-{seed}"
                    started = time.process_time()
                    try:
                        mark, why = run_variation(clip, path, exchanged, seed, work, out)
                    except Exception as err:  # noqa: BLE001 - one failing run must not stop the sweep
                        mark, why = "x", f"error: {type(err).__name__}: {err}"
                    tally[mark] += 1
                    cpu = time.process_time() - started
                    detail = "" if mark == "V" else f"  {why[:300]}"
                    params = f"  [{spec}]" if spec else ""
                    print(f"{clip} {name} seed {seed}: {mark} cpu {cpu:.0f}s{detail}{params}", flush=True)
    total = tally["V"] + tally["v"] + tally["x"]
    print(f"{tally['V']} V, {tally['v']} v, {tally['x']} x of {total} runs"
          + (f"; {tally['error']} takes not made" if tally["error"] else ""))
    return 0


if __name__ == "__main__":
    sys.exit(main())
