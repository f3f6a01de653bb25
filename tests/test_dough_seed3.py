"""The bundled dough on seed 3's places, reproduced whole (slow): no ball of liquid_two leaves the
bowl. The lip's lifts over its planned path (for the hand's boxes over the rim and for the arm's
measured lag) changed within one step, and the lag's lift fed itself: the lip's goal rose 9 cm and
fell again within 0.12 s, the jerk threw the balls up in the cup, and one left the lip at 1.1 m/s
and flew over the bowl's far rim onto the floor (`end_state.liquid_two.support`: fell)."""

from __future__ import annotations

from pathlib import Path

import pytest

pytest.importorskip("mujoco", reason="the robot runtime needs the 'robot' extra (mujoco)")
pytest.importorskip("placo", reason="the robot runtime needs the 'robot' extra (placo)")

from _dough_runs import reproduce_dough  # noqa: E402


@pytest.mark.slow
def test_dough_on_seed_3_pours_every_ball_into_the_bowl(tmp_path: Path) -> None:
    verdict, _ = reproduce_dough(tmp_path, seed=3)
    assert verdict["success"] and verdict["faithful"], verdict.get("summary")
    assert "20 of 20 balls in the bowl" in verdict["summary"]
