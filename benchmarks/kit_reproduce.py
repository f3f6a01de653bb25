"""`oacc reproduce` on the KIT Bimanual development clips: time per clip and verified seeds.

    python benchmarks/kit_reproduce.py [--clips dough,Pour,Stir] [--seeds 0,1,2,3,4,5] [--repeats N]
                                       [--keep DIR] [--library DIR] [--take NAME]

For each clip and seed (0: the scene's own places, the command's default) the whole job runs
in this process as `oacc reproduce CLIP.mmm.xml --library library/kit --no-render` does
(segment, match, compose, execute on ARMAR-III, verify, report; no run store; the library
copied to a temporary folder). Printed per clip: the median wall and CPU seconds over all its
runs, the verdict per seed (V: verified and faithful, v: verified, not faithful, x: not
verified, with the failed checks on stderr; `oacc verify`, docs/verify.md), the verify stage's
share of the run (what verifying adds: its wall seconds over the other stages' wall seconds;
`vcpu`: the same with this process's CPU seconds in each stage, `result.json`'s `cpu_s`: on a
shared machine the wall clock measures the load),
and the ratio against the baseline measured in the same process:
the segmentation alone (reading the recording and `oacc segment`'s AAS), median of
``--repeats`` runs. Target: < 30 s per clip (median wall, two cores).
Only the development clips are offered (and `dough`, the bundled demonstration); the evaluation
clips are never run here. `--keep DIR` keeps each run's folder (DIR/CLIP-SEED: report,
execution.c3d and its contacts) for `oacc verify` later. `--library DIR`: another library of
the KIT clips (`tests/data/kit_follow`: named skills replaced by the generic `follow`).
`--take NAME`: reproduce another take of each clip instead, one of the standard takes
(`oacc take --standard NAME`, e.g. `mirrored`: left-handed), written as MMM XML first.
`dough-handover`, `dough-overlap`: the dough task's other stories (`oacc synth dough --story
NAME`, synthesis seed 2013) reproduced with the bundled library, as `dough` is.
"""

from __future__ import annotations

import argparse
import shutil
import statistics
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT), str(ROOT / "tests")]

from _mocap import MOCAP  # noqa: E402

#: The development clips (issue 11); the evaluation clips are deliberately absent.
DEV = {
    "Pour": "Pour_files_motions_2967_Pour1_cs_ms_0_20l_04.mmm.xml",
    "Stir": "Stir_files_motions_2941_Stir1_bc_s_right_03.mmm.xml",
    "Mix": "Mix_files_motions_3121_Mix1_salad_gb_parallel_08.mmm.xml",
    "Wipe": "Wipe_files_motions_3091_Wipe1_pl_sp_front_angle_03.mmm.xml",
    "Scoop": "Scoop_files_motions_2989_Scoop1_mbg_l_CS_225_30o_04.mmm.xml",
    "Cut": "Cut_files_motions_3021_Cut1_c_0_05cm_03.mmm.xml",
}


def timed(fn):  # type: ignore[no-untyped-def]
    """(result, wall s, CPU s) of ``fn()``."""
    wall, cpu = time.perf_counter(), time.process_time()
    out = fn()
    return out, time.perf_counter() - wall, time.process_time() - cpu


def segmentation_only(recording: Path) -> None:
    from oacdsl.segmentation import AasParams, segment
    from oacdsl.segmentation.grouping import group_recording
    from oacdsl.segmentation.readers import read_recording

    rec, _ = group_recording(read_recording(recording), None)
    segment(rec, AasParams())


#: The bundled task's other stories (`oacc synth dough --story NAME`), offered as clips.
STORIES = ("dough-handover", "dough-overlap")


def write_story(clip: str, folder: Path) -> Path:
    """The dough story of ``clip`` (``dough-NAME``), synthesised as `oacc synth dough --story
    NAME -o FOLDER/NAME.c3d` writes it."""
    from oacdsl.cli import main as oacc

    story = clip.removeprefix("dough-")
    path = folder / f"{story}.c3d"
    if oacc(["synth", "dough", "-o", str(path), "--story", story]) != 0:
        raise SystemExit(f"oacc synth dough --story {story} failed")
    return path


def write_take(recording: Path, name: str, folder: Path) -> Path:
    """The standard take ``name`` of ``recording``, written as MMM XML into ``folder``
    (as ``oacc take --standard NAME`` writes it)."""
    from oacdsl.segmentation.readers import read_recording, write_recording
    from oacdsl.segmentation.takes import STANDARD_TAKES

    take, _ = STANDARD_TAKES[name](read_recording(recording))
    return write_recording(take, folder / recording.name.replace(".mmm.xml", f"_{name}.mmm.xml"), "mmm")


def reproduce_once(recording: Path | None, seed: int, work: Path, out: Path | None = None,
                   kit: Path = ROOT / "library" / "kit") -> tuple[str, str, float, float]:
    """(V/v/x, verdict and failed checks, the verify stage's wall share, its CPU share) of one
    `oacc reproduce` run: the stage's seconds over the other stages' seconds (what verifying adds),
    wall clock and this process's CPU time over the same stages (``result.json``'s ``stages``)."""
    from oacdsl.pipeline import load_inputs, reproduce
    from oacdsl.pipeline.inputs import default_name
    from oacdsl.segmentation import AasParams

    story = recording is not None and recording.suffix == ".c3d"  # a dough story
    which = "kit" if recording is not None and not story else "dough"
    library = work / which
    if not library.exists():
        source = kit if which == "kit" else ROOT / "library"
        shutil.copytree(source, library, ignore=shutil.ignore_patterns("learned", "drafts"))
    inputs = load_inputs(recording, library, None, AasParams())
    name = default_name(str(recording)) if recording is not None else "dough"
    outcome = reproduce(inputs, name=name, out=out or work / f"out{seed}", db=None,
                        seed=seed or None, render=False, quiet=True, force=True)
    verdict = outcome.result["verdict"]
    mark = "x" if not verdict.get("success") else "V" if verdict.get("faithful", True) else "v"
    failed = ", ".join(verdict.get("failed_checks", []))
    shares = []
    for key in ("duration_s", "cpu_s"):
        stages = {s["name"]: s.get(key) or 0.0 for s in outcome.result.get("stages", [])}
        rest = sum(stages.values()) - stages.get("verify", 0.0)
        shares.append(stages.get("verify", 0.0) / max(rest, 1e-9))
    return mark, f"{failed} | {verdict.get('summary', '')}", shares[0], shares[1]


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument(
        "--clips", default=",".join(DEV), help="development clips, comma-separated (default: all six)"
    )
    parser.add_argument("--seeds", default="0,1,2,3,4,5", help="0 = the scene's own places")
    parser.add_argument("--repeats", type=int, default=3, help="runs of the baseline")
    parser.add_argument("--keep", metavar="DIR", help="keep each run's folder in DIR/CLIP-SEED")
    parser.add_argument("--library", type=Path, default=ROOT / "library" / "kit", help="the KIT library")
    parser.add_argument("--take", metavar="NAME",
                        help="another take of each clip (oacc take --standard NAME)")
    args = parser.parse_args()
    from oacdsl.segmentation.takes import STANDARD_TAKES

    if args.take is not None and args.take not in STANDARD_TAKES:
        print(f"--take {args.take}: not a standard take (valid: {', '.join(STANDARD_TAKES)})",
              file=sys.stderr)
        return 2
    if MOCAP is None:
        print("shared/mocap is absent: nothing to measure", file=sys.stderr)
        return 2
    clips = [c.strip() for c in args.clips.split(",") if c.strip()]
    unknown = [c for c in clips if c not in DEV and c != "dough" and c not in STORIES]
    if unknown:
        valid = ", ".join([*DEV, "dough", *STORIES])
        print(f"not a development clip: {', '.join(unknown)} (valid: {valid})", file=sys.stderr)
        return 2
    seeds = [int(s) for s in args.seeds.split(",")]
    keep = Path(args.keep) if args.keep else None
    print(f"{'clip':6} {'wall s':>7} {'cpu s':>6} {'seg s':>6} {'ratio':>6} {'verify':>6} {'vcpu':>5}"
          "  verified faithful  per seed (V faithful, v verified, x not)", flush=True)
    for clip in clips:
        recording = MOCAP / "kit_bimanual" / DEV[clip] if clip in DEV else None
        base = statistics.median(
            timed(lambda r=recording: segmentation_only(r))[1] for _ in range(args.repeats)
        ) if recording is not None else float("nan")
        walls, cpus, verdicts, shares, cpu_shares = [], [], [], [], []
        with tempfile.TemporaryDirectory() as tmp:
            if clip in STORIES:
                recording = write_story(clip, Path(tmp))
            if recording is not None and args.take is not None:
                recording = write_take(recording, args.take, Path(tmp))
            for seed in seeds:
                out = keep / f"{clip}-{seed}" if keep is not None else None
                (mark, summary, share, cpu_share), wall, cpu = timed(
                    lambda s=seed, r=recording, o=out: reproduce_once(r, s, Path(tmp), o, args.library))
                cpu_shares.append(cpu_share)
                walls.append(wall)
                cpus.append(cpu)
                shares.append(share)
                verdicts.append(f"{seed}:{mark}")
                if mark != "V":
                    print(f"  {clip} seed {seed}: {summary[:400]}", file=sys.stderr, flush=True)
        wall, cpu = statistics.median(walls), statistics.median(cpus)
        n_v = sum(not v.endswith("x") for v in verdicts)
        n_f = sum(v.endswith("V") for v in verdicts)
        share, cpu_share = statistics.median(shares), statistics.median(cpu_shares)
        print(f"{clip:6} {wall:7.1f} {cpu:6.1f} {base:6.2f} {wall / base:6.1f} {share:6.0%} {cpu_share:5.0%}"
              f"  {n_v}/{len(seeds)} {n_f}/{len(seeds)}  " + " ".join(verdicts), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
