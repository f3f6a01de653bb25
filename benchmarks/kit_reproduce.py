"""`oacc reproduce` on the KIT Bimanual development clips: time per clip and verified seeds.

    python benchmarks/kit_reproduce.py [--clips Pour,Stir] [--seeds 0,1,2,3,4,5] [--repeats N]
                                       [--library DIR]

For each clip and seed (0: the scene's own places, the command's default) the whole job runs
in this process as `oacc reproduce CLIP.mmm.xml --library library/kit --no-render` does
(segment, match, compose, execute on ARMAR-III, verify, report; no run store; the library
copied to a temporary folder). Printed per clip: the median wall and CPU seconds over all its
runs, the verdict per seed, and the ratio against the baseline measured in the same process:
the segmentation alone (reading the recording and `oacc segment`'s AAS), median of
``--repeats`` runs. Target: < 30 s per clip (median wall, two cores). ``--library``: another
library of the KIT clips (``tests/data/kit_follow``: named skills replaced by ``follow``).
Only the development clips are offered; the evaluation clips are never run here.
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


def reproduce_once(recording: Path, seed: int, work: Path, source: Path) -> tuple[bool, str]:
    """(verified, verdict) of one whole `oacc reproduce` run."""
    from oacdsl.pipeline import load_inputs, reproduce
    from oacdsl.pipeline.inputs import default_name
    from oacdsl.segmentation import AasParams

    library = work / "kit"
    if not library.exists():
        shutil.copytree(source, library, ignore=shutil.ignore_patterns("learned", "drafts"))
    inputs = load_inputs(recording, library, None, AasParams())
    outcome = reproduce(inputs, name=default_name(str(recording)), out=work / f"out{seed}", db=None,
                        seed=seed or None, render=False, quiet=True, force=True)
    return outcome.exit_code == 0, str(outcome.result["verdict"].get("summary", ""))


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument(
        "--clips", default=",".join(DEV), help="development clips, comma-separated (default: all six)"
    )
    parser.add_argument("--seeds", default="0,1,2,3,4,5", help="0 = the scene's own places")
    parser.add_argument("--repeats", type=int, default=3, help="runs of the baseline")
    parser.add_argument("--library", type=Path, default=ROOT / "library" / "kit", help="the KIT library")
    args = parser.parse_args()
    if MOCAP is None:
        print("shared/mocap is absent: nothing to measure", file=sys.stderr)
        return 2
    clips = [c.strip() for c in args.clips.split(",") if c.strip()]
    unknown = [c for c in clips if c not in DEV]
    if unknown:
        print(f"not a development clip: {', '.join(unknown)} (valid: {', '.join(DEV)})", file=sys.stderr)
        return 2
    seeds = [int(s) for s in args.seeds.split(",")]
    print(f"{'clip':6} {'wall s':>7} {'cpu s':>6} {'seg s':>6} {'ratio':>6}  verified seeds")
    for clip in clips:
        recording = MOCAP / "kit_bimanual" / DEV[clip]
        base = statistics.median(
            timed(lambda r=recording: segmentation_only(r))[1] for _ in range(args.repeats)
        )
        walls, cpus, verdicts = [], [], []
        with tempfile.TemporaryDirectory() as tmp:
            for seed in seeds:
                (ok, summary), wall, cpu = timed(
                    lambda s=seed, r=recording: reproduce_once(r, s, Path(tmp), args.library)
                )
                walls.append(wall)
                cpus.append(cpu)
                verdicts.append(f"{seed}:{'ok' if ok else 'FAIL'}")
                if not ok:
                    print(f"  {clip} seed {seed}: {summary[:160]}", file=sys.stderr)
        wall, cpu = statistics.median(walls), statistics.median(cpus)
        n_ok = sum(v.endswith("ok") for v in verdicts)
        print(f"{clip:6} {wall:7.1f} {cpu:6.1f} {base:6.2f} {wall / base:6.1f}  {n_ok}/{len(seeds)} "
              + " ".join(verdicts))
    return 0


if __name__ == "__main__":
    sys.exit(main())
