"""The static distance, for pairs that never move together (``AdaptiveSettings.static_distance_m``):
only between two objects, and in the scene's length.

A hand touches an object by moving it (co-motion), holding it still (``hold_still``) or through a
tool, not by resting near it (``static_agents``, off): a hand resting 70 mm beside a rack from the
first frame is not holding it, in any take. Between two objects the static distance follows the
scene's length (the hands' size, :mod:`oacdsl.segmentation.scales`), both ways: a fork lying
beside a bowl stays apart in a smaller take, a liquid in a bowl stays in it in a larger one.
"""

from __future__ import annotations

import numpy as np
from _aas_helpers import path, recording, still, summary

from oacdsl.segmentation import AasParams, segment
from oacdsl.segmentation.adaptive import AdaptiveDetector, AdaptiveSettings
from oacdsl.segmentation.takes import scaled

N = 300
# a KIT-like hand (wrist to finger tip, 16 cm: the reference's size, length factor 1)
HAND = np.array([[0.0, 0.0, 0.0], [0.04, 0.0, 0.0], [0.0, 0.03, 0.01], [0.12, 0.05, 0.0], [0.15, 0.04, 0.02]])
RACK = np.array([[0.0, 0.0, 0.0], [0.30, 0.0, 0.0], [0.0, 0.17, 0.1], [0.30, 0.17, 0.1]])
BOWL = np.array([[0.1, 0.0, 0.12], [-0.1, 0.0, 0.12], [0.0, 0.1, 0.12], [0.0, -0.1, 0.0]])
FORK = np.array([[0.0, 0.0, 0.0], [0.09, 0.0, 0.005], [0.18, 0.0, 0.01]])


def run(rec, settings: AdaptiveSettings | None = None) -> list:
    params = AasParams()
    return summary(segment(rec, params, detector=AdaptiveDetector(params.resolved(rec.rate_hz), settings)))


def touched(keyframes: list, pair: tuple[str, str]) -> bool:
    return any(pair in rels for _, rels in keyframes)


def resting_hand() -> dict[str, np.ndarray]:
    """The left hand rests 70 mm beside a rack from the first frame, then leaves (150-250); the right
    hand moves about elsewhere."""
    left = path(N, [(0, (-0.07, 0.0, 0.0)), (150, (-0.07, 0.0, 0.0)), (250, (-0.5, -0.3, 0.3))])
    right = path(N, [(0, (1.0, 0.0, 0.2)), (100, (1.3, 0.2, 0.3)), (200, (1.0, 0.0, 0.2))])
    return {"rack": still(N, (0.0, 0.0, 0.0))[:, None, :] + RACK,
            "left_hand": left[:, None, :] + HAND * (-1, 1, 1), "right_hand": right[:, None, :] + HAND}


def test_a_hand_resting_beside_an_object_from_the_start_does_not_touch_it():
    rec = recording(resting_hand())
    for take in (rec, scaled(rec, 0.85), scaled(rec, 1.15)):
        assert not touched(run(take), ("left_hand", "rack"))
    assert touched(run(rec, AdaptiveSettings(static_agents=True)), ("left_hand", "rack"))  # the former rule


def beside(gap_m: float) -> dict[str, np.ndarray]:
    """A fork lying ``gap_m`` beside a bowl's nearest marker; a hand moving about far away."""
    bowl = still(N, (0.0, 0.0, 0.0))[:, None, :] + BOWL
    fork = still(N, (0.1 + gap_m, 0.0, 0.12))[:, None, :] + FORK
    hand = path(N, [(0, (1.0, 0.0, 0.2)), (100, (1.3, 0.2, 0.3)), (200, (1.0, 0.0, 0.2))])
    return {"bowl": bowl, "fork": fork, "right_hand": hand[:, None, :] + HAND}


def test_between_two_objects_the_static_distance_is_in_the_scenes_length():
    # the distance alone: side by side, neither over the other, the two do not touch at any distance
    # (``side_by_side``, tests/test_beside.py)
    scaled_d = AdaptiveSettings(side_by_side=False)
    fixed = AdaptiveSettings(rescale=False, side_by_side=False)  # in metres, whatever the scene
    apart, close = recording(beside(0.084)), recording(beside(0.075))
    pair = ("bowl", "fork")
    assert not touched(run(apart, scaled_d), pair) and touched(run(close, scaled_d), pair)
    smaller, larger = scaled(apart, 0.85), scaled(close, 1.15)  # 71 mm apart; 86 mm apart
    assert not touched(run(smaller, scaled_d), pair) and touched(run(smaller, fixed), pair)
    assert touched(run(larger, scaled_d), pair) and not touched(run(larger, fixed), pair)
    assert not touched(run(close), pair)  # the default: side by side, not touching


def test_a_hand_that_comes_to_a_still_bottle_and_holds_it_is_seen_at_every_rate():
    """The synthetic Close (``tests/_task_demos.py``): the right hand comes to the bottle (0.8-2 s,
    slowing down at the end) and holds it still to the end. Without the static distance for hands
    it is holding still that sees it; at 10 Hz the last half second of the approach closes less
    than a quarter of the bottle's size, so the arrival is judged on the whole approach."""
    import _task_demos as demos

    for capture in (demos.CLEAN, demos.KIT_LIKE, demos.KIT_10HZ):
        keyframes = run(demos.close_demo(capture))
        rate = capture.rate_hz or demos.RATE_HZ
        held = [f / rate for f, rels in keyframes if ("bottle", "right_hand") in rels]
        assert held and 1.9 <= held[0] <= 2.2, (capture, keyframes)
        assert ("bottle", "right_hand") in keyframes[-1][1]  # to the end
