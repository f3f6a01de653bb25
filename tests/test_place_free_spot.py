"""``place`` of an object that may not go back where it was taken (issue 19): a lid taken off
its bottle is set down on a free spot of the table, not on the bottle."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).parent))

pytest.importorskip("mujoco", reason="the robot runtime needs the 'robot' extra (mujoco)")
pytest.importorskip("placo", reason="the robot runtime needs the 'robot' extra (placo)")

from test_kit_general import FIRST_FRAME, LIBRARIES  # noqa: E402

from oacdsl.compiler import load_library  # noqa: E402
from oacdsl.runtime.executor import prepare, run_prepared  # noqa: E402
from oacdsl.runtime.motion.spots import free_spots  # noqa: E402

HERE = Path(__file__).parent


def _library():  # type: ignore[no-untyped-def]
    return load_library([*LIBRARIES, HERE / "data" / "put_down"])


def test_free_spots_keep_off_every_footprint_and_prefer_the_hands_side():
    run = prepare(_library(), "open_and_put_down", layout="demonstrated", demonstrated=FIRST_FRAME)
    world = run.world
    bottle = world.body_pose("bottle")[:2, 3]
    r = world.layout.bodies["lid"].radius
    spots = free_spots(world, "l", "lid", r)
    assert spots
    for p in spots:
        assert np.linalg.norm(p - bottle) >= r + world.layout.bodies["bottle"].radius
    assert spots[0][1] >= 0  # the left hand's side of the robot first


def test_free_spots_keep_room_for_the_hand_and_its_withdrawal():
    """A spot where the hand, or the hand backing off after letting go, would hit a neighbour
    is no free spot (a hand-over's cup set down beside another cup knocked it over)."""
    from oacdsl.runtime.motion.tuning import TUNING

    run = prepare(_library(), "open_and_put_down", layout="demonstrated", demonstrated=FIRST_FRAME)
    world = run.world
    bottle, r_bottle = world.body_pose("bottle")[:2, 3], world.layout.bodies["bottle"].radius
    r = world.layout.bodies["lid"].radius
    plain = free_spots(world, "l", "lid", r, limit=1000)
    hand = (np.array([0.0, 0.05]), np.array([0.0, 0.05 + TUNING.withdraw_back_m]))  # hand and way out at +y
    spots = free_spots(world, "l", "lid", r, limit=1000, hand_xy_m=hand)
    assert spots and len(spots) < len(plain)
    for p in spots:
        for d in hand:
            assert np.linalg.norm(p + d - bottle) >= r_bottle + TUNING.near_path_m / 2


def test_free_spots_keep_the_forearm_off_other_footprints():
    """Seen from above, the forearm (the last part of elbow → hand) passes over no object at a
    free spot: a cup set down beyond another was knocked over by the arm reaching over it."""
    from oacdsl.runtime.motion.paths import segment_distance
    from oacdsl.runtime.motion.tuning import TUNING

    run = prepare(_library(), "open_and_put_down", layout="demonstrated", demonstrated=FIRST_FRAME)
    world = run.world
    bottle, r_bottle = world.body_pose("bottle")[:2, 3], world.layout.bodies["bottle"].radius
    elbow = world.body_pose("elbow_l_link")[:2, 3]
    spots = free_spots(world, "l", "lid", world.layout.bodies["lid"].radius, limit=1000)
    assert spots
    for p in spots:
        start = p - (p - elbow) * min(1.0, TUNING.forearm_m / float(np.linalg.norm(p - elbow)))
        assert segment_distance(bottle, start, p) >= r_bottle + TUNING.near_path_m / 2


def test_a_way_down_beside_an_object_comes_straight_down_from_above_the_goal():
    """A carry whose slanting way down would pass low over an object beside the goal crosses at
    the way's height to above the goal first; with nothing beside the goal it stays three moves."""
    from oacdsl.runtime.motion.paths import carry_path
    from oacdsl.runtime.transforms import make_T

    run = prepare(_library(), "open_and_put_down", layout="demonstrated", demonstrated=FIRST_FRAME)
    world = run.world
    bottle = world.body_pose("bottle")
    top = bottle[2, 3] + world.layout.bodies["bottle"].height
    start = make_T(np.eye(3), (bottle[0, 3], bottle[1, 3] + 0.35, top + 0.05))
    beside = make_T(np.eye(3), (bottle[0, 3], bottle[1, 3] - 0.10, top - 0.10))  # low, just past the bottle
    path = carry_path(world, "l", start, beside, set(), 2.0)
    assert len(path) == 4
    above, goal = path[2][0], path[3][0]
    assert np.allclose(above[:2, 3], goal[:2, 3]) and above[2, 3] > goal[2, 3]
    assert above[2, 3] == pytest.approx(path[1][0][2, 3])
    assert sum(s for _, s in path[1:]) == pytest.approx(2.0)  # the climb comes on top
    far = make_T(np.eye(3), (bottle[0, 3], bottle[1, 3] + 0.60, top - 0.10))  # away from every object
    assert len(carry_path(world, "l", start, far, set(), 2.0)) == 3


def test_a_way_down_beside_what_the_other_hand_holds_comes_straight_down():
    """What the other hand holds is in the way like an object on the table, and the carried
    object's footprint is kept off the tops the slanting way down passes: a lid carried off the
    bottle the other hand holds up came down slanting onto the bottle's top (80 N)."""
    from oacdsl.runtime.motion.paths import carry_path, held_by_other
    from oacdsl.runtime.transforms import make_T

    run = prepare(_library(), "open_and_put_down", layout="demonstrated", demonstrated=FIRST_FRAME)
    world = run.world
    world.weld("r", "bottle")
    world.weld("l", "lid")
    assert held_by_other(world, "l", set())[0][2] > world.body_pose("bottle")[2, 3]  # its top, up in the air
    assert held_by_other(world, "l", {"bottle"}) == []
    grasp = world.frame_pose("grasp_l")
    bottle = world.body_pose("bottle")[:3, 3]
    start = make_T(grasp[:3, :3], grasp[:3, 3] + np.array([0.0, 0.0, 0.06]))  # the lid just off the bottle
    goal = make_T(grasp[:3, :3], (bottle[0], bottle[1] + 0.12, grasp[2, 3] - 0.25))  # low, beside it
    path = carry_path(world, "l", start, goal, set(), 2.0)
    assert len(path) == 4
    assert np.allclose(path[2][0][:2, 3], goal[:2, 3]) and path[2][0][2, 3] > goal[2, 3]


@pytest.mark.slow
def test_a_lid_taken_off_its_bottle_is_put_down_on_the_table_not_on_the_bottle():
    run = prepare(_library(), "open_and_put_down", layout="demonstrated", demonstrated=FIRST_FRAME)
    result = run_prepared(run)
    assert result.success, result.error
    world = run.world
    assert not world.touching("lid", "bottle")
    assert world.held["l"] is None and world.held["r"] == "bottle"
    lid, bottle = world.body_pose("lid"), world.body_pose("bottle")
    assert lid[2, 2] > 0.95  # upright
    assert lid[2, 3] < bottle[2, 3] + 0.05  # down on the table, not up on the bottle's top
    assert np.linalg.norm(lid[:2, 3] - bottle[:2, 3]) > 0.06


def test_a_way_into_the_other_hands_footprint_crosses_over_that_hand():
    """A carry that enters the other hand's footprint from outside it crosses above that hand:
    the red cup brought to pour beside the hand holding the mixer in the bowl, crossing at the
    way's height, met that hand's thumb (65 N). A way that starts within it (both hands putting
    down side by side) does not climb over it."""
    from oacdsl.runtime.grasping import HAND_BELOW_CENTRE_M
    from oacdsl.runtime.motion.paths import carry_path, other_hand_obstacle
    from oacdsl.runtime.transforms import make_T

    run = prepare(_library(), "open_and_put_down", layout="demonstrated", demonstrated=FIRST_FRAME)
    world = run.world
    assert other_hand_obstacle(world, "l") is None
    world.weld("r", "bottle")
    xy, radius, top = other_hand_obstacle(world, "l")
    low = top - 0.10
    goal = make_T(np.eye(3), (xy[0], xy[1] + 0.5 * radius, low))  # within its footprint, below its top
    outside = make_T(np.eye(3), (xy[0], xy[1] + radius + 0.25, low))
    crossing = carry_path(world, "l", outside, goal, set(), 2.0)[1][0]
    assert crossing[2, 3] >= top + HAND_BELOW_CENTRE_M
    inside = make_T(np.eye(3), (xy[0], xy[1] + 0.8 * radius, low))
    assert all(p[2, 3] < top for p, _ in carry_path(world, "l", inside, goal, set(), 2.0))


def test_a_stalled_set_down_goes_to_the_free_spot_the_hand_reaches_best():
    """When the descent onto an object's own place stalls with nothing felt (the arm at the edge
    of its reach), ``place`` sets it down on the free spot whose descent's end the whole-body IK
    reaches best: one of the free spots, the object upright, the hand at the hover height above."""
    from oacdsl.runtime.motion.tuning import TUNING
    from oacdsl.runtime.skills.free_spot import hand_offsets
    from oacdsl.runtime.skills.place import _best_reached_spot

    run = prepare(_library(), "open_and_put_down", layout="demonstrated", demonstrated=FIRST_FRAME)
    ctx = run.context
    run.world.weld("l", "lid")
    t_lid, lid_in_hand = ctx.held_pose("l", "lid")
    above = _best_reached_spot(ctx, "l", "lid", None)
    lid = above @ lid_in_hand
    xy = lid[:2, 3]
    assert lid[2, 2] == pytest.approx(1.0, abs=1e-6)  # upright
    assert lid[2, 3] == pytest.approx(ctx.support_height(xy, exclude="lid") + TUNING.hover_m)
    offsets = hand_offsets(np.linalg.inv(lid_in_hand), lid[:3, :3], np.array([0.0, 0.0, -1.0]))
    spots = free_spots(run.world, "l", "lid", run.world.layout.bodies["lid"].radius, hand_xy_m=offsets)
    assert any(np.allclose(xy, p) for p in spots)

    def miss(p: np.ndarray) -> float:
        bottom = lid.copy()
        bottom[:3, 3] = (p[0], p[1], ctx.support_height(p, exclude="lid") - TUNING.support_search_m)
        return ctx.ctl.ik.try_reach("l", bottom @ np.linalg.inv(lid_in_hand)).position_m

    assert len(spots) > 1 and miss(xy) <= min(miss(p) for p in spots) + 1e-9


def test_the_support_under_a_place_is_seen_through_what_the_other_hand_carries_away():
    """``place_both``: an object the other hand holds over this one's place and carries away at
    the same time is no support (a milk carton hung over the cup's place after pouring: the
    cup's hover went 28 cm up and the cup, lifted there, met the carton, 62 N)."""
    run = prepare(_library(), "open_and_put_down", layout="demonstrated", demonstrated=FIRST_FRAME)
    ctx, world = run.context, run.world
    xy = world.body_pose("bottle")[:2, 3]
    table = ctx.support_height(xy + np.array([0.0, 0.3]), exclude="lid")
    on_bottle = ctx.support_height(xy, exclude="lid")
    assert on_bottle > table + 0.05  # the bottle's top
    assert ctx.support_height(xy, exclude="lid", passing={"bottle"}) == pytest.approx(table, abs=1e-3)
    assert ctx.support_height(xy, exclude="lid", passing={"lid"}) == pytest.approx(on_bottle)
