"""``oacc pddl LIBRARY... --scene S [--goal ATOMS] -o DIR``: the library as a PDDL domain, the
scene's world state (and a goal) as a PDDL problem (docs/planning.md)."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from oacdsl.cli.planning_input import add_state_options, read_input
from oacdsl.errors import InputError, UsageError

__all__ = ["register", "run"]


def register(sub: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    p = sub.add_parser(
        "pddl",
        help="write the library as a PDDL domain and a scene's state as a PDDL problem",
        description="Write DIR/domain.pddl (one action per OAC that executes a skill; touching is"
        " symmetric; classes, inherited ones included, are unary predicates) and DIR/problem.pddl"
        " (the scene's instances and initial relations, the goal). Sorted, so the same input gives"
        " the same files. Exit 2 for usage or I/O errors, 1 for an invalid library.",
    )
    p.add_argument(
        "paths", nargs="+", metavar="LIBRARY", help=".oac file or folder (several form one library)"
    )
    add_state_options(p)
    p.add_argument(
        "-o", "--out", required=True, metavar="DIR", help="folder for domain.pddl and problem.pddl"
    )
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from oacdsl.atomic import write_atomic
    from oacdsl.planning.pddl import domain_text, problem_text
    from oacdsl.planning.planner import goal_task

    given = read_input(args, args.paths, need_goal=False)
    task = goal_task(given.library, given.scene, given.state, given.goal)
    folder = Path(args.out)
    if folder.exists() and not folder.is_dir():
        raise UsageError(f"-o {folder}: exists and is not a folder")
    try:
        folder.mkdir(parents=True, exist_ok=True)
        write_atomic(folder / "domain.pddl", domain_text(task))
        write_atomic(folder / "problem.pddl", problem_text(task))
    except OSError as error:
        raise InputError(f"cannot write: {error.strerror or error}", location=str(folder)) from None
    actions = ", ".join(sorted(a.oac.name for a in task.actions)) or "none"
    print(
        f"wrote {folder / 'domain.pddl'} ({len(task.actions)} actions: {actions}) and"
        f" {folder / 'problem.pddl'} ({len(task.classes)} instances, {len(given.goal)} goal atoms)",
        file=sys.stderr,
    )
    return 0
