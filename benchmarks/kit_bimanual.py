"""Accuracy of the hand–object contact keyframes on the KIT bimanual clips.

For each clip in ``../shared/mocap/kit_bimanual`` the MMM recording is read (its KIT
marker set is recognised: left_hand, right_hand, one group per object), segmented, and

- the contact starts and ends of each hand are scored against the dataset's own per-frame
  labels (contact = Move, Hold, Place or the main action) within ±3 frames; see
  :mod:`segeval.evaluate`;
- the contacts of the tool with what it works on during the main action are scored
  against the clip's tool–target pairs, and the frames where a hand touches the object
  the other hand holds are counted; see :mod:`segeval.toolscore`.

Development clips (Pour, Stir, Mix, Wipe, Scoop, Cut) are always scored. The evaluation
clips (Open, Close, Peel, RollOut, Transfer) are scored only with ``--evaluation``, in
a separate block: nothing may be tuned on them.

    python benchmarks/kit_bimanual.py                      # paper mode, default parameters
    python benchmarks/kit_bimanual.py --mode paper --mode adaptive
    python benchmarks/kit_bimanual.py --distance 100mm --speed 50mm/s --frames 2 --merge 0.3s
    python benchmarks/kit_bimanual.py --evaluation         # adds the held-out block
    python benchmarks/kit_bimanual.py --mode adaptive --contacts geometry --library library/kit
    python benchmarks/kit_bimanual.py --mode adaptive --take standard     # the seven standard takes
    python benchmarks/kit_bimanual.py --mode adaptive --take sweep --take double_speed

``--take NAME`` scores another take of each clip instead (a standard take of
:data:`oacdsl.segmentation.takes.STANDARD_TAKES`, a variation of ``benchmarks/takesweep.py``,
``standard``: all seven, ``sweep``: all its variations): the take's segmentation is put on the
original's frames (the state each original frame's moment shows) and scored against the
original's labels, the hands exchanged for the mirror (:mod:`segeval.takelabels`); a summary
line per take follows the blocks.
"""

from __future__ import annotations

import argparse
import json
import sys
from dataclasses import replace
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from segeval.evaluate import (  # noqa: E402
    ClipScore,
    Score,
    contact_from_labels,
    nearest_object,
    read_labels,
    score_clip,
)
from segeval.takelabels import labels_for_take, on_original_grid, stated_factor  # noqa: E402
from segeval.toolscore import KIT_TOOL_TARGETS, ToolScore, cross_hand_frames, score_tools  # noqa: E402

from oacdsl.library import Library  # noqa: E402
from oacdsl.segmentation import AasParams, segment  # noqa: E402
from oacdsl.segmentation.grouping import recognise_preset  # noqa: E402
from oacdsl.segmentation.readers import read_recording  # noqa: E402
from oacdsl.segmentation.shapes import ShapeModel, scene_shapes  # noqa: E402
from oacdsl.segmentation.takes import STANDARD_TAKES, Take  # noqa: E402
from oacdsl.units import parse_quantity  # noqa: E402

DEVELOPMENT = ("Pour", "Stir", "Mix", "Wipe", "Scoop", "Cut")
EVALUATION = ("Open", "Close", "Peel", "RollOut", "Transfer")


def data_folder(given: str | None) -> Path:
    if given:
        return Path(given)
    for shared in (ROOT.parent / "shared", ROOT.parents[1] / "shared"):
        if (shared / "mocap" / "kit_bimanual").is_dir():
            return shared / "mocap" / "kit_bimanual"
    sys.exit("kit_bimanual data not found next to the repository; pass --data FOLDER")


def clip_files(folder: Path, action: str) -> tuple[Path, Path]:
    found = sorted(folder.glob(f"{action}_*.mmm.xml"))
    if len(found) != 1:
        sys.exit(f"expected one {action}_*.mmm.xml in {folder}, found {len(found)}")
    xml = found[0]
    return xml, xml.with_name(xml.name[: -len(".mmm.xml")] + ".labels.csv")


def clip_shapes(library: Library | None, action: str) -> dict[str, ShapeModel] | None:
    """The shapes of the clip's scene ``kit_<action>`` in ``library`` (None without one)."""
    if library is None:
        return None
    scene = library.scenes.get(f"kit_{action.lower()}")
    return scene_shapes(library, scene) if scene is not None else {}


def takes() -> dict[str, Take]:
    """The takes ``--take`` knows: the standard seven and ``benchmarks/takesweep.py``'s variations."""
    sys.path.insert(0, str(ROOT / "benchmarks"))
    from takesweep import SWEEP

    return {**STANDARD_TAKES, **SWEEP}


def run_clip(folder: Path, action: str, params: AasParams, tolerance: int,
             library: Library | None = None,
             take: Take | None = None) -> tuple[ClipScore, dict[str, Any], ToolScore, dict[str, int]]:
    xml, labels_path = clip_files(folder, action)
    recording, preset = recognise_preset(read_recording(xml))
    if preset != "kit":
        sys.exit(f"{xml}: the KIT marker set was not recognised")
    labels = read_labels(labels_path)
    if take is not None:  # another take, on the original's frames, against its labels
        objects = {g: recording.group_positions(g) for g in recording.instances if g not in labels}
        nearest = {hand: nearest_object(recording.group_positions(hand), objects, contact_from_labels(lab))
                   for hand, lab in labels.items()}
        taken, hands = take(recording)
        segmentation = on_original_grid(segment(taken, params, shapes=clip_shapes(library, action)),
                                        recording.times_s, taken.times_s, stated_factor(taken.source))
        labels = labels_for_take(labels, hands)
        reference = {hands.get(hand, hand): obj for hand, obj in nearest.items()}
        result = score_clip(action, segmentation, labels, tolerance)
        tools = score_tools(action, segmentation, labels, KIT_TOOL_TARGETS[action], tolerance)
        return result, reference, tools, cross_hand_frames(segmentation, reference)
    segmentation = segment(recording, params, shapes=clip_shapes(library, action))
    if "geometry" in segmentation.parameters:
        measured = segmentation.parameters["geometry"].items()
        print(f"  {action}: " + ", ".join(f"{i} {how}" for i, how in measured))
    result = score_clip(action, segmentation, labels, tolerance)
    objects = {g: recording.group_positions(g) for g in recording.instances if g not in labels}
    reference = {hand: nearest_object(recording.group_positions(hand), objects, contact_from_labels(lab))
                 for hand, lab in labels.items()}
    tools = score_tools(action, segmentation, labels, KIT_TOOL_TARGETS[action], tolerance)
    return result, reference, tools, cross_hand_frames(segmentation, reference)


def describe(params: AasParams) -> str:
    n = "auto" if params.frames is None else str(params.frames)
    return (f"mode {params.mode}: d = {params.distance_m * 1000:g} mm, v = {params.speed_m_s * 1000:g} mm/s,"
            f" n = {n} frames, merge = {params.merge_s:g} s")


def block(title: str, folder: Path, actions: tuple[str, ...], params: AasParams, tolerance: int,
          verbose: bool, library: Library | None = None, take: Take | None = None) -> dict[str, Any]:
    print(f"  {title}")
    print(f"  {'clip':<9} {'P':>5} {'R':>5} {'F1':>5}  {'match/pred/lab':>14}  frames  touching (L | R)")
    total = Score()
    tool_total = Score()
    clips = []
    tool_lines = []
    for action in actions:
        result, reference, tools, cross = run_clip(folder, action, params, tolerance, library, take)
        total += result.score
        tool_total += tools.score
        tool_lines.append(tool_text(tools, cross))
        s = result.score
        agree = sum(result.frame_agreement.values()) / len(result.frame_agreement)

        def hand_text(hand: str, res: ClipScore = result, ref: dict[str, Any] = reference) -> str:
            found = ",".join(f"{o}({n})" for o, n in res.touched[hand].items()) or "-"
            mark = "" if ref[hand] is None or ref[hand] in res.touched[hand] else f" (expected {ref[hand]})"
            return found + mark

        print(f"  {action:<9} {s.precision:5.2f} {s.recall:5.2f} {s.f1:5.2f}  "
              f"{s.matched:>4}/{s.predicted:>3}/{s.labelled:>3}    {agree:5.1%}  "
              f"{hand_text('left_hand')} | {hand_text('right_hand')}")
        if verbose:
            print(f"      labelled:  {[(e.hand[0], e.kind, e.frame) for e in result.labelled]}")
            print(f"      predicted: {[(e.hand[0], e.kind, e.frame) for e in result.predicted]}")
        clips.append({"clip": action, "precision": s.precision, "recall": s.recall, "f1": s.f1,
                      "matched": s.matched, "predicted": s.predicted, "labelled": s.labelled,
                      "frame_agreement": result.frame_agreement, "touched": result.touched,
                      "nearest_in_labelled_contact": reference,
                      "tool_target": {"precision": tools.score.precision, "recall": tools.score.recall,
                                      "f1": tools.score.f1, "labelled": tools.labelled,
                                      "predicted": tools.predicted, "window": list(tools.window),
                                      "coverage": {f"{t}-{g}": c for (t, g), c in tools.coverage.items()},
                                      "not_scored": tools.other},
                      "cross_hand_frames": cross})
    print(f"  {'overall':<9} {total.precision:5.2f} {total.recall:5.2f} {total.f1:5.2f}  "
          f"{total.matched:>4}/{total.predicted:>3}/{total.labelled:>3}")
    print("  tool-target contacts during the main action (tool's contacts scored; coverage = labelled"
          " pair's share of main-action frames); cross-hand frames L | R")
    print(f"  {'clip':<9} {'P':>5} {'R':>5} {'F1':>5}  {'match/pred/lab':>14}  found / coverage / cross-hand")
    for line in tool_lines:
        print(line)
    print(f"  {'overall':<9} {tool_total.precision:5.2f} {tool_total.recall:5.2f} {tool_total.f1:5.2f}  "
          f"{tool_total.matched:>4}/{tool_total.predicted:>3}/{tool_total.labelled:>3}")
    return {"clips": clips,
            "overall": {"precision": total.precision, "recall": total.recall, "f1": total.f1,
                        "matched": total.matched, "predicted": total.predicted, "labelled": total.labelled},
            "tool_target": {"precision": tool_total.precision, "recall": tool_total.recall,
                            "f1": tool_total.f1, "matched": tool_total.matched,
                            "predicted": tool_total.predicted, "labelled": tool_total.labelled}}


def tool_text(tools: ToolScore, cross: dict[str, int]) -> str:
    s = tools.score
    labelled = {frozenset(p) for p in tools.labelled}
    found = ", ".join(f"{t}-{o}" + ("" if frozenset((t, o)) in labelled else " (extra)")
                      for t, o in tools.predicted) or "-"
    coverage = ", ".join(f"{c:.0%}" for c in tools.coverage.values()) or "-"
    dash = f"{'-':>5} {'-':>5} {'-':>5}"
    scored = f"{s.precision:5.2f} {s.recall:5.2f} {s.f1:5.2f}" if tools.labelled else dash
    return (f"  {tools.action:<9} {scored}  {s.matched:>4}/{s.predicted:>3}/{s.labelled:>3}    {found} / "
            f"{coverage} / {cross.get('left_hand', 0)} | {cross.get('right_hand', 0)}")


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--data", help="the kit_bimanual folder (default: ../shared/mocap/kit_bimanual)")
    ap.add_argument("--mode", action="append", help="touch detector(s) to compare (default: paper)")
    ap.add_argument("--distance", help="d, e.g. 150mm (default: the mode's default)")
    ap.add_argument("--speed", help="v, e.g. 100mm/s")
    ap.add_argument("--frames", type=int, help="n, frames")
    ap.add_argument("--merge", help="merge window, e.g. 0.3s")
    ap.add_argument("--contacts", choices=("markers", "geometry"), default="markers",
                    help="contacts between markers, or from the shapes of --library (mode adaptive)")
    ap.add_argument("--library", help="the library whose scenes kit_<clip> give the shapes (library/kit)")
    ap.add_argument("--tolerance", type=int, default=3, help="frames an event may be off (default 3)")
    ap.add_argument("--evaluation", action="store_true",
                    help="also score the held-out evaluation clips (never tune on them)")
    ap.add_argument("--verbose", action="store_true", help="print the events of each clip")
    ap.add_argument("--json", metavar="OUT", help="also write the figures to this JSON file")
    ap.add_argument("--take", action="append", metavar="NAME",
                    help="score this take of each development clip instead (repeatable; a standard take,"
                         " a takesweep.py variation, 'standard' for all seven, 'sweep' for all variations)")
    args = ap.parse_args(argv)
    known = takes() if args.take else {}
    chosen: list[str] = []
    groups = {"standard": list(STANDARD_TAKES), "sweep": [n for n in known if n not in STANDARD_TAKES]}
    for name in args.take or []:
        if name not in groups and name not in known:
            ap.error(f"--take {name}: not a take; one of standard, sweep, {', '.join(known)}")
        chosen += groups.get(name, [name])
    if chosen and args.evaluation:
        ap.error("--take scores the development clips only; drop --evaluation")
    folder = data_folder(args.data)
    library = None
    if args.library:
        from oacdsl.compiler import load_library

        library = load_library([args.library])
    report: dict[str, Any] = {}
    for mode in args.mode or ["paper"]:
        params = AasParams(mode=mode, contacts=args.contacts)
        if args.distance:
            params = replace(params, distance_m=parse_quantity(args.distance, "m"))
        if args.speed:
            params = replace(params, speed_m_s=parse_quantity(args.speed, "m/s"))
        if args.frames:
            params = replace(params, frames=args.frames)
        if args.merge:
            params = replace(params, merge_s=parse_quantity(args.merge, "s"))
        print(describe(params) + f", events matched within ±{args.tolerance} frames")
        if chosen:
            report[mode] = {"parameters": params.to_dict(), "takes": {}}
            for name in chosen:
                title = f"development clips, take {name}"
                report[mode]["takes"][name] = block(title, folder, DEVELOPMENT, params, args.tolerance,
                                                    args.verbose, library, known[name])
            print(f"  {'take':<28} {'hand P':>6} {'R':>5} {'F1':>5}  {'tools F1':>8}  clips below 1.00")
            for name, got in report[mode]["takes"].items():
                hand, tool = got["overall"], got["tool_target"]
                low = ", ".join(f"{c['clip']} {c['f1']:.2f}" for c in got["clips"] if c["f1"] < 1.0) or "-"
                print(f"  {name:<28} {hand['precision']:6.2f} {hand['recall']:5.2f} {hand['f1']:5.2f}"
                      f"  {tool['f1']:8.2f}  {low}")
            print()
            continue
        report[mode] = {"parameters": params.to_dict(),
                        "development": block("development clips", folder, DEVELOPMENT, params,
                                             args.tolerance, args.verbose, library)}
        if args.evaluation:
            report[mode]["evaluation"] = block("EVALUATION clips (held out: report only, never tune)",
                                               folder, EVALUATION, params, args.tolerance, args.verbose,
                                               library)
        print()
    if args.json:
        Path(args.json).write_text(json.dumps(report, indent=2), encoding="utf-8")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
