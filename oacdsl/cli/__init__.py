"""The ``oacc`` command line: one module per subcommand.

Each module in :data:`COMMANDS` has ``register(subparsers)``, which adds its
parser and sets ``func`` to a function ``(args) -> int``. Modules import heavy
dependencies (MuJoCo, placo, matplotlib) inside that function, not at the top,
so that ``oacc compile`` starts fast. Errors derived from
:class:`~oacdsl.errors.OacError` become one line on stderr and their exit code.
"""

from __future__ import annotations

import argparse
import contextlib
import functools
import importlib
import signal
import sys
import threading
from collections.abc import Iterator
from typing import Any

from oacdsl import __version__
from oacdsl.errors import OacError

#: Subcommand modules, in the order ``oacc --help`` lists them.
COMMANDS: list[str] = [
    "oacdsl.cli.reproduce_cmd",
    "oacdsl.cli.compile_cmd",
    "oacdsl.cli.fmt_cmd",
    "oacdsl.cli.inspect_cmd",
    "oacdsl.cli.segment_cmd",
    "oacdsl.cli.draft_cmd",
    "oacdsl.cli.match_cmd",
    "oacdsl.cli.compose_cmd",
    "oacdsl.cli.plan_cmd",
    "oacdsl.cli.pddl_cmd",
    "oacdsl.cli.run_cmd",
    "oacdsl.cli.verify_cmd",
    "oacdsl.cli.mine_cmd",
    "oacdsl.cli.stats_cmd",
    "oacdsl.cli.report_cmd",
    "oacdsl.cli.synth_cmd",
    "oacdsl.cli.take_cmd",
    "oacdsl.cli.skills_cmd",
]


#: The largest seed a command accepts (the run store keeps it as a signed 64-bit integer).
MAX_SEED = 2**63 - 1


def seed_arg(text: str) -> int:
    """argparse ``type`` of ``--seed``: a whole number from 0 to :data:`MAX_SEED`."""
    try:
        value = int(text)
    except ValueError:
        value = -1
    if not 0 <= value <= MAX_SEED:
        raise argparse.ArgumentTypeError(f"{text!r}: a seed is a whole number from 0 to 2^63-1")
    return value


class _StoreOnce(argparse._StoreAction):
    """A single-valued option given twice with different values is a usage error, not last-wins."""

    def __call__(self, parser: argparse.ArgumentParser, namespace: argparse.Namespace,
                 values: Any, option_string: str | None = None) -> None:
        given: dict[str, object] = namespace.__dict__.setdefault("_given_once", {})
        if self.dest in given and given[self.dest] != values:
            raise argparse.ArgumentError(
                self, f"given twice with different values ({given[self.dest]!r}, {values!r}); give it once"
            )
        given[self.dest] = values
        super().__call__(parser, namespace, values, option_string)


def _store_once(parser: argparse.ArgumentParser) -> None:
    """Make every single-valued option of ``parser`` and its subcommands a :class:`_StoreOnce`."""
    for action in parser._actions:
        if type(action) is argparse._StoreAction and action.option_strings:
            action.__class__ = _StoreOnce
        if isinstance(action, argparse._SubParsersAction):
            for sub in set(action.choices.values()):
                _store_once(sub)


#: The longest name of a composed OAC: ``NAME.oac`` must fit a file name (255 bytes).
MAX_NAME = 251


def check_oac_name(name: str, flag: str = "--name") -> str:
    """A composed OAC's name (it names the file ``NAME.oac``): an ASCII identifier of at most
    :data:`MAX_NAME` characters; :class:`~oacdsl.errors.UsageError` otherwise."""
    from oacdsl.errors import UsageError

    if not (name.isidentifier() and name.isascii()):
        raise UsageError(f"{flag} {name!r}: a name is letters, digits and '_', not starting with a digit")
    if len(name) > MAX_NAME:
        raise UsageError(f"{flag}: a name of {len(name)} characters; at most {MAX_NAME} (it names a file)")
    return name


def check_name_free(library: Any, name: str, output: str | None = None) -> None:
    """Refuse ``--name NAME`` when the library's own OAC ``NAME`` is not an earlier composition.

    Composing ``NAME`` leaves the OAC of that name out of matching (an earlier composition,
    ``learned/NAME.oac``, is replaced); an OAC the user wrote (one that executes a skill, or one
    outside a ``learned/`` folder and other than ``output``) would be left out silently, and the
    sub-actions it explains would match nothing (:class:`~oacdsl.errors.UsageError`, exit 2)."""
    from pathlib import Path

    from oacdsl.errors import UsageError

    oac = library.oacs.get(name)
    if oac is None or oac.span is None:
        return
    where = Path(oac.span.file)
    earlier = oac.skill is None and (
        where.parent.name == "learned" or (output is not None and where.resolve() == Path(output).resolve()))
    if not earlier:
        raise UsageError(f"--name {name}: the library's own OAC {name!r} ({oac.span}) has that name;"
                         " the composed OAC would replace it and leave it out of matching, so the sub-actions"
                         " it explains would match nothing: choose another --name")


def build_parser() -> argparse.ArgumentParser:
    """The full argument parser with every subcommand registered."""
    parser = argparse.ArgumentParser(
        prog="oacc",
        description="Reproduce a demonstrated manipulation task with Object-Action Complexes.",
    )
    parser.add_argument("--version", action="version", version=f"oacc {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    for name in COMMANDS:
        importlib.import_module(name).register(sub)
    _store_once(parser)
    return parser


class Terminated(BaseException):
    """SIGTERM arrived: raised in the main thread so that ``finally`` blocks run (a staging
    folder, a temporary file are removed) before ``oacc`` exits with status 143."""


def _raise_terminated(signum: int, frame: object) -> None:
    raise Terminated


@contextlib.contextmanager
def _terminated_cleanly() -> Iterator[None]:
    """SIGTERM becomes :class:`Terminated` for the block (main thread only; the old handler after)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = signal.signal(signal.SIGTERM, _raise_terminated)
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, previous)


@functools.cache
def _parser() -> argparse.ArgumentParser:
    """The parser :func:`main` uses, built once per process (building it takes ~50 ms)."""
    return build_parser()


def main(argv: list[str] | None = None) -> int:
    """Run ``oacc`` with ``argv`` (default: ``sys.argv[1:]``); return the exit status."""
    from oacdsl.cli.output import StdoutError, guarded_stdout, silence_stdout

    try:
        with guarded_stdout(), _terminated_cleanly():
            try:
                args = _parser().parse_args(argv)
            except SystemExit:  # --help, --version or a usage error: what it printed must reach stdout
                sys.stdout.flush()
                raise
            status: int = args.func(args)
    except StdoutError as error:
        silence_stdout()
        if error.broken_pipe:  # the reader is gone (``oacc … | head``): nobody to tell
            return 0
        print(f"oacc: error: {error}", file=sys.stderr)
        return error.exit_code
    except OacError as error:
        print(f"oacc: error: {error}", file=sys.stderr)
        return error.exit_code
    except KeyboardInterrupt:
        print("oacc: interrupted", file=sys.stderr)
        return 130
    except Terminated:
        print("oacc: terminated", file=sys.stderr)
        return 128 + signal.SIGTERM
    except BrokenPipeError:
        silence_stdout()
        return 0
    return status
