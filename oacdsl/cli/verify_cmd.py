"""``oacc verify``: does an execution reproduce the demonstration's physical outcome?"""

from __future__ import annotations

import argparse
import json
from pathlib import Path
from typing import Any

from oacdsl.cli.aas_options import PRESET_HELP, add_aas_options
from oacdsl.cli.reading import add_reading_options, allow_truncated, check_windows, printed_warnings

DESCRIPTION = """\
Compare a recording of an execution with the demonstration, judged on the physical outcome
(docs/verify.md):

  relations  the sequence of world-state changes (the AAS of both recordings; a change the
             robot makes in several steps matches: 'split'). A simulated run's own contacts
             (EXECUTION's NAME.contacts.json, written by oacc run/reproduce) are used when
             present; where the AAS of its markers sees otherwise, a finding is printed.
  end state  every tracked object ends on the demonstrated support (a hand, another object,
             the table), turned as demonstrated (upright / on its side / upside down), and
             away from its start when the demonstration put it elsewhere.
  motion     per sub-action where the demonstration's feature is reliable: strokes/cycles,
             turn about the target's axis, tilt reached.

verified = relations and end state hold; faithful = all three hold. EXECUTION is the robot's
virtual-marker recording of `oacc run --demonstration`/`oacc reproduce` (execution.c3d in the
run folder), a real robot's motion capture, or another person's take. A take at another speed
(x1/3..x3), frame rate or room frame (rotated about the vertical, translated) is compared as
it is; a take done with the other hands verifies only with --any-hands.

Exit status: 0 verified, 1 not verified (each failed check on its own line), 2 usage or
input error.
"""

EPILOG = """\
examples:
  oacc verify data/dough.c3d out/current/execution.c3d
  oacc verify Pour.mmm.xml my_pour.c3d --library library/kit --json
  oacc verify Wipe.mmm.xml left_handed_wipe.c3d --library library/kit --any-hands
"""


def register(sub: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    p = sub.add_parser(
        "verify",
        help="judge an execution against the demonstration: verified, faithful",
        description=DESCRIPTION,
        epilog=EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("demonstration", metavar="DEMONSTRATION",
                   help="the demonstration (.c3d, .mmm.xml, .tsv, .csv)")
    p.add_argument("execution", metavar="EXECUTION", help="the execution's recording (same formats)")
    p.add_argument("--library", metavar="DIR", action="append",
                   help="the OAC library (repeatable; default: library/)")
    p.add_argument("--scene", metavar="FILE|NAME",
                   help="the scene (default: the library's scene whose tracked instances are the"
                   " marker groups)")
    p.add_argument("--json", action="store_true", help="print the verdict and every check as JSON")
    p.add_argument("--any-hands", action="store_true",
                   help="the execution's hands may be exchanged consistently (a left-handed take)")
    g = p.add_argument_group("reading and segmenting (as oacc segment; values carry units)")
    g.add_argument("--format", metavar="FMT", help="read both recordings as this format")
    g.add_argument("--preset", metavar="NAME", help=PRESET_HELP)
    add_reading_options(g)
    add_aas_options(g)
    p.set_defaults(func=run)


def load_execution(path: str, inputs: Any, fmt: str | None, preset: str | None, truncated: bool) -> Any:
    """The execution's recording, grouped as the demonstration is (preset, then the scene)."""
    from oacdsl.errors import InputError
    from oacdsl.segmentation.grouping import apply_scene_groups, group_recording
    from oacdsl.segmentation.readers import read_recording

    if not Path(path).exists():
        raise InputError("no such recording file", location=path)
    rec, _ = group_recording(read_recording(path, fmt, allow_truncated=truncated), preset)
    if any(i.markers or i.ignored for i in inputs.scene.instances):
        rec = apply_scene_groups(rec, inputs.scene)
    return rec


def run(args: argparse.Namespace) -> int:
    from oacdsl.cli.aas_options import params_from_args
    from oacdsl.cli.demo_input import located
    from oacdsl.cli.demo_input import note as print_note
    from oacdsl.errors import MatchingError
    from oacdsl.pipeline import load_inputs
    from oacdsl.verify_contacts import contacts_path, read_contacts
    from oacdsl.verify_execution import verify_execution

    params = params_from_args(args)
    try:
        with printed_warnings():
            inputs = load_inputs(args.demonstration, args.library, args.scene, params, fmt=args.format,
                                 preset=args.preset, allow_truncated=allow_truncated(args), note=print_note)
            execution = load_execution(args.execution, inputs, args.format, args.preset,
                                       allow_truncated(args))
    except MatchingError as error:  # no scene fits: the input is wrong (exit 1)
        raise located(error, args.demonstration, args.scene) from None
    check_windows(args, inputs.motion_capture())
    sidecar = contacts_path(args.execution)
    contacts = read_contacts(sidecar) if sidecar.is_file() else None
    outcome = verify_execution(inputs.motion_capture(), execution, scene=inputs.scene, library=inputs.library,
                               params=params, contacts=contacts, any_hands=args.any_hands)
    if args.json:
        doc = outcome.to_json()
        doc["demonstration"], doc["execution"] = args.demonstration, args.execution
        doc["contacts"] = str(sidecar) if contacts is not None else None
        print(json.dumps(doc, indent=2))
    else:
        print(format_outcome(outcome))
    return 0 if outcome.verified else 1


def format_outcome(outcome: Any) -> str:
    """The verdict line, each failed check on its own line, then findings and notes."""
    lines = [outcome.summary()]
    for c in outcome.failed():
        lines.append(f"FAILED {c.name}: {c.detail} (demonstration: {c.demonstration}; execution:"
                     f" {c.execution}; tolerance: {c.tolerance})")
    if outcome.hand_map:
        pairs = sorted(outcome.hand_map.items())
        lines.append("hands exchanged: " + ", ".join(f"{a} -> {b}" for a, b in pairs))
    judged = [c for c in outcome.checks if c.kind == "motion"]
    if judged:
        lines.append("motion judged where reliable: " + ", ".join(c.name for c in judged))
    lines += [f"finding: {f}" for f in outcome.findings]
    lines += [f"note: {n}" for n in outcome.notes]
    return "\n".join(lines)
