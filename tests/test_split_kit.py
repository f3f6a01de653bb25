"""The six KIT development clips with events up to 0.6 s apart merged into one keyframe: the
keyframes that then match no OAC as a whole are split, and the clips compose to the steps of the
0.3 s window (issue 20, "simultaneous changes of the two hands"). Segmented with the paper's
merging and fixed constants (``AdaptiveSettings(merge="paper", rescale=False)``), which join
changes of both hands into one keyframe; the default detector keeps them apart
(tests/test_coincident.py, tests/test_takes_compose.py)."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import pytest
from _mocap import mocap_file

from oacdsl.matching import Matcher
from oacdsl.matching.demonstration import compose_demonstration, match_segmentation
from oacdsl.pipeline.inputs import load_inputs
from oacdsl.segmentation import segment
from oacdsl.segmentation.adaptive import AdaptiveDetector, AdaptiveSettings
from oacdsl.segmentation.params import AasParams

ROOT = Path(__file__).resolve().parents[1]
KIT = ROOT / "library" / "kit"
CLIPS = ["Pour", "Stir", "Mix", "Wipe", "Scoop", "Cut"]


def composed(clip: str, merge_s: float) -> tuple[list[list[str]], int]:
    """The composed steps, a together block as one sorted list, and how many sub-actions were split."""
    xml = next(mocap_file("kit_bimanual").glob(f"{clip}_*.mmm.xml"))
    params = dataclasses.replace(AasParams(), merge_s=merge_s)
    inputs = load_inputs(xml, [KIT], None, params)
    rec = inputs.motion_capture()

    def paper_merge(p: AasParams) -> AdaptiveDetector:
        return AdaptiveDetector(p.resolved(rec.rate_hz), AdaptiveSettings(merge="paper", rescale=False))

    unmerged = dataclasses.replace(params, merge_s=0.0)
    matches = match_segmentation(segment(rec, params, detector=paper_merge(params)),
                                 Matcher.from_library(inputs.library, inputs.scene),
                                 unmerged=lambda: segment(rec, unmerged, detector=paper_merge(unmerged)))
    assert all(m.matched for m in matches), [m.explanation for m in matches if not m.matched]
    comp = compose_demonstration(f"kit_{clip.lower()}", matches, inputs.library, inputs.scene).composition
    groups: list[list[str]] = []
    for s in comp.steps:
        if s.together:
            groups[-1].append(s.oac.name)
        else:
            groups.append([s.oac.name])
    return groups, sum(m.split is not None for m in matches)


@pytest.mark.slow
@pytest.mark.parametrize("clip", CLIPS)
def test_a_wider_merge_window_composes_to_the_same_steps(clip):
    default, split_default = composed(clip, 0.3)
    wide, _ = composed(clip, 0.6)
    assert split_default == 0  # today's compositions are untouched
    flat = [name for g in default for name in g]
    if clip == "Cut":  # library/kit's place_both matches the two hands letting go 0.4 s apart as one
        assert flat[-2:] == ["place", "place"] and wide[-1] == ["place_both"]
        flat, wide = flat[:-2], wide[:-1]
    assert sum(map(len, wide)) == len(flat)
    k = 0
    for group in wide:  # the same steps in the same order; a together block: its steps in any order
        assert sorted(group) == sorted(flat[k:k + len(group)]), (wide, flat)
        k += len(group)
