"""What KIT Wipe needs on the robot (library/kit/wipe.oac): ``hold_up`` brings a plate in
front of the robot, and a plate's virtual markers cover its faces, so that the closed loop
sees a hand pinching its edge and a sponge anywhere on it. The whole clip is reproduced in
tests/test_kit_reproduce.py."""

from __future__ import annotations

from functools import lru_cache

import numpy as np
import pytest

pytest.importorskip("mujoco", reason="the robot runtime needs the 'robot' extra (mujoco)")
pytest.importorskip("placo", reason="the robot runtime needs the 'robot' extra (placo)")

from runtime_lib import ROOT  # noqa: E402

from oacdsl.compiler import load_library  # noqa: E402
from oacdsl.pipeline.markers import ROBOT_DISTANCE_M, VirtualMarkers  # noqa: E402
from oacdsl.runtime.executor import prepare, run_prepared  # noqa: E402
from oacdsl.runtime.shapes import world_corners  # noqa: E402
from oacdsl.skills import SIGNATURES  # noqa: E402

#: The plate where the demonstrated layout puts it (the recording is not needed here).
PLATE_AT = (0.71, -0.10)


@lru_cache(maxsize=1)
def kit():
    return load_library([ROOT / "library" / "kit"])


def test_hold_up_takes_the_plate_and_holds_it_in_front_of_the_robot_on_the_hands_side():
    run = prepare(kit(), "take_plate", {"h": "left_hand", "p": "plate_dish"}, "kit_wipe",
                  places={"plate_dish": PLATE_AT, "sponge_small": (0.65, -0.33)})
    result = run_prepared(run)
    assert result.success, result.steps[-1].error
    world = run.world
    assert world.held["l"] == "plate_dish"
    corners = world_corners(world.layout.bodies["plate_dish"], world.body_pose("plate_dish"))
    middle = 0.5 * (corners.min(axis=0) + corners.max(axis=0))
    # its middle 50 cm out and 10 cm to the left (the left hand's side), 20 cm off the table
    assert np.linalg.norm(middle[:2] - [SIGNATURES["hold_up"].defaults()["forward"], 0.10]) < 0.05
    assert corners[:, 2].min() > world.body_pose("sponge_small")[2, 3] + 0.15


def test_a_plate_has_a_marker_within_the_contact_distance_of_every_point_of_its_faces():
    run = prepare(kit(), "take_plate", {"h": "left_hand", "p": "plate_dish"}, "kit_wipe",
                  places={"plate_dish": PLATE_AT})
    markers = VirtualMarkers(run.world)
    markers(run.world)
    plate = run.world.body_pose("plate_dish")
    local = (markers.points(["plate_dish"])["plate_dish"][0] - plate[:3, 3]) @ plate[:3, :3]
    radius, height = 0.12, 0.02  # library/kit/classes.oac: Plate
    rng = np.random.default_rng(0)
    r = radius * np.sqrt(rng.uniform(0, 1, 400))
    a = rng.uniform(0, 2 * np.pi, 400)
    top = np.column_stack([r * np.cos(a), r * np.sin(a), np.full(400, height)])
    rim = np.column_stack([radius * np.cos(a), radius * np.sin(a), rng.uniform(0, height, 400)])
    for probe in (top, rim):
        nearest = np.linalg.norm(probe[:, None] - local[None], axis=2).min(axis=1)
        assert nearest.max() < ROBOT_DISTANCE_M
