"""``oacc skills``: list the skills the robot runtime provides, with their signatures."""

from __future__ import annotations

import argparse
import json

from oacdsl.skills import SIGNATURES


def register(sub: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    p = sub.add_parser(
        "skills",
        help="list the runtime skills an OAC can execute",
        description="List the skills an OAC can 'execute': each one's arguments (in order, with the"
        " class each instance must have) and its named parameters with unit, default and range,"
        " as 'oacc compile' checks them. Example: execute pour(h, c, l, b) { tilt 110deg }.",
    )
    p.add_argument("--json", action="store_true", help="print the signatures as JSON (values in SI units)")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    if args.json:
        doc = {
            name: {
                "doc": sig.doc,
                "args": [{"name": a.name, "class": a.cls} for a in sig.args],
                "params": [
                    {
                        "name": p.name,
                        "unit": p.unit,
                        "default": p.default,
                        "min": p.low,
                        "max": p.high,
                        "doc": p.doc,
                        "source": None
                        if p.source is None
                        else {
                            "feature": p.source.feature,
                            "scale": p.source.scale,
                            "axis": p.source.axis,
                            "needs": p.source.needs,
                            "least": p.source.least,
                        },
                    }
                    for p in sig.params
                ],
            }
            for name, sig in sorted(SIGNATURES.items())
        }
        print(json.dumps(doc, indent=2))
        return 0
    for name in sorted(SIGNATURES):
        sig = SIGNATURES[name]
        print(f"{sig.name}(" + ", ".join(f"{a.name}: {a.cls}" for a in sig.args) + ")")
        print(f"    {sig.doc}")
        for p in sig.params:
            print(f"    {p.describe()}")
    return 0
