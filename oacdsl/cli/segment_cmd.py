"""``oacc segment``: cut a motion-capture recording into keyframes where objects start/stop touching."""

from __future__ import annotations

import argparse
import json
import sys
from typing import Any

from oacdsl.cli.aas_options import PRESET_HELP, add_aas_options, params_from_args
from oacdsl.cli.reading import add_reading_options, allow_truncated, check_windows, printed_warnings

DESCRIPTION = """\
Automatic action segmentation (AAS, Wächter et al. 2013, III-A). Two markers of
different instances start touching when they are closer than --distance and their
distance changes slower than --speed for --frames consecutive frames (Eq. 1); they
stop when, for --frames consecutive frames, they are farther or their distance
changes faster (Eq. 2). Instances touch while any pair of their markers touches.
Every change of the world state is a keyframe; keyframes closer than --merge are
merged into the last of them. Frames count from 0 at the file's first frame;
keyframe 0 is the initial world state.

Values carry units: --distance 150mm (or 15cm, 0.15m), --speed 100mm/s,
--merge 0.3s (or 300ms); --frames is a whole number of frames. --frames and
--merge must fit in the recording. A recording that breaks a reader's limits
(rate 1 Hz..10 kHz, finite coordinates, size; docs/readers.md) is an error (exit 1).

--motion adds the demonstrated motion of every sub-action: which object a hand
moved, what it works on (the other side of the relation it makes, breaks or keeps),
and that object's path in the target's frame from a rigid fit of each instance's
markers (>= 3): path length, extent, the period of an oscillation (stirring,
wiping), the tilt reached (pouring). See docs/motion.md.
"""

EPILOG = """\
examples:
  oacc segment demo.c3d
  oacc segment Pour.mmm.xml --json            # KIT/MMM: hands recognised (note on stderr)
  oacc segment demo.c3d --scene library/ --scene-name kitchen --plot aas.png --graphs graphs/
  oacc segment Stir.mmm.xml --motion --plot-motion stir.png   # what moved, relative to what
  oacc segment Cut.mmm.xml --scene library/kit --scene-name kit_cut --contacts geometry
"""


def register(sub: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    p = sub.add_parser(
        "segment",
        help="segment a recording into keyframes of touching relations (AAS)",
        description=DESCRIPTION,
        epilog=EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("recording", metavar="RECORDING", help="a .c3d, .mmm.xml/.xml, .tsv or .csv file")
    p.add_argument("--format", metavar="FMT", help="read as this format, not by the file's extension")
    add_reading_options(p)
    groups = p.add_argument_group("marker groups (default: as the file groups them)")
    groups.add_argument(
        "--scene",
        metavar="PATH",
        action="append",
        help=".oac file or folder (repeatable, loaded as one library) with a scene whose"
        " instances and markers define the groups",
    )
    groups.add_argument("--scene-name", metavar="NAME", help="which scene (needed if there are several)")
    groups.add_argument("--preset", metavar="NAME", help=PRESET_HELP)
    add_aas_options(p.add_argument_group("AAS parameters"))
    out = p.add_argument_group("output")
    out.add_argument("--json", action="store_true", help="print the segmentation as JSON")
    out.add_argument(
        "--plot",
        metavar="OUT.png",
        help="draw distances, thresholds and keyframes over time (the paper's Fig. 3)",
    )
    out.add_argument(
        "--graphs",
        metavar="DIR",
        help="write the world state of every keyframe as a graph picture (the paper's Fig. 4)",
    )
    out.add_argument(
        "--motion",
        action="store_true",
        help="also the demonstrated motion of every sub-action: moved object, target,"
        " path features (with --json: the records, T_target_object per frame)",
    )
    out.add_argument(
        "--plot-motion",
        metavar="OUT.png",
        help="draw each sub-action's object path in its target's frame, one panel each",
    )
    p.set_defaults(func=run)


def load(args: argparse.Namespace) -> Any:
    """The recording, grouped by --scene or --preset when given (and ``args.shapes`` set: the
    scene's shapes, for --contacts geometry)."""
    from oacdsl.errors import UsageError
    from oacdsl.segmentation.readers import read_recording

    if args.scene and args.preset:
        raise UsageError("--scene and --preset both define the marker groups; give one of them")
    with printed_warnings():
        recording = read_recording(args.recording, args.format, allow_truncated=allow_truncated(args))
    check_windows(args, recording)
    recording = apply_grouping(recording, args.preset)
    if args.scene:
        from oacdsl.segmentation.grouping import apply_scene_groups

        scene = pick_scene(args.scene, args.scene_name)
        recording = apply_scene_groups(recording, scene)
        if getattr(args, "contacts", "markers") == "geometry":
            from oacdsl.compiler import load_library
            from oacdsl.segmentation.shapes import scene_shapes

            args.shapes = scene_shapes(load_library(args.scene), scene)
    elif args.scene_name:
        raise UsageError("--scene-name needs --scene FILE")
    elif getattr(args, "contacts", "markers") == "geometry":
        raise UsageError("--contacts geometry needs --scene: the library gives the classes' shapes")
    return recording


def apply_grouping(recording: Any, preset: str | None) -> Any:
    """The recording grouped by ``--preset`` (a name, ``none``, or unset: recognised, with a note)."""
    from oacdsl.segmentation.grouping import group_recording, recognised_note

    recording, recognised = group_recording(recording, preset)
    if recognised is not None:
        print(f"oacc: note: {recognised_note(recording, recognised)}", file=sys.stderr)
    return recording


def pick_scene(paths: list[str], name: str | None) -> Any:
    """The scene ``name`` of the library at ``paths`` (or its only scene)."""
    from oacdsl.compiler import load_library
    from oacdsl.errors import UsageError, did_you_mean

    scenes = load_library(paths).scenes
    where = ", ".join(paths)
    if name is not None:
        if name not in scenes:
            raise UsageError(f"no scene {name!r}{did_you_mean(name, scenes)}", location=where)
        return scenes[name]
    if len(scenes) != 1:
        listed = ", ".join(sorted(scenes)) or "none"
        raise UsageError(f"{len(scenes)} scenes ({listed}); choose one with --scene-name", location=where)
    return next(iter(scenes.values()))


def run(args: argparse.Namespace) -> int:
    from oacdsl.segmentation import segment

    params = params_from_args(args)  # bad units fail before any reading
    from oacdsl.atomic import check_target

    for written in (args.plot, args.plot_motion):  # a FIFO, a device, a read-only file: refused now
        if written:
            check_target(written)
    recording = load(args)
    seg = segment(recording, params, progress=_progress_printer(recording.n_frames),
                  shapes=getattr(args, "shapes", None))
    motions = None
    if args.motion or args.plot_motion:
        from oacdsl.segmentation.motion import sub_action_motions

        motions = sub_action_motions(recording, seg)
    if args.json:
        doc = seg.to_json()
        if args.motion and motions is not None:
            doc["motions"] = [m.to_json() for m in motions]
        print(json.dumps(doc, indent=2))
    else:
        print(format_table(seg))
        if args.motion and motions is not None:
            from oacdsl.cli.motion_table import format_motion_table

            print()
            print(format_motion_table(motions))
    if args.plot_motion or args.plot or args.graphs:
        import matplotlib

        # names are text, not TeX: a group called '$x^$' is no formula (that would fail to parse)
        with matplotlib.rc_context({"text.parse_math": False}):
            _pictures(args, recording, seg, motions)
    return 0


def _pictures(args: argparse.Namespace, recording: Any, seg: Any, motions: Any) -> None:
    """``--plot-motion``, ``--plot`` and ``--graphs``."""
    if args.plot_motion and motions is not None:
        from oacdsl.segmentation.motionplot import save_motion_plot

        written = save_motion_plot(motions, args.plot_motion, title=str(recording.source))
        print(f"wrote {written}", file=sys.stderr)
    if args.plot:
        from oacdsl.segmentation.plots import save_distance_plot

        written = save_distance_plot(recording, seg, args.plot)
        print(f"wrote {written}", file=sys.stderr)
    if args.graphs:
        from oacdsl.segmentation.plots import write_graphs

        files = write_graphs(seg, args.graphs)
        print(f"wrote {len(files)} keyframe graph(s) to {args.graphs}", file=sys.stderr)


def format_table(seg: Any) -> str:
    """The readable summary: one line per keyframe with the relations it adds and removes."""
    from oacdsl.segmentation.plots import change_labels
    from oacdsl.units import format_quantity

    p = seg.parameters
    speed = "off" if p.get("speed_m_s") is None else format_quantity(p["speed_m_s"], "m/s")
    duration = (seg.frames - 1) / seg.rate_hz  # first to last frame, as `oacc inspect` says
    lines = [
        f"{seg.recording}: {seg.frames} frames at {seg.rate_hz:g} Hz ({duration:.2f} s),"
        f" {len(seg.instances)} instances: {', '.join(seg.instances) or '(none)'}",
        f"d = {format_quantity(p['distance_m'], 'm')}, v = {speed}, n = {p['frames']} frames,"
        f" merge = {format_quantity(p['merge_s'], 's')}, mode = {p['mode']}"
        + (
            f", change window = {format_quantity(p['change_window_s'], 's')}"
            if p.get("mode") != "paper" and "change_window_s" in p
            else ""
        )
        + (f", contacts = {p['contacts']}" if p.get("contacts", "markers") != "markers" else ""),
        "",
        f"{'#':>3}  {'frame':>7}  {'time [s]':>9}  relations",
    ]
    prev = None
    for i, k in enumerate(seg.keyframes):
        if prev is None:
            rels = [f"{a} <-> {b}" for a, b in k.state.sorted_relations()]
            changes = ["initial: " + (", ".join(rels) if rels else "nothing touches")]
        else:
            changes = change_labels(prev, k.state)
        lines.append(f"{i:>3}  {k.frame:>7}  {k.time_s:>9.3f}  {changes[0]}")
        lines.extend(f"{'':>3}  {'':>7}  {'':>9}  {c}" for c in changes[1:])
        prev = k.state
    n_sub = max(len(seg.keyframes) - 1, 0)
    lines += ["", f"{len(seg.keyframes)} keyframe(s), {n_sub} sub-action(s)"]
    return "\n".join(lines)


def _progress_printer(total: int) -> Any:
    """Progress on stderr for long recordings when stderr is a terminal, else None."""
    if total < 200_000 or not sys.stderr.isatty():
        return None
    last = [-1]

    def show(done: int, total: int) -> None:
        pct = 100 * done // total
        if pct != last[0]:
            last[0] = pct
            end = "\n" if done >= total else ""
            print(f"\rsegmenting: {pct:3d}% of {total} frames", end=end, file=sys.stderr, flush=True)

    return show
