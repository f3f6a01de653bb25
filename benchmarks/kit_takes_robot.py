"""Other takes of the development clips on the robot: is each reproduced and verified?

    python benchmarks/kit_takes_robot.py [--clips Stir,Scoop,Cut,dough] [--takes mirrored,scaled]
                                         [--seeds 0,1,2] [--keep DIR] [--markdown]

For each clip (the six development clips of ``benchmarks/kit_reproduce.py`` and ``dough``, the
bundled demonstration with ``library/``) and each take of issue 19 (from
:data:`oacdsl.segmentation.takes.STANDARD_TAKES`: ``mirrored`` (left-handed), ``half_speed``,
``double_speed``, ``scaled`` (15 % larger), ``rotated_translated``), the take is written to a
file (MMM XML for a KIT clip, C3D for the dough) and the whole ``oacc reproduce TAKE --library
library/kit --no-render --seed N`` job runs on it in this process (segment, match, compose,
execute on ARMAR-III, verify; seed 0: the scene's own places). A mirrored take is judged as
``oacc verify TAKE execution.c3d --any-hands`` judges it (the robot's hands may be exchanged
consistently), the others as ``oacc reproduce`` does. Printed per clip and take: V (verified and
faithful), v (verified, not faithful) or x (not verified) per seed, and on stderr the failed
stage or checks of every run that is not V. ``--markdown``: the table for docs/kit.md. Only the
development clips are offered; the evaluation clips are never run here.
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT), str(ROOT / "tests"), str(ROOT / "benchmarks")]

from _mocap import MOCAP  # noqa: E402
from kit_reproduce import DEV, reproduce_once  # noqa: E402

#: The takes issue 19 asks for (names of STANDARD_TAKES).
TAKES = ("mirrored", "half_speed", "double_speed", "scaled", "rotated_translated")


def source_of(clip: str) -> tuple[Path, Path]:
    """(the clip's recording, its library)."""
    if clip == "dough":
        return ROOT / "data" / "dough.c3d", ROOT / "library"
    if MOCAP is None:
        raise SystemExit("shared/mocap is absent: no KIT clip to take")
    return MOCAP / "kit_bimanual" / DEV[clip], ROOT / "library" / "kit"


def write_take(clip: str, take: str, folder: Path) -> Path:
    """The take of ``clip`` written into ``folder`` (C3D for the dough, MMM XML otherwise)."""
    from oacdsl.segmentation.readers import read_recording, write_recording
    from oacdsl.segmentation.takes import STANDARD_TAKES

    recording, _ = source_of(clip)
    rec, _hands = STANDARD_TAKES[take](read_recording(recording))
    suffix = ".c3d" if recording.suffix == ".c3d" else ".mmm.xml"
    return Path(write_recording(rec, folder / f"{clip}_{take}{suffix}"))


def any_hands_verdict(take: Path, library: Path, run: Path) -> tuple[str, str]:
    """(V/v/x, failed checks) of the kept run in ``run`` judged against ``take`` with the hands
    free to be exchanged (``oacc verify TAKE run/execution.c3d --library LIB --any-hands``)."""
    from oacdsl.cli.verify_cmd import load_execution
    from oacdsl.pipeline import load_inputs
    from oacdsl.pipeline.robot import EXECUTION_FILE
    from oacdsl.segmentation import AasParams
    from oacdsl.verify_contacts import contacts_path, read_contacts
    from oacdsl.verify_execution import verify_execution

    params = AasParams()
    inputs = load_inputs(take, library, None, params)
    execution = load_execution(str(run / EXECUTION_FILE), inputs, None, None, False)
    sidecar = contacts_path(run / EXECUTION_FILE)
    contacts = read_contacts(sidecar) if sidecar.is_file() else None
    outcome = verify_execution(inputs.motion_capture(), execution, scene=inputs.scene,
                               library=inputs.library, params=params, contacts=contacts, any_hands=True)
    mark = "V" if outcome.faithful else "v" if outcome.verified else "x"
    return mark, ", ".join(c.name for c in outcome.failed())


def untracked_failures(run: Path) -> list[str]:
    """The verdict's failed ``untracked.NAME`` checks of the kept run in ``run`` (a liquid whose
    last judging step failed: the recording cannot show it, so re-judging it with either hand
    does not clear it)."""
    import json

    result = run / "result.json"
    if not result.is_file():
        return []
    failed = json.loads(result.read_text()).get("verdict", {}).get("failed_checks", [])
    return [c for c in failed if c.startswith("untracked.")]


def rejudged_with_any_hands(take: Path, library: Path, run: Path) -> tuple[str, str]:
    """(V/v/x, why not V) of the kept run judged with the hands free to be exchanged, an
    untracked liquid's failure kept."""
    mark, failed = any_hands_verdict(take, library, run)
    spilt = untracked_failures(run)
    if spilt:
        mark, failed = "x", ", ".join([*([failed] if failed else []), *spilt])
    return mark, f"{failed} | any hands" if failed else "any hands"


def run_one(clip: str, take: str, path: Path, seed: int, work: Path, out: Path) -> tuple[str, str]:
    """(V/v/x, why not V) of one reproduction of the take at ``path``."""
    _, library = source_of(clip)
    mark, summary, *_shares = reproduce_once(path, seed, work, out, library)
    if take == "mirrored" and mark != "V" and (out / "execution.c3d").is_file():
        mark, summary = rejudged_with_any_hands(path, work / ("dough" if clip == "dough" else "kit"), out)
    return mark, summary


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--clips", default=",".join([*DEV, "dough"]),
                        help="development clips and dough, comma-separated (default: all seven)")
    parser.add_argument("--takes", default=",".join(TAKES), help=f"takes (default: {','.join(TAKES)})")
    parser.add_argument("--seeds", default="0,1,2", help="0 = the scene's own places")
    parser.add_argument("--keep", metavar="DIR", help="keep each run's folder in DIR/CLIP-TAKE-SEED")
    parser.add_argument("--markdown", action="store_true", help="also print a Markdown table")
    args = parser.parse_args()
    clips = [c.strip() for c in args.clips.split(",") if c.strip()]
    takes = [t.strip() for t in args.takes.split(",") if t.strip()]
    bad = [c for c in clips if c not in DEV and c != "dough"] + [t for t in takes if t not in TAKES]
    if bad:
        print(f"not a development clip or take: {', '.join(bad)} (clips: {', '.join(DEV)}, dough;"
              f" takes: {', '.join(TAKES)})", file=sys.stderr)
        return 2
    seeds = [int(s) for s in args.seeds.split(",")]
    keep = Path(args.keep) if args.keep else None
    rows: dict[tuple[str, str], list[str]] = {}
    print(f"{'clip':6} {'take':18} {'wall s':>6}  verified faithful"
          "  per seed (V faithful, v verified, x not)", flush=True)
    with tempfile.TemporaryDirectory(prefix="oac-takes-robot-") as tmp:
        for clip in clips:
            for take in takes:
                work = Path(tmp) / f"{clip}-{take}"
                work.mkdir()
                path = write_take(clip, take, work)
                marks, started = [], time.perf_counter()
                for seed in seeds:
                    out = (keep if keep is not None else work) / f"{clip}-{take}-{seed}"
                    mark, why = run_one(clip, take, path, seed, work, out)
                    marks.append(f"{seed}:{mark}")
                    if mark != "V":
                        print(f"  {clip} {take} seed {seed}: {why[:400]}", file=sys.stderr, flush=True)
                wall = (time.perf_counter() - started) / len(seeds)
                n_v = sum(not m.endswith("x") for m in marks)
                n_f = sum(m.endswith("V") for m in marks)
                rows[clip, take] = marks
                print(f"{clip:6} {take:18} {wall:6.1f}  {n_v}/{len(seeds)} {n_f}/{len(seeds)}  "
                      + " ".join(marks), flush=True)
    if args.markdown:
        print("\n| clip | " + " | ".join(takes) + " |")
        print("| --- |" + " --- |" * len(takes))
        for clip in clips:
            cells = [" ".join(m.split(":")[1] for m in rows[clip, t]) for t in takes]
            print(f"| {clip} | " + " | ".join(cells) + " |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
