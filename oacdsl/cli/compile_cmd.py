"""``oacc compile PATH...``: parse and validate an OAC library, report every diagnostic."""

from __future__ import annotations

import argparse
import json
import sys
from typing import TYPE_CHECKING

from oacdsl.errors import UsageError

if TYPE_CHECKING:
    from oacdsl.compiler.loader import CompileResult

_HELP = """\
Parse and validate the .oac files at PATH (files, or folders searched
recursively); all of them form one library and may use each other's names.
Every error and warning is reported, sorted by position, as
'file:line:col: error[CODE]: message' with the source line and a caret.
A file with a syntax error does not stop the others: the checks run over the
files that parsed (leaving out "unknown name" errors a broken file may explain).
Exit status: 0 no errors, 1 errors (or warnings with --strict), 2 usage or I/O
error (a missing path, a file that is not UTF-8). Codes are documented in
docs/language.md."""


def register(sub: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    p = sub.add_parser(
        "compile",
        help="validate an OAC library and report all diagnostics",
        description=_HELP,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("paths", nargs="+", metavar="PATH", help=".oac file or folder of .oac files")
    p.add_argument(
        "--format",
        choices=("text", "json"),
        default="text",
        help="text (default, on stderr) or json (on stdout)",
    )
    p.add_argument("--strict", action="store_true", help="treat warnings as errors (exit 1)")
    p.add_argument("-q", "--quiet", action="store_true", help="text format: no summary line when clean")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from oacdsl.compiler.diagnostics import diagnostics_json, render, summary
    from oacdsl.compiler.loader import compile_paths

    if not args.paths:
        raise UsageError("give at least one .oac file or folder")
    result = compile_paths(args.paths)
    failed = not result.ok or (args.strict and bool(result.diagnostics))
    counts = _counts(result)
    if args.format == "json":
        doc = {
            "ok": not failed,
            "files": sorted(result.sources),
            "declarations": counts,
            "errors": len(result.errors),
            "warnings": len(result.diagnostics) - len(result.errors),
            "diagnostics": diagnostics_json(result.diagnostics),
        }
        print(json.dumps(doc, indent=2))
        return _status(result, failed)
    if result.diagnostics:
        print(render(result.diagnostics, result.sources), file=sys.stderr)
    if not failed and not args.quiet:
        what = ", ".join(f"{n} {k}" for k, n in counts.items())
        tail = f" ({summary(result.diagnostics)})" if result.diagnostics else ""
        print(f"ok: {len(result.sources)} file{'s' if len(result.sources) != 1 else ''}, {what}{tail}")
    return _status(result, failed)


def _status(result: CompileResult, failed: bool) -> int:
    if result.undecodable:
        return 2  # input that cannot be read as text, like a missing file
    return 1 if failed else 0


def _counts(result: object) -> dict[str, int]:
    from oacdsl.compiler.loader import CompileResult
    from oacdsl.model import Grasp, Oac, ObjectClass, Scene

    counts = {"classes": 0, "scenes": 0, "grasps": 0, "OACs": 0}
    kinds = {ObjectClass: "classes", Scene: "scenes", Grasp: "grasps", Oac: "OACs"}
    if isinstance(result, CompileResult):
        for module in result.modules:
            for decl in module.decls:
                counts[kinds[type(decl)]] += 1
    return counts
