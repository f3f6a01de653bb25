"""The motion layer (issue 19): skills compose primitives, the controller's drive() is the one
control loop, defaults live in one tuning record, and the other hand follows a policy."""

from __future__ import annotations

import ast
import dataclasses
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]
SKILLS = sorted((ROOT / "oacdsl" / "runtime" / "skills").glob("*.py"))


def _calls(path: Path) -> set[str]:
    tree = ast.parse(path.read_text(encoding="utf-8"))
    calls = [n for n in ast.walk(tree) if isinstance(n, ast.Call)]
    return {n.func.attr for n in calls if isinstance(n.func, ast.Attribute)}


def test_no_skill_runs_its_own_control_loop():
    # ticking the simulation, or driving the controller's loop directly, is the motion layer's job
    offenders = {p.name: sorted(_calls(p) & {"tick", "drive", "step"}) for p in SKILLS}
    assert {k: v for k, v in offenders.items() if v} == {}


def test_no_skill_imports_the_verifier_or_the_closed_loop():
    for p in SKILLS:
        tree = ast.parse(p.read_text(encoding="utf-8"))
        mods = {n.module or "" for n in ast.walk(tree) if isinstance(n, ast.ImportFrom)}
        mods |= {a.name for n in ast.walk(tree) if isinstance(n, ast.Import) for a in n.names}
        bad = {m for m in mods if m.startswith(("oacdsl.verify", "oacdsl.pipeline", "oacdsl.segmentation"))}
        assert not bad, (p.name, bad)


def test_skills_take_their_defaults_from_their_signatures():
    from oacdsl.skills import SIGNATURES

    for p in SKILLS:
        text = p.read_text(encoding="utf-8")
        if "SIGNATURES[" in text:
            for name in SIGNATURES:
                if f'SIGNATURES["{name}"]' in text:
                    assert name in SIGNATURES


def test_the_tuning_record_is_frozen_and_in_si_units():
    from oacdsl.runtime.motion import TUNING, Tuning

    with pytest.raises(dataclasses.FrozenInstanceError):
        TUNING.hover_m = 0.1  # type: ignore[misc]
    units = ("_m", "_s", "_n", "_m_s", "_rad", "_share", "_factor", "_tries")
    assert all(f.name.endswith(units) for f in dataclasses.fields(Tuning)), [
        f.name for f in dataclasses.fields(Tuning) if not f.name.endswith(units)
    ]
    assert dataclasses.replace(TUNING, hover_m=0.05).hover_m == 0.05


def test_a_fast_cycle_is_cut_into_waypoints_of_two_control_ticks_at_least():
    from oacdsl.runtime.control import CONTROL_DT_S
    from oacdsl.runtime.motion import TUNING, waypoints_per_cycle

    assert TUNING.waypoint_min_s >= 2 * CONTROL_DT_S - 1e-12
    assert waypoints_per_cycle(0.89, 16) == 16  # KIT Mix as demonstrated: as before
    for period in (0.3, 0.44, 0.6):  # KIT Mix at double speed: 0.44 s circles
        n = waypoints_per_cycle(period, 16)
        ticks = round(period / n / CONTROL_DT_S)
        assert n < 16 and ticks >= 2 and n * ticks * CONTROL_DT_S <= period + 1e-9, (period, n, ticks)


pytest.importorskip("mujoco", reason="the robot runtime needs the 'robot' extra (mujoco)")
pytest.importorskip("placo", reason="the robot runtime needs the 'robot' extra (placo)")


@pytest.fixture(scope="module")
def run():  # type: ignore[no-untyped-def]
    from runtime_lib import task_library

    from oacdsl.runtime.executor import prepare

    return prepare(task_library(), "pick_and_place", scene="pouring")


def _lift_both(run, policy):  # type: ignore[no-untyped-def]
    """Raise the right hand 6 cm with the left hand's policy; returns how far the left hand's
    goal and grasp frame moved, m."""
    from oacdsl.runtime.motion import Motion

    ik = run.controller.ik
    m = Motion(run.context, "r", policy)
    before_goal, before = ik.goal("l"), run.world.frame_pose("grasp_l")
    m.rise(0.06, 0.8)
    m.hold_still()
    return (
        float(np.linalg.norm(ik.target("l")[:3, 3] - before_goal[:3, 3])),
        float(np.linalg.norm(run.world.frame_pose("grasp_l")[:3, 3] - before[:3, 3])),
    )


def test_other_hand_policies(run):
    from oacdsl.runtime.motion import OtherHand

    goal_moved, _ = _lift_both(run, OtherHand.STEADY)
    assert goal_moved < 1e-9  # its goal is the one it had
    goal_moved, hand_moved = _lift_both(run, OtherHand.FOLLOW)
    assert goal_moved == pytest.approx(0.06, abs=0.005)  # carried along rigidly
    assert hand_moved > 0.04


def test_a_guarded_approach_stops_on_its_guard_and_a_press_goes_down(run):
    from oacdsl.runtime.motion import Motion, down

    m = Motion(run.context, "r")
    start = m.here()
    ticks = []
    stopped = m.approach(down(start, 0.05), lambda: len(ticks) > 5 or ticks.append(1) is not None and False)
    assert stopped
    travelled = float(start[2, 3] - m.here()[2, 3])
    assert 0.0 < travelled < 0.05  # stopped early, where the hand was
    before = m.here()[2, 3]
    m.press(0.004)
    assert before - m.here()[2, 3] == pytest.approx(0.004, abs=1e-6)


def test_a_slide_that_loses_its_contact_is_lowered_until_it_touches_again(run):
    from oacdsl.runtime.control import CONTROL_DT_S
    from oacdsl.runtime.motion import TUNING, Motion

    m = Motion(run.context, "r")
    pose = m.here()
    touching = [False]
    path = m._pressed(lambda s: pose, lambda: touching[0])
    depths = [float(pose[2, 3] - path(0.0)[2, 3]) for _ in range(5)]
    assert depths == pytest.approx([TUNING.seek_speed_m_s * CONTROL_DT_S * k for k in range(1, 6)])
    touching[0] = True
    assert float(pose[2, 3] - path(0.0)[2, 3]) == pytest.approx(depths[-1])  # kept, not raised
    touching[0] = False
    for _ in range(1000):
        lowest = path(0.0)
    assert float(pose[2, 3] - lowest[2, 3]) == pytest.approx(TUNING.seek_max_m)


def test_hand_corners_are_the_hands_boxes_in_its_grasp_frame(run):
    from oacdsl.runtime.motion import Motion
    from oacdsl.runtime.shapes import hand_corners, hand_reach_below

    world = run.world
    before = hand_corners(world, "r")
    t = world.frame_pose("grasp_r")
    # the lowest corner in the world is how far the hand reaches below its grasp centre
    assert -float((before @ t[:3, :3].T)[:, 2].min()) == pytest.approx(hand_reach_below(world, "r"))
    m = Motion(run.context, "r")
    m.rise(0.03, 0.5)
    m.hold_still()
    assert np.abs(hand_corners(world, "r") - before).max() < 0.002  # moved with the hand


def test_a_carry_flies_over_the_other_hand_while_it_holds_something(run):
    from oacdsl.runtime.motion.paths import carry_path, other_hand_obstacle

    world = run.world
    assert other_hand_obstacle(world, "r") is None  # the left hand holds nothing
    xy, radius, top = None, 0.0, 0.0
    world.held["l"] = "orange_bowl"  # as if it held it: where its boxes are is what counts
    try:
        xy, radius, top = other_hand_obstacle(world, "r")
        t_l = world.frame_pose("grasp_l")
        assert top > t_l[2, 3] and radius > 0.05  # the thumb and fingers reach past the grasp centre
        now, goal = world.frame_pose("grasp_r"), world.frame_pose("grasp_r")
        now[:3, 3] = (xy[0], xy[1] - 0.2, top - 0.05)
        goal[:3, 3] = (xy[0], xy[1] + 0.2, top - 0.05)
        plain = carry_path(world, "r", now, goal, {"orange_bowl", "green_cup"}, 2.0)
        over = carry_path(world, "r", now, goal, {"orange_bowl", "green_cup"}, 2.0, over_other_hand=True)
    finally:
        world.held["l"] = None
    assert plain[1][0][2, 3] < top  # the plain way would cross the hand's height
    climb, via, *_, end = over
    assert climb[1] > 0 and climb[0][2, 3] > top and via[0][2, 3] > top  # up first, then across
    assert np.allclose(end[0], goal)


def test_only_a_carry_to_what_the_other_hand_holds_flies_over_that_hand(run, monkeypatch):
    from oacdsl.runtime.motion import Motion
    from oacdsl.runtime.motion import hand as hand_module

    seen: list[bool] = []

    def fake_path(*args, **kwargs):  # type: ignore[no-untyped-def]
        seen.append(kwargs["over_other_hand"])
        return []

    monkeypatch.setattr(hand_module, "carry_path", fake_path)
    m = Motion(run.context, "r")
    run.world.held["l"] = "orange_bowl"
    try:
        m.carry(m.here(), {"green_cup", "orange_bowl"})  # to the bowl the left hand holds
        m.carry(m.here(), {"green_cup"})  # elsewhere: the left hand may be above the way
    finally:
        run.world.held["l"] = None
    m.carry(m.here(), {"green_cup"})
    assert seen == [True, False, False]


def test_turn_both_follows_the_arc_about_each_pivot():
    # a tool leaned about its head's edge on a floor: the hand keeps its distance from the edge
    # all the way (a straight move between the two ends cuts the chord: 1.3 cm inside at 22 cm
    # and 40°, the head pushed into the floor and the fingers onto the rim, KIT Mix)
    import math

    from oacdsl.runtime.motion.both import turn_both
    from oacdsl.runtime.transforms import make_T

    class Recorder:
        def drive(self, paths, duration_s, guards=None, **_):
            self.paths, self.duration_s = paths, duration_s
            return dict.fromkeys(paths, False)

    ctl = Recorder()
    starts = {"l": make_T(np.eye(3), (0.5, 0.1, 1.02)), "r": make_T(np.eye(3), (0.5, -0.1, 1.02))}
    pivots = {s: starts[s][:3, 3] - [-0.03, 0.0, 0.22] for s in starts}
    axis = np.array([0.0, 1.0, 0.0])
    turn_both(ctl, starts, axis, pivots, math.radians(40.0), 1.0)
    assert ctl.duration_s == 1.0 and set(ctl.paths) == {"l", "r"}
    for s in starts:
        radius = np.linalg.norm(starts[s][:3, 3] - pivots[s])
        for u in np.linspace(0.0, 1.0, 9):
            pose = ctl.paths[s](u)
            assert abs(np.linalg.norm(pose[:3, 3] - pivots[s]) - radius) < 1e-9
            turned = math.degrees(math.acos((np.trace(pose[:3, :3]) - 1.0) / 2.0))
            assert abs(turned - 40.0 * u) < 1e-6
        end = ctl.paths[s](1.0)[:3, 3]
        assert end[0] > starts[s][0, 3] + 0.1 and end[2] < starts[s][2, 3]  # leaned away, lower
