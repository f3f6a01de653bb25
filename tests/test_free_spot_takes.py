"""Where ``place`` sets down what may not go back where it was taken (a cup taken from the other
hand): out of the way of the takes the run's later steps make, judged by the arm's posture.

The executor tells a skill the (hand, object) takes still to come (``coming_takes``); an
object set down where the arm or hand taking one of them would pass
(``room_to_object``) comes after the spots out of that way: in the dough hand-over the red
cup set down beside the green cup was brushed by the fingers taking the green cup."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from oacdsl.compiler import load_library
from oacdsl.model import Oac
from oacdsl.runtime.binding import Step
from oacdsl.runtime.intent import coming_takes

ROOT = Path(__file__).resolve().parents[1]


def _step(library, name: str, **binding: str) -> Step:  # type: ignore[no-untyped-def]
    oac = library.oacs[name]
    assert isinstance(oac, Oac)
    return Step(oac, dict(binding))


def test_coming_takes_are_the_later_steps_hand_relations_in_order_each_once():
    library = load_library([ROOT / "library"])
    steps = [
        _step(library, "pour", h="right_hand", c="green_cup", l="liquid_two", b="orange_bowl"),
        _step(library, "place", h="right_hand", o="green_cup"),
        _step(library, "grasp", h="right_hand", o="mixer"),
        _step(library, "grasp", h="left_hand", o="red_cup"),
        _step(library, "mix", h="right_hand", m="mixer", b="orange_bowl"),
        _step(library, "grasp", h="right_hand", o="mixer"),
    ]
    hands = {"left_hand", "right_hand"}
    assert coming_takes(steps, hands) == (("right_hand", "mixer"), ("left_hand", "red_cup"))
    assert coming_takes(steps[:2], hands) == ()  # a pour and a place take nothing


def test_an_object_set_down_in_the_way_of_a_coming_take_is_within_the_arms_reach_of_it():
    pytest.importorskip("mujoco", reason="the robot runtime needs the 'robot' extra (mujoco)")
    pytest.importorskip("placo", reason="the robot runtime needs the 'robot' extra (placo)")
    from oacdsl.runtime.armroom import room_to_object
    from oacdsl.runtime.executor import prepare
    from oacdsl.runtime.motion import TUNING
    from oacdsl.runtime.skills.grasp import grasp_candidates
    from oacdsl.runtime.transforms import make_T

    library = load_library([ROOT / "library"])
    run = prepare(library, "grasp", {"h": "right_hand", "o": "green_cup"}, "kitchen")
    ctx, world = run.context, run.world
    plan = grasp_candidates(ctx, "right_hand", "green_cup")[0]
    poses = [plan.pre_grasp, plan.grasp]
    postures = [q for _, q in ctx.ctl.ik.reach_postures("r", poses, TUNING.pose_solve_tries)]
    cup, before = world.body_pose("green_cup"), world.body_pose("red_cup")
    # the right hand comes from the right (-y): beside the cup on that side is in its way,
    # the same distance in front of the robot's left hand side is not
    in_the_way = make_T(np.eye(3), (cup[0, 3], cup[1, 3] - 0.12, cup[2, 3]))
    aside = make_T(np.eye(3), (cup[0, 3], cup[1, 3] + 0.2, cup[2, 3]))
    rooms = [room_to_object(world, "r", q, "red_cup", in_the_way) for q in postures]
    assert min(rooms) < TUNING.arm_room_m
    assert all(room_to_object(world, "r", q, "red_cup", aside) >= TUNING.arm_room_m for q in postures)
    assert np.array_equal(world.body_pose("red_cup"), before)  # measured in a scratch copy only
