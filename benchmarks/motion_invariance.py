"""The demonstration's motion features on other takes of the development clips, against the
original: which differ beyond their physical tolerance (docs/motion.md, *Rate and pace*).

    python benchmarks/motion_invariance.py [--clips Stir,Mix] [--takes x0.5,x0.6,x1.6,x2,10Hz,30Hz,60Hz,240Hz]

Each clip is segmented once; every sub-action whose moved object is no hand is measured on the
original and, over the same stretch of the motion (the original frames' times × the time
factor), on each take (``oacdsl/segmentation/takes.py``: ``xK`` stretched K times in time at the
clip's rate, ``NHz`` resampled). One line per sub-action and take with a feature beyond its
tolerance (``beyond_tolerance``, which ``tests/test_motion_invariance.py`` asserts empty on the
takes holding every original frame; durations compared ÷ K), and a count per take. No
simulator. Only the development clips are offered.
"""

from __future__ import annotations

import argparse
import functools
import math
import sys
from collections.abc import Callable, Iterable, Iterator
from dataclasses import replace
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT), str(ROOT / "tests")]

from _mocap import mocap_file  # noqa: E402
from kit_reproduce import DEV  # noqa: E402

from oacdsl.matching.transient import agents_of, stable_segmentation  # noqa: E402
from oacdsl.pipeline import load_inputs  # noqa: E402
from oacdsl.segmentation import AasParams, segment, takes  # noqa: E402
from oacdsl.segmentation.motion import SubActionMotion, sub_action_motion  # noqa: E402
from oacdsl.segmentation.poses import fit_poses  # noqa: E402
from oacdsl.segmentation.recording import Recording  # noqa: E402
from oacdsl.segmentation.result import SubAction  # noqa: E402
from oacdsl.verify_motion import tilt_gain  # noqa: E402

#: Largest difference of a tilt gain between two takes of the same motion, radians: the
#: verifier's tolerance is 35°, its threshold 45°.
TILT_NOISE_RAD = math.radians(6.0)
#: A take: (its name, the function making it from the original, its time factor).
Take = tuple[str, Callable[[Recording], Recording], float]
#: Features beyond their tolerance: name → (on the original, on the take).
Beyond = dict[str, tuple[float | None, float | None]]


@functools.cache
def dev_clip(name: str) -> tuple[Recording, tuple[SubAction, ...], frozenset[str]]:
    """A development clip's recording, its stable sub-actions and its agents (the test skips
    without the recordings)."""
    inputs = load_inputs(mocap_file(f"kit_bimanual/{DEV[name]}"), ROOT / "library" / "kit", None, AasParams())
    agents = agents_of(inputs.library.instance_classes(inputs.scene))
    seg = stable_segmentation(segment(inputs.recording, inputs.params), agents.__contains__)[0]
    return inputs.recording, tuple(seg.sub_actions()), frozenset(agents)


def tilt_gain_rad(m: SubActionMotion) -> float:
    """The tilt the verifier reads the sub-action to gain, radians."""
    return tilt_gain(m.T_target_object, m.times_s)


def same_stretch(rec: Recording, take: Recording, factor: float, sub: SubAction) -> SubAction:
    """``sub`` on ``take``: its frames nearest the original frames' times × ``factor``."""
    t = np.asarray(take.times_s, dtype=np.float64)

    def frame(k: int) -> int:
        return int(np.argmin(np.abs(t - rec.times_s[k] * factor)))

    return replace(sub, start=replace(sub.start, frame=frame(sub.start.frame)),
                   end=replace(sub.end, frame=frame(sub.end.frame)))


def _per(value: float | None, factor: float) -> float | None:
    """A duration of a take in the original's time (÷ the time factor)."""
    return None if value is None else value / factor


def _close(a: float | None, b: float | None, rel: float, absolute: float) -> bool:
    if a is None or b is None:
        return a is None and b is None
    return abs(a - b) <= rel * abs(a) + absolute


def beyond_tolerance(clip: str, variants: Iterable[Take]
                     ) -> Iterator[tuple[str, SubAction, SubActionMotion, Beyond]]:
    """(take name, sub-action, its motion on the original, {feature: (original, take)}) for every
    sub-action of ``clip`` moving no hand with a feature beyond its tolerance on a take.

    What the verifier and the skills read (lengths, extents, tilts, turns, the oscillation;
    durations × the time factor) within a frame's worth of each: 3 % (5 % for the extent, whose
    principal axes are those of the frames) and 3 mm, 3°, 5° of a twist, 5 % of a period, 10 % of
    the cycles, 15 % + 0.1 s of the tilt's rise and time, 0.1 s of the duration, 15 % of the radius
    (only where there is an oscillation: the skills read it only then), 6° of the tilt gain (where
    the relation is kept or broken). Angles are compared and given in degrees."""
    deg = math.radians(1.0)
    rec, subs, _ = dev_clip(clip)
    posed = fit_poses(rec)
    motions = [(s, sub_action_motion(rec, s, posed)) for s in subs]
    motions = [(s, m) for s, m in motions if m.features is not None and m.moved != m.hand]
    for name, make, factor in variants:
        take = make(rec)
        take_posed = fit_poses(take)
        for s, m in motions:
            stretch = same_stretch(rec, take, factor, s)
            g = sub_action_motion(take, stretch, take_posed, (m.moved, m.target))
            f, h = m.features, g.features
            assert f is not None and h is not None
            rows = {
                "path_length_m": (f.path_length_m, h.path_length_m, 0.03, 0.003),
                "extent_m": (f.extent_m[0], h.extent_m[0], 0.05, 0.003),
                "tilt_max_deg": (math.degrees(f.tilt_max_rad), math.degrees(h.tilt_max_rad), 0.0, 3.0),
                "end_tilt_deg": (math.degrees(f.end_tilt_rad), math.degrees(h.end_tilt_rad), 0.0, 3.0),
                "twist_deg": (math.degrees(f.twist_rad), math.degrees(h.twist_rad), 0.0, 5.0),
                "period_s": (f.period_s, _per(h.period_s, factor), 0.05, 0.0),
                "cycles": (f.cycles, h.cycles, 0.10, 0.0),
                "tilt_rise_s": (f.tilt_rise_s, _per(h.tilt_rise_s, factor), 0.15, 0.1),
                "tilt_time_s": (f.tilt_time_s, _per(h.tilt_time_s, factor), 0.15, 0.1),
                "duration_s": (f.duration_s, _per(h.duration_s, factor), 0.0, 0.1),
            }
            if f.period_s is not None:
                rows["radius_m"] = (f.radius_m, h.radius_m, 0.15, 0.0)
            if m.relation in ("kept", "broken"):
                noise_deg = TILT_NOISE_RAD / deg
                rows["tilt_gain_deg"] = (tilt_gain_rad(m) / deg, tilt_gain_rad(g) / deg, 0.0, noise_deg)
            wrong = {k: (a, b) for k, (a, b, rel, ab) in rows.items() if not _close(a, b, rel, ab)}
            if wrong:
                yield name, s, m, wrong


def _take(name: str) -> Take:
    """The take ``xK`` or ``NHz``."""
    if name.endswith("Hz"):
        rate = float(name[:-2])
        return name, (lambda r: takes.resampled(r, rate)), 1.0
    factor = float(name.lstrip("x"))
    return name, (lambda r: takes.stretched(r, factor)), factor


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--clips", default=",".join(DEV), help="development clips, comma-separated")
    parser.add_argument("--takes", default="x0.5,x0.6,x1.6,x2,30Hz,60Hz,240Hz", help="takes, comma-separated")
    args = parser.parse_args(argv)
    counts = dict.fromkeys(args.takes.split(","), 0)
    for clip in args.clips.split(","):
        if clip not in DEV:
            print(f"error: {clip!r} is no development clip ({', '.join(DEV)})", file=sys.stderr)
            return 2
        for name, s, m, wrong in beyond_tolerance(clip, [_take(n) for n in counts]):
            counts[name] += 1
            print(f"{clip:6s} {name:6s} sub-action {s.index} {m.moved} -> {m.target or 'world'}: "
                  + "; ".join(f"{k} {a if a is None else f'{a:.3g}'} -> {b if b is None else f'{b:.3g}'}"
                              for k, (a, b) in wrong.items()))
    print("sub-actions with a feature beyond its tolerance: "
          + ", ".join(f"{k} {v}" for k, v in counts.items()))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
