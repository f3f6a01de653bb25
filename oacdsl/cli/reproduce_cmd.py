"""``oacc reproduce``: the main job — from a demonstration to a verified robot execution and its report."""

from __future__ import annotations

import argparse
import os
import shlex
import sys
from pathlib import Path

from oacdsl.cli import check_name_free, check_oac_name, seed_arg
from oacdsl.cli.aas_options import PRESET_HELP, add_aas_options
from oacdsl.cli.reading import add_reading_options, allow_truncated, check_windows, printed_warnings
from oacdsl.cli.scene_options import add_scene_options, scene_overrides

DESCRIPTION = """\
Reproduce a demonstrated task on the simulated ARMAR-III, and check it (Wächter et al. 2013,
plus a closed loop): segment the recording into keyframes where objects start or stop touching
(AAS), match every sub-action to an OAC of the library, compose them into a new OAC (written to
LIBRARY/learned/NAME.oac), execute it in MuJoCo, record the robot with virtual markers, segment
and match that recording the same way, and compare the robot's world-state changes with the
demonstration's. Without RECORDING: the bundled dough demonstration (data/dough.c3d).

Writes into --out: report.html (one self-contained page), result.json (its data), NAME.oac and
figures/ — links into --out/runs/<id>/, switched to the new run in one atomic step (the last 3
runs are kept; what killed runs left behind is removed). Every executed OAC's outcome goes into
the run store (oacc stats).

Exit status: 0 reproduced and verified; 1 a stage failed, the robot failed or the closed loop
differs (the report says which), or the recording's content is wrong (nothing is written); 2 usage
or input error (nothing is written).
"""

EPILOG = """\
examples:
  oacc reproduce                                   # the bundled dough demonstration
  oacc reproduce demo.c3d --scene kitchen --name make_dough --out results/
  oacc reproduce demo.c3d --seed 3                 # objects moved by up to 10 cm
  oacc reproduce demo.c3d --layout demonstrated    # objects where the demonstrator had them
  oacc reproduce --place orange_bowl=66cm,2cm --fill liquid_one=red_cup:12
"""


def register(sub: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    p = sub.add_parser(
        "reproduce",
        help="the main job: demonstration → OAC → robot → verified report",
        description=DESCRIPTION,
        epilog=EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument(
        "recording",
        metavar="RECORDING",
        nargs="?",
        help="motion capture (.c3d, .mmm.xml, .tsv, .csv); default: the bundled dough demonstration",
    )
    p.add_argument(
        "--library",
        metavar="DIR",
        action="append",
        help="the OAC library: a folder (drafts/ left out) or a file (default: library/); repeatable:"
        " several are one library, the first folder given gets the composed OAC (learned/)",
    )
    p.add_argument(
        "--scene",
        metavar="FILE|NAME",
        help="the scene (default: the library's scene whose tracked instances are the marker groups)",
    )
    p.add_argument(
        "--name",
        metavar="NAME",
        help="name of the composed OAC (default: from the recording's file name, e.g. dough)",
    )
    p.add_argument(
        "--seed",
        type=seed_arg,
        metavar="N",
        help="move every object of the robot's scene by up to 10 cm at random"
        " (default: where the scene puts them)",
    )
    add_scene_options(p)
    from oacdsl.cli.run_cmd import add_adaptive_options

    add_adaptive_options(p)
    p.add_argument(
        "--state",
        metavar="ATOMS",
        help='relations at the robot\'s start, checked against the scene: a liquid in a container'
        ' ("liquid_one <-> orange_bowl", as --fill) or a hand holding an object ("knife <-> right_hand":'
        " the hand grasps it before the run)",
    )
    p.add_argument("--out", metavar="DIR", default="out", help="folder for the report (default: out/)")
    p.add_argument(
        "--db",
        metavar="PATH",
        help="run store (default: $OACDSL_DB, else ~/.local/share/oacdsl/runs.sqlite3)",
    )
    p.add_argument("--no-record", action="store_true", help="do not store the run's outcome in the run store")
    p.add_argument("--no-render", action="store_true", help="no pictures of the robot (faster)")
    p.add_argument(
        "--no-demo-params",
        action="store_true",
        help="compose the paper's plain steps: no skill parameters from the demonstrated motion"
        " (by default a pour takes the demonstrated tilt and duration, a stir its radius and"
        " period, retargeted to the robot; docs/motion.md)",
    )
    p.add_argument(
        "--force", action="store_true", help="replace a different OAC of the same name in LIBRARY/learned/"
    )
    p.add_argument("--quiet", action="store_true", help="no progress on stderr")
    g = p.add_argument_group("reading and segmenting the recording (as oacc segment; values carry units)")
    g.add_argument("--format", metavar="FMT", help="read as this format (c3d, mmm, tsv, csv)")
    g.add_argument("--preset", metavar="NAME", help=PRESET_HELP)
    add_reading_options(g)
    add_aas_options(
        g,
        mode_help="touch detector for the demonstration: adaptive (per-pair distances"
        " learned from co-motion; default) or paper (Eq. 1/2 as printed); the robot's own"
        " recording is always segmented with paper",
    )
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from oacdsl.cli.aas_options import params_from_args
    from oacdsl.cli.backend import prepare_backend
    from oacdsl.cli.demo_input import located
    from oacdsl.cli.demo_input import note as print_note
    from oacdsl.errors import InputError, MatchingError, UsageError
    from oacdsl.pipeline import default_name, load_inputs, reproduce
    from oacdsl.pipeline.inputs import BUNDLED_NAME

    if args.name is not None:
        check_oac_name(args.name)
    params = params_from_args(args)  # bad units fail before any reading
    overrides = scene_overrides(args)
    if args.max_repairs < 0:
        raise UsageError("--max-repairs: a whole number ≥ 0")
    import dataclasses

    overrides = dataclasses.replace(overrides, strict=args.strict, max_repairs=args.max_repairs)
    if args.state:
        from oacdsl.planning.state import parse_atoms

        parse_atoms(args.state, "--state")  # a syntax error fails before the recording is read
    db = None
    if not args.no_record:
        from oacdsl.stats import ensure_writable, resolve_db_path

        db = ensure_writable(resolve_db_path(args.db))  # a foreign, newer or unwritable store: now
    out = Path(args.out)
    if out.is_symlink():  # publishing replaces links inside --out; --out itself must be the folder
        raise UsageError(f"--out is a symbolic link (to {os.readlink(out)}); give the folder itself")
    if out.exists() and not out.is_dir():
        raise InputError("--out must be a folder; this is a file", location=str(out))
    try:
        with printed_warnings():
            inputs = load_inputs(
                args.recording,
                args.library,
                args.scene,
                params,
                fmt=args.format,
                preset=args.preset,
                allow_truncated=allow_truncated(args),
                note=print_note,
            )
    except MatchingError as error:  # no scene fits the recording: input wrong (exit 1), nothing written
        raise located(error, args.recording or BUNDLED_NAME, args.scene) from None
    if inputs.recording is not None:
        check_windows(args, inputs.recording)
    note = prepare_backend(not args.no_render)  # before MuJoCo is imported: it reads MUJOCO_GL once
    if note:
        note += "; no pictures of the robot"
    try:
        import mujoco  # noqa: F401  (the robot extra)
        import placo  # noqa: F401
    except ImportError as error:
        raise UsageError(f"reproduce needs the 'robot' extra (pip install -e '.[robot]'): {error}") from None
    from oacdsl.cli.scene_check import check_overrides

    if args.state:
        from oacdsl.planning.state import state_as_setup

        stated_fills, held = state_as_setup(inputs.library, inputs.scene, args.state)
        overrides = dataclasses.replace(overrides, fill={**stated_fills, **overrides.fill}, held=held)
    check_overrides(inputs.library, inputs.scene, overrides)  # before anything is composed or written
    name = args.name or default_name(inputs.source)
    check_name_free(inputs.library, name)

    def warn(text: str) -> None:
        print(f"oacc: warning: {text}", file=sys.stderr)

    if note:
        warn(note)
    command = (
        "oacc " + " ".join(shlex.quote(a) for a in sys.argv[1:]) if sys.argv[1:2] == ["reproduce"] else None
    )
    outcome = reproduce(
        inputs,
        name=name,
        out=out,
        db=db,
        seed=args.seed,
        render=not args.no_render and not note,
        force=args.force,
        quiet=args.quiet,
        command=command,
        warn=warn,
        overrides=overrides,
        demo_params=not args.no_demo_params,
    )
    verdict = outcome.result["verdict"]
    mark = "FAILED"
    if verdict["success"]:
        mark = "verified, faithful" if verdict.get("faithful", True) else "verified, not faithful"
    report = out / "report.html"
    print(f"{mark}: {verdict['summary']}")
    print(f"report: {report}  (data: {out / 'result.json'})")
    return outcome.exit_code
