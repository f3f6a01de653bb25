"""Does another take of a demonstration compose to the same OAC? (issue 20's measurement)

For each development clip (``../shared/mocap/kit_bimanual/{Pour,Stir,Mix,Wipe,Scoop,Cut}_*``,
library ``library/kit``) and the bundled ``data/dough.c3d`` (library ``library/``), and each
standard take of :data:`oacdsl.segmentation.takes.STANDARD_TAKES`: the take is written to a
file (MMM XML for a KIT clip, C3D for the dough), read back, segmented, matched and composed
as ``oacc compose`` does (default parameters, strict matching), and its steps (OAC and
binding) are compared with the original's, the hands exchanged for the mirror.

A cell is ``same``, ``differs`` (the first differing step, original → take) or the stage
that failed (``scene``, ``match``, ``compose``) with its message; ``kf`` is the number of
keyframes of the take (the original's in the first column), and the time is the take's
read + segment + match + compose, seconds.

    python benchmarks/takes.py                       # all clips, all takes
    python benchmarks/takes.py --clip Pour --take mirrored --take half_speed
    python benchmarks/takes.py --markdown            # the table for docs/segmentation.md
"""

from __future__ import annotations

import argparse
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from oacdsl.errors import OacError  # noqa: E402
from oacdsl.segmentation.params import AasParams  # noqa: E402
from oacdsl.segmentation.readers import read_recording, write_recording  # noqa: E402
from oacdsl.segmentation.recording import Recording  # noqa: E402
from oacdsl.segmentation.takes import IDENTITY, STANDARD_TAKES  # noqa: E402

DEVELOPMENT = ("Pour", "Stir", "Mix", "Wipe", "Scoop", "Cut")
Steps = list[tuple[str, dict[str, str]]]
#: Per step, its bound preconditions and effects: (negated, the two instances) atoms.
Bound = list[tuple[frozenset, frozenset]]


@dataclass
class Outcome:
    status: str  # same | differs | scene | segment | match | compose
    detail: str
    keyframes: int | None
    seconds: float
    steps: Steps | None = None
    bound: Bound | None = None


def data_folder(given: str | None) -> Path | None:
    if given:
        return Path(given)
    for shared in (ROOT.parent / "shared", ROOT.parents[1] / "shared"):
        if (shared / "mocap" / "kit_bimanual").is_dir():
            return shared / "mocap" / "kit_bimanual"
    return None


def clips(folder: Path | None, wanted: list[str]) -> list[tuple[str, Path, Path]]:
    """(name, recording, library) of each clip asked for."""
    out = []
    for name in wanted:
        if name == "dough":
            out.append(("dough", ROOT / "data" / "dough.c3d", ROOT / "library"))
            continue
        if folder is None:
            sys.exit("kit_bimanual data not found next to the repository; pass --data FOLDER")
        found = sorted(folder.glob(f"{name}_*.mmm.xml"))
        if len(found) != 1:
            sys.exit(f"expected one {name}_*.mmm.xml in {folder}, found {len(found)}")
        out.append((name, found[0], ROOT / "library" / "kit"))
    return out


def _call(step: tuple[str, dict[str, str]]) -> str:
    name, binding = step
    return f"{name}({', '.join(binding.values())})"


def compose_file(path: Path, library: Path, contacts: str = "markers") -> Outcome:
    """Read, segment, match and compose ``path`` as ``oacc compose`` does (``contacts``:
    ``AasParams.contacts``, ``oacc compose --contacts``)."""
    from oacdsl.matching.demonstration import compose_demonstration, match_segmentation
    from oacdsl.matching.matcher import Matcher
    from oacdsl.pipeline.inputs import load_inputs

    start = time.perf_counter()

    def done(status: str, detail: str, kf: int | None, steps: Steps | None = None,
             bound: Bound | None = None) -> Outcome:
        return Outcome(status, detail, kf, time.perf_counter() - start, steps, bound)

    try:
        inputs = load_inputs(path, [library], None, AasParams(contacts=contacts))
    except OacError as err:
        return done("scene", err.message, None)
    try:
        segmentation = inputs.segmented()
    except OacError as err:
        return done("segment", err.message, None)
    kf = len(segmentation.keyframes)
    matcher = Matcher.from_library(inputs.library, inputs.scene, mode="strict")
    matches = match_segmentation(segmentation, matcher, unmerged=inputs.unmerged(), travel=inputs.travel())
    for m in matches:
        if not m.matched:
            sa = m.sub_action
            before, after = set(sa.before), set(sa.after)
            change = [f"+{'<->'.join(sorted(r))}" for r in sorted(after - before, key=sorted)]
            change += [f"-{'<->'.join(sorted(r))}" for r in sorted(before - after, key=sorted)]
            text = (f"sub-action {sa.index + 1} ({sa.start.time_s:.1f}-{sa.end.time_s:.1f} s:"
                    f" {' '.join(change)}) matches no OAC")
            return done("match", text, kf)
    try:
        demo = compose_demonstration("take", matches, inputs.library, inputs.scene)
    except OacError as err:
        return done("compose", err.message, kf)
    steps = [(s.oac.name, dict(s.binding)) for s in demo.composition.steps]
    bound = [(_bind(s.oac.pre, dict(s.binding)), _bind(s.oac.effect, dict(s.binding)))
             for s in demo.composition.steps]
    return done("composed", "", kf, steps, bound)


def _bind(atoms: tuple, binding: dict[str, str]) -> frozenset:  # type: ignore[type-arg]
    return frozenset((a.negated, frozenset((binding.get(a.left, a.left), binding.get(a.right, a.right))))
                     for a in atoms)


def _exchanged(bound: Bound, hands: dict[str, str]) -> Bound:
    def swap(atoms: frozenset) -> frozenset:  # type: ignore[type-arg]
        return frozenset((neg, frozenset(hands.get(x, x) for x in pair)) for neg, pair in atoms)

    return [(swap(pre), swap(effect)) for pre, effect in bound]


def compare(original: Outcome, take: Outcome, hands: dict[str, str]) -> tuple[str, str]:
    """``same``; ``same*``: the same OACs, whose bound preconditions and effects are equal but
    whose arguments come in another order (a symmetric OAC such as grasp_both); else ``differs``."""
    if original.steps is None or take.steps is None or original.bound is None or take.bound is None:
        raise ValueError("compare composed outcomes only")
    expected = [(name, {p: hands.get(v, v) for p, v in b.items()}) for name, b in original.steps]
    got = take.steps
    if got == expected:
        return "same", ""
    first = next((i for i, (a, b) in enumerate(zip(expected, got, strict=False)) if a != b), None)
    if first is None:
        return "differs", f"{len(expected)} steps -> {len(got)}"
    detail = f"step {first + 1}: {_call(expected[first])} -> {_call(got[first])}"
    same_oacs = [n for n, _ in got] == [n for n, _ in expected]
    if same_oacs and take.bound == _exchanged(original.bound, hands):
        return "same*", detail
    return "differs", detail


def run_take(
    rec: Recording, take_name: str, library: Path, suffix: str, folder: Path, contacts: str = "markers"
) -> tuple[Outcome, dict[str, str]]:
    take, hands = STANDARD_TAKES[take_name](rec)
    path = write_recording(take, folder / f"{take_name}{suffix}")
    return compose_file(path, library, contacts), hands


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--data", help="the kit_bimanual folder (default: ../shared/mocap/kit_bimanual)")
    parser.add_argument("--clip", action="append", choices=[*DEVELOPMENT, "dough"],
                        help="a clip (repeatable; default: the six development clips and dough)")
    parser.add_argument("--take", action="append", choices=list(STANDARD_TAKES),
                        help="a standard take (repeatable; default: all seven)")
    parser.add_argument("--markdown", action="store_true", help="print a Markdown table")
    parser.add_argument("--contacts", choices=("markers", "geometry"), default="markers",
                        help="contacts between markers (default) or from the library's shapes")
    args = parser.parse_args(argv)
    wanted = args.clip or [*DEVELOPMENT, "dough"]
    take_names = args.take or list(STANDARD_TAKES)
    rows = []
    with tempfile.TemporaryDirectory(prefix="oac-takes-") as tmp:
        for name, path, library in clips(data_folder(args.data), wanted):
            folder = Path(tmp) / name
            folder.mkdir()
            suffix = ".c3d" if path.suffix == ".c3d" else ".mmm.xml"
            rec = read_recording(path)
            base = compose_file(path, library, args.contacts)
            cells: list[Outcome] = []
            for take_name in take_names:
                if base.steps is None:
                    cells.append(Outcome("-", "original fails", None, 0.0))
                    continue
                outcome, hands = run_take(rec, take_name, library, suffix, folder, args.contacts)
                if outcome.steps is not None:
                    outcome.status, outcome.detail = compare(base, outcome, hands or dict(IDENTITY))
                cells.append(outcome)
                print(f"{name:6} {take_name:18} {outcome.status:8} kf {outcome.keyframes} "
                      f"{outcome.seconds:5.1f}s {outcome.detail}", file=sys.stderr, flush=True)
            rows.append((name, base, cells))
    same = sum(c.status == "same" for _, _, cells in rows for c in cells)
    symmetric = sum(c.status == "same*" for _, _, cells in rows for c in cells)
    total = sum(len(cells) for _, _, cells in rows)
    if args.markdown:
        print("| clip (steps, kf) | " + " | ".join(take_names) + " |")
        print("|---" * (len(take_names) + 1) + "|")
        for name, base, cells in rows:
            head = f"{name} ({len(base.steps)}, {base.keyframes})" if base.steps else f"{name} (fails)"
            print(f"| {head} | " + " | ".join(_cell(c) for c in cells) + " |")
        print(f"\n{same} of {total} takes compose to the same steps, {symmetric} more to the same steps"
              " with a symmetric OAC's arguments in another order (same*).")
        failures = [(n, t, c) for n, _, cells in rows for t, c in zip(take_names, cells, strict=True)
                    if c.status != "same"]
        if failures:
            print("\nFirst difference of each other take:\n")
            for n, t, c in failures:
                print(f"- {n} {t}: {c.status}: {c.detail}")
        return 0
    width = max(len(t) for t in take_names)
    for name, base, cells in rows:
        print(f"{name}: original {base.status}, {len(base.steps or [])} steps, {base.keyframes} keyframes,"
              f" {base.seconds:.1f} s {base.detail}")
        for take_name, c in zip(take_names, cells, strict=True):
            print(f"  {take_name:{width}}  {c.status:8} kf {c.keyframes}  {c.seconds:5.1f} s  {c.detail}")
    print(f"{same} of {total} takes compose to the same steps, {symmetric} more up to a symmetric OAC's"
          " argument order")
    return 0


def _cell(c: Outcome) -> str:
    return f"{c.status} ({c.keyframes} kf, {c.seconds:.1f} s)" if c.keyframes is not None else c.status


if __name__ == "__main__":
    sys.exit(main())
