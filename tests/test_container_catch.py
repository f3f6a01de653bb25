"""A container's floor holds the balls that fall onto it fast (its catch: a collision-only disc
under the floor that only the balls touch, under containers no hand carries), and the catch
touches nothing else."""

import itertools

import numpy as np
import pytest

pytest.importorskip("mujoco", reason="the robot runtime needs the 'robot' extra (mujoco)")
pytest.importorskip("placo", reason="the robot runtime needs the 'robot' extra (placo)")

import mujoco  # noqa: E402
from runtime_lib import task_library  # noqa: E402

from oacdsl.runtime.build import build_model, home_posture  # noqa: E402
from oacdsl.runtime.layout import plan_layout  # noqa: E402
from oacdsl.runtime.simworld import SimWorld  # noqa: E402


def _kitchen() -> SimWorld:
    lib = task_library()
    world = SimWorld(build_model(plan_layout(lib, lib.scenes["kitchen"]), None))
    world.set_targets(home_posture())
    return world


@pytest.mark.parametrize("height_m", [0.15, 0.3, 0.5])
def test_balls_dropped_into_the_bowl_stay_on_its_floor(height_m):
    # before the catch, balls dropped from 25 cm or more went through the bowl's 8 mm floor
    # (2.2 m/s: some 11 mm per time step, then sinking while the contact slows them)
    world = _kitchen()
    m, d = world.model, world.data
    bowl = world.layout.bodies["orange_bowl"]
    t_bowl = world.body_pose("orange_bowl")
    floor_z = t_bowl[2, 3] + bowl.floor
    ids = [m.body(name).id for name in world.built.balls["liquid_one"]]
    rng = np.random.default_rng(0)
    for i, b in enumerate(ids):
        q, v = m.jnt_qposadr[m.body_jntadr[b]], m.jnt_dofadr[m.body_jntadr[b]]
        a, r = rng.uniform(0.0, 2 * np.pi), rng.uniform(0.0, 0.6 * bowl.inner_radius)
        d.qpos[q : q + 7] = [t_bowl[0, 3] + r * np.cos(a), t_bowl[1, 3] + r * np.sin(a),
                             floor_z + height_m + 0.025 * (i % 3), 1.0, 0.0, 0.0, 0.0]
        d.qvel[v : v + 6] = 0.0
    mujoco.mj_forward(m, d)
    world.step(int(1.5 / m.opt.timestep))
    radius = world.layout.bodies["liquid_one"].ball_radius
    z = d.xpos[ids, 2] - floor_z
    assert world.balls_inside("orange_bowl", "liquid_one") == len(ids)
    assert z.min() > radius - 0.003  # resting on the floor, none sunk into it
    assert world.warnings() == {}


def test_the_catch_touches_only_the_balls():
    m = _kitchen().model
    catches = [g for g in range(m.ngeom) if m.geom(g).name.endswith("/catch")]

    def touch(a: int, b: int) -> bool:
        return bool(m.geom_contype[a] & m.geom_conaffinity[b] or m.geom_contype[b] & m.geom_conaffinity[a])

    # the bowl's; not the cups' (a hand carries them: there a catch would reach out under them)
    assert [m.geom(c).name for c in catches] == ["orange_bowl/catch"]
    balls = {g for g in range(m.ngeom) if m.geom(g).name.split("/")[0].startswith("liquid_")}
    for c, g in itertools.product(catches, range(m.ngeom)):
        assert touch(c, g) == (g in balls), m.geom(g).name
    for c in catches:  # invisible, massless, out of the group rays cast against
        assert m.geom_rgba[c][3] == 0.0 and m.geom_group[c] != 0
    body = {int(m.geom_bodyid[c]) for c in catches}
    bases = [g for g in range(m.ngeom) if m.geom(g).name.endswith("/base") and int(m.geom_bodyid[g]) in body]
    for base, ball in itertools.product(bases, balls):  # the visible floor is the catch's, to a ball
        assert not touch(base, ball)


def test_a_cup_has_no_catch_and_its_floor_holds_its_balls():
    m = _kitchen().model
    base, ball = m.geom("red_cup/base").id, m.geom("liquid_one/ball0").id
    assert m.geom_contype[ball] & m.geom_conaffinity[base] or m.geom_contype[base] & m.geom_conaffinity[ball]
