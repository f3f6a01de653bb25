"""``oacc run NAME --seeds A:B``: an OAC's success measure over many runs on Dask (docs/mining.md)."""

from __future__ import annotations

import argparse
import json
import sys
from typing import Any

from oacdsl.errors import UsageError

__all__ = ["add_many_options", "check_many_options", "parse_seeds", "run_many_cmd"]


def add_many_options(p: argparse.ArgumentParser) -> None:
    g = p.add_argument_group("many runs (the success measure, on Dask: the 'scale' extra)")
    g.add_argument(
        "--seeds", metavar="A:B", type=parse_seeds, help="run once per seed A, A+1, …, B-1 (replaces --seed)"
    )
    g.add_argument(
        "--place-samples",
        type=int,
        default=1,
        metavar="N",
        help="per seed, N placements: the seed's own and N-1 sampled ones (default 1)",
    )
    g.add_argument("--workers", type=int, metavar="N", help="worker processes (default: one per core)")
    g.add_argument("--scheduler", metavar="ADDRESS", help="a running Dask scheduler (tcp://host:8786)")
    g.add_argument(
        "--worker-wait",
        type=float,
        metavar="SECONDS",
        help="with --scheduler: stop when no worker has joined it after SECONDS (default 120)",
    )


def parse_seeds(text: str) -> range:
    """``A:B`` → range(A, B) with 0 ≤ A < B."""
    a, sep, b = text.partition(":")
    try:
        first, stop = int(a), int(b)
    except ValueError:
        first, stop = -1, -1
    if not sep or not 0 <= first < stop:
        raise argparse.ArgumentTypeError(f"{text!r}: expected A:B, whole numbers with 0 <= A < B")
    return range(first, stop)


def check_many_options(args: argparse.Namespace) -> None:
    """``--seeds`` and the options that go with it, checked before the library is read."""
    if args.seeds is None:
        many = (args.workers, args.scheduler, args.worker_wait)
        if args.place_samples != 1 or any(x is not None for x in many):
            raise UsageError("--workers, --scheduler, --worker-wait and --place-samples go with --seeds A:B")
        return
    if args.seed is not None:
        raise UsageError("--seed and --seeds: give one")
    if args.video or args.frames or args.view or args.demonstration:
        raise UsageError("--seeds runs without --video, --frames, --view or --demonstration")
    if args.worker_wait is not None and args.scheduler is None:
        raise UsageError("--worker-wait goes with --scheduler (the embedded cluster's workers are its own)")
    if args.place_samples < 1:
        raise UsageError(f"--place-samples {args.place_samples}: at least 1")


def run_many_cmd(
    args: argparse.Namespace,
    library_paths: list[str],
    scene: str | None,
    bindings: dict[str, str],
    overrides: Any,
) -> int:
    from oacdsl.mining.runs import RunSpec, run_many
    from oacdsl.stats import RunStore, ensure_writable, resolve_db_path, wilson_interval

    kw = overrides.kwargs()
    if kw.get("layout") or kw.get("balls") or kw.get("held"):
        raise UsageError("--seeds takes --place and --fill, not --layout, balls or a held object (--state)")
    db = None if args.no_record else ensure_writable(resolve_db_path(args.db))
    spec = RunSpec(library_paths, args.name, bindings, scene, kw.get("fill"), kw.get("places"))
    store = RunStore(db) if db is not None else None

    def record(doc: dict[str, Any]) -> None:
        if store is not None and doc.get("steps"):
            store.record_run_json(doc, seed=doc["seed"], command="run --seeds")

    try:
        docs = run_many(
            spec,
            list(args.seeds),
            args.place_samples,
            workers=args.workers,
            scheduler=args.scheduler,
            worker_wait_s=args.worker_wait,
            on_result=record,
            progress=sys.stderr,
        )
    finally:
        if store is not None:
            store.close()
    wins = sum(1 for d in docs if d.get("success"))
    if args.json:
        print(json.dumps(docs, indent=2))
    else:
        for d in docs:
            verdict = "success" if d.get("success") else f"failed: {d.get('error') or d.get('failed_step')}"
            print(f"seed {d['seed']} sample {d['sample']}: {verdict}")
        low, high = wilson_interval(wins, len(docs))
        print(
            f"{args.name}: {wins}/{len(docs)} succeeded ({100 * wins / len(docs):.0f} %,"
            f" Wilson 95 % {100 * low:.0f}-{100 * high:.0f} %)"
        )
    return 0 if wins == len(docs) else 1
