"""``oacc take``: write another take of a recording (mirrored, rotated, slower, resampled, …)."""

from __future__ import annotations

import argparse
import re

from oacdsl.cli import seed_arg
from oacdsl.cli.reading import add_reading_options

DESCRIPTION = """\
Write another take of a recording: the same demonstration as another person or lab would
record it, for measuring what the segmentation, matching and reproduction are invariant to.
The take keeps the recording's marker names and groups (the file's own: MMM motions, C3D
subjects), so it is segmented, matched and composed with the same library and scene as
the original. It is written as C3D or MMM XML (markers only) by the extension of OUT.

The changes apply in this order: --mirror, --scale, --rotate, --translate, --speed,
--rate/--jitter, --gap (whose times are those of the take). Or --standard NAME, one of
the seven standard takes (docs/segmentation.md, "Other takes"):
"""

EPILOG = """\
examples:
  oacc take Pour.mmm.xml -o pour_left.mmm.xml --mirror        # left-handed
  oacc take data/dough.c3d -o d.c3d --rotate 90deg --translate 2m,0m
  oacc take data/dough.c3d -o d.c3d --speed 0.5               # half the speed: twice as long
  oacc take data/dough.c3d -o d.c3d --rate 240Hz --jitter 0.2mm --seed 3
  oacc take data/dough.c3d -o d.c3d --gap red_cup:RC1@5s+0.5s
  oacc take Pour.mmm.xml -o p.mmm.xml --standard mirrored
  oacc compose p.mmm.xml --library library/kit --name p       # composes as Pour, hands exchanged
"""

_GAP = re.compile(r"^(?P<marker>.+)@(?P<start>[^+]+)\+(?P<duration>.+)$")


def register(sub: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    from oacdsl.segmentation.takes import STANDARD_DESCRIPTIONS

    standards = "\n".join(f"  {name:<19} {text}" for name, text in STANDARD_DESCRIPTIONS.items())
    p = sub.add_parser(
        "take",
        help="write another take of a recording (mirrored, rotated, slower, resampled, with a gap, …)",
        description=DESCRIPTION + standards,
        epilog=EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("recording", metavar="RECORDING", help="motion capture (.c3d, .mmm.xml, .tsv, .csv)")
    p.add_argument(
        "-o",
        "--output",
        metavar="OUT",
        required=True,
        help="the take to write: .c3d or .mmm.xml (written to a temporary file, then renamed)",
    )
    p.add_argument("--format", metavar="FMT", help="read RECORDING as this format (c3d, mmm, tsv, csv)")
    p.add_argument(
        "--standard",
        metavar="NAME",
        choices=sorted(STANDARD_DESCRIPTIONS),
        help="one of the standard takes (above); not combined with the options below",
    )
    p.add_argument(
        "--mirror",
        action="store_true",
        help="reflect across the demonstrator's sagittal plane (torso markers, else the hands),"
        " left and right exchanged",
    )
    p.add_argument(
        "--scale",
        metavar="FACTOR",
        type=float,
        help="scale every position (1.15: 15 %% larger), about the mean xy on the floor",
    )
    p.add_argument("--rotate", metavar="ANGLE", help="rotate about the vertical through the mean xy (90deg)")
    p.add_argument("--translate", metavar="X,Y[,Z]", help="move by lengths with units (2m,0m)")
    p.add_argument(
        "--speed",
        metavar="FACTOR",
        type=float,
        help="the demonstration done this much faster (0.5: half the speed, twice as long)",
    )
    p.add_argument("--rate", metavar="FREQ", help="resample to this frame rate (100Hz)")
    p.add_argument(
        "--jitter", metavar="LENGTH", help="Gaussian noise per coordinate, standard deviation (0.2mm)"
    )
    p.add_argument("--seed", metavar="N", type=seed_arg, default=0, help="seed of the jitter (default: 0)")
    p.add_argument(
        "--gap",
        metavar="MARKER@START+DUR",
        action="append",
        default=[],
        help="a marker missing from START for DUR (RC1@5s+0.5s); repeatable",
    )
    add_reading_options(p)
    p.set_defaults(func=run)


def _changes(args: argparse.Namespace) -> list[str]:
    flags = ["mirror", "scale", "rotate", "translate", "speed", "rate", "jitter", "gap"]
    return [
        f"--{f}"
        for f in flags
        if getattr(args, f) is not None and getattr(args, f) is not False and getattr(args, f) != []
    ]


def _positive(value: float | None, flag: str) -> float | None:
    from oacdsl.errors import UsageError

    if value is not None and not (0 < value < float("inf")):
        raise UsageError(f"{flag} must be a positive factor, got {value:g}")
    return value


def _translation(text: str) -> tuple[float, ...]:
    from oacdsl.errors import UsageError
    from oacdsl.units import parse_quantity

    parts = text.split(",")
    if len(parts) not in (2, 3):
        raise UsageError(f"--translate {text!r}: expected X,Y or X,Y,Z, lengths with units (2m,0m)")
    return tuple(parse_quantity(v, "m", what="--translate") for v in parts)


def _gap(text: str) -> tuple[str, float, float]:
    from oacdsl.errors import UsageError
    from oacdsl.units import parse_quantity

    m = _GAP.match(text)
    if m is None:
        raise UsageError(f"--gap {text!r}: expected MARKER@START+DURATION, e.g. RC1@5s+0.5s")
    start = parse_quantity(m["start"], "s", what="--gap start")
    duration = parse_quantity(m["duration"], "s", what="--gap duration")
    if duration <= 0:
        raise UsageError(f"--gap {text!r}: the duration must be positive")
    return m["marker"], start, duration


def run(args: argparse.Namespace) -> int:
    from oacdsl.cli.reading import allow_truncated, printed_warnings
    from oacdsl.errors import UsageError
    from oacdsl.segmentation import takes
    from oacdsl.segmentation.readers import WRITABLE, format_of, read_recording, write_recording
    from oacdsl.units import parse_quantity

    changes = _changes(args)
    if args.standard and changes:
        raise UsageError(f"--standard {args.standard} is one take; drop {', '.join(changes)}")
    if not args.standard and not changes:
        raise UsageError(
            "nothing to change: give --standard NAME or at least one of --mirror, --scale,"
            " --rotate, --translate, --speed, --rate, --jitter, --gap"
        )
    out_format = format_of(args.output)
    if out_format not in WRITABLE:
        raise UsageError(f"-o {args.output}: a take is written as .c3d or .mmm.xml")
    # every value is checked before anything is read
    scale = _positive(args.scale, "--scale")
    speed = _positive(args.speed, "--speed")
    angle = parse_quantity(args.rotate, "rad", what="--rotate") if args.rotate else None
    offset = _translation(args.translate) if args.translate else None
    rate = parse_quantity(args.rate, "Hz", what="--rate") if args.rate else None
    if rate is not None and not 0 < rate <= 10000:
        raise UsageError(f"--rate {args.rate}: a frame rate is above 0 and at most 10kHz")
    jitter = parse_quantity(args.jitter, "m", what="--jitter") if args.jitter else 0.0
    if not 0 <= jitter <= 0.1:
        raise UsageError(f"--jitter {args.jitter}: from 0mm to 100mm")
    gaps = [_gap(g) for g in args.gap]
    from oacdsl.atomic import check_target

    check_target(args.output)  # a FIFO, a device, a read-only file: refused before anything is read

    with printed_warnings():
        rec = read_recording(args.recording, args.format, allow_truncated=allow_truncated(args))
    hands = dict(takes.IDENTITY)
    if args.standard:
        rec, hands = takes.STANDARD_TAKES[args.standard](rec)
    else:
        if args.mirror:
            rec, hands = takes.mirrored(rec)
        if scale is not None:
            rec = takes.scaled(rec, scale)
        if angle is not None:
            rec = takes.rotated(rec, angle)
        if offset is not None:
            rec = takes.translated(rec, offset)
        if speed is not None:
            rec = takes.stretched(rec, 1.0 / speed)
        if rate is not None or jitter:
            rec = takes.resampled(rec, rate or rec.rate_hz, jitter_m=jitter, seed=args.seed)
        for marker, start, duration in gaps:
            rec = takes.with_gap(rec, marker, start, duration)
    path = write_recording(rec, args.output, out_format)
    swapped = [f"{a} -> {b}" for a, b in sorted(hands.items()) if a != b]
    print(
        f"{path}: {rec.n_frames} frames at {rec.rate_hz:g} Hz, {len(rec.marker_names)} markers,"
        f" {len(rec.groups)} groups; {rec.source}"
    )
    if swapped:
        print(f"  hands exchanged: {', '.join(swapped)}")
    return 0
