"""``oacc plan --library L... --scene S --goal ATOMS``: a plan of library OACs reaching a goal,
or which goal atoms cannot be reached and why (docs/planning.md).

Exit 0 planned, 1 no plan exists, 2 usage or I/O error.
"""

from __future__ import annotations

import argparse
import json
import sys

from oacdsl.cli.planning_input import add_state_options, read_input
from oacdsl.errors import PlanningError

__all__ = ["register", "run"]


def register(sub: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    from oacdsl.planning.engines import ENGINES

    p = sub.add_parser(
        "plan",
        help="plan a goal with the library's OACs (Fast Downward or pyperplan)",
        description="Plan from the scene's initial state (or --from / --state) to --goal with the"
        " library's OACs that execute a skill, by a real planner through unified-planning. Prints"
        " the plan's steps with their bindings, checked by the matcher's semantics; when no plan"
        " exists, each goal atom that cannot be reached and why. Exit 0 planned, 1 no plan, 2 usage.",
    )
    p.add_argument(
        "--library",
        action="append",
        metavar="DIR",
        default=None,
        help="OAC library folder or file (repeatable; default: library/)",
    )
    add_state_options(p)
    p.add_argument(
        "--engine", choices=ENGINES, default="fast-downward", help="the planner (default: %(default)s)"
    )
    p.add_argument("--optimal", action="store_true", help="a shortest plan (slower on large tasks)")
    p.add_argument("--json", action="store_true", help="print the result as JSON on stdout")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from oacdsl.model import atom_text
    from oacdsl.planning.planner import plan_goal

    given = read_input(args, args.library or ["library"], need_goal=True)
    result = plan_goal(given.library, given.scene, given.state, given.goal, args.engine, optimal=args.optimal)
    goal = ", ".join(atom_text(a) for a in given.goal)
    if args.json:
        print(json.dumps(result.to_json(), indent=2))
    elif result.plan is not None:
        steps = len(result.plan)
        print(f"plan for {goal} ({args.engine}, {steps} step{'s' * (steps != 1)}, {result.time_s:.2f} s):")
        if not result.plan:
            print("  (the goal holds already)")
        for index, step in enumerate(result.plan, 1):
            print(f"  {index}. {step.oac}({', '.join(f'{k}={v}' for k, v in step.binding.items())})")
    else:
        print(f"no plan for {goal} ({args.engine}, {result.time_s:.2f} s):")
        for atom, why in result.unreachable:
            print(f"  {atom_text(atom)}: {why}")
        if not result.unreachable:
            print(f"  {result.why}")
    if result.plan is None:
        print(f"oacc: error: {PlanningError(f'no plan: {result.why}')}", file=sys.stderr)
        return 1
    return 0
