"""A lid let go on a pot's rim off its middle is slid onto the middle first (``place`` →
:func:`~oacdsl.runtime.motion.rotate.centre_over`), on the pot scene of library/examples/pot.oac."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).parent))

pytest.importorskip("mujoco", reason="the robot runtime needs the 'robot' extra (mujoco)")
pytest.importorskip("placo", reason="the robot runtime needs the 'robot' extra (placo)")

from test_kit_general import LIBRARIES  # noqa: E402

from oacdsl.compiler import load_library  # noqa: E402
from oacdsl.runtime.executor import prepare, run_step  # noqa: E402
from oacdsl.runtime.motion import Motion  # noqa: E402
from oacdsl.runtime.skills.place import place  # noqa: E402
from oacdsl.runtime.transforms import down, raised  # noqa: E402

COVER = {"h": "left_hand", "l": "pot_lid", "p": "pot"}


@pytest.mark.slow
@pytest.mark.parametrize("off_m", [0.03, -0.025])
def test_a_lid_let_go_off_the_pots_middle_ends_on_its_middle(off_m: float) -> None:
    """The left hand holds the lid resting on the pot's rim ``off_m`` off the pot's axis (its
    near edge over the opening); after ``place`` the lid lies upright on the pot, let go, within
    1 cm of the pot's axis (let go where it was, it stays 2-3 cm off; slid pressed on the rim,
    its dipped near edge met the pot's inner wall, a safety stop)."""
    library = load_library(list(LIBRARIES))
    run = prepare(library, "cover", COVER, scene="covering", held={"left_hand": "pot_lid"})
    world, ctx = run.world, run.context
    assert run_step(ctx, run.steps[0], None) is None  # touch: the lid onto the pot

    def off() -> np.ndarray:
        return world.body_pose("pot_lid")[:2, 3] - world.body_pose("pot")[:2, 3]

    m = Motion(ctx, "l")
    above = raised(m.here(), 0.02)
    above[:2, 3] += np.array([0.0, off_m]) - off()
    m.go(raised(m.here(), 0.02), 1.0)
    m.go(above, 1.0)
    m.approach(down(above, 0.05), m.touching("pot_lid", "pot"))
    m.hold_still(1.0)
    assert world.touching("pot_lid", "pot") and abs(off()[1]) > 0.02  # resting on the rim, off its middle

    ctx.expected = world.relations()  # place's predicted state: the lid stays on the pot
    place(ctx, "left_hand", "pot_lid")
    ctx.expected = None
    assert world.held["l"] is None
    assert world.touching("pot_lid", "pot")
    assert world.body_pose("pot_lid")[2, 2] > 0.999  # upright, not tipped into the pot
    assert float(np.linalg.norm(off())) < 0.01
