"""``oacc compose``: compose a demonstration into a new OAC and write it into the library."""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from oacdsl.atomic import check_target
from oacdsl.cli import check_name_free, check_oac_name
from oacdsl.cli.demo_input import add_input_options


def register(sub: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    p = sub.add_parser(
        "compose",
        help="compose a demonstration into a new OAC (library/learned/NAME.oac)",
        description="Segment a demonstration, match its sub-actions and compose them into one new OAC"
        " (the paper's Algorithm 1, per relation), written by the canonical printer into"
        " LIBRARY/learned/NAME.oac after checking it compiles with the library. Composing"
        " the same demonstration again changes nothing; a different OAC of the same name"
        " is kept unless --force.",
    )
    add_input_options(p)
    p.add_argument("--name", required=True, help="name of the new OAC")
    p.add_argument("-o", "--output", metavar="FILE", help="write here instead of LIBRARY/learned/NAME.oac")
    p.add_argument("--json", action="store_true", help="print the result as JSON")
    p.add_argument(
        "--propose",
        action="store_true",
        help="for a sub-action that matches no OAC, write a draft OAC to LIBRARY/drafts/ for"
        " review and go on (the new OAC then goes to drafts/ too)",
    )
    p.add_argument(
        "--paper-effects",
        action="store_true",
        help="effects as in the paper: only the relations that started (default: also those that"
        " ended, as 'not a <-> b', so that the OAC is sound)",
    )
    p.add_argument(
        "--no-demo-params",
        action="store_true",
        help="write the steps without skill parameters (the paper's plain steps); by default each"
        " step carries the parameters its skill takes from the demonstrated motion (a pour's"
        " tilt and duration, a stir's radius and period), retargeted to the robot, with a"
        " comment saying what was scaled (docs/motion.md)",
    )
    p.add_argument("--force", action="store_true", help="replace a different OAC already in the target file")
    p.add_argument("--dry-run", action="store_true", help="print the new OAC; write nothing")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from oacdsl.cli.demo_input import load_inputs, transient_s
    from oacdsl.matching.demonstration import compose_demonstration, match_segmentation, reaching
    from oacdsl.matching.emit import DRAFTS, LEARNED, Emitted, emit, library_files, render
    from oacdsl.matching.matcher import Matcher
    from oacdsl.matching.results import Mode

    check_oac_name(args.name)
    if args.output is not None:  # a FIFO, a device, a read-only file …: refused before anything is read
        check_target(args.output)
    window = transient_s(args)  # a bad value fails before any reading
    inputs = load_inputs(args)
    check_name_free(inputs.library, args.name, args.output)
    mode: Mode = "paper" if args.paper else "strict"
    # an earlier composition of this name is replaced, never a step of its own recomposition
    matcher = Matcher.from_library(inputs.library, inputs.scene, mode=mode,
                                   exclude=reaching(inputs.library, args.name))
    matches = match_segmentation(inputs.segmented(), matcher, transient_s=window, unmerged=inputs.unmerged(),
                                 travel=inputs.travel())
    demo = compose_demonstration(
        args.name,
        matches,
        inputs.library,
        inputs.scene,
        propose=args.propose,
        paper_effects=args.paper_effects,
    )
    comp = demo.composition
    warnings = list(comp.warnings)
    if not args.no_demo_params:
        if inputs.recording is None:
            warnings.append(
                "the demonstration is a segmentation, without motion: the steps carry no"
                " skill parameters from it"
            )
        else:
            from oacdsl.matching.composedparams import with_demo_params
            from oacdsl.matching.demoparams import demonstrated_motions

            motions = demonstrated_motions(inputs.recording, [m.sub_action for m in matches])
            comp = with_demo_params(comp, motions, inputs.library, inputs.scene)
    oac = comp.oac
    if inputs.outside_scene is not None:  # defaults would name instances the library does not know
        bare = tuple(p.model_copy(update={"default": None}) for p in oac.params)
        oac = oac.model_copy(update={"params": bare})
        warnings.append(
            f"the scene comes from {inputs.outside_scene}, outside the library: the new OAC's"
            " parameters carry no default binding (put the scene into the library to keep them)"
        )
    for warning in warnings:
        print(f"oacc: warning: {warning}", file=sys.stderr)
    root = inputs.library_path if inputs.library_path.is_dir() else inputs.library_path.parent
    header = [
        f"Composed by oacc compose from {inputs.source} ({mode} matching,"
        f" {len(comp.steps)} steps, scene {inputs.scene.name})."
    ]
    folder = DRAFTS if demo.drafts else LEARNED
    target = Path(args.output) if args.output else root / folder / f"{args.name}.oac"
    drafts_dir = root / DRAFTS
    if args.dry_run:
        sys.stdout.write(render([oac], str(target), header) if not args.json else "")
        if args.json:
            print(json.dumps(comp.to_json(None), indent=2))
        return 0
    from oacdsl.atomic import remove_stale_temporaries

    for written_to in {target.parent, root / LEARNED, drafts_dir}:  # what killed runs left behind
        remove_stale_temporaries(written_to)
    others = [f for p in inputs.library_paths if p != inputs.library_path for f in library_files(p)]
    # Check everything before writing anything: the drafts, then the OAC that calls them.
    drafts = {drafts_dir / f"{d.name}.oac": d for _, d in demo.drafts}
    pending = {path: render([d], str(path)) for path, d in drafts.items()}
    for path, draft in drafts.items():
        emit([draft], path, library=inputs.library_path, force=args.force, drafts=True, pending=pending,
             write=False, also=others)

    def composed(write: bool) -> Emitted:  # checked with every --library given
        return emit([oac], target, library=inputs.library_path, header=header, force=args.force,
                    drafts=bool(drafts), also=[*others, *([drafts_dir] if drafts else [])], pending=pending,
                    write=write)

    composed(write=False)
    written = []
    for path, draft in drafts.items():
        e = emit([draft], path, library=inputs.library_path, force=args.force, drafts=True, pending=pending,
                 also=others)
        written.append(e)
        print(f"oacc: {e.status} draft {e.path}: sub-action matched no OAC; review it", file=sys.stderr)
    result = composed(write=True)
    if args.json:
        doc = comp.to_json(str(result.path))
        if written:
            doc["drafts"] = [str(e.path) for e in written]
        print(json.dumps(doc, indent=2))
        return 0
    changed = f" ({result.changes})" if result.status == "replaced" else ""
    print(f"{args.name}: {result.status} {result.path}{changed}")
    print(f"  pre     {_atoms(comp.pre)}")
    print(f"  effect  {', '.join(f'{a} <-> {b}' for a, b in comp.added) or '(none)'}")
    print(f"  ended   {', '.join(f'{a} <-> {b}' for a, b in comp.ended) or '(none)'}")
    print(f"  steps   {' '.join(('& ' if s.together else '') + s.oac.name for s in comp.steps)}")
    return 0


def _atoms(atoms: tuple) -> str:  # type: ignore[type-arg]
    from oacdsl.model import atom_text

    return ", ".join(atom_text(a) for a in atoms) or "(none)"
