"""A side approach whose pre-grasp stands over a neighbouring object is shortened
(:func:`oacdsl.runtime.skills.grasp.clear_pre_grasp`): the hand comes down to its pre-grasp
from above, and the left hand of a mirrored Stack take came down on the crate beside the
block (83 N, ``benchmarks/evaltakes.py --robot --task Stack --take mirrored``)."""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("mujoco", reason="the runtime's modules import mujoco")

from oacdsl.runtime.grasping import PRE_GRASP_M, GraspPlan  # noqa: E402
from oacdsl.runtime.motion.paths import segment_distance  # noqa: E402
from oacdsl.runtime.motion.tuning import TUNING  # noqa: E402
from oacdsl.runtime.skills.grasp_choice import HAND_HALF_WIDTH_M, clear_pre_grasp  # noqa: E402
from oacdsl.runtime.transforms import make_T  # noqa: E402


class _Ctx:
    """What clear_pre_grasp asks of a skill context: the gap to the objects' footprints."""

    def __init__(self, obstacles: list[tuple[tuple[float, float], float]]) -> None:
        self.obstacles = [(np.array(xy), r) for xy, r in obstacles]

    def clearance(self, a: np.ndarray, b: np.ndarray, exclude: set[str]) -> float:
        return min((segment_distance(xy, a[:2], b[:2]) - r for xy, r in self.obstacles), default=np.inf)


def _side_plan(approach: tuple[float, float, float]) -> GraspPlan:
    d = np.array(approach, dtype=float)
    grasp = np.array([0.56, -0.28, 0.83])
    return GraspPlan(make_T(np.eye(3), grasp), make_T(np.eye(3), grasp - PRE_GRASP_M * d), d,
                     make_T(np.eye(3), grasp + 0.06 * d))


def test_a_pre_grasp_over_a_neighbour_moves_in_along_the_approach_until_the_hand_clears_it():
    plan = _side_plan((0.0, -1.0, 0.0))  # the left hand, from +y, past a crate at y = 0.02
    ctx = _Ctx([((0.62, 0.02), 0.099)])
    assert ctx.clearance(plan.pre_grasp[:3, 3], plan.pre_grasp[:3, 3], set()) < HAND_HALF_WIDTH_M
    moved = clear_pre_grasp(ctx, plan, "block")
    pre = moved.pre_grasp[:3, 3]
    assert ctx.clearance(pre, pre, set()) >= HAND_HALF_WIDTH_M
    length = float(np.linalg.norm(pre - plan.grasp[:3, 3]))
    assert TUNING.pre_grasp_min_m <= length < PRE_GRASP_M
    assert np.allclose(np.cross(pre - plan.grasp[:3, 3], plan.approach), 0.0)  # on the approach line
    assert moved.grasp is plan.grasp and moved.end is plan.end


def test_a_clear_or_top_or_hopeless_approach_is_kept():
    plan = _side_plan((0.0, -1.0, 0.0))
    assert clear_pre_grasp(_Ctx([]), plan, "block") is plan
    assert clear_pre_grasp(_Ctx([((0.56, -0.25), 0.3)]), plan, "block") is plan  # nothing clears it
    top = _side_plan((0.0, 0.0, -1.0))
    assert clear_pre_grasp(_Ctx([((0.56, -0.28), 0.05)]), top, "block") is top
