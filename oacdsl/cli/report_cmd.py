"""``oacc report``: render report.html again from a result.json (e.g. after an upgrade)."""

from __future__ import annotations

import argparse


def register(sub: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    p = sub.add_parser(
        "report",
        help="render report.html from a result.json written by `oacc reproduce`",
        description="Render the self-contained report page again from RESULT (a result.json, see"
        " docs/report.md). The page is written next to it as report.html; pictures are read from"
        " the paths RESULT names, relative to its folder.",
    )
    p.add_argument("result", metavar="RESULT", help="a result.json file")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    import json
    import sys
    from pathlib import Path

    from oacdsl.errors import InputError
    from oacdsl.report import write_report

    path = Path(args.result)
    try:
        doc = json.loads(path.read_text(encoding="utf-8"))
    except OSError as e:
        raise InputError(f"cannot read: {e.strerror or e}", location=str(path)) from None
    except (UnicodeDecodeError, json.JSONDecodeError) as e:
        line = getattr(e, "lineno", None)
        raise InputError(f"not JSON: {e}", location=f"{path}:{line}" if line else str(path)) from None
    if not isinstance(doc, dict):
        raise InputError("not a result document (expected a JSON object)", location=str(path))
    report = write_report(doc, path.parent, source=str(path))
    for warning in report.warnings:
        print(f"oacc: warning: {warning}", file=sys.stderr)
    print(report.html)
    return 0
