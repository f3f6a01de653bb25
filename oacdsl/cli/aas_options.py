"""The segmentation options every command that segments a recording takes (``segment``,
``match``, ``compose``, ``verify``, ``reproduce``, ``draft``, ``mine``): their help texts,
:func:`add_aas_options` and :func:`params_from_args`, which reads them into
:class:`~oacdsl.segmentation.params.AasParams` (units and mode checked, exit 2 if wrong)."""

from __future__ import annotations

import argparse
from typing import Any

from oacdsl.segmentation.params import DEFAULT_MODE

__all__ = ["MODE_HELP", "PRESET_HELP", "add_aas_options", "params_from_args"]


PRESET_HELP = (
    "built-in marker grouping: 'kit' (KIT/MMM hand markers → left_hand, right_hand; applied"
    " unasked when the file has them, with a note on stderr) or 'none' (the file's own groups)"
)

MODE_HELP = (
    "touch detector: adaptive (per-pair distances learned from co-motion, distance change"
    " fitted over --change-window; default: F1 1.00 against 0.85 on the KIT clips), robust"
    " (Eq. 1/2 at one distance, distance change fitted over --change-window) or paper"
    " (Eq. 1/2 as printed: one-frame difference)"
)


def add_aas_options(group: Any, mode_help: str = MODE_HELP) -> None:
    """The AAS parameters every command that segments takes (read by :func:`params_from_args`)."""
    group.add_argument("--distance", metavar="LEN", help="distance threshold d (default: 150mm)")
    group.add_argument("--speed", metavar="SPEED", help="distance-change threshold v (default: 100mm/s)")
    group.add_argument(
        "--hold",
        metavar="TIME",
        help="how long a condition must hold: n as a duration (default: 0.1s, at least 2 frames)",
    )
    group.add_argument("--frames", metavar="N", help="n as a number of frames (instead of --hold)")
    group.add_argument(
        "--change-window",
        metavar="TIME",
        help="window of the least-squares fit that estimates the distance change in modes"
        " robust and adaptive (default: 0.1s; paper: one frame, as printed)",
    )
    group.add_argument("--merge", metavar="TIME", help="keyframe merge window (default: 0.3s; 0s = off)")
    group.add_argument("--mode", metavar="MODE", default=DEFAULT_MODE, help=mode_help)
    group.add_argument(
        "--contacts",
        metavar="HOW",
        default="markers",
        help="markers (distances between markers, default) or geometry: surface to surface where"
        " the library gives a class its shape and markers (mode adaptive; needs the scene's library)",
    )


def params_from_args(args: argparse.Namespace) -> Any:
    """:class:`AasParams` from the command-line values (units and mode checked)."""
    from oacdsl.errors import UsageError, did_you_mean
    from oacdsl.segmentation.detectors import DETECTORS
    from oacdsl.segmentation.params import AasParams
    from oacdsl.units import parse_quantity

    if args.mode not in DETECTORS:
        raise UsageError(f"--mode: unknown mode {args.mode!r}{did_you_mean(args.mode, DETECTORS)}")
    kwargs: dict[str, Any] = {"mode": args.mode}
    contacts = getattr(args, "contacts", "markers")
    if contacts not in ("markers", "geometry"):
        raise UsageError(f"--contacts: {contacts!r} is neither markers nor geometry")
    if contacts == "geometry":
        if args.mode != "adaptive":
            raise UsageError(f"--contacts geometry needs --mode adaptive, not {args.mode!r}")
        kwargs["contacts"] = contacts
    if args.distance is not None:
        kwargs["distance_m"] = parse_quantity(args.distance, "m", what="--distance")
    if args.speed is not None:
        kwargs["speed_m_s"] = parse_quantity(args.speed, "m/s", what="--speed")
    if args.frames is not None and args.hold is not None:
        raise UsageError("--frames and --hold both set n; give one of them")
    if args.frames is not None:
        kwargs["frames"] = int(parse_quantity(args.frames, "frames", what="--frames"))
    if args.hold is not None:
        kwargs["hold_s"] = parse_quantity(args.hold, "s", what="--hold")
    if args.change_window is not None:
        kwargs["change_window_s"] = parse_quantity(args.change_window, "s", what="--change-window")
    if args.merge is not None:
        kwargs["merge_s"] = parse_quantity(args.merge, "s", what="--merge")
    return AasParams(**kwargs)
