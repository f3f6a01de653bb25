"""Rules that keep the adaptive detector's decisions the same across takes (issue 20): the same
durations at every frame rate and pace."""

from __future__ import annotations

import numpy as np

from oacdsl.segmentation.comotion import frames_within
from oacdsl.segmentation.episodes import find_episodes


def _mask(n: int, *runs: tuple[int, int]) -> np.ndarray:
    m = np.zeros(n, dtype=bool)
    for a, b in runs:
        m[a:b] = True
    return m


def test_a_flickering_grasp_leads_up_to_its_carry():
    # 3 frames, 5 frames before a long run (30 Hz: a grasp lifting the cup in jerks, then carrying it)
    carry = _mask(60, (10, 13), (18, 50))
    assert find_episodes(carry, min_len=4, bridge=7) == [(10, 13), (18, 50)]
    assert find_episodes(carry, min_len=4, bridge=4) == [(18, 50)]  # interrupted too long: alone
    chain = _mask(60, (2, 4), (5, 6), (8, 20))
    assert find_episodes(chain, min_len=5, bridge=2) == [(2, 4), (5, 6), (8, 20)]


def test_short_pieces_alone_or_after_a_carry_are_no_episode():
    carry = _mask(60, (10, 12), (14, 15), (40, 42))
    assert find_episodes(carry, min_len=5, bridge=3) == []  # no carry follows
    assert find_episodes(_mask(60, (10, 30), (32, 33)), min_len=5, bridge=3) == [(10, 30)]  # the let-go


def test_a_bridge_holds_the_frames_an_excursion_of_at_most_its_duration_spans():
    assert frames_within(0.2, 10.0) == 2
    assert frames_within(0.3, 10.0) == 3  # exactly: float error does not drop a frame
    assert frames_within(0.388, 10.0) == 3  # 4 frames last 0.4 s: more than 0.388 s
    assert frames_within(0.05, 10.0) == 0
    assert frames_within(0.24, 100.0) == 24
