"""``oacc stats``: the measured reliability of each OAC (the OAC's success measure)."""

from __future__ import annotations

import argparse
import json
import sys
from typing import Any

_EPILOG = """\
Every `oacc run` and `oacc reproduce` records the outcome of each OAC it executed
(success, duration, error, binding), and what an adaptive run skipped or replanned,
in a SQLite database: --db PATH, else $OACDSL_DB,
else $XDG_DATA_HOME/oacdsl/runs.sqlite3 (default ~/.local/share/oacdsl/runs.sqlite3).
The 95 % interval of the success rate is the Wilson score interval.
"""


def register(sub: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    p = sub.add_parser(
        "stats",
        help="show the measured reliability of each OAC from recorded runs",
        description="Show the measured reliability of each OAC: runs, successes, success rate with a"
        " Wilson 95 % interval, median duration and the last failure.",
        epilog=_EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("--db", metavar="PATH", help="run database (default: $OACDSL_DB or the XDG data dir)")
    p.add_argument("--json", action="store_true", help="print the figures as JSON")
    p.add_argument("--oac", metavar="NAME", help="show this OAC only")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from oacdsl.errors import UsageError, did_you_mean
    from oacdsl.stats import RunStore, resolve_db_path, summarise
    from oacdsl.stats.writable import check_store_path

    path = resolve_db_path(args.db)
    check_store_path(path)  # a folder, a FIFO, a path under a file: an error, not "no runs yet"
    rows: list[dict[str, Any]] = []
    adapted: list[dict[str, Any]] = []
    names: list[str] = []
    runs = 0
    if RunStore.exists(path) and path.stat().st_size > 0:
        with RunStore(path, create=False) as store:
            runs = store.run_count()
            names = store.oac_names()
            if args.oac is not None and names and args.oac not in names:
                hint = did_you_mean(args.oac, names)
                raise UsageError(f"no runs of OAC '{args.oac}' recorded in {path}{hint}")
            rows = store.rows(args.oac)
            adapted = store.adaptations(args.oac)
    table = summarise(rows)
    if args.json:
        doc = {"db": str(path), "runs": runs, "oacs": [r.to_json() for r in table], "adaptations": adapted}
        print(json.dumps(doc, indent=2))
        return 0
    if not table:
        print(f"No runs recorded yet in {path}.")
        print("`oacc run` and `oacc reproduce` record every execution there.")
        return 0
    print(f"{runs} run{'s' if runs != 1 else ''} recorded in {path}\n")
    _print_table(table)
    _print_adaptations(adapted)
    return 0


#: The latest adaptations ``oacc stats`` lists (``--json`` gives all).
SHOWN_ADAPTATIONS = 10


def _print_adaptations(adapted: list[dict[str, Any]]) -> None:
    """How often adaptive runs skipped, replanned, … and the latest adaptations, one a line."""
    if not adapted:
        return
    counts: dict[str, int] = {}
    for a in adapted:
        counts[a["kind"]] = counts.get(a["kind"], 0) + 1
    n_runs = len({a["run_id"] for a in adapted})
    kinds = ", ".join(f"{n} {kind}" for kind, n in sorted(counts.items()))
    runs = f"{n_runs} run{'s' * (n_runs != 1)}"
    sys.stdout.write(f"\nAdaptations of adaptive runs ({len(adapted)} in {runs}): {kinds}\n")
    for a in adapted[-SHOWN_ADAPTATIONS:]:
        text = str(a["text"]) + (f" → {', '.join(a['plan'])}" if a["plan"] else "")
        text = text if len(text) <= 100 else text[:99] + "…"
        sys.stdout.write(f"  {_when(a['time_utc'])}  {a['oac']}  {text}\n")


def _pct(x: float) -> str:
    return f"{100 * x:.0f} %"


def _when(iso: str | None) -> str:
    return iso.replace("T", " ")[:16] if iso else ""


def _print_table(table: list[Any]) -> None:
    head = ["OAC", "runs", "ok", "rate", "95 % interval", "median", "last failure (UTC)"]
    lines = []
    for r in table:
        failure = ""
        if r.last_failure is not None:
            reason = r.last_failure if len(r.last_failure) <= 60 else r.last_failure[:59] + "…"
            failure = f"{_when(r.last_failure_utc)}  {reason}"
        median = "" if r.median_duration_s is None else f"{r.median_duration_s:.2f} s"
        lines.append(
            [
                r.oac,
                str(r.runs),
                str(r.successes),
                _pct(r.rate),
                f"{_pct(r.ci_low)} – {_pct(r.ci_high)}",
                median,
                failure or "—",
            ]
        )
    widths = [max(len(row[i]) for row in [head, *lines]) for i in range(len(head) - 1)]
    right = {1, 2, 3, 5}
    for row in [head, *lines]:
        cells = [row[i].rjust(w) if i in right else row[i].ljust(w) for i, w in enumerate(widths)]
        sys.stdout.write("  ".join([*cells, row[-1]]).rstrip() + "\n")
