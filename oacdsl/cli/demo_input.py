"""What ``oacc match`` and ``oacc compose`` share: the options naming a demonstration and a library.

The demonstration is a motion-capture recording, segmented with the options of
``oacc segment``, or a segmentation already made (the ``.json`` that ``oacc
segment --json`` prints); the library is ``--library`` (default ``library/``),
the scene ``--scene``. :func:`oacdsl.pipeline.inputs.load_inputs` reads and
checks them, as for ``oacc reproduce``.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import TYPE_CHECKING

from oacdsl.cli.aas_options import PRESET_HELP, add_aas_options
from oacdsl.cli.reading import add_reading_options, allow_truncated, check_windows, printed_warnings
from oacdsl.errors import MatchingError, OacError, UsageError
from oacdsl.segmentation.params import DEFAULT_MODE

if TYPE_CHECKING:
    from oacdsl.pipeline.inputs import Inputs

__all__ = ["add_input_options", "load_inputs", "located", "note", "transient_s"]


def add_input_options(p: argparse.ArgumentParser) -> None:
    """The demonstration, library and scene arguments, and the segmentation options."""
    p.add_argument("recording", metavar="RECORDING",
                   help="motion capture (.c3d, .mmm.xml, .tsv, .csv) or a segmentation"
                        " (the .json of oacc segment --json)")
    p.add_argument("--library", metavar="DIR", action="append",
                   help="the OAC library: a folder (drafts/ left out) or a file (default: library/);"
                        " repeatable: several are one library (a scene drafted by oacc draft and library/),"
                        " the first folder given gets what compose writes")
    p.add_argument("--scene", metavar="NAME|FILE",
                   help="the scene of the demonstration (default: the library's scene whose tracked"
                        " instances are the recording's marker groups)")
    p.add_argument("--paper", action="store_true",
                   help="match by the paper's rule alone (pre holds before, effects after); default: strict,"
                        " the effects must also account for every changed relation")
    p.add_argument("--transient", metavar="TIME",
                   help="a state shorter than this in which an object (not a Hand) touches nothing between"
                        " two contacts -- a liquid in flight, a dropped object -- splits no sub-action"
                        " (default: 1.5s; 0s = off; docs/matching.md)")
    g = p.add_argument_group("reading and segmenting a recording (as oacc segment; values carry units)")
    g.add_argument(
        "--format",
        metavar="FMT",
        help="read as this format (c3d, mmm, tsv, csv), not by the file's extension",
    )
    g.add_argument("--preset", metavar="NAME", help=PRESET_HELP)
    add_reading_options(g)
    add_aas_options(g)


def load_inputs(args: argparse.Namespace) -> Inputs:
    """Library, scene and demonstration for a ``match``/``compose`` command line."""
    from oacdsl.cli.aas_options import params_from_args
    from oacdsl.pipeline.inputs import load_inputs as load

    if Path(args.recording).suffix.lower() == ".json":
        segmenting = ("format", "preset", "distance", "speed", "hold", "frames", "change_window", "merge")
        given = [f"--{k.replace('_', '-')}" for k in segmenting if getattr(args, k) is not None]
        given += ["--mode"] if args.mode != DEFAULT_MODE else []
        given += ["--allow-truncated"] if allow_truncated(args) else []
        if given:
            raise UsageError(
                f"{', '.join(given)}: these read and segment a recording; {args.recording} is a"
                " segmentation already (.json)"
            )
    params = params_from_args(args)  # bad units fail before any reading
    try:
        with printed_warnings():
            inputs = load(args.recording, args.library or ["library"], args.scene, params, fmt=args.format,
                          preset=args.preset, allow_truncated=allow_truncated(args), segmentations=True,
                          note=note)
    except MatchingError as error:  # no scene, or several, fit the demonstration: name it
        raise located(error, args.recording, args.scene) from None
    for text in inputs.warnings:  # learned files left out of the library (they no longer compile)
        print(f"oacc: warning: {text}", file=sys.stderr)
    if inputs.recording is not None:
        check_windows(args, inputs.recording)
    return inputs


def located(error: MatchingError, recording: str, scene: str | None) -> OacError:
    """``error`` (no scene, or several, fit the demonstration) as every command that reads a
    demonstration reports it (``match``, ``compose``, ``verify``, ``reproduce``).

    Found by the recording's marker groups: an input error (exit 1) named by the recording, which
    is wrong for the library. ``--scene NAME`` naming no scene of the library: a usage error
    (exit 2), as in ``oacc plan`` and ``oacc segment``. An error already located (a scene file)
    stays as it is.
    """
    if error.location is not None:
        return error
    if scene is not None:
        return UsageError(f"--scene: {error.message}")
    return MatchingError(error.message, location=recording)


def transient_s(args: argparse.Namespace) -> float:
    """The ``--transient`` window, seconds (default :data:`~oacdsl.matching.transient.TRANSIENT_S`)."""
    from oacdsl.matching.transient import TRANSIENT_S
    from oacdsl.units import parse_quantity

    if getattr(args, "transient", None) is None:
        return TRANSIENT_S
    value = parse_quantity(args.transient, "s", what="--transient")
    if value < 0:
        raise UsageError(f"--transient must be a duration ≥ 0, got {args.transient!r}")
    return value


def note(text: str) -> None:
    """A note for the user on stderr (``oacc: note: …``), e.g. a marker set recognised unasked."""
    print(f"oacc: note: {text}", file=sys.stderr)
