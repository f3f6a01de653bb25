"""The ground truth of a synthetic demonstration: intended keyframes, sub-actions, realism features.

The world states are the script's; their frames are where the paper's rule fires
on the noise-free scene (:mod:`oacdsl.segmentation.synth.reference`). Building the
truth checks the two agree — the scene produces exactly the scripted changes,
each within 0.6 s of its scripted moment — and refuses otherwise.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from typing import Any

import numpy as np

from oacdsl.errors import SegmentationError
from oacdsl.segmentation.synth.dough import Script
from oacdsl.segmentation.synth.reference import PaperRule, merge_keyframes, pair_distances
from oacdsl.world import relation

__all__ = ["OAC_PARAMS", "TRUTH_FORMAT", "Timing", "pass_by_facts", "time_script", "truth_document"]

#: Version tag of the ground-truth JSON document.
TRUTH_FORMAT = "oacdsl-synth-truth/1"
#: Parameter names of the standard library's OACs, for the bindings in the truth.
OAC_PARAMS: dict[str, tuple[str, ...]] = {
    "grasp": ("h", "o"),
    "place": ("h", "o"),
    "pour": ("h", "c", "l", "b"),
    "mix": ("h", "m", "b"),
}


class Timing:
    """The paper's rule applied to a script's noise-free markers: raw changes and merged keyframes."""

    def __init__(
        self, script: Script, pairs: list[tuple[str, str]], touching: np.ndarray, rule: PaperRule
    ) -> None:
        self.script = script
        self.pairs = pairs
        self.touching = touching
        self.rule = rule
        diff = np.flatnonzero((touching[1:] != touching[:-1]).any(axis=1)) + 1
        self.raw = [0] + [int(f) for f in diff]
        merged = merge_keyframes(self.raw, script.rate_hz, rule.merge_s)
        #: (frame, objects in flight) of merged keyframes that are transient states (a liquid in
        #: flight longer than the merge window): no sub-action starts or ends there
        self.transient = self._transient(merged)
        skip = {f for f, _ in self.transient}
        self.keyframes = [f for f in merged if f not in skip]

    def _transient(self, frames: list[int]) -> list[tuple[int, tuple[str, ...]]]:
        """The transient keyframes among ``frames`` by the matching's rule (hands are the agents)."""
        from oacdsl.matching.transient import stable_segmentation
        from oacdsl.segmentation.result import Keyframe, Segmentation
        from oacdsl.world import WorldState

        names = sorted(self.script.labels)
        rate = self.script.rate_hz
        kfs = tuple(Keyframe(f, f / rate, WorldState.of(names, self.relations(f))) for f in frames)
        seg = Segmentation("synth", self.script.rate_hz, int(self.script.times_s.shape[0]), tuple(names), kfs)
        _, dropped = stable_segmentation(seg, lambda name: name.endswith("_hand"))
        return [(t.keyframe.frame, t.objects) for t in dropped]

    def relations(self, frame: int) -> list[tuple[str, str]]:
        """Sorted relations at ``frame``."""
        return sorted(self.pairs[k] for k in np.flatnonzero(self.touching[frame]))

    def check(self, seed: int) -> None:
        """Raise unless the merged keyframes are exactly the script's steps, near their moments."""
        s = self.script
        expected = [set(relation(a, b) for a, b in s.initial)]
        for st in s.steps:
            removed = {relation(*r) for r in st.removed}
            expected.append((expected[-1] - removed) | {relation(*r) for r in st.added})
        got = [set(self.relations(f)) for f in self.keyframes]
        if got != expected:
            raise SegmentationError(
                f"seed {seed}: the scene does not produce the scripted keyframes"
                f" (got {len(got)} world states, expected {len(expected)})",
                location="synth dough",
            )
        for f, st in zip(self.keyframes[1:], s.steps, strict=True):
            if abs(f / s.rate_hz - st.time_s) > 0.6:
                raise SegmentationError(
                    f"seed {seed}: {st.oac} keyframe at {f / s.rate_hz:.2f} s, scripted at {st.time_s:.2f} s",
                    location="synth dough",
                )

    def near_changes(self, margin_s: float) -> list[tuple[int, int]]:
        """Frame spans within ``margin_s`` of any raw change (where gaps must not go)."""
        m = int(round(margin_s * self.script.rate_hz))
        return [(f - m, f + m) for f in self.raw[1:]]


def time_script(
    script: Script, touching: np.ndarray, pairs: list[tuple[str, str]], rule: PaperRule, seed: int
) -> Timing:
    """Time a script and check it (see :meth:`Timing.check`)."""
    timing = Timing(script, pairs, touching, rule)
    timing.check(seed)
    return timing


def _pair_json(pairs: Iterable[tuple[str, str]]) -> list[list[str]]:
    return [list(p) for p in sorted(pairs)]


def pass_by_facts(script: Script, hand: str, obj: str, rule: PaperRule) -> dict[str, Any]:
    """Closest approach of ``hand`` to ``obj`` around the scripted pass-by, and why it is no touch."""
    rate = script.rate_hz
    f0 = int(round(script.marks["pass_by"] * rate))
    lo, hi = max(f0 - int(0.8 * rate), 1), min(f0 + int(0.8 * rate), script.times_s.shape[0])
    dist = pair_distances(script.markers_m[hand][lo:hi], script.markers_m[obj][lo:hi])
    change = (
        np.abs(
            np.diff(
                pair_distances(script.markers_m[hand][lo - 1 : hi], script.markers_m[obj][lo - 1 : hi]),
                axis=0,
            )
        )
        * rate
    )
    k = int(np.argmin(dist.min(axis=1)))
    ok = (dist < rule.distance_m) & (change < rule.speed_m_s)
    longest = 0
    for col in ok.T:
        run = 0
        for v in col:
            run = run + 1 if v else 0
            longest = max(longest, run)
    speed = np.linalg.norm(np.diff(script.markers_m[hand][lo - 1 : hi].mean(axis=1), axis=0), axis=1) * rate
    return {
        "hand": hand,
        "object": obj,
        "frame": lo + k,
        "time_s": round((lo + k) / rate, 4),
        "min_distance_m": round(float(dist[k].min()), 5),
        "hand_speed_m_s": round(float(speed[k]), 4),
        "longest_slow_run_frames": int(longest),
    }


def truth_document(
    script: Script, timing: Timing, seed: int, labels: Mapping[str, Sequence[str]], realism: dict[str, Any]
) -> dict[str, Any]:
    """The ground-truth JSON document (see docs/demonstration.md for every field)."""
    rate = script.rate_hz
    kfs = timing.keyframes
    keyframes = []
    for i, f in enumerate(kfs):
        rels = timing.relations(f)
        before = set(timing.relations(kfs[i - 1])) if i else set()
        keyframes.append(
            {
                "frame": f,
                "time_s": round(f / rate, 4),
                "relations": _pair_json(rels),
                "added": _pair_json(set(rels) - before) if i else [],
                "removed": _pair_json(before - set(rels)) if i else [],
            }
        )
    subs = []
    for i, st in enumerate(script.steps):
        subs.append(
            {
                "index": i,
                "from_frame": kfs[i],
                "to_frame": kfs[i + 1],
                "oac": st.oac,
                "args": list(st.args),
                "binding": dict(zip(OAC_PARAMS[st.oac], st.args, strict=True)),
                "scripted_time_s": round(st.time_s, 4),
            }
        )
    first, last = set(timing.relations(kfs[0])), set(timing.relations(kfs[-1]))
    return {
        "format": TRUTH_FORMAT,
        "scene": "dough",
        "seed": seed,
        "rate_hz": rate,
        "frames": int(script.times_s.shape[0]),
        "duration_s": round(float(script.times_s[-1]), 4),
        "instances": sorted(labels),
        "markers": {k: list(v) for k, v in sorted(labels.items())},
        "environment": [{"name": "table", "top_z_m": 0.75, "tracked": False}],
        "parameters": {
            "distance_m": timing.rule.distance_m,
            "speed_m_s": timing.rule.speed_m_s,
            "frames": timing.rule.frames,
            "merge_s": timing.rule.merge_s,
        },
        "keyframes": keyframes,
        "sub_actions": subs,
        "oac_sequence": [f"{st.oac}({', '.join(st.args)})" for st in script.steps],
        "initial_relations": _pair_json(first),
        "final_relations": _pair_json(last),
        "added": _pair_json(last - first),
        "ended": _pair_json(first - last),
        "raw_changes": [
            {"frame": f, "time_s": round(f / rate, 4), "relations": _pair_json(timing.relations(f))}
            for f in timing.raw
        ],
        "transient": [
            {
                "frame": f,
                "time_s": round(f / rate, 4),
                "in_flight": list(objects),
                "relations": _pair_json(timing.relations(f)),
            }
            for f, objects in timing.transient
        ],
        "realism": realism,
    }
