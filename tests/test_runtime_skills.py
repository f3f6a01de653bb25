"""Every skill alone on a small scene, with the physical outcome checked in the simulation."""

import math

import numpy as np
import pytest

pytest.importorskip("mujoco", reason="the robot runtime needs the 'robot' extra (mujoco)")
pytest.importorskip("placo", reason="the robot runtime needs the 'robot' extra (placo)")

from runtime_lib import task_library  # noqa: E402

from oacdsl.runtime.control import FORCE_LIMIT_N  # noqa: E402
from oacdsl.runtime.executor import execute, prepare, run_prepared  # noqa: E402
from oacdsl.runtime.layout import BALLS_PER_LIQUID  # noqa: E402
from oacdsl.runtime.motion import TUNING  # noqa: E402
from oacdsl.runtime.objects import TABLE_TOP  # noqa: E402


class ForceLog:
    """Observer: the largest wrist force change (N) of each hand since the start of each motion."""

    rate_hz = 100.0

    def __init__(self):
        self.peak = {"r": 0.0, "l": 0.0}
        self.controller = None

    def __call__(self, world):
        if self.controller is not None:
            for s in "rl":
                self.peak[s] = max(self.peak[s], float(np.linalg.norm(self.controller.force_change(s))))


def run_task(name, scene, observers=()):
    run = prepare(task_library(), name, scene=scene)
    for obs in observers:
        obs.controller = run.controller
        run.controller.add_observer(obs)
    return run, run_prepared(run)


def test_grasp_then_place_puts_the_cup_back_by_force_sensing():
    log = ForceLog()
    run, result = run_task("pick_and_place", "pouring", [log])
    assert result.success, result.error
    grasp, place = result.steps
    assert ["green_cup", "right_hand"] in grasp.observed
    assert ["right_hand", "nothing"] in place.observed
    world = run.world
    t = world.body_pose("green_cup")
    placement = world.layout.placement("green_cup")
    assert math.dist(t[:2, 3], (placement.x, placement.y)) < 0.03
    assert t[2, 2] > 0.99  # upright
    assert world.held["r"] is None
    # the descent was stopped by the wrist sensor: it felt the table, but never came near the limit
    assert TUNING.support_force_n < log.peak["r"] < FORCE_LIMIT_N
    assert world.warnings() == {}


def test_pour_gets_at_least_90_percent_of_the_balls_into_the_bowl():
    run, result = run_task("pour_task", "pouring")
    assert result.success, result.error
    pour = result.steps[1]
    assert ["liquid_two", "orange_bowl"] in pour.observed
    assert ["green_cup", "liquid_two"] not in pour.observed
    total = len(run.world.built.balls["liquid_two"])
    assert total == BALLS_PER_LIQUID and result.metrics["balls_total"] == total
    assert run.world.balls_inside("orange_bowl", "liquid_two") >= 0.9 * total
    assert result.metrics["balls_in_bowl"] >= 0.9 * total


def test_mix_ends_with_the_mixer_in_the_bowl():
    run, result = run_task("mix_task", "mixing")
    assert result.success, result.error
    assert ["mixer", "orange_bowl"] in result.steps[-1].observed
    world = run.world
    mixer, bowl = world.body_pose("mixer"), world.body_pose("orange_bowl")
    shape = run.world.layout.bodies["orange_bowl"]
    assert math.dist(mixer[:2, 3], bowl[:2, 3]) < shape.inner_radius
    assert mixer[2, 3] < bowl[2, 3] + shape.height


def test_wipe_keeps_the_sponge_on_the_tray():
    run, result = run_task("wipe_task", "wiping")
    assert result.success, result.error
    assert ["sponge", "tray"] in result.steps[-1].observed
    assert ["right_hand", "sponge"] in result.steps[-1].observed


def test_a_force_above_the_safety_limit_aborts_the_skill_with_a_reason():
    run = prepare(task_library(), "pick_and_place", scene="pouring")
    run.controller.force_limit_n = 2.0  # N: any contact (or a brisk move) trips it
    result = run_prepared(run)
    assert not result.success
    assert "safety stop" in result.steps[0].error and "wrist felt" in result.steps[0].error
    assert len(result.steps) == 1


def test_skills_read_object_poses_at_execution_time():
    # the cup is not where the nominal layout has it: the grasp must follow it there
    result = execute(
        task_library(),
        "grasp",
        {"h": "right_hand", "o": "green_cup"},
        "pouring",
        places={"green_cup": (0.62, -0.36)},
    )
    assert result.success, result.error


class HeldLog:
    """Observer: while the right hand holds ``obj``, the hand's grasp centre and the object's
    origin in the world (m), and whether the hand touches the object."""

    rate_hz = 50.0

    def __init__(self, obj):
        self.obj = obj
        self.hand, self.body, self.touching = [], [], []
        self.controller = None

    def __call__(self, world):
        if world.held["r"] == self.obj:
            self.hand.append(world.frame_pose("grasp_r")[:3, 3].copy())
            self.body.append(world.body_pose(self.obj)[:3, 3].copy())
            self.touching.append(world.touching("right_hand", self.obj))


def test_a_bowl_is_held_by_its_rim_lifted_and_put_back():
    # `grasp CarryBowl { type rim approach top … }`: fingers down, the wall between plate and thumb
    log = HeldLog("bowl")
    run, result = run_task("carry_bowl", "carrying", [log])
    assert result.success, result.error
    grasp, place = result.steps
    assert ["bowl", "right_hand"] in grasp.observed
    assert ["right_hand", "nothing"] in place.observed
    start = run.world.layout.placement("bowl")
    hand, body = np.array(log.hand), np.array(log.body)
    assert len(body) > 20
    # the bowl went up with the hand (lifted several cm off the table) …
    table_z = body[0, 2]
    assert body[:, 2].max() > table_z + 0.06
    # … keeping its place in the hand while held, and the hand touched it all the time
    rel = body - hand
    assert np.linalg.norm(rel - rel[0], axis=1).max() < 0.01
    assert all(log.touching)
    # it stands upright on the table where it was picked up, and the hand is empty again
    t = run.world.body_pose("bowl")
    assert math.dist(t[:2, 3], (start.x, start.y)) < 0.03
    assert abs(t[2, 3] - table_z) < 0.005 and t[2, 2] > 0.99
    assert run.world.held["r"] is None
    assert run.world.warnings() == {}


def test_place_sets_the_sponge_down_on_the_tray_the_composed_effect_names():
    # grasp, wipe, place as a demonstration composes it: `place` itself predicts only
    # `h <-> nothing`; the composed effect `sponge <-> tray` decides where the sponge goes
    run, result = run_task("wipe_and_leave", "wiping")
    assert result.success, result.error
    assert [s.oac for s in result.steps] == ["grasp", "wipe", "place"]
    place = result.steps[-1]
    assert ["sponge", "tray"] in place.observed and ["right_hand", "nothing"] in place.observed
    world = run.world
    sponge, tray = world.body_pose("sponge"), world.body_pose("tray")
    local = np.linalg.inv(tray) @ sponge
    assert abs(local[0, 3]) < 0.15 and abs(local[1, 3]) < 0.11  # on the plate (30 × 22 cm)
    assert sponge[2, 2] > 0.99 and world.held["r"] is None
    assert [(c.oac, c.success) for c in result.composed] == [("wipe_and_leave", True)]


def test_a_hand_over_keeps_the_cup_still_and_ends_in_the_other_hand():
    # the right hand takes the cup the left hand holds (no lift: both hold it), then the
    # left hand lets go (no set-down: the right hand holds it)
    log = ForceLog()
    run, result = run_task("hand_over", "handing", [log])
    assert result.success, result.error
    grasp_l, grasp_r, release = result.steps
    assert ["cup", "left_hand"] in grasp_r.observed and ["cup", "right_hand"] in grasp_r.observed
    assert ["cup", "right_hand"] in release.observed and ["left_hand", "nothing"] in release.observed
    world = run.world
    assert world.held == {"r": "cup", "l": None}
    assert world.body_pose("cup")[2, 3] > TABLE_TOP + 0.05  # still up in the air, in the right hand
    assert max(log.peak.values()) < 0.5 * FORCE_LIMIT_N
    assert world.warnings() == {}


class PartsLog(HeldLog):
    """HeldLog, plus which parts of the right hand touch the object while it holds it."""

    def __init__(self, obj):
        super().__init__(obj)
        self.parts = []

    def __call__(self, world):
        super().__call__(world)
        if world.held["r"] == self.obj:
            self.parts.append(world.hand_parts_touching("r", self.obj))


def test_a_flat_tray_is_pinched_at_its_edge_lifted_and_put_back():
    # `grasp Tray { type pinch approach top … }`: the finger plate beside the edge, the thumb on top
    log = PartsLog("tray")
    run, result = run_task("carry_tray", "wiping", [log])
    assert result.success, result.error
    assert ["right_hand", "tray"] in result.steps[0].observed
    assert log.parts and {"fingers", "thumb"} <= log.parts[0]  # pinched, not held by the palm
    body = np.array(log.body)
    assert body[:, 2].max() > TABLE_TOP + 0.06  # lifted
    t = run.world.body_pose("tray")
    start = run.world.layout.placement("tray")
    assert math.dist(t[:2, 3], (start.x, start.y)) < 0.03 and t[2, 2] > 0.99
    assert run.world.held["r"] is None and run.world.warnings() == {}


def test_a_stick_is_taken_by_its_handle_lifted_and_put_back():
    # `grasp Whisk { type handle approach side … }`: a handle on the object's axis, taken
    # from the hand's own side, the fingers wrapped around the grip
    log = PartsLog("whisk")
    run, result = run_task("carry_whisk", "whisking", [log])
    assert result.success, result.error
    assert log.parts and "fingers" in log.parts[0]
    assert np.array(log.body)[:, 2].max() > TABLE_TOP + 0.06
    t = run.world.body_pose("whisk")
    start = run.world.layout.placement("whisk")
    assert math.dist(t[:2, 3], (start.x, start.y)) < 0.03 and t[2, 2] > 0.99


def test_place_carries_the_sponge_onto_the_tray_when_the_composed_effect_says_so():
    # seed 1: the sponge stands elsewhere; a grasp from above must not stop on the thumb alone
    run = prepare(task_library(), "put_on_tray", scene="wiping", seed=1)
    start = run.world.body_pose("sponge")
    result = run_prepared(run)
    assert result.success, result.error
    assert ["sponge", "tray"] in result.steps[-1].observed
    sponge, tray = run.world.body_pose("sponge"), run.world.body_pose("tray")
    local = np.linalg.inv(tray) @ sponge
    assert abs(local[0, 3]) < 0.15 and abs(local[1, 3]) < 0.11 and sponge[2, 2] > 0.99
    assert math.dist(sponge[:2, 3], start[:2, 3]) > 0.15  # not back where it came from


def test_a_jug_is_taken_by_its_handle_poured_from_and_put_back():
    # the jug written only in tests/data/new_objects/jug_plate.oac (a shell and a box handle
    # 6 cm out along +x); tests/data/jug_handle.oac grasps it `type handle` at the handle
    from runtime_lib import ROOT, STANDARD

    from oacdsl.compiler import load_library

    data = ROOT / "tests" / "data"
    lib = load_library([*STANDARD, data / "new_objects" / "jug_plate.oac", data / "jug_handle.oac"])
    run = prepare(lib, "pour_from_jug", scene="jug_by_handle")
    held = {}

    def on_step(index, step, world):
        if step.oac == "grasp":
            t_jug, t_grasp = world.body_pose("jug"), world.frame_pose("grasp_l")
            held["centre"] = (np.linalg.inv(t_jug) @ t_grasp[:, 3])[:3]
            held["palm"] = t_jug[:3, :3].T @ -t_grasp[:3, 0]
            held["parts"] = world.hand_parts_touching("l", "jug")

    result = run_prepared(run, on_step=on_step)
    assert result.success, result.error
    assert held["centre"][0] > 0.03  # the hand is at the handle, outside the body (radius 4.5 cm)
    assert held["palm"] @ np.array([-1.0, 0.0, 0.0]) > 0.9  # palm facing the jug's axis
    assert "fingers" in held["parts"]
    assert run.world.balls_inside("basin", "water") >= 9
    assert run.world.held["l"] is None and run.world.body_pose("jug")[2, 2] > 0.99


def test_a_failing_skill_is_named_once_when_its_step_has_its_name(monkeypatch):
    # "stir: stir: the spoon lost contact" read twice the same word; a step named otherwise keeps
    # its own name in front ("stir_in: stir: …": which step, then which skill)
    from types import SimpleNamespace

    from oacdsl.errors import RuntimeFailure
    from oacdsl.runtime import executor

    def failing(ctx, *args, **params):
        raise RuntimeFailure("stir: spoon lost contact with cup while stirring")

    monkeypatch.setitem(executor.IMPLEMENTATIONS, "stir", failing)
    ctx = SimpleNamespace(world=SimpleNamespace(warnings=dict))

    def step(name):
        return SimpleNamespace(oac=SimpleNamespace(name=name, skill="stir"), args=(), params={})

    assert executor._run_skill(ctx, step("stir")) == "stir: spoon lost contact with cup while stirring"
    assert executor._run_skill(ctx, step("stir_in")) == (
        "stir_in: stir: spoon lost contact with cup while stirring"
    )
