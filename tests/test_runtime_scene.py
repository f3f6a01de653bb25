"""The simulated scene: built from a DSL scene, steps without MuJoCo warnings, seeded layouts."""

import math

import numpy as np
import pytest

pytest.importorskip("mujoco", reason="the robot runtime needs the 'robot' extra (mujoco)")
pytest.importorskip("placo", reason="the robot runtime needs the 'robot' extra (placo)")

from runtime_lib import inst, task_library  # noqa: E402

from oacdsl.errors import RuntimeFailure  # noqa: E402
from oacdsl.model import Scene  # noqa: E402
from oacdsl.runtime.build import build_model, home_posture  # noqa: E402
from oacdsl.runtime.layout import MAX_SHIFT_M, MIN_GAP_M, plan_layout  # noqa: E402
from oacdsl.runtime.simworld import SimWorld  # noqa: E402
from oacdsl.runtime.skills import IMPLEMENTATIONS  # noqa: E402
from oacdsl.skills import SKILLS  # noqa: E402

KITCHEN = task_library().scenes["kitchen"]


def test_every_skill_name_has_an_implementation():
    assert set(IMPLEMENTATIONS) == set(SKILLS)


@pytest.mark.parametrize(
    ("scene", "seed"),
    [("kitchen", None), ("kitchen", 3), ("pouring", None), ("mixing", 1), ("wiping", None), ("wiping", 4)],
)
def test_every_scene_steps_quietly_and_rests_as_laid_out(scene, seed):
    lib = task_library()
    layout = plan_layout(lib, lib.scenes[scene], seed=seed)
    world = SimWorld(build_model(layout, seed))
    world.set_targets(home_posture())
    world.step(int(1.5 / world.model.opt.timestep))
    assert world.warnings() == {}
    # at rest: each liquid touches its cup, nothing else touches anything
    assert set(world.relations().relations) == {tuple(sorted(kv)) for kv in layout.liquids.items()}
    for liquid, cup in layout.liquids.items():
        assert world.balls_inside(cup, liquid) == layout.ball_count(liquid)
    for p in layout.placements:
        t = world.body_pose(p.name)
        assert math.dist(t[:2, 3], (p.x, p.y)) < 0.005, p.name
        assert t[2, 2] > 0.999, f"{p.name} tipped over"


def test_seeded_layouts_move_objects_up_to_10_cm_and_keep_them_apart():
    lib = task_library()
    moved = []
    nominal = {p.name: (p.x, p.y) for p in plan_layout(lib, KITCHEN).placements}
    for seed in range(12):
        layout = plan_layout(lib, KITCHEN, seed=seed)
        assert layout == plan_layout(lib, KITCHEN, seed=seed)  # deterministic
        for p in layout.placements:
            shift = math.dist((p.x, p.y), nominal[p.name])
            assert shift <= MAX_SHIFT_M + 1e-9
            moved.append(shift)
        ps = layout.placements
        for i, a in enumerate(ps):
            for b in ps[i + 1 :]:
                gap = math.dist((a.x, a.y), (b.x, b.y)) - a.body.radius - b.body.radius
                assert gap >= MIN_GAP_M - 1e-9, (seed, a.name, b.name)
    assert np.median(moved) > 0.03


def test_liquids_start_where_the_scene_or_the_caller_says():
    lib = task_library()
    # library/kitchen.oac: liquid_one in red_cup, liquid_two in green_cup
    assert plan_layout(lib, KITCHEN).liquids == {"liquid_one": "red_cup", "liquid_two": "green_cup"}
    # a liquid moved into the other's cup: the other takes its place (a swap)
    swapped = plan_layout(lib, KITCHEN, {"liquid_one": "green_cup"})
    assert swapped.liquids == {"liquid_one": "green_cup", "liquid_two": "red_cup"}
    with pytest.raises(RuntimeFailure, match="not a container"):
        plan_layout(lib, KITCHEN, {"liquid_one": "mixer"})
    bare = KITCHEN.model_copy(update={"fills": ()})
    with pytest.raises(RuntimeFailure, match="liquid 'liquid_one' has no container.*liquid_one in CONTAINER"):
        plan_layout(lib, bare)


def test_layout_errors_name_the_problem():
    lib = task_library()
    odd = Scene(name="odd", instances=(inst("left_hand", "Hand"), inst("teapot", "Graspable")))
    with pytest.raises(RuntimeFailure, match="teapot.*has no shape.*Cup"):
        plan_layout(lib, odd)
    hands = Scene(name="hands", instances=(inst("hand_a", "Hand"), inst("right_hand", "Hand")))
    with pytest.raises(RuntimeFailure, match="left from right"):
        plan_layout(lib, hands)
    with pytest.raises(RuntimeFailure, match="off the table"):
        plan_layout(lib, KITCHEN, places={"red_cup": (2.0, 0.0)})
    # where the table is, and where the object's origin may stand on it (its circle on the table)
    with pytest.raises(RuntimeFailure, match=r"off the table \(x from 0.4 to 1.4 m, y within ±0.8 m;"
                       r" the circle of radius 0.\d\d m .*: x from 0.4\d to 1.3\d m, y within ±0.7\d m\)"):
        plan_layout(lib, KITCHEN, places={"red_cup": (0.41, 0.0)})


def test_weld_holds_an_object_where_it_was():
    lib = task_library()
    world = SimWorld(build_model(plan_layout(lib, KITCHEN)))
    before = world.body_pose("mixer")
    world.weld("r", "mixer")
    world.step(100)
    assert np.allclose(world.body_pose("mixer"), before, atol=1e-3)
    world.release("r")
    assert world.held["r"] is None


def test_wrist_sensor_reads_the_hand_weight_at_rest():
    lib = task_library()
    world = SimWorld(build_model(plan_layout(lib, KITCHEN)))
    force, _ = world.wrist_wrench("r")
    # palm 0.8 kg + four finger segments of 0.1 kg, 9.81 m/s²
    assert abs(np.linalg.norm(force) - 1.2 * 9.81) < 0.3


def test_a_seed_that_moves_nothing_says_so():
    from oacdsl.runtime.layout import seed_note

    lib = task_library()
    assert seed_note(plan_layout(lib, KITCHEN)) is None  # no seed: nothing to say
    assert seed_note(plan_layout(lib, KITCHEN, seed=3)) is None  # every object moved
    # every object placed by the caller: no seed can move any of them
    everywhere = {p.name: (p.x, p.y) for p in plan_layout(lib, KITCHEN).placements}
    pinned = plan_layout(lib, KITCHEN, seed=3, places=everywhere)
    assert set(pinned.unmoved) == set(everywhere)
    note = seed_note(pinned)
    assert note is not None and "--seed 3 moves no object of scene kitchen" in note
    # one object pinned by the caller: by design, no warning for it alone
    one = dict(list(everywhere.items())[:1])
    partly = plan_layout(lib, KITCHEN, seed=3, places=one)
    assert set(partly.unmoved) == set(one)
    assert seed_note(partly) is None
