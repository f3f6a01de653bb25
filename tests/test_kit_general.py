"""Actions no KIT development clip has (issue 11), written only in ``.oac`` files on top of the
KIT library: ``library/examples/`` (open and close a bottle: ``twist``; peel and transfer:
``stroke``; …), each run on ARMAR-III with its effects judged, and the skills' parameters from a
demonstrated motion."""

from __future__ import annotations

import json
import math
import subprocess
import sys
from functools import lru_cache
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).parent))

pytest.importorskip("mujoco", reason="the robot runtime needs the 'robot' extra (mujoco)")
pytest.importorskip("placo", reason="the robot runtime needs the 'robot' extra (placo)")

from oacdsl.compiler import load_library  # noqa: E402
from oacdsl.matching.demoparams import step_params  # noqa: E402
from oacdsl.runtime.executor import prepare, run_prepared  # noqa: E402
from oacdsl.segmentation.motion import SubActionMotion  # noqa: E402
from oacdsl.segmentation.motionfeatures import MotionFeatures  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
LIBRARIES = (ROOT / "library" / "kit", ROOT / "library" / "examples")


@lru_cache(maxsize=1)
def library():
    return load_library(list(LIBRARIES))


class Yaw:
    """Observer: the object's turn about the world's z axis (rad) while it touches ``on``, 100
    times a second."""

    rate_hz = 100.0

    def __init__(self, obj, on):
        self.obj, self.on, self.yaw = obj, on, []

    def __call__(self, world):
        if world.touching(self.obj, self.on):
            r = world.body_pose(self.obj)[:3, :3]
            self.yaw.append(math.atan2(r[1, 0], r[0, 0]))

    def unwrapped(self):
        """The turn since it first touched, rad."""
        yaw = np.unwrap(np.array(self.yaw))
        return yaw - yaw[0]


def test_twist_screws_the_lid_on_and_off_the_bottle_the_other_hand_holds():
    run = prepare(library(), "close_and_open")
    lid = Yaw("lid", on="bottle")
    run.controller.add_observer(lid)
    result = run_prepared(run)
    assert result.success, result.error
    grasp_bottle, grasp_lid, screw_on, screw_off = result.steps
    # each twist turned the lid by about its angle (240°, in strokes of at most 40° and
    # regrasps), clockwise to close and counterclockwise to open
    yaw = np.degrees(lid.unwrapped())
    assert yaw.min() == pytest.approx(-240, abs=10)  # screwed on
    assert yaw[-1] - yaw.min() == pytest.approx(240, abs=10)  # and off again
    assert ["bottle", "lid"] in screw_on.observed
    assert ["bottle", "lid"] not in screw_off.observed and ["left_hand", "lid"] in screw_off.observed
    world = run.world
    # the lid ended 6 cm above the bottle's top, on its axis
    offset = world.body_pose("lid")[:3, 3] - world.body_pose("bottle")[:3, 3]
    assert np.hypot(*offset[:2]) < 0.02 and offset[2] == pytest.approx(0.18 + 0.06, abs=0.02)


#: First-frame positions (m, motion capture frame) as a recording gives them to ``layout
#: demonstrated``: the lid's markers above the bottle's, a little off its axis.
FIRST_FRAME = {
    "left_hand": np.array([0.3, 0.25, 1.0]),
    "right_hand": np.array([0.3, -0.25, 1.0]),
    "bottle": np.array([0.6, -0.05, 0.95]),
    "lid": np.array([0.61, -0.04, 1.14]),
}


def test_a_lid_on_its_bottle_at_the_first_frame_starts_on_it_and_is_unscrewed():
    run = prepare(library(), "open_bottle", layout="demonstrated", demonstrated=FIRST_FRAME)
    lid, bottle = (run.world.layout.placement(n) for n in ("lid", "bottle"))
    assert lid.on == "bottle" and (lid.x, lid.y) == (bottle.x, bottle.y)
    assert run.world.touching("lid", "bottle")  # the precondition l <-> b holds at the start
    result = run_prepared(run)
    assert result.success, result.error
    assert ["left_hand", "lid"] in result.steps[-1].observed
    assert ["bottle", "lid"] not in result.steps[-1].observed
    # side by side at the first frame, they are laid out apart, as before
    apart = dict(FIRST_FRAME, lid=np.array([0.6, 0.2, 0.9]))
    layout = prepare(library(), "open_bottle", layout="demonstrated", demonstrated=apart).world.layout
    lid, bottle = layout.placement("lid"), layout.placement("bottle")
    assert lid.on is None and lid.y > bottle.y + 0.1


def test_the_hand_lets_go_of_the_lid_only_on_the_middle_of_the_bottle_top():
    # the arm lags the turning hand by up to 3 cm sideways, and the bottle in the right hand
    # leans: a lid let go 4 cm off the top's middle tipped over its edge as the hand rose
    # (seed 2 lost it so); each time the hand lets go, the lid's base is within 1 cm of the
    # middle of the bottle's top (18 cm up its own, leaning axis)
    run = prepare(library(), "open_bottle", seed=2, layout="demonstrated", demonstrated=FIRST_FRAME)
    world, offs = run.world, []
    release = world.release

    def spy(side):
        t_bottle, t_lid = world.body_pose("bottle"), world.body_pose("lid")
        off = t_lid[:3, 3] - (t_bottle[:3, 3] + 0.18 * t_bottle[:3, 2])  # m
        axis = t_lid[:3, 2]
        if world.held.get(side) == "lid" and world.touching("lid", "bottle"):
            offs.append(float(np.linalg.norm(off - (off @ axis) * axis)))
        release(side)

    world.release = spy
    result = run_prepared(run)
    assert result.success, result.error
    assert len(offs) >= 6  # 240° in strokes of 25°: a regrasp between each two
    assert max(offs) < 0.01, [round(o * 100, 1) for o in offs]


@pytest.mark.slow
def test_the_lid_taken_beside_the_held_bottle_is_held_upright_and_goes_on():
    # seed 9: the lid beside the bottle the right hand holds up; no top grasp of it keeps the
    # 3 cm wanted from that hand, and the roomiest, turned a quarter, is reached only with the
    # torso leaning as far as it goes: the hand closed tipped 14° and the lid, held 10-16°
    # tilted, sprang off the bottle's edge ("lid did not reach bottle"). Taken upright instead:
    # the lid is held within 8° of upright and screwed on
    run = prepare(library(), "close_and_open", seed=9)
    tilt_deg = []

    def on_step(index, step, world):
        if index == 1:
            tilt_deg.append(math.degrees(math.acos(min(1.0, float(world.body_pose("lid")[2, 2])))))

    result = run_prepared(run, on_step=on_step)
    assert result.success, result.error
    assert tilt_deg and tilt_deg[0] < 8.0, tilt_deg


def test_oacc_run_closes_and_opens_the_bottle_from_the_command_line():
    args = [a for p in LIBRARIES for a in ("--library", str(p))]
    out = subprocess.run(
        [sys.executable, "-m", "oacdsl", "run", "close_and_open", *args, "--seed", "2", "--no-record"],
        capture_output=True, text=True, timeout=300, cwd=ROOT,
    )
    assert out.returncode == 0, out.stderr
    assert "step 3 screw_on(left_hand, lid, bottle): ok" in out.stdout  # an adaptive run numbers what it ran
    assert "close_and_open: success" in out.stdout
    assert "balls" not in out.stdout  # no liquid in this task: no "0/0 balls in a bowl"


class Strokes:
    """Observer: while ``tool`` touches ``target``, the tool's position (m, world), 100 times a
    second; and the longest time without a contact since the first (s)."""

    rate_hz = 100.0

    def __init__(self, tool, target):
        self.tool, self.target, self.points, self._was = tool, target, [], False
        self.longest_gap_s, self._left = 0.0, None

    def __call__(self, world):
        now = world.touching(self.tool, self.target)
        if self._was and not now:
            self._left = world.time_s
        if now and not self._was and self._left is not None:
            self.longest_gap_s = max(self.longest_gap_s, world.time_s - self._left)
        self._was = now
        if now:
            self.points.append(world.body_pose(self.tool)[:3, 3].copy())


def test_stroke_peels_the_cucumber_the_other_hand_holds_away_from_that_hand():
    run = prepare(library(), "peel_cucumber")
    peeler = Strokes("peeler", "cucumber")
    run.controller.add_observer(peeler)
    result = run_prepared(run)
    assert result.success, result.error
    assert ["cucumber", "peeler"] in result.steps[-1].observed
    # the peeler slides back on the cucumber between strokes: never off it for more than a few
    # control ticks (lifted back through the air, it left the cucumber for 1.3 s each time: a
    # change the demonstration does not have)
    assert peeler.longest_gap_s < 0.1, peeler.longest_gap_s
    world = run.world
    # along the cucumber (its length, x), from near the left hand towards its free end
    along = world.body_pose("cucumber")[:3, 0]
    hand = world.frame_pose("grasp_l")[:3, 3]
    way = np.array(peeler.points) @ along
    assert np.ptp(way) > 0.05
    free_end = float((world.body_pose("cucumber")[:3, 3] - hand) @ along)
    assert np.sign(way[-1] - way[0]) == np.sign(free_end)
    # three strokes towards the free end: the way crosses its middle that way three times
    side = np.sign(free_end) * (way - 0.5 * (way.min() + way.max())) > 0
    assert int(np.count_nonzero(side[1:] & ~side[:-1])) == 3


def test_oacc_run_pushes_across_the_board_towards_the_held_bowl():
    args = [a for p in LIBRARIES for a in ("--library", str(p))]
    out = subprocess.run(
        [sys.executable, "-m", "oacdsl", "run", "transfer_to_bowl", *args, "--seed", "1", "--no-record",
         "--json"],
        capture_output=True, text=True, timeout=300, cwd=ROOT,
    )
    assert out.returncode == 0, out.stderr
    doc = json.loads(out.stdout)
    assert doc["success"] and doc["steps"][-1]["oac"] == "push_into"
    assert ["board", "knife_black"] in doc["steps"][-1]["observed"]


def test_a_stroke_takes_the_demonstrated_count_and_period():
    lib = library()
    found = step_params("stroke", motion(period_s=0.62, cycles=4.4, radius_m=0.03),
                        ("right_hand", "peeler", "cucumber"), lib, lib.scenes["peeling"])
    values = {p.name: (p.value.value, p.value.unit) for p in found.params}
    assert values == {"strokes": (4.0, ""), "period": (0.62, "s")}


class Path:
    """Observer: an object's position (m, world) and whether it touches ``on``, 50 times a second."""

    rate_hz = 50.0

    def __init__(self, obj, on):
        self.obj, self.on, self.points, self.touching = obj, on, [], []

    def __call__(self, world):
        self.points.append(world.body_pose(self.obj)[:3, 3].copy())
        self.touching.append(world.touching(self.obj, self.on))


def test_both_hands_take_the_rolling_pin_roll_it_on_the_dough_and_put_it_down():
    run = prepare(library(), "roll_the_pin", seed=4)
    pin = Path("rolling_pin", on="dough")
    run.controller.add_observer(pin)
    result = run_prepared(run)
    assert result.success, result.error
    take, roll, put_down = result.steps[0], result.steps[1], result.steps[2]
    assert ["left_hand", "rolling_pin"] in take.observed and ["right_hand", "rolling_pin"] in take.observed
    assert ["dough", "rolling_pin"] in roll.observed
    assert ["left_hand", "nothing"] in put_down.observed and ["right_hand", "nothing"] in put_down.observed
    # to and fro on the dough, touching it: 6 cm to either side, away from the robot and back
    on = np.array(pin.touching)
    first = int(np.argmax(on))
    rolled = np.array(pin.points)[first : first + round(roll.duration_s * Path.rate_hz)]
    assert on[first : first + len(rolled)].mean() > 0.8
    assert np.ptp(rolled[:, 0]) == pytest.approx(0.12, abs=0.015) and np.ptp(rolled[:, 1]) < 0.02


def test_a_roll_takes_the_demonstrated_strokes():
    lib = library()
    found = step_params("roll", motion(period_s=1.1, cycles=3.2, radius_m=0.06),
                        ("left_hand", "rolling_pin", "right_hand", "dough"), lib, lib.scenes["rolling"])
    values = {p.name: (p.value.value, p.value.unit) for p in found.params}
    assert values == {"strokes": (3.0, ""), "length": (85.0, "mm"), "period": (1.1, "s")}


def motion(**features: object) -> SubActionMotion:
    base = dict(duration_s=4.2, path_length_m=0.05, extent_m=(0.02, 0.01, 0.01), core_s=(0.0, 4.2),
                period_s=None, cycles=None, radius_m=0.01, tilt_max_rad=0.02, tilt_time_s=0.0)
    base.update(features)
    t = np.arange(3) * 0.1
    return SubActionMotion(1, 10, 52, "left_hand", "lid", "bottle", "made", t, np.full((3, 4, 4), np.nan),
                           MotionFeatures(**base), 0.0)  # type: ignore[arg-type]


def test_a_twist_takes_the_demonstrated_turn_and_its_sense():
    lib = library()
    scene = lib.scenes["bottle_lid"]
    args = ("left_hand", "lid", "bottle")
    found = step_params("twist", motion(twist_rad=math.radians(-301.4)), args, lib, scene)
    values = {p.name: (p.value.value, p.value.unit) for p in found.params}
    assert values == {"angle": (-301.0, "deg"), "duration": (4.2, "s")}
    assert "angle -301deg = twist -301deg" in (found.comment or "")


def test_a_precondition_the_layout_breaks_names_the_layout():
    # open_bottle needs the lid on the bottle; the scene stands it beside it ('lid at (56cm, 18cm)')
    run = prepare(library(), "open_bottle", scene="bottle_lid")
    result = run_prepared(run)
    assert not result.success
    assert "precondition of open_bottle not met: bottle <-> lid does not hold (bottle touches nothing);" \
        " the initial state comes from the layout: bottle stands alone at (0.54, -0.06) m, from the scene's" \
        " 'at'; lid stands alone at (0.56, 0.18) m, from the scene's 'at'" in result.error
    assert "'layout demonstrated'" in result.error


def test_a_precondition_about_a_hand_does_not_blame_the_layout():
    from oacdsl.runtime.layout_cause import layout_cause

    run = prepare(library(), "open_bottle", scene="bottle_lid")
    assert layout_cause(run.world.layout, [("left_hand", "lid", False)]) is None
    assert layout_cause(run.world.layout, [("lid", "nothing", False)]) == (
        "the initial state comes from the layout: lid stands alone at (0.56, 0.18) m, from the scene's 'at'"
    )
