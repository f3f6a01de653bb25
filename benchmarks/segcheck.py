"""Do two versions of the segmentation give the same keyframes? (a check for changes that must
not change any result, such as speed-ups)

Segments a fixed set of inputs and writes each segmentation (``oacc segment --json``'s document:
keyframe frames, times, event times below the frame, relations, the parameters in force) as one
line of a JSON-lines file; ``--against FILE`` compares with a file written before the change and
prints every input whose segmentation differs (exit 1 if any).

The inputs: each KIT development clip (``../shared/mocap/kit_bimanual``: Pour, Stir, Mix, Wipe,
Scoop, Cut) and the bundled dough, original and its seven standard takes, written to a file and
read back as ``benchmarks/takes.py`` does, segmented as ``oacc compose`` does (default
parameters, merged and unmerged; the originals also ``--mode paper`` and ``--contacts
geometry``); the synthetic task demonstrations of ``tests/_task_demos.py`` under the clean, KIT-like
and 10 Hz captures (the KIT-like ones through the standard takes too); the synthetic dough at four
rates with 0.5 mm jitter and with a second of flight (``tests/test_synth_robust.py``); and
``benchmarks/segmentation.py``'s random-walk recording (``table`` and ``dense``, two minutes).

    python benchmarks/segcheck.py --out before.jsonl          # on the old version
    python benchmarks/segcheck.py --against before.jsonl      # on the new one
    python benchmarks/segcheck.py --quick --against before.jsonl   # originals only, no takes
"""

from __future__ import annotations

import argparse
import json
import sys
import tempfile
import time
from collections.abc import Callable, Iterator
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT), str(ROOT / "tests"), str(ROOT / "benchmarks")]

import takes as bench  # noqa: E402

from oacdsl.segmentation import AasParams, segment  # noqa: E402
from oacdsl.segmentation.readers import write_recording  # noqa: E402
from oacdsl.segmentation.recording import Recording  # noqa: E402
from oacdsl.segmentation.result import Segmentation  # noqa: E402
from oacdsl.segmentation.takes import STANDARD_TAKES  # noqa: E402

Case = tuple[str, Callable[[], Segmentation]]


def _document(seg: Segmentation) -> dict:  # type: ignore[type-arg]
    doc = seg.to_json()
    doc.pop("recording")  # a temporary file's name
    return doc


def _file_cases(name: str, path: Path, library: list[Path], variants: bool) -> Iterator[Case]:
    """Segmentations of the recording file ``path`` as ``oacc compose`` makes them."""
    from oacdsl.pipeline.inputs import load_inputs

    modes = [("default", AasParams())]
    if variants:
        modes += [("paper", AasParams(mode="paper")), ("geometry", AasParams(contacts="geometry"))]
    for label, params in modes:
        inputs = load_inputs(path, library, None, params)
        yield f"{name} {label}", inputs.segmented
        if label == "default":
            unmerged = inputs.unmerged()
            if unmerged is not None:
                yield f"{name} {label} unmerged", unmerged


def _with_takes(name: str, rec: Recording, original: Path, library: list[Path], suffix: str,
                folder: Path, takes: bool) -> Iterator[Case]:
    yield from _file_cases(f"{name} original", original, library, variants=True)
    if not takes:
        return
    for take_name, make in STANDARD_TAKES.items():
        take, _hands = make(rec)
        path = write_recording(take, folder / f"{name}-{take_name}{suffix}")
        yield from _file_cases(f"{name} {take_name}", path, library, variants=False)


def cases(folder: Path, takes: bool) -> Iterator[Case]:
    """(label, a function segmenting one input) of every input (module doc)."""
    import _task_demos as demos
    from segmentation import SCENARIOS, make_recording

    from oacdsl.segmentation.readers import read_recording
    from oacdsl.segmentation.synth import dough_demonstration
    from oacdsl.segmentation.synth.realism import NoiseModel

    for name, path, library in bench.clips(bench.data_folder(None), [*bench.DEVELOPMENT, "dough"]):
        suffix = ".c3d" if path.suffix == ".c3d" else ".mmm.xml"
        yield from _with_takes(name, read_recording(path), path, [library], suffix, folder, takes)
    libs = [ROOT / "library" / "kit", ROOT / "library" / "examples"]
    captures = {"clean": demos.CLEAN, "kit": demos.KIT_LIKE, "kit10": demos.KIT_10HZ}
    for task in demos.TASKS:
        for capture_name, capture in captures.items():
            rec = demos.TASKS[task][0](capture)
            path = write_recording(rec, folder / f"{task}-{capture_name}.c3d")
            label = f"synthetic {task} {capture_name}"
            if capture_name == "kit":
                yield from _with_takes(label, rec, path, libs, ".c3d", folder, takes)
            else:
                yield from _file_cases(label, path, libs, variants=False)
    for rate, seed in ((50.0, 11), (100.0, 12), (200.0, 13), (240.0, 14)):
        demo = dough_demonstration(seed, rate_hz=rate, noise=NoiseModel(white_m=0.0005))
        yield f"synthetic dough {rate:g} Hz seed {seed}", lambda r=demo.recording: segment(r, AasParams())
    flight = dough_demonstration(4, flight_s=1.0).recording
    yield "synthetic dough flight 1 s", lambda: segment(flight, AasParams())
    for scenario in SCENARIOS:
        walk = make_recording(2.0, SCENARIOS[scenario], seed=0)
        for mode in ("paper", "adaptive"):
            yield f"random walk {scenario} {mode}", lambda r=walk, m=mode: segment(r, AasParams(mode=m))


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", help="write the segmentations here (JSON lines)")
    parser.add_argument("--against", help="compare with segmentations written before")
    parser.add_argument("--quick", action="store_true", help="originals only, no standard takes")
    args = parser.parse_args(argv)
    if not args.out and not args.against:
        parser.error("give --out FILE, --against FILE or both")
    before: dict[str, dict] = {}  # type: ignore[type-arg]
    if args.against:
        with open(args.against) as f:
            before = {row["case"]: row["segmentation"] for row in map(json.loads, f)}
    rows, differ, missing = [], [], []
    start = time.process_time()
    with tempfile.TemporaryDirectory(prefix="oac-segcheck-") as tmp:
        for label, run in cases(Path(tmp), takes=not args.quick):
            doc = _document(run())
            rows.append({"case": label, "segmentation": doc})
            if args.against:
                if label not in before:
                    missing.append(label)
                elif before[label] != doc:
                    differ.append(label)
                    print(f"DIFFERS: {label}", file=sys.stderr, flush=True)
    if args.out:
        with open(args.out, "w") as f:
            for row in rows:
                f.write(json.dumps(row, sort_keys=True) + "\n")
    print(f"{len(rows)} segmentations, {sum(len(r['segmentation']['keyframes']) for r in rows)} keyframes,"
          f" {time.process_time() - start:.0f} s CPU")
    if args.against:
        print(f"{len(rows) - len(differ) - len(missing)} identical, {len(differ)} differ,"
              f" {len(missing)} not in {args.against}")
        for label in differ:
            print(f"  differs: {label}")
    return 1 if differ else 0


if __name__ == "__main__":
    sys.exit(main())
