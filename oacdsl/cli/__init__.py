"""The ``oacc`` command line: one module per subcommand.

Each module in :data:`COMMANDS` has ``register(subparsers)``, which adds its
parser and sets ``func`` to a function ``(args) -> int``. Modules import heavy
dependencies (MuJoCo, placo, matplotlib) inside that function, not at the top,
so that ``oacc compile`` starts fast. Errors derived from
:class:`~oacdsl.errors.OacError` become one line on stderr and their exit code.
"""

from __future__ import annotations

import argparse
import functools
import importlib
import sys

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
    "oacdsl.cli.run_cmd",
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
    return parser


@functools.cache
def _parser() -> argparse.ArgumentParser:
    """The parser :func:`main` uses, built once per process (building it takes ~50 ms)."""
    return build_parser()


def main(argv: list[str] | None = None) -> int:
    """Run ``oacc`` with ``argv`` (default: ``sys.argv[1:]``); return the exit status."""
    args = _parser().parse_args(argv)
    try:
        status: int = args.func(args)
    except OacError as error:
        print(f"oacc: error: {error}", file=sys.stderr)
        return error.exit_code
    except KeyboardInterrupt:
        print("oacc: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:
        return 0
    return status
