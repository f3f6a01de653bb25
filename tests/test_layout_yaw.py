"""An object's yaw on the robot's table: the scene's ``turned``, the demonstration's first frame
(``layout demonstrated``, for a class that declares ``markers``), and the built model's body.
The pin has a handle at one end: it is not alike half turned."""

import math

import numpy as np
import pytest

from oacdsl.compiler import load_library
from oacdsl.runtime.demo_layout import demonstrated_poses
from oacdsl.runtime.layout import plan_layout
from oacdsl.runtime.layout_yaw import alike_half_turned, nearer_half_turn
from oacdsl.segmentation.points import recording_from_points
from oacdsl.segmentation.synth.kinematics import rot_z
from oacdsl.segmentation.synth.scene import hand_markers

LIBRARY = """\
class Hand { shape hand }
class Table { shape table }
class Graspable
class Pin : Graspable {
    shape box(length 30cm, width 5cm, height 5cm)
    shape cylinder(radius 1cm, height 8cm) at (14cm, 0, 0)
    markers (14cm, 0, 5cm), (-14cm, 1cm, 5cm), (5cm, 2cm, 0), (-6cm, -2cm, 5cm)
}
class Block : Graspable {
    shape box(length 8cm, width 4cm, height 4cm)
}
grasp Pin { type power approach side offset (0.0, 0.0, 0.025) }
grasp Block { type power approach side offset (0.0, 0.0, 0.02) }

scene bench {
    block                 : Block
    left_hand, right_hand : Hand
    pin                   : Pin
    table                 : Table environment

    layout demonstrated
    block at (60cm, 30cm) turned -45deg
    pin   at (62cm, -10cm) turned 90deg
}
"""
#: The pin's markers in its class's frame, m (as LIBRARY declares them).
PIN_MARKERS = np.array([(0.14, 0, 0.05), (-0.14, 0.01, 0.05), (0.05, 0.02, 0), (-0.06, -0.02, 0.05)])
BLOCK_MARKERS = np.array([(0.04, 0.02, 0.04), (-0.04, 0.02, 0.04), (0.03, -0.02, 0.0), (-0.02, -0.02, 0.04)])
TABLE_Z_M = 0.75


def _library(tmp_path, text=LIBRARY):
    path = tmp_path / "bench.oac"
    path.write_text(text, encoding="utf-8")
    return load_library([path])


def _recording(pin_yaw_rad: float, frames: int = 20):
    """The demonstrator's hands 50 cm apart (the right one at +x: forward is +y), the pin at
    ``pin_yaw_rad`` about the vertical (motion capture frame) and the block unturned."""
    def still(local, at, yaw=0.0):
        world = local @ rot_z(yaw).T + np.asarray(at)
        return np.repeat(world[None], frames, axis=0)

    groups = {
        "right_hand": still(hand_markers("right"), (0.25, 0.0, TABLE_Z_M + 0.1)),
        "left_hand": still(hand_markers("left"), (-0.25, 0.0, TABLE_Z_M + 0.1)),
        "pin": still(PIN_MARKERS, (0.05, 0.40, TABLE_Z_M), pin_yaw_rad),
        "block": still(BLOCK_MARKERS, (-0.20, 0.35, TABLE_Z_M), 0.3),
    }
    return recording_from_points(groups, 100.0, "synthetic bench")


def _angle(a: float, b: float) -> float:
    """The smallest difference of two angles, rad."""
    return abs((a - b + math.pi) % (2 * math.pi) - math.pi)


def test_the_scene_turns_an_object_whatever_places_it(tmp_path):
    lib = _library(tmp_path)
    scene = lib.scenes["bench"]
    at = plan_layout(lib, scene)
    assert at.placement("pin").yaw == pytest.approx(math.pi / 2)
    assert at.placement("block").yaw == pytest.approx(-math.pi / 4)
    moved = plan_layout(lib, scene, places={"pin": (0.60, 0.20)}, seed=3)  # --place moves, the turn stays
    assert moved.placement("pin").yaw == pytest.approx(math.pi / 2)
    places = tuple(p.model_copy(update={"yaw": None}) for p in scene.places)
    unturned = scene.model_copy(update={"places": places})
    assert {p.yaw for p in plan_layout(lib, unturned).placements} == {0.0}


@pytest.mark.parametrize("robot_yaw_deg", [0.0, 35.0, 90.0, -120.0])
def test_layout_demonstrated_takes_the_yaw_of_the_markers_rigid_fit(robot_yaw_deg, tmp_path):
    """Forward is +y in this recording, left -x: a pin whose x axis points along +y stands
    unturned on the robot's table; one turned by ψ from it is turned by ψ there."""
    lib = _library(tmp_path)
    scene = lib.scenes["bench"]
    yaw = math.radians(robot_yaw_deg)
    first, headings = demonstrated_poses(_recording(yaw + math.pi / 2), scene, lib)
    assert set(headings) == {"pin"}  # the block's class declares no markers: no heading
    layout = plan_layout(lib, scene, layout="demonstrated", demonstrated=first, headings=headings)
    assert layout.sources["pin"] == layout.sources["block"] == "demonstrated"
    assert _angle(layout.placement("pin").yaw, yaw) < math.radians(0.5)
    # the block's markers say nothing of its class's x axis: the scene's word stands
    assert layout.placement("block").yaw == pytest.approx(-math.pi / 4)
    # without the headings (before this feature), the pin keeps the scene's turn
    plain = plan_layout(lib, scene, layout="demonstrated", demonstrated=first)
    assert plain.placement("pin").yaw == pytest.approx(math.pi / 2)


def test_a_class_whose_markers_lie_on_its_axis_tells_no_turn(tmp_path):
    lib = _library(tmp_path, LIBRARY.replace(
        "markers (14cm, 0, 5cm), (-14cm, 1cm, 5cm), (5cm, 2cm, 0), (-6cm, -2cm, 5cm)",
        "markers (0, 0, 5cm), (0, 0, 1cm), (0, 0, 3cm), (0, 0, 4cm)",
    ))
    scene = lib.scenes["bench"]
    on_axis = np.array([(0, 0, 0.05), (0, 0, 0.01), (0, 0, 0.03), (0, 0, 0.04)], dtype=float)
    rec = _recording(1.0)
    groups = {n: rec.group_positions(n) for n in rec.groups}
    groups["pin"] = np.repeat((on_axis + [0.05, 0.40, TABLE_Z_M])[None], rec.n_frames, axis=0)
    _, headings = demonstrated_poses(recording_from_points(groups, 100.0), scene, lib)
    assert "pin" not in headings


def test_the_built_body_stands_turned_by_its_yaw(tmp_path):
    pytest.importorskip("mujoco", reason="the robot runtime needs the 'robot' extra (mujoco)")
    from oacdsl.runtime.build import build_model

    lib = _library(tmp_path)
    built = build_model(plan_layout(lib, lib.scenes["bench"]))
    quat = built.model.body("pin").quat  # (w, x, y, z) about the vertical
    assert quat == pytest.approx([math.cos(math.pi / 4), 0.0, 0.0, math.sin(math.pi / 4)])
    block = built.model.body("block").quat
    assert block == pytest.approx([math.cos(-math.pi / 8), 0.0, 0.0, math.sin(-math.pi / 8)])


def test_an_object_alike_half_turned_takes_the_demonstrated_yaw_nearer_zero(tmp_path):
    """Without its handle the pin is one box, the same half turned: of the two yaws that stand
    it so, the one nearer 0 (its class's grasp point stays on the side written for the robot)."""
    handle = "    shape cylinder(radius 1cm, height 8cm) at (14cm, 0, 0)\n"
    lib = _library(tmp_path, LIBRARY.replace(handle, ""))
    scene = lib.scenes["bench"]
    first, headings = demonstrated_poses(_recording(math.radians(-120.0) + math.pi / 2), scene, lib)
    layout = plan_layout(lib, scene, layout="demonstrated", demonstrated=first, headings=headings)
    assert _angle(layout.placement("pin").yaw, math.radians(60.0)) < math.radians(0.5)
    assert alike_half_turned(layout.bodies["pin"]) and alike_half_turned(layout.bodies["block"])
    handled = _library(tmp_path)  # with its handle at one end
    assert not alike_half_turned(plan_layout(handled, handled.scenes["bench"]).bodies["pin"])
    turns = [round(math.degrees(nearer_half_turn(math.radians(d)))) for d in (-178, 178, -90, 90, 45, 270)]
    assert turns == [2, -2, 90, 90, 45, 90]
