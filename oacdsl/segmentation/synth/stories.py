"""Other takes of the dough task than the paper's order, for testing what the paper's order hides.

- ``handover``: the left hand pours liquid one, then hands the empty red cup to the right
  hand (both hold it for a moment), which sets it down on the right; then the right hand
  pours liquid two and mixes, as in the paper.
- ``overlap``: the two hands work at once: the right hand reaches for the green cup while
  the left hand carries the red cup, so that their grasps, pours and set-downs interleave.

Each story writes onto a :class:`~oacdsl.segmentation.synth.stage.Stage` and returns the
number of frames of the recording; the ground truth checks (as for the paper's order) that
the paper's rule sees exactly the scripted changes.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from oacdsl.segmentation.synth.dough import (
    R_CUP_LEFT_HAND,
    R_CUP_RIGHT_HAND,
    YAW_PI,
    mix_until_end,
    paper_story,
    pour_with,
)
from oacdsl.segmentation.synth.scene import CUP_HANDLE_GRASP_M, TABLE_Z_M
from oacdsl.segmentation.synth.stage import Stage

__all__ = ["STORY_SCRIPTS", "handover_story", "overlap_story"]

#: Where the red cup changes hands: in front of the bowl, 15 cm up (its origin, world m).
_HANDOVER_AT_M = np.array([0.0, -0.34, TABLE_Z_M + 0.15])
#: Where the right hand sets the handed-over cup down (world m).
_RED_CUP_RIGHT_M = np.array([0.22, -0.30, TABLE_Z_M])
_ALL_BUT_MIXER = ("left_hand", "right_hand", "red_cup", "green_cup", "liquid_one", "liquid_two")


def handover_story(stage: Stage) -> int:
    dur = stage.dur
    stage.sync(dur(1.0))
    t = stage.grasp(
        stage["left_hand"].now_s, "left_hand", "red_cup", CUP_HANDLE_GRASP_M, R_CUP_LEFT_HAND, -1.0
    )
    t = stage.pour(t, "left_hand", "red_cup", -1.0, np.eye(3))
    t = stage.carry(t, "left_hand", "red_cup", _HANDOVER_AT_M, 1.3)
    # the right hand takes the empty cup's far side while the left hand holds it still by the handle
    stage["right_hand"].hold(t - dur(0.4))
    t = stage.grasp(
        stage["right_hand"].now_s,
        "right_hand",
        "red_cup",
        YAW_PI @ CUP_HANDLE_GRASP_M,
        YAW_PI @ R_CUP_RIGHT_HAND,
        +1.0,
    )
    stage["left_hand"].hold(t)
    t = stage.release(t + dur(0.2), "left_hand", "red_cup", -1.0, holder="right_hand")
    stage.set_down(t, "right_hand", "red_cup", _RED_CUP_RIGHT_M, np.eye(3), +1.0, bounce=True)
    # then the right hand pours liquid two and mixes, as in the paper
    stage.sync(stage["right_hand"].now_s + dur(0.6))
    pour_with(stage, "right_hand", "green_cup", +1.0, R_CUP_RIGHT_HAND)
    return mix_until_end(stage, max(stage[k].now_s for k in _ALL_BUT_MIXER) + dur(0.8))


def overlap_story(stage: Stage) -> int:
    dur = stage.dur
    stage.sync(dur(1.0))
    start_s = stage["left_hand"].now_s
    # the right hand sets off 1.5 s after the left: it grasps while the left hand carries, pours
    # while the left hand tilts back, and sets its cup down after the left hand's
    stage["right_hand"].hold(start_s + dur(1.5))
    pour_with(stage, "left_hand", "red_cup", -1.0, R_CUP_LEFT_HAND, bounce=True)
    pour_with(stage, "right_hand", "green_cup", +1.0, R_CUP_RIGHT_HAND)
    return mix_until_end(stage, max(stage[k].now_s for k in _ALL_BUT_MIXER) + dur(0.8))


#: Story name → script, for :func:`~oacdsl.segmentation.synth.dough.dough_script`.
STORY_SCRIPTS: dict[str, Callable[[Stage], int]] = {
    "paper": paper_story,
    "handover": handover_story,
    "overlap": overlap_story,
}
