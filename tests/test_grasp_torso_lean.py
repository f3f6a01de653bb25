"""Among grasps none of whose ways in keeps full room from the other hand, one the whole-body
IK reaches only with the torso leaning as far as it goes comes after the others
(``skills/grasp_choice.fallback_rank``, ``motion/approach.torso_margin_rad``): no simulation.

The numbers are those of the ``close_and_open`` example, seed 9: the right hand held the
bottle up, and the left hand's top grasps of the lid beside it kept 0.2-2.7 cm from that hand
(3 cm wanted). The roomiest, turned a quarter from the natural heading, was reached with the
hip's roll at its limit; the arm yielded to the thumb landing on the lid's top, the hand
closed tilted 14° and the lid, held 10-16° tilted, sprang off the bottle's edge."""

from __future__ import annotations

import pytest

from oacdsl.runtime.motion import TUNING
from oacdsl.runtime.motion.approach import torso_margin_rad

pytest.importorskip("mujoco", reason="the skills' modules import mujoco")

from oacdsl.runtime.skills.grasp_choice import HANDS_APART_M, fallback_rank  # noqa: E402

#: The IK's torso postures (rad) at the lid's grasps of seed 9: a quarter turned (the roomiest),
#: an eighth turned, and the natural heading.
QUARTER = {"hip_pitch": -0.60, "hip_roll": -0.7854, "hip_yaw": -0.56, "elbow_l": 0.82}
EIGHTH = {"hip_pitch": 0.19, "hip_roll": -0.33, "hip_yaw": -0.46}
NATURAL = {"hip_pitch": 0.18, "hip_roll": -0.31, "hip_yaw": -0.13}


def test_the_torso_margin_is_the_nearest_torso_joints_distance_from_its_limit():
    assert torso_margin_rad(QUARTER) == pytest.approx(0.0, abs=1e-4)
    assert torso_margin_rad(EIGHTH) == pytest.approx(0.7854 - 0.46, abs=1e-4)
    assert torso_margin_rad(NATURAL) == pytest.approx(0.7854 - 0.31, abs=1e-4)
    assert torso_margin_rad({"elbow_l": 0.96}) == float("inf")  # an arm joint at its limit is no lean


def test_a_grasp_reached_with_the_torso_at_its_limit_loses_to_a_tighter_one_reached_upright():
    grasps = {"quarter": (True, 0.027, torso_margin_rad(QUARTER)),
              "eighth": (True, 0.027 - 1e-3, torso_margin_rad(EIGHTH)),
              "natural": (True, 0.006, torso_margin_rad(NATURAL))}
    order = sorted(grasps, key=lambda k: fallback_rank(*grasps[k]))
    assert order == ["eighth", "natural", "quarter"]
    # without the lean, the roomiest still wins
    assert fallback_rank(True, 0.027, 0.3) < fallback_rank(True, 0.026, 0.3)


def test_collisions_rank_before_the_lean():
    upright, leaning = TUNING.torso_margin_rad + 0.1, 0.0
    # a way in through the other hand, or an arm on what it holds, is worse than a lean
    assert fallback_rank(True, 0.001, leaning) < fallback_rank(True, -0.001, upright)
    assert fallback_rank(True, -0.02, leaning) < fallback_rank(False, HANDS_APART_M - 1e-3, upright)
    # room beyond what is wanted counts as what is wanted
    assert fallback_rank(True, 0.05, upright) == fallback_rank(True, HANDS_APART_M, upright)
