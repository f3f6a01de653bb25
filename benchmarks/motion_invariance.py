"""The demonstration's motion features on other takes of the development clips, against the
original: which differ beyond their physical tolerance (docs/motion.md, *Rate and pace*).

    python benchmarks/motion_invariance.py [--clips Stir,Mix] [--takes x0.5,x0.6,x1.6,x2,10Hz,30Hz,60Hz,240Hz]

Each clip is segmented once; every sub-action whose moved object is no hand is measured on the
original and, over the same stretch of the motion (the original frames' times × the time
factor), on each take (``oacdsl/segmentation/takes.py``: ``xK`` stretched K times in time at the
clip's rate, ``NHz`` resampled). One line per sub-action and take with a feature beyond its
tolerance (the tolerances of ``tests/test_motion_invariance.py``; durations compared ÷ K), and a
count per take. No simulator. Only the development clips are offered.
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT), str(ROOT / "tests")]

from test_motion_invariance import DEV, _clip, _close, _gain, _per, _same_stretch  # noqa: E402

from oacdsl.segmentation import takes  # noqa: E402
from oacdsl.segmentation.motion import sub_action_motion  # noqa: E402
from oacdsl.segmentation.poses import fit_poses  # noqa: E402


def _take(name: str):  # type: ignore[no-untyped-def]
    """(the take function, its time factor) of ``xK`` or ``NHz``."""
    if name.endswith("Hz"):
        rate = float(name[:-2])
        return (lambda r: takes.resampled(r, rate)), 1.0
    factor = float(name.lstrip("x"))
    return (lambda r: takes.stretched(r, factor)), factor


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--clips", default=",".join(DEV), help="development clips, comma-separated")
    parser.add_argument("--takes", default="x0.5,x0.6,x1.6,x2,30Hz,60Hz,240Hz", help="takes, comma-separated")
    args = parser.parse_args(argv)
    deg = math.radians(1.0)
    counts: dict[str, int] = {}
    for clip in args.clips.split(","):
        if clip not in DEV:
            print(f"error: {clip!r} is no development clip ({', '.join(DEV)})", file=sys.stderr)
            return 2
        rec, subs, _ = _clip(clip)
        posed = fit_poses(rec)
        motions = [(s, sub_action_motion(rec, s, posed)) for s in subs]
        motions = [(s, m) for s, m in motions if m.features is not None and m.moved != m.hand]
        for name in args.takes.split(","):
            make, factor = _take(name)
            take = make(rec)
            take_posed = fit_poses(take)
            counts.setdefault(name, 0)
            for s, m in motions:
                stretch = _same_stretch(rec, take, factor, s)
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
                }
                if f.period_s is not None:
                    rows["radius_m"] = (f.radius_m, h.radius_m, 0.15, 0.0)
                if m.relation in ("kept", "broken"):
                    rows["tilt_gain_deg"] = (_gain(m) / deg, _gain(g) / deg, 0.0, 6.0)
                wrong = [f"{k} {a if a is None else f'{a:.3g}'} -> {b if b is None else f'{b:.3g}'}"
                         for k, (a, b, rel, ab) in rows.items() if not _close(a, b, rel, ab)]
                if wrong:
                    counts[name] += 1
                    print(f"{clip:6s} {name:6s} sub-action {s.index} {m.moved} -> {m.target or 'world'}: "
                          + "; ".join(wrong))
    print("sub-actions with a feature beyond its tolerance: "
          + ", ".join(f"{k} {v}" for k, v in counts.items()))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
