"""A second hand takes an object the other hand holds at a free grasp point (issue 19): the
declared point mirrored through the object's axis, not the point the first hand occupies."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).parent))

pytest.importorskip("mujoco", reason="the robot runtime needs the 'robot' extra (mujoco)")
pytest.importorskip("placo", reason="the robot runtime needs the 'robot' extra (placo)")

from test_kit_general import library  # noqa: E402

from oacdsl.runtime.executor import prepare  # noqa: E402
from oacdsl.runtime.handgap import hands_gap  # noqa: E402
from oacdsl.runtime.skills import IMPLEMENTATIONS  # noqa: E402
from oacdsl.runtime.skills.grasp import (
    HANDS_APART_M,  # noqa: E402
    handover_candidates,  # noqa: E402
)


@pytest.mark.slow
def test_a_second_hand_takes_the_object_at_the_other_handle():
    run = prepare(library(), "roll_the_pin")
    ctx, world = run.context, run.world
    IMPLEMENTATIONS["reach_and_grasp"](ctx, "left_hand", "rolling_pin", lift=0.05)
    held = world.frame_pose("grasp_l")
    first = handover_candidates(ctx, "right_hand", "rolling_pin")[0]
    assert np.linalg.norm(first.grasp[:3, 3] - held[:3, 3]) > 0.2  # the other handle, 31 cm away
    gap = hands_gap(("r", first.grasp, ctx.ctl.fingers["r"]), ("l", held, ctx.ctl.fingers["l"]))
    assert gap >= HANDS_APART_M
    IMPLEMENTATIONS["reach_and_grasp"](ctx, "right_hand", "rolling_pin")
    assert world.held == {"l": "rolling_pin", "r": "rolling_pin"}
    assert world.touching("right_hand", "rolling_pin") and world.touching("left_hand", "rolling_pin")
