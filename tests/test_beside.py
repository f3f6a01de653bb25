"""Two objects at the static distance touch only where one is over the other (``beside.py``)."""

from __future__ import annotations

import numpy as np
from _aas_helpers import path, recording, still, summary
from segeval.reference import segment_reference

from oacdsl.segmentation import AasParams, segment
from oacdsl.segmentation.adaptive import AdaptiveDetector, AdaptiveSettings

F = 600
BOX = np.array([[0.03, 0.03, 0.0], [-0.03, 0.03, 0.0], [0.03, -0.03, 0.0], [-0.03, -0.03, 0.04]])


def _scene(end: tuple[float, float, float]) -> dict[str, np.ndarray]:
    """A box slides from 40 cm away (frames 100-250) to ``end`` beside or over a still bowl at the
    origin and stays there (no hand: no tool rule, only the static distance relates the two)."""
    box = path(F, [(0, (0.4, 0.0, 0.0)), (100, (0.4, 0.0, 0.0)), (250, end), (F - 1, end)])
    cluster = lambda centre, layout: centre[:, None, :] + layout[None]  # noqa: E731
    return {"bowl": cluster(still(F, (0.0, 0.0, 0.0)), BOX * 2), "box": cluster(box, BOX)}


def _relations(rec, settings: AdaptiveSettings) -> set[tuple[str, str]]:
    params = AasParams(merge_s=0.0).resolved(rec.rate_hz)
    seg = segment(rec, params, detector=AdaptiveDetector(params, settings))
    return set(summary(seg)[-1][1])  # at the end, the box standing where it was left


def test_a_box_set_down_beside_the_bowl_does_not_touch_it_one_set_into_it_does():
    settings = AdaptiveSettings(rescale=False)
    beside = recording(_scene((0.125, 0.0, 0.0)))  # markers 35 mm apart, within the static 80 mm
    box, bowl = beside.group_positions("box")[400], beside.group_positions("bowl")[400]
    gap = np.linalg.norm(box[:, None] - bowl[None], axis=-1).min()
    assert gap < settings.static_distance_m
    assert ("bowl", "box") not in _relations(beside, settings)
    assert ("bowl", "box") in _relations(beside, AdaptiveSettings(rescale=False, side_by_side=False))
    inside = recording(_scene((0.02, 0.0, 0.02)))  # over the bowl's markers
    assert ("bowl", "box") in _relations(inside, settings)


def test_the_per_frame_reference_agrees_beside():
    rec = recording(_scene((0.125, 0.0, 0.0)))
    params = AasParams(merge_s=0.3)
    settings = AdaptiveSettings(rescale=False)
    fast = segment(rec, params, detector=AdaptiveDetector(params.resolved(rec.rate_hz), settings))
    assert fast.keyframes == segment_reference(rec, params, settings).keyframes
