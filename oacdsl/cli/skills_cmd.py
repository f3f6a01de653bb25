"""``oacc skills``: list the skills the robot runtime provides."""

from __future__ import annotations

import argparse
import json

from oacdsl.skills import SKILLS


def register(sub: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    p = sub.add_parser("skills", help="list the runtime skills an OAC can execute")
    p.add_argument("--json", action="store_true", help="print the list as JSON")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    if args.json:
        print(json.dumps(SKILLS, indent=2, sort_keys=True))
    else:
        width = max(map(len, SKILLS))
        for name in sorted(SKILLS):
            print(f"{name:<{width}}  {SKILLS[name]}")
    return 0
