"""``oacc match``: link every sub-action of a demonstration to an OAC of the library."""

from __future__ import annotations

import argparse
import json

from oacdsl.cli.demo_input import add_input_options


def register(sub: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    p = sub.add_parser(
        "match",
        help="match each sub-action of a demonstration to an OAC",
        description="Segment a demonstration and match every sub-action (keyframe to keyframe) to the"
        " OACs of a library: one line per sub-action with the chosen OAC and its binding,"
        " the reason when several match, the closest OACs and what failed when none does."
        " Exit status 1 when a sub-action matches no OAC.",
    )
    add_input_options(p)
    p.add_argument("--json", action="store_true", help="print the result as JSON")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from oacdsl.cli.demo_input import load_inputs, transient_s
    from oacdsl.matching.demonstration import match_segmentation
    from oacdsl.matching.matcher import Matcher
    from oacdsl.matching.results import Mode

    window = transient_s(args)  # a bad value fails before any reading
    inputs = load_inputs(args)
    mode: Mode = "paper" if args.paper else "strict"
    matcher = Matcher.from_library(inputs.library, inputs.scene, mode=mode)
    matches = match_segmentation(inputs.segmented(), matcher, transient_s=window, unmerged=inputs.unmerged(),
                                 travel=inputs.travel())
    unmatched = sum(1 for m in matches if not m.matched)
    if args.json:
        print(json.dumps({"sub_actions": [m.to_json() for m in matches]}, indent=2))
        return 1 if unmatched else 0
    width = len(str(len(matches)))
    span = max((len(f"{m.sub_action.start.frame}→{m.sub_action.end.frame}") for m in matches), default=0)
    for m in matches:
        frames = f"{m.sub_action.start.frame}→{m.sub_action.end.frame}"
        print(f"{m.index + 1:>{width}}  frames {frames:<{span}}  {m.text()}")
        for t in m.transient:
            print(
                f"{'':>{width}}  through a transient state at frame {t.keyframe.frame}"
                f" ({t.duration_s:.2f} s: {', '.join(t.objects)} touching nothing)"
            )
        if m.explanation:
            print(f"{'':>{width}}  {m.explanation}")
    ambiguous = sum(1 for m in matches if m.result.ambiguous)
    print(
        f"{len(matches)} sub-actions ({mode} matching, scene {inputs.scene.name}): "
        f"{len(matches) - unmatched} matched, {unmatched} unmatched, {ambiguous} ambiguous"
    )
    return 1 if unmatched else 0
