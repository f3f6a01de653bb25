"""KIT Mix's salad servers, let go of leaning in the green bowl, stay apart
(``benchmarks/mix_rest.py``, no robot). Modelled round (a disc head, a round handle) they
rolled along the bowl's round rim until their heads touched, from nearly any start (3 of 112
mirrored poses ended apart); modelled flat, as salad servers are (``library/kit``), they do
not roll."""

from __future__ import annotations

import pytest

pytestmark = pytest.mark.slow

pytest.importorskip("mujoco", reason="the robot runtime needs the 'robot' extra (mujoco)")

#: Mirrored poses as ``mix_both { lean … }`` lets the servers go (head x, y in cm in the bowl's
#: frame, the direction they lean towards and how far, degrees): behind the middle, either side.
POSES = (
    ((-5.0, 4.5, 0.0, 48.0), (-5.0, -4.5, 0.0, 48.0)),
    ((-5.0, 5.5, 15.0, 48.0), (-5.0, -5.5, -15.0, 48.0)),
    ((-7.0, 4.5, 15.0, 48.0), (-7.0, -4.5, -15.0, 48.0)),
)


def test_flat_salad_servers_let_go_of_leaning_in_the_bowl_stay_apart() -> None:
    from mix_rest import ROOT, _world, trial

    world, floor_m = _world(ROOT / "library" / "kit")
    start = (world.data.qpos.copy(), world.data.qvel.copy())
    for pair in POSES:
        world.data.qpos[:], world.data.qvel[:] = start
        touched, leans, heads = trial(world, floor_m, pair, 2.0)
        assert not touched, pair
        # still leaning in the bowl, the heads on their own sides of the middle line
        assert min(leans) > 30.0, (pair, leans)
        assert heads[0][1] > 2.0 and heads[1][1] < -2.0, (pair, heads)
