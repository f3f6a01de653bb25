"""``oacc report``: render report.html again from a result.json (e.g. after an upgrade)."""

from __future__ import annotations

import argparse


def register(sub: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    p = sub.add_parser(
        "report",
        help="render report.html from a result.json written by `oacc reproduce`",
        description="Render the self-contained report page again from RESULT (a result.json, see"
        " docs/report.md). The page is written next to it as report.html; pictures are read from"
        " the paths RESULT names, relative to its folder. RESULT is checked first: types, finite"
        " numbers, counts and indices in range, fidelity and rates in [0, 1]; a link to a video"
        " is kept only for a relative path or an http(s)/file URL. Exit status: 0 written,"
        " 1 RESULT is not a valid result document (one line naming the field), 2 unreadable or"
        " not JSON.",
    )
    p.add_argument("result", metavar="RESULT", help="a result.json file")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    import json
    import sys
    from pathlib import Path

    from oacdsl.documents import read_document
    from oacdsl.errors import InputError, ResultError
    from oacdsl.report import write_report

    path = Path(args.result)
    text = read_document(path, "a result document")  # a regular file only, at most 64 MiB
    try:
        doc = json.loads(text)
    except json.JSONDecodeError as e:
        line = getattr(e, "lineno", None)
        raise InputError(f"not JSON: {e}", location=f"{path}:{line}" if line else str(path)) from None
    except RecursionError:
        raise ResultError("nested too deeply; not a result document", location=str(path)) from None
    if not isinstance(doc, dict):
        raise ResultError("not a result document (expected a JSON object)", location=str(path))
    # the folder of the file itself: through out/result.json, a link, that is the run's own folder
    folder = path.resolve().parent if path.is_symlink() else path.parent
    report = write_report(doc, folder, source=str(path))
    for warning in report.warnings:
        print(f"oacc: warning: {warning}", file=sys.stderr)
    print(report.html)
    return 0
