"""Lifted out (``oacdsl.segmentation.liftout``): a tool lifted out of its target and held above it
stops touching it, however near it is held, and touches it again when dipped back in.

A hand-made recording: a cup stands on the table; the right hand takes a spoon lying 30 cm away,
brings it into the cup, stirs (2-5 s), lifts it ``LIFT_M`` out (5-5.5 s) and holds it above the
cup (its markers within the tool reach of the cup's), then ``then``: holds it there, or dips it
back in and stirs again.
"""

from __future__ import annotations

import numpy as np
import pytest
from _aas_helpers import closest_m, on_spans, path, recording, still, summary

from oacdsl.segmentation import AasParams, segment
from oacdsl.segmentation.takes import STANDARD_TAKES

RATE = 100.0
N = 1000
CUP = np.array([[0.04, 0.0, 0.10], [-0.04, 0.0, 0.10], [0.0, 0.04, 0.10], [0.0, -0.04, 0.095]])  # rim
SPOON = np.array([[0.0, 0.0, 0.06], [0.005, 0.0, 0.10], [0.01, 0.0, 0.14], [0.012, 0.01, 0.16]])  # handle
HAND = np.array([[0.0, 0.0, 0.17], [0.03, 0.0, 0.18], [0.0, 0.03, 0.19], [0.06, 0.02, 0.18]])
BASE = np.array([0.2, 0.5, 0.75])  # the cup's place on the table
LIFT = (500, 550)  # frames: the spoon rises out of the cup
LIFT_M = 0.11
PAIR = ("cup", "spoon")


def scene(then: str = "hold") -> dict[str, np.ndarray]:
    frames = np.arange(N)
    inside = (0.0, 0.0, 0.02)  # the spoon's tip 2 cm above the cup's bottom
    up = (0.0, 0.0, 0.02 + LIFT_M)
    keys = [(0, (0.3, 0.0, 0.0)), (100, (0.3, 0.0, 0.0)), (200, inside), (LIFT[0], inside), (LIFT[1], up)]
    keys += [(N, up)] if then == "hold" else [(750, up), (800, inside), (N, inside)]
    tip = path(N, keys)
    stirring = ((frames >= 200) & (frames < LIFT[0])) | ((frames >= 800) if then == "dip" else False)
    phase = 2 * np.pi * frames / RATE
    circle = 0.02 * np.stack([np.cos(phase) - 1, np.sin(phase)], axis=1)  # stirring: 2 cm, once a second
    tip[:, :2] += np.where(stirring[:, None], circle, 0.0)
    spoon = BASE + tip[:, None, :] + SPOON
    reach = path(N, [(0, (0.5, -0.2, 0.3)), (100, (0.3, 0.0, 0.0))])
    hand = BASE + np.where(frames[:, None] < 100, reach, tip)[:, None, :] + HAND
    left = still(N, (-0.4, 0.0, 0.05))[:, None, :] + BASE + HAND * (-1, 1, 1)
    return {"cup": BASE + still(N, (0, 0, 0))[:, None, :] + CUP, "spoon": spoon, "right_hand": hand,
            "left_hand": left}


def run(rec) -> list:
    return summary(segment(rec, AasParams(mode="adaptive")))


def test_the_spoon_held_up_stays_within_the_tool_reach():
    assert closest_m(scene(), "spoon", "cup")[LIFT[1]:].max() < AasParams().distance_m * 0.8


def test_a_spoon_lifted_out_and_held_above_the_cup_leaves_it():
    (span,) = on_spans(run(recording(scene())), PAIR)
    assert span[0] < 300 and span[1] is not None and LIFT[0] <= span[1] <= LIFT[1] + 10, span


def test_a_spoon_dipped_back_in_touches_again():
    spans = on_spans(run(recording(scene("dip"))), PAIR)
    assert len(spans) == 2 and LIFT[0] <= spans[0][1] <= LIFT[1] + 10, spans
    assert 750 <= spans[1][0] <= 810 and spans[1][1] is None, spans


@pytest.mark.parametrize("take", sorted(STANDARD_TAKES))
def test_every_standard_take_sees_the_lift_out(take):
    rec = recording(scene())
    other, _ = STANDARD_TAKES[take](rec)
    (span,) = on_spans(run(other), PAIR)
    factor = other.times_s[-1] / rec.times_s[-1]
    assert span[1] is not None, (take, span)
    assert LIFT[0] / RATE * factor <= other.times_s[span[1]] <= (LIFT[1] + 10) / RATE * factor, (take, span)


def test_the_per_frame_reference_agrees():
    from segeval.reference import segment_reference

    from oacdsl.segmentation.takes import resampled

    rec = resampled(recording(scene("dip")), 30.0)
    params = AasParams(mode="adaptive")
    assert segment(rec, params).keyframes == segment_reference(rec, params).keyframes
