"""Rules that keep the adaptive detector's decisions the same across takes (issue 20): the same
durations at every frame rate and pace."""

from __future__ import annotations

import numpy as np

from oacdsl.segmentation.comotion import _episodes, frames_within


def _mask(n: int, *runs: tuple[int, int]) -> np.ndarray:
    m = np.zeros(n, dtype=bool)
    for a, b in runs:
        m[a:b] = True
    return m


def test_a_flickering_grasp_is_one_episode_when_its_pieces_together_last_long_enough():
    # 3 frames, 5 frames apart from a long run (30 Hz: a grasp lifting the cup in two jerks)
    carry = _mask(60, (10, 13), (18, 50))
    assert _episodes(carry, min_len=4, bridge=7) == [(10, 13), (18, 50)]
    assert _episodes(carry, min_len=4, bridge=4) == [(18, 50)]  # interrupted too long: alone


def test_short_pieces_alone_are_no_episode():
    carry = _mask(60, (10, 12), (14, 15), (40, 42))
    assert _episodes(carry, min_len=6, bridge=3) == []  # together 5 frames: too short
    assert _episodes(carry, min_len=5, bridge=3) == [(10, 12), (14, 15)]


def test_a_bridge_holds_the_frames_an_excursion_of_at_most_its_duration_spans():
    assert frames_within(0.2, 10.0) == 2
    assert frames_within(0.3, 10.0) == 3  # exactly: float error does not drop a frame
    assert frames_within(0.388, 10.0) == 3  # 4 frames last 0.4 s: more than 0.388 s
    assert frames_within(0.05, 10.0) == 0
    assert frames_within(0.24, 100.0) == 24
