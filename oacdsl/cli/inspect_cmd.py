"""``oacc inspect``: what a recording holds, before segmenting it.

Prints the frame rate, the number of frames and the duration, the extent of the
markers (a wrong unit shows at once), and every marker group with its markers and
their gap percentages (occluded frames).
"""

from __future__ import annotations

import argparse
import json
from typing import Any

from oacdsl.cli.reading import add_reading_options, allow_truncated, printed_warnings
from oacdsl.segmentation.grouping import PRESETS
from oacdsl.segmentation.readers import FORMATS


def register(sub: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    p = sub.add_parser(
        "inspect",
        help="show a recording's rate, frames, marker groups and gaps",
        description="Read a motion-capture recording (C3D, MMM XML, Qualisys TSV, CSV) and show what it "
        "holds: rate, frames, duration, extent, marker groups with their markers and gap percentages. "
        "A file that breaks a reader's limits (docs/readers.md) is an error here as in segment.",
    )
    p.add_argument("recording", metavar="RECORDING", help="a .c3d, .mmm.xml/.xml, .tsv or .csv file")
    p.add_argument(
        "--format", dest="fmt", choices=sorted(FORMATS), help="file format (default: by extension)"
    )
    p.add_argument(
        "--units",
        choices=["mm", "cm", "m"],
        help="length unit of a TSV/CSV file (default: TSV mm, CSV its '# units:' line or m)",
    )
    p.add_argument(
        "--preset",
        choices=[*sorted(PRESETS), "none"],
        help="marker grouping preset (kit: KIT/MMM hand markers → left_hand, right_hand;"
        " applied unasked when the file has them, with a note on stderr;"
        " none: the file's own groups)",
    )
    add_reading_options(p)
    p.add_argument("--json", action="store_true", help="print the summary as JSON")
    p.set_defaults(func=run)


def summary(recording: Any, fmt: str) -> dict[str, Any]:
    """The facts ``oacc inspect`` prints, as a JSON-ready dict (fractions 0..1, metres, seconds)."""
    import numpy as np

    gaps = np.isnan(recording.positions_m).any(axis=-1)  # (F, M)
    per_marker = gaps.mean(axis=0)
    finite = recording.positions_m[~gaps]

    def markers(idx: Any) -> list[dict[str, Any]]:
        return [{"name": recording.marker_names[i], "gap_fraction": float(per_marker[i])} for i in idx]

    grouped = {i for idx in recording.groups.values() for i in idx}
    return {
        "recording": recording.source,
        "format": fmt,
        "rate_hz": float(recording.rate_hz),
        "frames": recording.n_frames,
        "duration_s": float(recording.times_s[-1]),
        "first_frame": int(recording.first_frame),
        "markers": len(recording.marker_names),
        "gap_fraction": float(gaps.mean()) if gaps.size else 0.0,
        "extent_m": {
            "min": [float(v) for v in finite.min(axis=0)] if finite.size else None,
            "max": [float(v) for v in finite.max(axis=0)] if finite.size else None,
        },
        "groups": [
            {
                "name": name,
                "gap_fraction": float(gaps[:, list(recording.groups[name])].mean()),
                "markers": markers(recording.groups[name]),
            }
            for name in recording.instances
        ],
        "ungrouped": markers(i for i in range(len(recording.marker_names)) if i not in grouped),
    }


def _percent(fraction: float) -> str:
    return "0 %" if fraction == 0 else f"{100 * fraction:.1f} %" if fraction >= 0.001 else "<0.1 %"


def _marker_list(markers: list[dict[str, Any]]) -> str:
    return " ".join(
        m["name"] + (f"({_percent(m['gap_fraction'])})" if m["gap_fraction"] else "") for m in markers
    )


def render(doc: dict[str, Any]) -> str:
    """The readable form of :func:`summary`."""
    lines = [
        f"recording  {doc['recording']}  ({doc['format']})",
        f"rate       {doc['rate_hz']:g} Hz, {doc['frames']} frames, {doc['duration_s']:.2f} s"
        f" (first frame {doc['first_frame']})",
        f"markers    {doc['markers']}, gaps {_percent(doc['gap_fraction'])}",
    ]
    lo, hi = doc["extent_m"]["min"], doc["extent_m"]["max"]
    if lo is not None:
        ranges = (f"{a} {lo[k]:.3f}..{hi[k]:.3f} m" for k, a in enumerate("xyz"))
        lines.append("extent     " + ", ".join(ranges))
    lines.append(f"groups     {len(doc['groups'])}")
    width = max((len(g["name"]) for g in doc["groups"]), default=0)
    for g in doc["groups"]:
        gap = _percent(g["gap_fraction"])
        head = f"  {g['name']:<{width}}  {len(g['markers']):>3} markers  gaps {gap:>7}  "
        lines.append(_wrapped(head, _marker_list(g["markers"])))
    if doc["ungrouped"]:
        lines.append(_wrapped(f"ungrouped  {len(doc['ungrouped'])}: ", _marker_list(doc["ungrouped"])))
    return "\n".join(lines)


def _wrapped(head: str, text: str, width: int = 110) -> str:
    import textwrap

    indent = " " * min(len(head), 40)
    return textwrap.fill(
        text,
        width=width,
        initial_indent=head,
        subsequent_indent=indent,
        break_on_hyphens=False,
        break_long_words=False,
    )


def run(args: argparse.Namespace) -> int:
    from oacdsl.cli.segment_cmd import apply_grouping
    from oacdsl.segmentation.readers import format_of, read_recording

    with printed_warnings():
        recording = read_recording(
            args.recording, args.fmt, units=args.units, allow_truncated=allow_truncated(args)
        )
    recording = apply_grouping(recording, args.preset)
    doc = summary(recording, args.fmt or format_of(args.recording))
    print(json.dumps(doc, indent=2) if args.json else render(doc))
    return 0
