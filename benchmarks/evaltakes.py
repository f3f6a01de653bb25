"""Other takes of the synthetic evaluation-task demonstrations: do they compose, and run, as
the original? (issues 19 and 20: "measured on clips and variations it has not seen")

The evaluation recordings (Open, Close, Peel, RollOut, Transfer) are never opened. Instead each
synthetic demonstration of ``tests/_task_demos.py`` (those five, and Stack, HandOver, Cover,
tasks written from the docs alone), recorded as a capture would (``--capture kit``, the default:
:data:`_task_demos.KIT_LIKE`, marker noise, markers on stalks, a marker gap; ``--capture clean``:
the ideal tracks), is taken through every standard take of
:data:`oacdsl.segmentation.takes.STANDARD_TAKES`: written to a C3D file, read back, segmented,
matched and composed as ``oacc compose DEMO --library library/kit --library library/examples``
does (``benchmarks/takes.py``), and its steps are compared with those of the *clean* original
(the task as it was written), the hands exchanged for the mirror.

A cell is ``same``, ``same*`` (a symmetric OAC's arguments in another order), ``differs`` (the
first differing step) or the stage that stopped (``scene``, ``segment``, ``match``,
``compose``); the ``capture`` column is the captured original itself.

    python benchmarks/evaltakes.py                           # every task, every take
    python benchmarks/evaltakes.py --task Close --take mirrored --capture clean
    python benchmarks/evaltakes.py --markdown                # the table for docs/kit.md
    python benchmarks/evaltakes.py --robot --task Close --take mirrored --seeds 0,1

``--robot``: instead, each chosen take (default: ``mirrored`` and ``scaled``) of each chosen task
is reproduced on ARMAR-III (``oacc reproduce TAKE --library library/kit --library
library/examples --seed N``, the task's layout of ``_task_demos.LAYOUT``), one run at a time;
V (verified and faithful), v (verified), x (not) per seed, the failed checks on stderr. A
mirrored take is judged with the hands free to be exchanged (``oacc verify --any-hands``).
``--layout scene`` or ``--layout demonstrated``: every task laid out so instead.
"""

from __future__ import annotations

import argparse
import shutil
import sys
import tempfile
from dataclasses import replace
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT), str(ROOT / "tests"), str(ROOT / "benchmarks")]

import _task_demos as demos  # noqa: E402
import takes as bench  # noqa: E402

from oacdsl.segmentation.readers import write_recording  # noqa: E402
from oacdsl.segmentation.takes import IDENTITY, STANDARD_TAKES  # noqa: E402

CAPTURES = {"clean": demos.CLEAN, "kit": demos.KIT_LIKE, "kit10": demos.KIT_10HZ}
#: The takes ``--robot`` runs unless told: the other hand, and a larger scene.
ROBOT_TAKES = ("mirrored", "scaled")


def libraries(folder: Path) -> list[Path]:
    """``library/kit`` and ``library/examples`` copied into ``folder`` (without their learned
    OACs and drafts, as a new user's checkout has them)."""
    out = []
    for name in ("kit", "examples"):
        target = folder / name
        if not target.exists():
            ignore = shutil.ignore_patterns("learned", "drafts")
            shutil.copytree(ROOT / "library" / name, target, ignore=ignore)
        out.append(target)
    return out


def compose_takes(task: str, take_names: list[str], capture: demos.Capture, folder: Path,
                  contacts: str = "markers") -> tuple[bench.Outcome, bench.Outcome, list[bench.Outcome]]:
    """(the clean original, the captured original, each take of the captured one), the last two
    compared with the first (``contacts``: ``oacc compose --contacts``)."""
    libs = libraries(folder)
    work = folder / task
    (work / "clean").mkdir(parents=True, exist_ok=True)
    clean = bench.compose_file(demos.write(task, work / "clean"), libs, contacts)
    rec = demos.TASKS[task][0](capture)
    captured = bench.compose_file(write_recording(rec, work / "captured.c3d"), libs, contacts)
    if clean.steps is not None and captured.steps is not None:
        captured.status, captured.detail = bench.compare(clean, captured, dict(IDENTITY))
    cells = []
    for name in take_names:
        if clean.steps is None:
            cells.append(bench.Outcome("-", "the clean original fails", None, 0.0))
            continue
        outcome, hands = bench.run_take(rec, name, libs, ".c3d", work, contacts)
        if outcome.steps is not None:
            outcome.status, outcome.detail = bench.compare(clean, outcome, hands or dict(IDENTITY))
        cells.append(outcome)
    return clean, captured, cells


def robot_run(task: str, take: str, capture: demos.Capture, seed: int, folder: Path,
              layout: str = "task") -> tuple[str, str]:
    """(V/v/x, why not V) of one ``oacc reproduce`` of a take of ``task``'s demonstration;
    ``layout``: the task's (:data:`_task_demos.LAYOUT`), ``scene`` (the example scene's
    places) or ``demonstrated`` (the take's first frame, ``--layout demonstrated``)."""
    from kit_takes_robot import any_hands_verdict

    from oacdsl.pipeline import load_inputs, reproduce
    from oacdsl.runtime.overrides import SceneOverrides
    from oacdsl.segmentation import AasParams

    # a library of its own: a run writes its composed OAC into the first library (learned/), and
    # a whole-task OAC there would be a candidate for the next run's sub-actions
    libs = libraries(folder / f"lib-{task}-{take}-{seed}")
    rec = demos.TASKS[task][0](capture)
    if take != "capture":
        rec, _hands = STANDARD_TAKES[take](rec)
    path = write_recording(rec, folder / f"{task}_{take}.c3d")
    out = folder / f"{task}-{take}-{seed}"
    inputs = load_inputs(path, libs, None, AasParams())
    outcome = reproduce(inputs, name=f"{task.lower()}_{take}", out=out, db=None, seed=seed or None,
                        render=False, quiet=True, force=True,
                        overrides=SceneOverrides(layout=_layout(task, layout)))
    verdict = outcome.result["verdict"]
    mark = "x" if not verdict.get("success") else "V" if verdict.get("faithful", True) else "v"
    why = f"{', '.join(verdict.get('failed_checks', []))} | {verdict.get('summary', '')}"
    if take == "mirrored" and mark != "V" and (out / "execution.c3d").is_file():
        mark, failed = any_hands_verdict(path, libs, out)
        why = f"{failed} | any hands" if failed else "any hands"
    return mark, why


def _layout(task: str, layout: str) -> str | None:
    """The ``--layout`` a run uses: None for the scene's own places."""
    return demos.LAYOUT[task] if layout == "task" else "demonstrated" if layout == "demonstrated" else None


def _cell(c: bench.Outcome) -> str:
    text = c.status if c.keyframes is None else f"{c.status} ({c.keyframes} kf)"
    return text


def _capture(args: argparse.Namespace) -> demos.Capture:
    capture = CAPTURES[args.capture]
    return capture if args.capture_seed is None else replace(capture, seed=args.capture_seed)


def compose_main(args: argparse.Namespace, tasks: list[str], take_names: list[str]) -> int:
    capture = _capture(args)
    rows = []
    with tempfile.TemporaryDirectory(prefix="oac-evaltakes-") as tmp:
        for task in tasks:
            clean, captured, cells = compose_takes(task, take_names, capture, Path(tmp), args.contacts)
            for name, c in [("capture", captured), *zip(take_names, cells, strict=True)]:
                print(f"{task:8} {name:18} {c.status:8} kf {c.keyframes} {c.seconds:5.1f}s {c.detail}",
                      file=sys.stderr, flush=True)
            rows.append((task, clean, captured, cells))
    every = [c for _, _, cap, cells in rows for c in (cap, *cells)]
    same = sum(c.status in ("same", "same*") for c in every)
    if args.markdown:
        print("| task (steps, kf clean) | capture | " + " | ".join(take_names) + " |")
        print("|---" * (len(take_names) + 2) + "|")
        for task, clean, captured, cells in rows:
            head = f"{task} ({len(clean.steps)}, {clean.keyframes})" if clean.steps else f"{task} (fails)"
            print(f"| {head} | {_cell(captured)} | " + " | ".join(_cell(c) for c in cells) + " |")
        print(f"\n{same} of {len(every)} ({args.capture} capture and its takes) compose to the clean"
              " demonstration's steps.")
        failures = [(t, n, c) for t, _, cap, cells in rows
                    for n, c in [("capture", cap), *zip(take_names, cells, strict=True)]
                    if c.status not in ("same", "same*")]
        if failures:
            print("\nWhat the others compose to:\n")
            for t, n, c in failures:
                print(f"- {t} {n}: {c.status}: {c.detail}")
        return 0
    for task, clean, captured, cells in rows:
        print(f"{task}: clean {clean.status}, {len(clean.steps or [])} steps, {clean.keyframes} keyframes")
        for name, c in [("capture", captured), *zip(take_names, cells, strict=True)]:
            print(f"  {name:18}  {c.status:8} kf {c.keyframes}  {c.detail}")
    print(f"{same} of {len(every)} compose to the clean demonstration's steps ({args.capture} capture)")
    return 0


def robot_main(args: argparse.Namespace, tasks: list[str], take_names: list[str]) -> int:
    capture = _capture(args)
    seeds = [int(s) for s in args.seeds.split(",")]
    rows = {}
    with tempfile.TemporaryDirectory(prefix="oac-evaltakes-robot-") as tmp:
        folder = Path(args.keep) if args.keep else Path(tmp)
        folder.mkdir(parents=True, exist_ok=True)
        for task in tasks:
            for take in take_names:
                marks = []
                for seed in seeds:
                    mark, why = robot_run(task, take, capture, seed, folder, args.layout)
                    marks.append(mark)
                    if mark != "V":
                        print(f"  {task} {take} seed {seed}: {why[:400]}", file=sys.stderr, flush=True)
                rows[task, take] = marks
                per_seed = " ".join(f"{s}:{m}" for s, m in zip(seeds, marks, strict=True))
                print(f"{task:8} {take:18} {per_seed}", flush=True)
    if args.markdown:
        print(f"\n| task (seeds {args.seeds}) | " + " | ".join(take_names) + " |")
        print("| --- |" + " --- |" * len(take_names))
        for task in tasks:
            print(f"| {task} | " + " | ".join(" ".join(rows[task, t]) for t in take_names) + " |")
    return 0


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--task", action="append", choices=list(demos.TASKS),
                        help="a synthetic demonstration (repeatable; default: all)")
    parser.add_argument("--take", action="append", choices=["capture", *STANDARD_TAKES],
                        help="a standard take (repeatable; default: all seven, or with --robot "
                             f"{', '.join(ROBOT_TAKES)}); with --robot, 'capture': the captured original")
    parser.add_argument("--capture", choices=list(CAPTURES), default="kit",
                        help="kit: noise, stalks and a gap (default); kit10: the same at 10 Hz, the"
                             " KIT clips' rate; clean: the ideal tracks at 100 Hz")
    parser.add_argument("--capture-seed", type=int, metavar="N",
                        help="draw the capture's noise, stalks and gap from seed N (default 0)")
    parser.add_argument("--contacts", choices=("markers", "geometry"), default="markers",
                        help="contacts between markers (default) or from the library's shapes")
    parser.add_argument("--markdown", action="store_true", help="print a Markdown table")
    parser.add_argument("--robot", action="store_true", help="reproduce the takes on the robot instead")
    parser.add_argument("--seeds", default="0,1", help="with --robot: seeds (0 = the scene's own places)")
    parser.add_argument("--keep", metavar="DIR", help="with --robot: keep each run's folder in DIR")
    parser.add_argument("--layout", choices=("task", "scene", "demonstrated"), default="task",
                        help="with --robot: the task's layout (default: _task_demos.LAYOUT), the example"
                             " scene's places, or the take's first frame (--layout demonstrated)")
    args = parser.parse_args(argv)
    tasks = args.task or list(demos.TASKS)
    if args.robot:
        return robot_main(args, tasks, args.take or list(ROBOT_TAKES))
    if args.take and "capture" in args.take:
        parser.error("--take capture: only with --robot (the compose table always has the capture column)")
    return compose_main(args, tasks, args.take or list(STANDARD_TAKES))


if __name__ == "__main__":
    sys.exit(main())
