"""``oacc synth``: write a synthetic marker-based demonstration (C3D) and its ground truth (JSON)."""

from __future__ import annotations

import argparse
import contextlib
import json
import os
import secrets
import sys
from pathlib import Path

#: oacdsl.segmentation.synth.STORIES, spelled out so that building the parser imports no numpy.
_STORIES = ("paper", "handover", "overlap")

DESCRIPTION = """\
Write a synthetic motion-capture demonstration of a scene as a C3D file (100 Hz
unless --rate, millimetres, one subject prefix per instance: 'red_cup:RC1') and its ground truth
as JSON. The one scene is 'dough', the paper's demonstration (Wächter et al. 2013,
IV-B): the left hand pours liquid one from the red cup into the orange bowl, the
right hand pours liquid two from the green cup, then mixes with the mixer. The
recording has about 1 mm of marker noise, occlusion gaps (one during a contact,
one hiding an instance's only marker), a quick hand pass-by that must not count
as touching, and a cup that bounces when set down (merged by the AAS).

The truth lists the intended keyframes with their world states (timed by the
paper's rule with the AAS defaults on the noise-free scene), the intended OAC
sequence, and where each realism feature is. Everything is a function of --seed
(and --rate, --jitter, --flight); the bundled data/dough.c3d is seed 2013 with the
defaults.

--jitter sets the white per-frame marker jitter (per axis; the slow wobble of about
1 mm stays), --rate the frame rate, --flight how long each liquid is in the air
between its cup and the bowl: longer than the merge window (0.3 s), the pour shows
as two changes with a transient state in between (the liquid touches nothing),
which matching joins into one pour (docs/matching.md, "Transient states").
"""

EPILOG = """\
examples:
  oacc synth dough -o dough.c3d                 # also writes dough.truth.json
  oacc synth dough -o runs/d7.c3d --seed 7 --truth runs/d7.json
  oacc synth dough -o clean.c3d --clean         # no noise, no gaps
  oacc synth dough -o fast.c3d --rate 240 --jitter 0.5   # 240 Hz, 0.5 mm white jitter
  oacc synth dough -o fly.c3d --flight 1s       # the liquids are in the air for a second
  oacc synth dough -o handover.c3d --story handover   # the red cup changes hands
"""


def register(sub: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    from oacdsl.segmentation.synth import DEFAULT_SEED, SCENES

    p = sub.add_parser(
        "synth",
        help="write a synthetic demonstration (C3D) with its ground truth (JSON)",
        description=DESCRIPTION,
        epilog=EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("scene", metavar="SCENE", choices=sorted(SCENES), help="the scene: " + ", ".join(SCENES))
    p.add_argument("-o", "--output", metavar="FILE.c3d", required=True, help="the C3D file to write")
    p.add_argument(
        "--seed",
        metavar="N",
        type=int,
        default=DEFAULT_SEED,
        help=f"random seed: timing, noise and gaps (default: {DEFAULT_SEED})",
    )
    p.add_argument(
        "--truth",
        metavar="FILE.json",
        help="where to write the ground truth (default: FILE.truth.json next to the C3D)",
    )
    p.add_argument("--clean", action="store_true", help="write the noise-free, gap-free scene instead")
    p.add_argument(
        "--rate", metavar="HZ", type=float, default=100.0, help="frame rate, Hz, 10 to 1000 (default: 100)"
    )
    p.add_argument(
        "--jitter",
        metavar="MM",
        type=float,
        default=None,
        help="white marker jitter per frame and axis, millimetres, 0 to 5 (default: 0.05)",
    )
    p.add_argument(
        "--flight",
        metavar="TIME",
        default=None,
        help="time each liquid is in the air from its cup to the bowl, 0.05s to 1.5s"
        " (default: 0.16s, a thrown-down parabola; longer: a slow straight stream)",
    )
    p.add_argument(
        "--story",
        choices=_STORIES,
        default="paper",
        help="the order of the sub-actions: 'paper' (the default, as above), 'handover' (the left"
        " hand pours, then hands the empty red cup to the right hand, which sets it down on the"
        " right) or 'overlap' (the right hand grasps and pours while the left hand is still at work)",
    )
    p.set_defaults(func=run)


def truth_path(output: Path) -> Path:
    """``dir/name.c3d`` → ``dir/name.truth.json``."""
    return output.with_name(output.name[: -len(".c3d")] + ".truth.json")


def run(args: argparse.Namespace) -> int:
    from oacdsl.errors import InputError, UsageError
    from oacdsl.segmentation.readers import write_c3d
    from oacdsl.segmentation.synth import SCENES

    out = Path(args.output)
    if not out.name.lower().endswith(".c3d") or out.name.lower() == ".c3d":
        raise UsageError(f"-o: the output must be a .c3d file, got {args.output!r}")
    if args.seed < 0:
        raise UsageError(f"--seed must be a whole number ≥ 0, got {args.seed}")
    from oacdsl.segmentation.synth import FLIGHT_S
    from oacdsl.segmentation.synth.realism import NoiseModel
    from oacdsl.units import parse_quantity

    if not (10.0 <= args.rate <= 1000.0):
        raise UsageError(f"--rate must be between 10 and 1000 Hz, got {args.rate:g}")
    if args.jitter is not None and not (0.0 <= args.jitter <= 5.0):
        raise UsageError(f"--jitter must be between 0 and 5 mm, got {args.jitter:g}")
    flight = FLIGHT_S if args.flight is None else parse_quantity(args.flight, "s", what="--flight")
    if not (0.05 <= flight <= 1.5):
        raise UsageError(f"--flight must be between 0.05s and 1.5s, got {args.flight}")
    noise = NoiseModel() if args.jitter is None else NoiseModel(white_m=args.jitter * 1e-3)  # mm → m
    truth_file = Path(args.truth) if args.truth else truth_path(out)
    if truth_file.resolve() == out.resolve():
        raise UsageError("--truth must differ from the C3D output")
    from oacdsl.atomic import check_target

    for written in (out, truth_file):  # a FIFO, a device, a read-only file: refused before any work
        check_target(written)
    demo = SCENES[args.scene](
        seed=args.seed, source=out.name, rate_hz=args.rate, noise=noise, flight_s=flight, story=args.story
    )
    recording = demo.clean if args.clean else demo.recording
    truth = dict(demo.truth, recording=out.name, clean=bool(args.clean))
    text = json.dumps(truth, indent=1) + "\n"
    # the truth goes to a temporary file first, the C3D is written atomically, then the truth is renamed
    tmp = truth_file.with_name(f".{truth_file.name}.{os.getpid()}.{secrets.token_hex(4)}.tmp")
    try:
        for folder in {out.parent, truth_file.parent}:
            folder.mkdir(parents=True, exist_ok=True)
        with open(tmp, "x", encoding="utf-8") as fh:  # permissions by the umask, like any new file
            fh.write(text)
        write_c3d(recording, out)
        os.replace(tmp, truth_file)
    except OSError as err:
        raise InputError(
            f"cannot write: {err.strerror or err}", location=str(err.filename or truth_file)
        ) from None
    finally:
        with contextlib.suppress(OSError):
            tmp.unlink(missing_ok=True)
    n_gaps = len(truth["realism"]["gaps"])
    print(
        f"wrote {out} ({len(recording.marker_names)} markers, {recording.n_frames} frames,"
        f" {recording.times_s[-1]:.1f} s at {recording.rate_hz:g} Hz"
        f"{', noise-free' if args.clean else f', {n_gaps} gaps'})",
        file=sys.stderr,
    )
    print(
        f"wrote {truth_file} ({len(truth['keyframes'])} keyframes: {', '.join(truth['oac_sequence'])})",
        file=sys.stderr,
    )
    return 0
