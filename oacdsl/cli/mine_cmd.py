"""``oacc mine``: segment and match many recordings against a library on Dask (docs/mining.md)."""

from __future__ import annotations

import argparse
import json
import sys

_EPILOG = """\
examples:
  oacc mine recordings/ --library library/kit --out mined/            # every core of this machine
  oacc mine 'takes/**/*.c3d' --library library --out mined --workers 2 --compose
  oacc mine recordings/ --library L --out mined --scheduler tcp://head:8786   # a running cluster

Results: OUT/mine.sqlite3 (a row per recording and per sub-action) and OUT/summary.html (OAC
frequencies, unexplained sub-actions with a drafted OAC per kind, errors, time per stage). A bad
recording is a row with its error, never the job's end. Run the same command again after a kill:
the recordings already in the table are skipped. Dask is the extra 'scale'.
"""


def register(sub: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    from oacdsl.cli.aas_options import add_aas_options
    from oacdsl.mining.cluster import WORKER_WAIT_S

    p = sub.add_parser(
        "mine",
        help="segment and match many recordings against a library, on Dask",
        description="Segment and match every recording (files, folders, glob patterns) against the"
        " library on a Dask cluster; write a table and a summary page into --out.",
        epilog=_EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("recordings", nargs="+", metavar="RECORDING", help="files, folders or glob patterns")
    p.add_argument(
        "--library",
        action="append",
        required=True,
        metavar="DIR",
        help="an OAC library folder or file (repeatable: all are one library)",
    )
    p.add_argument("--scene", metavar="NAME", help="the scene (default: found per recording by its groups)")
    p.add_argument("--out", required=True, metavar="DIR", help="the job's folder: table and summary")
    p.add_argument("--compose", action="store_true", help="also compose each fully matched recording")
    p.add_argument(
        "--workers",
        type=int,
        metavar="N",
        help="worker processes of the embedded cluster (default: one per core)",
    )
    p.add_argument(
        "--scheduler",
        metavar="ADDRESS",
        help="use a running Dask scheduler (tcp://host:8786) instead of an embedded cluster",
    )
    p.add_argument(
        "--worker-wait",
        type=float,
        metavar="SECONDS",
        help=f"with --scheduler: stop when no worker has joined it after SECONDS (default {WORKER_WAIT_S:g})",
    )
    p.add_argument("--dashboard", action="store_true", help="start the Dask dashboard and print its address")
    p.add_argument("--json", action="store_true", help="print the summary's figures as JSON")
    g = p.add_argument_group("segmentation (as oacc segment)")
    add_aas_options(g)
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from oacdsl.cli.aas_options import params_from_args
    from oacdsl.errors import UsageError
    from oacdsl.mining import MineTable, mine, summarise
    from oacdsl.mining.cluster import WORKER_WAIT_S

    if args.worker_wait is not None and args.scheduler is None:
        raise UsageError("--worker-wait goes with --scheduler (the embedded cluster's workers are its own)")

    params = params_from_args(args)  # bad units fail before anything starts

    def note(text: str) -> None:
        print(f"oacc: {text}", file=sys.stderr)

    result = mine(
        args.recordings,
        args.library,
        out=args.out,
        scene=args.scene,
        params=params,
        compose=args.compose,
        workers=args.workers,
        scheduler=args.scheduler,
        worker_wait_s=WORKER_WAIT_S if args.worker_wait is None else args.worker_wait,
        dashboard=args.dashboard,
        progress=sys.stderr,
        note=note,
    )
    if args.json:
        with MineTable(result.table) as table:
            print(json.dumps(summarise(table), indent=2))
    else:
        print(
            f"{result.found} recordings: {result.analysed} analysed now ({result.errors} could not be),"
            f" {result.skipped} done before; {result.wall_s:.1f} s"
        )
        print(f"table: {result.table}\nsummary: {result.summary}")
    return 0
