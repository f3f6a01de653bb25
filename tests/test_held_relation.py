"""A hand holds what its grasp holds: the world state counts a grasped object as held by the
hand even while the fingers do not touch it (the simulation's grasp is a weld), so that a step
letting go of it is neither skipped nor judged done before the hand has let go."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("mujoco", reason="the robot runtime needs the 'robot' extra (mujoco)")
pytest.importorskip("placo", reason="the robot runtime needs the 'robot' extra (placo)")

from oacdsl.compiler import load_library  # noqa: E402
from oacdsl.runtime.executor import prepare  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]


@pytest.mark.slow
def test_a_grasped_object_is_held_until_the_hand_lets_go_not_until_its_contact_ends(monkeypatch):
    lib = load_library([ROOT / "library"])
    run = prepare(lib, "place", {"h": "right_hand", "o": "mixer"}, scene="kitchen",
                  held={"right_hand": "mixer"})
    world = run.world
    assert world.relations().touches("mixer", "right_hand")
    # no contact at all between the hand and the mixer (a tool turned in the hand's grasp, the
    # fingers off its handle): the grasp still holds it
    monkeypatch.setattr(world, "contact_geoms", lambda: np.zeros((0, 2), dtype=int))
    assert world.held["r"] == "mixer"
    assert world.relations().touches("mixer", "right_hand")
    assert world.relations().sorted_relations() == [("mixer", "right_hand")]
    world.release("r")
    assert not world.relations().touches("mixer", "right_hand")
