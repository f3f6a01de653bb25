"""``oacc fmt PATH... [--check]``: rewrite .oac files in canonical form."""

from __future__ import annotations

import argparse
import difflib
import sys
from pathlib import Path

from oacdsl.atomic import write_atomic
from oacdsl.errors import InputError, OacError

_HELP = """\
Print the .oac files at PATH (files, or folders searched recursively) in
canonical form: sorted where order carries no meaning, aligned, comments kept.
Files are rewritten in place (atomically; a symbolic link's target is rewritten
and the link kept; CR LF and CR line ends become LF); with --check nothing is written and
the files that would change are listed. 'oacc fmt -' formats stdin to stdout.
A file is left alone, with an error line, when rewriting it would change more than
its text: read-only (no write bit in its mode, also for root), another user's
(unless run as root, which keeps the owner), with several hard links, or edited
while fmt ran (run fmt again); the other files are still formatted.
Exit status: 0 done (or nothing to change), 1 a file would change (--check) or
has a syntax error, 2 usage or I/O error (a file could not be rewritten)."""


def register(sub: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    p = sub.add_parser(
        "fmt",
        help="rewrite .oac files in canonical form",
        description=_HELP,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("paths", nargs="+", metavar="PATH", help=".oac file, folder, or '-' for stdin")
    p.add_argument("--check", action="store_true", help="write nothing; exit 1 if a file would change")
    p.add_argument("--diff", action="store_true", help="with --check: show what would change as a diff")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from oacdsl.compiler.loader import collect_files
    from oacdsl.compiler.parser import decode_source, parse_text, read_bytes
    from oacdsl.compiler.printer import print_module
    from oacdsl.errors import LanguageError

    if args.paths == ["-"]:  # decoded as a file is: bytes that are not UTF-8 are E024, exit 2
        stream = getattr(sys.stdin, "buffer", None)
        data = stream.read() if stream is not None else sys.stdin.read().encode("utf-8", "surrogateescape")
        text = decode_source(data, "<stdin>")
        try:
            print(print_module(parse_text(text, "<stdin>")), end="")
        except LanguageError as error:
            print(error.rendered, file=sys.stderr)
            return 1
        return 0
    files = collect_files(args.paths)
    changed: list[Path] = []
    broken = unwritten = 0
    for path in files:
        raw = read_bytes(path)
        source = decode_source(raw, str(path))
        try:
            text = print_module(parse_text(source, str(path)))
        except LanguageError as error:
            print(error.rendered, file=sys.stderr)
            broken += 1
            continue
        if text == source:
            continue
        changed.append(path)
        if args.check:
            if args.diff:
                sys.stdout.writelines(
                    difflib.unified_diff(
                        source.splitlines(keepends=True),
                        text.splitlines(keepends=True),
                        f"{path} (now)",
                        f"{path} (formatted)",
                    )
                )
            else:
                print(path)
        else:
            try:  # a symlink stays a link: its target is formatted (collect_files lists each target once)
                write_atomic(path.resolve(), text, unchanged_since=raw)
            except OSError as error:
                print(f"oacc: error: {path}: cannot write: {error.strerror or error}", file=sys.stderr)
                unwritten += 1
                continue
            except OacError as error:  # read-only, another user's, hard links, edited meanwhile
                print(f"oacc: error: {path}: {error.message}", file=sys.stderr)
                unwritten += 1
                continue
            print(f"formatted {path}")
    if args.check and changed:
        print(
            f"{len(changed)} of {len(files)} file{'s' if len(files) != 1 else ''} would be reformatted",
            file=sys.stderr,
        )
    if unwritten:
        return InputError.exit_code
    return 1 if broken or (args.check and changed) else 0
