"""The seeded random combined takes of ``benchmarks/random_takes.py`` (``kit_sweep_robot.py
--random N``): drawn within their ranges, the same take for the same parameters, a printed
parameter line that makes the take again, the hands exchanged exactly when mirrored."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
import random_takes as rt
from test_takes import synthetic

from oacdsl.segmentation.takes import IDENTITY, mirrored


def test_draws_are_seeded_within_their_ranges_and_independent_of_order():
    takes = [rt.draw(0, i, key=7) for i in range(40)]
    assert rt.draw(0, 5, key=7) == takes[5]  # drawn alone: the same as in the sequence
    assert rt.draw(1, 5, key=7) != takes[5] and rt.draw(0, 5, key=8) != takes[5]
    assert {t.mirror for t in takes} == {True, False}
    for name, (lo, hi) in rt.RANGES.items():
        values = [getattr(t, name) for t in takes]
        assert lo <= min(values) and max(values) <= hi
        assert max(values) - min(values) > 0.5 * (hi - lo)  # spread over the range


def test_the_printed_line_makes_the_same_take():
    rec = synthetic()
    take = rt.draw(3, 2)
    again = rt.parse(take.spec())
    assert again == take
    a, hands_a = take.apply(rec)
    b, hands_b = again.apply(rec)
    assert hands_a == hands_b
    assert a.rate_hz == pytest.approx(take.rate_hz)
    assert np.array_equal(a.times_s, b.times_s)
    assert np.array_equal(a.positions_m, b.positions_m, equal_nan=True)


def test_parameters_shape_the_take():
    rec = synthetic(frames=80)
    take = rt.RandomTake(mirror=False, speed=1.6, rate_hz=50.0, scale=1.1, rotation_deg=90.0,
                         gap_at=0.5, jitter_seed=1)
    out, hands = take.apply(rec)
    assert hands == dict(IDENTITY)
    assert out.rate_hz == 50.0
    assert out.times_s[-1] == pytest.approx(rec.times_s[-1] / 1.6, abs=1 / 20 + 1 / 50)  # whole frames
    # the gap: one cup marker missing for 0.3 s (15 frames at 50 Hz) beyond the cup's own gap
    cup = [out.marker_names.index(f"cup_{k}") for k in (1, 2, 3)]
    missing = np.isnan(out.positions_m[:, cup, 0]).sum(axis=0)
    assert missing.max() >= 15
    # the jitter: 0.2 mm about the untouched take; a different jitter seed, a different take
    other, _ = replace(take, jitter_seed=2).apply(rec)
    both = np.isfinite(out.positions_m) & np.isfinite(other.positions_m)
    spread = np.std((out.positions_m - other.positions_m)[both]) / np.sqrt(2)
    assert spread == pytest.approx(rt.JITTER_M, rel=0.2)


def test_the_mirror_flag_exchanges_the_hands():
    rec = synthetic()
    plain = rt.RandomTake(mirror=False, speed=0.8, rate_hz=33.0, scale=0.9, rotation_deg=200.0,
                          gap_at=0.3, jitter_seed=5)
    left_handed = replace(plain, mirror=True)
    out, hands = left_handed.apply(rec)
    assert hands == {"left_hand": "right_hand", "right_hand": "left_hand"}
    assert plain.apply(rec)[1] == dict(IDENTITY)
    # mirroring first, then the same variation: the take of the mirrored recording
    expected, _ = plain.apply(mirrored(rec)[0])
    assert np.array_equal(out.positions_m, expected.positions_m, equal_nan=True)
    assert not np.allclose(out.positions_m, plain.apply(rec)[0].positions_m, equal_nan=True)


@pytest.mark.parametrize("line", [
    "mirror=1 speed=1.2",
    "mirror=2 speed=1 rate_hz=30 scale=1 rotation_deg=0 gap_at=0.5 jitter_seed=1",
    "mirror=1 speed=-1 rate_hz=30 scale=1 rotation_deg=0 gap_at=0.5 jitter_seed=1",
    "mirror=1 speed=x rate_hz=30 scale=1 rotation_deg=0 gap_at=0.5 jitter_seed=1",
    "mirror=1 speed=1 rate_hz=30 scale=1 rotation_deg=0 gap_at=0.5 jitter_seed=1 colour=red",
    "speed",
])
def test_a_bad_line_is_refused(line):
    with pytest.raises(ValueError, match="random take|NAME=VALUE"):
        rt.parse(line)
