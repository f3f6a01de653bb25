"""``grasp_both`` reaches with both hands together only where the whole-body IK keeps both on
their ways (:func:`oacdsl.runtime.motion.both.lockstep_miss`, :func:`~oacdsl.runtime.motion.both.paced`).

A planning check without the simulator: the IK runs alone over the two ways (open loop: its
model is what the arms are commanded), nothing is stepped. The layout is KIT Wipe x2's on seed 1
(the plate 77 cm out near the robot's middle, the sponge on its right, the rack on its left),
where both reaching at once bent the torso to its limits and the left hand sagged 17 cm below
its way onto the rack (a 92 N safety stop), although the pair of grasps is reachable at its end.
"""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).parent))

pytest.importorskip("mujoco", reason="the robot runtime needs the 'robot' extra (mujoco)")
pytest.importorskip("placo", reason="the robot runtime needs the 'robot' extra (placo)")

from runtime_lib import STANDARD  # noqa: E402

from oacdsl.compiler import load_library  # noqa: E402
from oacdsl.runtime.executor import prepare  # noqa: E402
from oacdsl.runtime.motion import TUNING  # noqa: E402
from oacdsl.runtime.motion.both import lockstep_miss, paced  # noqa: E402
from oacdsl.runtime.skills import bimanual  # noqa: E402
from oacdsl.runtime.skills.base import REACH_TOLERANCE_M  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
#: Where Wipe x2 seed 1 had its objects (m, robot frame): the plate, the sponge, the rack.
WIPE_X2_SEED_1 = {
    "plate_dish": (0.771, -0.095), "sponge_small": (0.601, -0.30), "draining_rack": (0.649, 0.266),
}


def _ways(library: list[Path], scene: str, objects: tuple[str, str],
          places: dict[str, tuple[float, float]] | None = None):  # type: ignore[no-untyped-def]
    """The controller and the two hands' ways to grasp ``objects`` (left, right) as grasp_both
    plans them, in ``scene`` laid out with ``places``."""
    o1, o2 = objects
    binding = {"h1": "left_hand", "o1": o1, "h2": "right_hand", "o2": o2}
    run = prepare(load_library(library), "grasp_two" if scene == "kit_touching" else "grasp_both",
                  binding, scene=scene, layout="auto" if places else None, places=places)
    ctx = run.context
    p1, p2 = bimanual._pair(ctx, ("left_hand", o1), ("right_hand", o2))
    motions = [bimanual.plan_grasp(ctx, "left_hand", o1, p1), bimanual.plan_grasp(ctx, "right_hand", o2, p2)]
    return run.controller, {m.side: bimanual._way(m) for m in motions}


def test_two_hands_reaching_far_across_the_table_at_once_leave_their_ways() -> None:
    """Together, a hand gets 23 cm off its way and no slower pace keeps it on (so grasp_both
    takes one object after the other); the right hand alone keeps to its way at the planned
    pace, and the left alone gets off it by much less than with the other reaching too."""
    ctl, ways = _ways([ROOT / "library" / "kit"], "kit_wipe", ("plate_dish", "sponge_small"), WIPE_X2_SEED_1)
    slower, settle = TUNING.pace_factor, TUNING.settle_s
    together = lockstep_miss(ctl, ways, settle)
    assert together > 5 * REACH_TOLERANCE_M
    assert paced(ctl, ways, REACH_TOLERANCE_M, slower, settle) is None
    assert paced(ctl, {"r": ways["r"]}, REACH_TOLERANCE_M, slower, settle) == 1.0
    assert lockstep_miss(ctl, {"l": ways["l"]}, settle) < 0.7 * together
    # the trial leaves the IK where it was: measuring twice gives the same
    assert lockstep_miss(ctl, ways, settle) == pytest.approx(together, abs=1e-9)


def test_two_hands_taking_a_cup_and_a_block_in_front_of_them_reach_together() -> None:
    """A cup and a block each in front of its own hand (tests/data/kit_skills.oac): both ways are
    kept together, the planned pace made half again as slow (the hands turning to their grasps
    swung 2.9 cm off their ways at it, 1.1 cm slowed), and grasp_both reaches with both at once
    (KIT Stir and Mix take their cup and spoon, their two servers so, at the planned pace)."""
    library = [*STANDARD, ROOT / "tests" / "data" / "kit_skills.oac"]
    ctl, ways = _ways(library, "kit_touching", ("cup", "block"))
    slower, settle = TUNING.pace_factor, TUNING.settle_s
    assert lockstep_miss(ctl, ways, settle) > REACH_TOLERANCE_M
    assert paced(ctl, ways, REACH_TOLERANCE_M, slower, settle) == 1.5
