"""A grasp's approach keeps room from the other hand and what it holds
(``runtime/motion/approach.py``, ``skills/grasp.py``), and the hands are exchanged for a task
whose objects stand on the other hands' sides (``runtime/reach.py``): geometry only, no
simulation. The numbers are those of a left-handed (mirrored) synthetic Peel in the example
scene's places, seed 1 (``benchmarks/evaltakes.py --robot --task Peel --take mirrored
--seeds 1``): the right hand held the cucumber up on the left, and the left hand, sent for
the peeler on the right from its own side, came in through the cucumber (66 N)."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest

from oacdsl.model import Grasp
from oacdsl.model.oac import Atom
from oacdsl.runtime import reach
from oacdsl.runtime.grasping import PRE_GRASP_M, GraspPlan, plan_grasps
from oacdsl.runtime.hands import OPEN, TOP_PRESHAPE
from oacdsl.runtime.motion import TUNING
from oacdsl.runtime.motion.approach import approach_gap, hand_boxes_at, over_other_side
from oacdsl.runtime.motion.paths import segment_distance
from oacdsl.runtime.transforms import make_T

pytest.importorskip("mujoco", reason="the skills' modules import mujoco")

from oacdsl.runtime.skills.grasp_choice import HANDS_APART_M, clear_pre_grasp  # noqa: E402


def _box(lo: tuple[float, float, float], hi: tuple[float, float, float]) -> tuple[np.ndarray, np.ndarray]:
    return np.array(lo), np.array(hi)


#: The right hand's boxes (palm, thumb root, finger plates) as it held the cucumber up, and
#: the cucumber's, in the world (m).
RIGHT_HAND = [_box((0.43, 0.038, 0.925), (0.504, 0.069, 1.035)),
              _box((0.504, 0.052, 0.935), (0.545, 0.07, 1.028)),
              _box((0.544, 0.053, 0.934), (0.594, 0.074, 1.028))]
CUCUMBER = [_box((0.501, 0.071, 0.9), (0.652, 0.122, 0.948))]
STILL = RIGHT_HAND + CUCUMBER
#: The peeler standing on its blade at the grasp height its declaration gives.
PEELER = make_T(np.eye(3), (0.524, -0.135, 0.80))
PEELER_GRASP = Grasp(cls="Peeler", type="power", approach="side", offset=(0.0, 0.0, 0.1))


def _left_hand_plans() -> list[GraspPlan]:
    return plan_grasps(PEELER_GRASP, False, PEELER, "l", support_z=0.75, top_z=0.94)


def test_a_side_grasp_on_the_axis_may_be_taken_turned_like_a_round_objects():
    plans = _left_hand_plans()
    assert len(plans) == 5
    assert all(np.allclose(p.grasp[:3, 3], plans[0].grasp[:3, 3]) for p in plans)  # the same point
    assert np.allclose(plans[0].approach, (0.0, -1.0, 0.0))  # the left hand's own side first
    headings = {round(float(np.degrees(np.arctan2(p.approach[1], p.approach[0])))) for p in plans}
    assert headings == {-90, -60, -120, -30, -150}
    cucumber = Grasp(cls="Cucumber", type="power", approach="side", offset=(-0.06, 0.0, 0.085))
    assert len(plan_grasps(cucumber, False, PEELER, "l", support_z=0.75)) == 1  # off the axis: as declared


def test_the_approach_from_the_hands_own_side_runs_into_what_the_other_hand_holds_unless_shorter():
    natural = _left_hand_plans()[0]
    assert approach_gap("l", natural, OPEN, STILL) < 0.0  # through the cucumber and the right hand
    assert approach_gap("l", natural, OPEN, []) == np.inf
    # the objects on the table alone leave the corridor free: the cucumber is held, not standing
    pre = natural.grasp[:3, 3] - TUNING.pre_grasp_min_m * natural.approach
    shorter = GraspPlan(natural.grasp, make_T(natural.grasp[:3, :3], pre), natural.approach, natural.end)
    assert approach_gap("l", shorter, OPEN, STILL) > approach_gap("l", natural, OPEN, STILL) + 0.04
    assert approach_gap("l", shorter, OPEN, STILL) > 0.0



def test_a_side_approach_keeps_its_room_as_far_as_the_hand_may_go_past_the_grasp_point():
    # the guarded approach goes on past the grasp point until the hand touches the object (a
    # right hand's palm met a peeler's handle 2.4 cm past it, and its thumb the cucumber the
    # other hand held up beside it): something just past the hand at the grasp pose counts
    side = _left_hand_plans()[0]
    at_grasp = GraspPlan(side.grasp, side.pre_grasp, side.approach, side.grasp)
    reach_at_grasp = min(lo[1] for lo, _ in hand_boxes_at("l", side.grasp, OPEN))  # the approach is -y
    beyond = [_box((0.45, reach_at_grasp - 0.06, 0.75), (0.60, reach_at_grasp - 0.035, 1.0))]
    assert approach_gap("l", at_grasp, OPEN, beyond) > HANDS_APART_M
    assert approach_gap("l", side, OPEN, beyond) < 0.0
    assert float(np.linalg.norm(side.end[:3, 3] - side.grasp[:3, 3])) > 0.04
    # from above the hand stops on the object's top: what lies below (the object, what it
    # stands on, the other hand holding that) is not on its way
    lid = plan_grasps(Grasp(cls="Lid", type="power", approach="top", offset=(0.0, 0.0, 0.02)), True,
                      PEELER, "l", support_z=0.75, top_z=0.82)[0]
    lowest = min(lo[2] for lo, _ in hand_boxes_at("l", lid.grasp, TOP_PRESHAPE))
    under = [_box((0.45, -0.2, lowest - 0.05), (0.6, -0.05, lowest - 0.035))]
    assert approach_gap("l", lid, TOP_PRESHAPE, under) > HANDS_APART_M

class _Ctx:
    """What clear_pre_grasp asks of a skill context: the gap to the objects' footprints."""

    def __init__(self, obstacles: list[tuple[tuple[float, float], float]]) -> None:
        self.obstacles = [(np.array(xy), r) for xy, r in obstacles]

    def clearance(self, a: np.ndarray, b: np.ndarray, exclude: set[str]) -> float:
        return min((segment_distance(xy, a[:2], b[:2]) - r for xy, r in self.obstacles), default=np.inf)


def test_a_pre_grasp_moves_in_off_the_other_hand_to_the_roomiest_approach_when_none_keeps_full_room():
    natural = _left_hand_plans()[0]

    def room(p: GraspPlan) -> float:
        return approach_gap("l", p, OPEN, STILL)

    moved = clear_pre_grasp(_Ctx([]), natural, "peeler", room)
    length = float(np.linalg.norm(moved.pre_grasp[:3, 3] - moved.grasp[:3, 3]))
    assert TUNING.pre_grasp_min_m - 1e-9 <= length < PRE_GRASP_M
    assert room(moved) > room(natural)
    # every other length it could have taken leaves less room (or reaches the full room)
    for k in range(int(round((PRE_GRASP_M - TUNING.pre_grasp_min_m) / TUNING.pre_grasp_step_m)) + 1):
        pre = natural.grasp[:3, 3] - (PRE_GRASP_M - k * TUNING.pre_grasp_step_m) * natural.approach
        other = GraspPlan(natural.grasp, make_T(natural.grasp[:3, :3], pre), natural.approach, natural.end)
        assert room(other) <= room(moved) + 1e-9 or room(moved) >= HANDS_APART_M
    # with nothing held by the other hand, the plan is kept as it was
    assert clear_pre_grasp(_Ctx([]), natural, "peeler", lambda p: np.inf) is natural


def test_the_way_to_the_pre_grasp_flies_over_the_other_hand_when_it_would_meet_it():
    home = make_T(np.eye(3), (0.54, 0.36, 1.13))
    moving = hand_boxes_at("l", home, OPEN)
    over_pre = np.array([0.524, -0.055, 0.98])  # above the shortened pre-grasp
    high = over_other_side(moving, STILL, home[:3, 3], [over_pre, over_pre - [0.0, 0.0, 0.08]])
    assert high is not None
    below = home[2, 3] - min(lo[2] for lo, _ in moving)
    assert high == pytest.approx(max(hi[2] for _, hi in STILL) + below + TUNING.over_m)
    # flown at that height, the way keeps the room
    up, across = home[:3, 3].copy(), over_pre.copy()
    up[2] = across[2] = high
    from oacdsl.runtime.motion.detour import way_gap

    assert way_gap(moving, STILL, home[:3, 3], [home[:3, 3], up, across]) >= TUNING.over_m - 1e-9
    # a way on the hand's own side, away from them: as planned
    assert over_other_side(moving, STILL, home[:3, 3], [np.array([0.55, 0.30, 1.0])]) is None
    assert over_other_side(moving, [], home[:3, 3], [over_pre]) is None


# --- which hand takes what ---------------------------------------------------------------------

def _world(objects: dict[str, tuple[float, float]]) -> SimpleNamespace:
    frames = {"grasp_l": make_T(np.eye(3), (0.54, 0.36, 1.13)),
              "grasp_r": make_T(np.eye(3), (0.54, -0.36, 1.13))}
    return SimpleNamespace(
        layout=SimpleNamespace(hands={"left_hand": "l", "right_hand": "r"}),
        frame_pose=frames.__getitem__,
        body_pose=lambda name: make_T(np.eye(3), (*objects[name], 0.8)),
    )


def _ctx(objects: dict[str, tuple[float, float]]) -> SimpleNamespace:
    return SimpleNamespace(world=_world(objects), objects=lambda: frozenset(objects))


def _grasp(hand: str, obj: str) -> SimpleNamespace:
    oac = SimpleNamespace(effect=(Atom(left="h", right="o"),))
    return SimpleNamespace(oac=oac, binding={"h": hand, "o": obj})


PEEL = {"cucumber": (0.57, 0.084), "peeler": (0.524, -0.135)}


def test_crossed_is_how_far_the_hands_reach_past_the_robots_middle():
    across, why = reach.crossed(_ctx(PEEL), {"cucumber": "right_hand", "peeler": "left_hand"})
    assert across == pytest.approx(0.084 + 0.135)
    assert "left_hand takes peeler 14 cm past the middle" == why
    assert reach.crossed(_ctx(PEEL), {"cucumber": "left_hand", "peeler": "right_hand"}) == (0.0, "")


@pytest.fixture
def equal_arms(monkeypatch: pytest.MonkeyPatch) -> None:
    """Both arms alone reach every object as well (no whole-body IK here)."""
    monkeypatch.setattr(reach, "arm_miss_m", lambda ctx, hand, obj: 0.05)


@pytest.mark.usefixtures("equal_arms")
def test_a_left_handed_task_in_a_scene_laid_out_for_the_right_hand_is_done_with_the_hands_exchanged():
    steps = [_grasp("right_hand", "cucumber"), _grasp("left_hand", "peeler")]
    found = reach.exchanged_hands(_ctx(PEEL), steps)
    assert found is not None
    assert found[0] == {"left_hand": "right_hand", "right_hand": "left_hand"}
    assert "22 cm across the robot's middle" in found[1]
    # as laid out for it: as demonstrated
    as_laid = [_grasp("left_hand", "cucumber"), _grasp("right_hand", "peeler")]
    assert reach.exchanged_hands(_ctx(PEEL), as_laid) is None
    # a hand-over: one object, taken first on the other hand's side
    mug = {"mug": (0.58, -0.26)}
    left_first = [_grasp("left_hand", "mug"), _grasp("right_hand", "mug")]
    assert reach.exchanged_hands(_ctx(mug), left_first) is not None
    assert reach.exchanged_hands(_ctx(mug), left_first[::-1]) is None


def _grasp_both(h1: str, h2: str, obj: str) -> SimpleNamespace:
    oac = SimpleNamespace(effect=(Atom(left="h1", right="o"), Atom(left="h2", right="o")))
    return SimpleNamespace(oac=oac, binding={"h1": h1, "h2": h2, "o": obj})


@pytest.mark.usefixtures("equal_arms")
def test_an_object_both_hands_take_at_once_is_on_neither_hands_side():
    # a rolling pin left of the middle, taken by both hands in one step: whichever hand the
    # step names first, nothing to exchange
    pin = {"rolling_pin": (0.55, 0.30)}
    for first, second in (("right_hand", "left_hand"), ("left_hand", "right_hand")):
        assert reach.exchanged_hands(_ctx(pin), [_grasp_both(first, second, "rolling_pin")]) is None


@pytest.mark.usefixtures("equal_arms")
def test_what_either_assignment_reaches_as_far_across_keeps_its_hands():
    # a lid on a bottle right of the middle: the left hand reaches across for the lid, or,
    # exchanged, for the bottle, as far: nothing gained
    stacked = {"bottle": (0.55, -0.15), "lid": (0.55, -0.15)}
    steps = [_grasp("right_hand", "bottle"), _grasp("left_hand", "lid")]
    assert reach.exchanged_hands(_ctx(stacked), steps) is None
    # near the middle (less than a hand's width across in all): as demonstrated
    near = {"cucumber": (0.57, 0.04), "peeler": (0.524, -0.05)}
    crossing = [_grasp("right_hand", "cucumber"), _grasp("left_hand", "peeler")]
    assert reach.exchanged_hands(_ctx(near), crossing) is None


def test_hands_are_not_exchanged_when_the_exchanged_arms_would_miss_more(monkeypatch: pytest.MonkeyPatch):
    steps = [_grasp("right_hand", "cucumber"), _grasp("left_hand", "peeler")]
    def miss(ctx: object, hand: str, obj: str) -> float:  # the left arm would miss the cucumber
        return 0.2 if (hand, obj) == ("left_hand", "cucumber") else 0.05

    monkeypatch.setattr(reach, "arm_miss_m", miss)
    assert reach.exchanged_hands(_ctx(PEEL), steps) is None


@pytest.mark.slow
def test_on_the_robot_the_left_hands_first_approach_keeps_off_the_cucumber_the_right_hand_holds_up():
    """In the simulation: the right hand holds the cucumber up on the left (the example scene's
    places of seed 1), and the left hand's grasps of the peeler on the right, most preferred
    first, start with one that comes in with room from the right hand and the cucumber and
    whose arm does not lie on the cucumber (before: from its own side, 20 cm out, through the
    cucumber, 66 N; then, from behind, its forearm on it, 61 N)."""
    pytest.importorskip("placo", reason="the robot runtime needs the 'robot' extra (placo)")
    from pathlib import Path

    from oacdsl.compiler import load_library
    from oacdsl.runtime.executor import prepare
    from oacdsl.runtime.motion.approach import arm_room_to, other_side_boxes
    from oacdsl.runtime.skills.grasp_choice import grasp_candidates, preshape

    root = Path(__file__).resolve().parents[1]
    lib = load_library([root / "library" / "kit", root / "library" / "examples"])
    places = {"cucumber": (0.574, 0.084), "peeler": (0.524, -0.135)}
    run = prepare(lib, "grasp", {"h": "left_hand", "o": "peeler"}, scene="peeling", places=places,
                  held={"right_hand": "cucumber"})
    ctx = run.context
    assert ctx.world.held["r"] == "cucumber"
    still = other_side_boxes(ctx.world, "l", {"peeler"})
    first = next(p for p in grasp_candidates(ctx, "left_hand", "peeler")
                 if ctx.ctl.ik.try_reach("l", p.grasp).position_m <= 0.02)  # what plan_grasp takes
    assert approach_gap("l", first, preshape(ctx, "peeler"), still) > 0.0
    assert arm_room_to(ctx.world, ctx.ctl.ik, "l", first, "cucumber") >= 0.0
