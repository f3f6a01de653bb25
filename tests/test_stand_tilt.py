"""``touch``'s ``tilt`` onto a target without slots (:func:`oacdsl.runtime.skills.stand._tilted_poses`):
the candidate poses hold the object turned by the demonstrated angle, over the target's middle."""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).parent))

pytest.importorskip("mujoco", reason="the robot runtime needs the 'robot' extra (mujoco)")
pytest.importorskip("placo", reason="the robot runtime needs the 'robot' extra (placo)")

import mujoco  # noqa: E402
from test_kit_general import LIBRARIES  # noqa: E402

from oacdsl.compiler import load_library  # noqa: E402
from oacdsl.runtime.executor import prepare  # noqa: E402
from oacdsl.runtime.motion import TUNING  # noqa: E402
from oacdsl.runtime.shapes import world_corners  # noqa: E402
from oacdsl.runtime.skills.stand import _tilted_poses  # noqa: E402
from oacdsl.runtime.turning import hull_points  # noqa: E402


@pytest.mark.parametrize(("tilt_rad", "lean_rad"), [(0.4, 0.0), (2.5, 0.0), (1.0, 0.14)])
def test_tilted_candidates_make_the_asked_angle_over_the_targets_middle(
    tilt_rad: float, lean_rad: float
) -> None:
    """Each candidate pose of the lid over the pot (which has no slots) has the lid's axis at
    ``tilt_rad`` from the pot's, tilted towards a different compass direction, its bounding box's
    middle over the middle of the pot's top and its lowest point ``hover`` above that top; also
    when the lid leans ``lean_rad`` to start with, as a held object does (turned by what is left
    of the tilt about the compass axes, a lid leaning 8° missed it by up to 16°)."""
    run = prepare(load_library(list(LIBRARIES)), "cover", {"h": "left_hand", "l": "pot_lid", "p": "pot"},
                  scene="covering")
    world, ctx = run.world, run.context
    q = world.model.jnt_qposadr[world.model.body("pot_lid").jntadr[0]] + 3  # its free joint's quaternion
    world.data.qpos[q : q + 4] = (math.cos(lean_rad / 2), math.sin(lean_rad / 2), 0.0, 0.0)
    mujoco.mj_forward(world.model, world.data)
    assert world.body_pose("pot_lid")[2, 2] == pytest.approx(math.cos(lean_rad), abs=1e-6)
    hover = 0.05
    poses = _tilted_poses(ctx, "pot_lid", "pot", tilt_rad, hover, TUNING)
    pot = world_corners(ctx.body("pot"), world.body_pose("pot"))
    mid, top = (pot.min(axis=0) + pot.max(axis=0)) / 2, float(pot[:, 2].max())
    z_pot = world.body_pose("pot")[:3, 2]
    leans = set()
    assert len(poses) == TUNING.stand_spin_tries
    for pose, depth, what, slot in poses:
        z = pose[:3, 2]
        assert math.acos(float(np.clip(z @ z_pot, -1.0, 1.0))) == pytest.approx(tilt_rad, abs=1e-6)
        c = hull_points(ctx.body("pot_lid")) @ pose[:3, :3].T + pose[:3, 3]
        assert np.allclose((c.min(axis=0) + c.max(axis=0))[:2] / 2, mid[:2], atol=1e-6)
        assert float(c[:, 2].min()) == pytest.approx(top + hover, abs=1e-6)
        assert depth == pytest.approx(hover + float(np.ptp(pot[:, 2])))
        assert slot is None and what == "the top of pot"
        leans.add(round(math.degrees(math.atan2(z[1], z[0]))) % 360)
    assert len(leans) == TUNING.stand_spin_tries  # tilted towards every compass direction tried
