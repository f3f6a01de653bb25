"""``follow``: the demonstrated path as a skill parameter (language), its extraction from a
motion (composer) and its retargeting into the robot's reach (runtime, numpy only)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from oacdsl.errors import LanguageError, RuntimeFailure
from oacdsl.segmentation.followpath import from_rotvec, rotvec, turn_z, turned_path

SCENE = """
class Hand { shape hand }
class Graspable
class Container
class Tool : Graspable { shape cylinder(radius 1cm, height 20cm) }
class Cup : Container, Graspable { shape shell(radius 4cm, height 10cm, wall 5mm) }
scene s { left_hand, right_hand : Hand   spoon : Tool   cup : Cup }
oac work_in(h: Hand, s: Tool, c: Container) {
    pre     h <-> s
    effect  s <-> c
    execute follow(h, s, c)
}
"""

STEP = """
oac stir_like(h: Hand = right_hand, s: Tool = spoon, c: Cup = cup) {
    pre     h <-> s
    steps {
        work_in(h, s, c) { speed 10cm/s  path [
                0s (120mm, 0mm, 150mm) (0deg, 0deg, 0deg),
                0.1s (60mm, 2mm, 120mm) (0deg, 3deg, 0deg),
                0.25s (10mm, -4mm, 90mm) (1deg, 5deg, -2deg),
            ] }
    }
}
"""


def _module(text: str):  # type: ignore[no-untyped-def]
    from oacdsl.compiler import parse_text

    return parse_text(text, "t.oac")


def _codes(text: str) -> list[str]:
    from oacdsl.compiler import compile_sources

    return [d.code for d in compile_sources({"t.oac": text}).diagnostics]


# --- language ----------------------------------------------------------------------------------


def test_a_path_parameter_round_trips_through_the_printer() -> None:
    from oacdsl.compiler import print_module
    from oacdsl.model import PathValue

    module = _module(SCENE + STEP)
    printed = print_module(module)
    assert "path [\n" in printed and "0.25s (10mm, -4mm, 90mm) (1deg, 5deg, -2deg)," in printed
    again = _module(printed)
    assert again == module and print_module(again) == printed
    (call,) = [d for d in again.decls if getattr(d, "name", "") == "stir_like"][0].steps
    path = next(p.value for p in call.skill_params if p.name == "path")
    assert isinstance(path, PathValue)
    si = path.si()
    assert len(si) == 3 and si[2][0] == 0.25 and si[1][1] == pytest.approx(0.06)
    assert si[2][5] == pytest.approx(math.radians(5))


def test_a_path_compiles_and_bad_paths_are_named() -> None:
    assert "E043" not in _codes(SCENE + STEP) and "E044" not in _codes(SCENE + STEP)
    # a scalar where the path goes, a path where a number goes
    assert "E043" in _codes(SCENE + STEP.replace("speed 10cm/s  path [", "path 3cm  speed ["))
    # times must increase; two keyframes at least; units of their kind
    assert "E044" in _codes(SCENE + STEP.replace("0.25s (10mm", "0.05s (10mm"))
    one = STEP.replace("0.1s (60mm, 2mm, 120mm) (0deg, 3deg, 0deg),", "").replace(
        "0.25s (10mm, -4mm, 90mm) (1deg, 5deg, -2deg),", "")
    assert "E044" in _codes(SCENE + one)
    assert "E043" in _codes(SCENE + STEP.replace("(60mm, 2mm, 120mm)", "(60deg, 2mm, 120mm)"))
    assert "E043" in _codes(SCENE + STEP.replace("0.1s (60mm", "0.1m (60mm"))


def test_an_unclosed_path_is_one_syntax_error() -> None:
    from oacdsl.compiler import parse_text

    with pytest.raises(LanguageError) as error:
        parse_text(SCENE + STEP.replace("            ] }", "            }"), "t.oac")
    assert len(error.value.diagnostics) == 1 and error.value.diagnostics[0].code.startswith("E")


def test_follow_has_a_signature_and_an_implementation() -> None:
    from oacdsl.skills import PATH, SIGNATURES

    sig = SIGNATURES["follow"]
    assert [a.name for a in sig.args] == ["h", "o", "t"]
    assert sig.param("path") is not None and sig.param("path").unit == PATH  # type: ignore[union-attr]
    assert "path" not in sig.defaults() and sig.defaults()["speed"] == 0.25
    assert "a path" in sig.param("path").describe()  # type: ignore[union-attr]


# --- the composer: a motion becomes a path ------------------------------------------------------


def _motion(moved: str = "spoon", target: str = "cup"):  # type: ignore[no-untyped-def]
    from oacdsl.segmentation.motion import SubActionMotion

    t = np.arange(0.0, 2.0, 0.05)  # 20 Hz: keyframes every 0.1 s
    T = np.tile(np.eye(4), (len(t), 1, 1))
    T[:, 0, 3] = 0.0
    T[:, 1, 3] = 0.3 - 0.1 * t  # starts 30 cm along the target's y
    T[:, 2, 3] = 0.1
    for k, tk in enumerate(t):
        T[k, :3, :3] = from_rotvec(np.array([0.0, 0.2 * tk, 0.0]))
    T[3] = np.nan  # a gap
    return SubActionMotion(2, 10, 10 + len(t) - 1, "right_hand", moved, target, "made", t, T, None, 0.0)


def test_turned_path_starts_along_x_and_rotates_from_its_start() -> None:
    m = _motion()
    found = turned_path(m.times_s, m.T_target_object)
    assert found is not None
    t, pos, rot = found
    assert t[0] == 0.0 and np.all(np.diff(t)[:-1] >= 0.1 - 1e-9)  # every other frame, gap skipped
    assert t[-1] == pytest.approx(m.times_s[-1] - m.times_s[0])  # the last frame always kept
    assert pos[0] == pytest.approx([0.3, 0.0, 0.1])  # turned: the start on +x
    assert np.allclose(rot[0], 0.0)
    # the demonstrated turn about the target's y becomes one about the turned frame's -x
    assert from_rotvec(rot[-1]) == pytest.approx(turn_z(-math.pi / 2) @ from_rotvec(
        np.array([0.0, 0.2 * (m.times_s[-1] - m.times_s[0]), 0.0])) @ turn_z(math.pi / 2), abs=1e-9)


def test_the_composer_writes_the_path_of_the_step_s_own_objects() -> None:
    from oacdsl.matching.demoparams import path_params
    from oacdsl.model import PathValue

    found = path_params(_motion(), ("right_hand", "spoon", "cup"))
    (param,) = found.params
    assert param.name == "path" and isinstance(param.value, PathValue)
    assert param.value.poses[0].position.x.unit == "mm" and param.value.poses[0].position.x.value == 300
    assert found.comment is not None and "spoon relative to cup" in found.comment
    other = path_params(_motion("fork"), ("right_hand", "spoon", "cup"))
    assert other.params == () and other.comment is not None and "moved fork" in other.comment


def test_a_path_the_demonstrator_made_by_moving_the_target_is_the_inverse_relative_motion() -> None:
    """KIT Pour: the cup is lifted to the carton; the carton's path relative to the cup is the
    same relative motion seen from the cup."""
    from oacdsl.matching.demoparams import path_params
    from oacdsl.segmentation.poses import invert

    m = _motion()
    found = path_params(m, ("right_hand", "cup", "spoon"))  # the cup's path relative to the spoon
    (param,) = found.params
    assert found.comment is not None and "cup relative to spoon" in found.comment
    t, pos, rot = turned_path(m.times_s, invert(m.T_target_object))  # type: ignore[misc]
    first, last = param.value.poses[0], param.value.poses[-1]
    assert len(param.value.poses) == len(t)
    assert first.position.x.value == round(pos[0, 0] * 1000)
    assert last.position.y.value == round(pos[-1, 1] * 1000)
    assert last.rotation.y.value == round(math.degrees(rot[-1, 1]))
    # and not the spoon's own path: that one starts 30 cm out and 10 cm up, this one 10 cm down
    assert first.position.z.value == -100


# --- retargeting -------------------------------------------------------------------------------


def _stir_path() -> np.ndarray:
    """30 cm away, then 3 circles of 4 cm, 0.5 s each, 10 cm above the target, then away."""
    t = np.arange(0.0, 3.0, 0.05)
    pos = np.zeros((len(t), 3))
    rv = np.zeros((len(t), 3))
    inn, out = 0.5, 2.0
    for k, tk in enumerate(t):
        if tk < inn:
            pos[k] = [0.3 * (1 - tk / inn), 0.0, 0.1 + 0.1 * (1 - tk / inn)]
        elif tk <= out:
            a = 2 * math.pi * (tk - inn) / 0.5
            pos[k] = [0.04 * math.sin(a), 0.04 * (1 - math.cos(a)), 0.1]
            rv[k] = [0.0, 0.3 * math.sin(a), 0.0]
        else:
            pos[k] = [0.3 * (tk - out), 0.0, 0.1 + 0.2 * (tk - out)]
    return np.column_stack([t, pos, rv])


def test_the_core_is_fitted_into_the_room_and_slowed_where_asked() -> None:
    from oacdsl.runtime.retarget import MIN_SEGMENT_S, retarget

    path = _stir_path()
    r = retarget(path, room_m=0.015, speed_m_s=0.25, turn_rad=math.radians(10), stay=True,
                 core_speed_m_s=0.05)
    core = r.positions_m[r.core:]
    assert 0 < r.core < 15  # the way in is not the core
    assert np.max(np.linalg.norm(core[:, :2], axis=1)) <= 0.015 + 1e-9  # within the room of the axis
    assert r.scale < 0.5
    assert len(r.times_s) < len(path)  # stay: the way out is left out
    assert np.linalg.norm(r.positions_m[-1, :2]) < 0.02
    dt = np.diff(r.times_s)
    dist = np.linalg.norm(np.diff(r.positions_m, axis=0), axis=1)
    assert np.all(dt >= MIN_SEGMENT_S - 1e-12)
    assert np.all(dist[r.core:] / dt[r.core:] <= 0.05 + 1e-9)
    assert np.all(dist / dt <= 0.25 + 1e-9)
    assert r.slowed_s > 0
    # no turn before the core, at most 10 degrees in it
    assert all(np.allclose(m, np.eye(3)) for m in r.rotations[: r.core + 1])
    assert max(np.linalg.norm(rotvec(m)) for m in r.rotations) <= math.radians(10) + 1e-9
    assert r.turn_scale < 1


def test_a_path_that_fits_keeps_its_shape_and_timing() -> None:
    from oacdsl.runtime.retarget import retarget

    path = _stir_path()
    path[:, 4:] *= 0.1  # turns slower than the arm's limit (1.5 rad/s)
    r = retarget(path, room_m=None, speed_m_s=10.0, turn_rad=math.pi)
    assert len(r.times_s) == len(path) and r.scale == 1.0 and r.turn_scale == 1.0
    assert r.times_s == pytest.approx(path[:, 0] - path[0, 0])
    assert r.positions_m == pytest.approx(path[:, 1:4])


def test_shrunk_and_shifted_variants_stay_on_the_target() -> None:
    from oacdsl.runtime.retarget import retarget, shifted, shrunk

    r = retarget(_stir_path(), room_m=0.05, speed_m_s=1.0, turn_rad=math.pi)
    middle = np.median(r.positions_m[r.core:, :2], axis=0)
    small = shrunk(r, 0.5)
    spread = np.linalg.norm(r.positions_m[r.core:, :2] - middle, axis=1).max()
    small_spread = np.linalg.norm(small.positions_m[small.core:, :2] - middle, axis=1).max()
    assert small_spread == pytest.approx(spread / 2)
    moved = shifted(r, np.array([0.2, 0.0, 0.0]), 0.05)  # far more than the room allows
    assert np.max(np.linalg.norm(moved.positions_m[moved.core:, :2], axis=1)) <= 0.05 + 1e-9
    assert np.median(moved.positions_m[moved.core:, 0]) > np.median(r.positions_m[r.core:, 0])


def test_bad_paths_are_refused() -> None:
    from oacdsl.runtime.retarget import retarget

    with pytest.raises(RuntimeFailure, match="two or more keyframes"):
        retarget(np.zeros((1, 7)), room_m=None, speed_m_s=1.0, turn_rad=1.0)
    backwards = _stir_path()[::-1].copy()
    with pytest.raises(RuntimeFailure, match="do not increase"):
        retarget(backwards, room_m=None, speed_m_s=1.0, turn_rad=1.0)


def test_rotation_vectors_round_trip() -> None:
    rng = np.random.default_rng(3)
    for v in [*rng.normal(size=(20, 3)), np.array([math.pi, 0.0, 0.0]), np.zeros(3)]:
        v = v / max(1.0, np.linalg.norm(v) / 3.0)
        assert from_rotvec(rotvec(from_rotvec(v))) == pytest.approx(from_rotvec(v), abs=1e-9)


def test_the_kit_follow_library_compiles_and_uses_follow() -> None:
    from pathlib import Path

    from oacdsl.compiler import compile_paths

    root = Path(__file__).resolve().parent / "data" / "kit_follow"
    result = compile_paths([root])
    assert not result.errors
    skills = {d.name: d.skill for m in result.modules for d in m.decls if getattr(d, "kind", "") == "oac"}
    assert skills["work_in"] == skills["bring_to"] == skills["wipe_held"] == "follow"
    assert "stir" not in skills  # the named skill's OAC is not there: the matcher takes work_in


def test_a_core_is_kept_from_going_deeper_than_where_it_touched() -> None:
    # a knife cutting into the demonstrator's cucumber went 5 cm below where it first touched:
    # the robot's rigid cucumber stops it there, and the rest of the core stays on it
    from oacdsl.runtime.retarget import floored, retarget

    t = np.arange(30) * 0.1
    z = np.where(t < 0.5, 0.2 - 0.3 * t, -0.02 - 0.05 * np.abs(np.sin(2.0 * (t - 0.5))))
    x = np.where(t < 0.5, 0.3 - 0.5 * t, 0.02 * np.sin(4.0 * t))
    path = np.column_stack([t, x, np.zeros_like(t), z, np.zeros((len(t), 3))])
    r = retarget(path, room_m=None, speed_m_s=10.0, turn_rad=math.pi)
    f = floored(r)
    first = r.positions_m[r.core, 2]
    assert r.positions_m[r.core:, 2].min() < first - 0.03  # the demonstrated cut goes deeper
    assert np.all(f.positions_m[f.core:, 2] >= first - 1e-12)  # the robot's stays on top
    assert np.allclose(f.positions_m[f.core:, :2], r.positions_m[r.core:, :2])  # the strokes are kept
    assert np.allclose(f.positions_m[: f.core], r.positions_m[: r.core])  # the way in too


def test_a_core_is_fitted_onto_a_solid_targets_top() -> None:
    # a knife drawn 8 cm across and 5 cm along a cucumber 4.5 cm wide (its box's y) and 15 cm long:
    # across, the core is shrunk to the box less its margins and moved onto it; along, it stays
    from oacdsl.runtime.retarget import FOLLOW, boxed, retarget

    t = np.arange(30) * 0.1
    x = np.where(t < 0.5, 0.3 - 0.5 * t, -0.08 * (t - 0.5) / 2.4)
    y = np.where(t < 0.5, 0.0, 0.025 * np.sin(4.0 * t))
    path = np.column_stack([t, x, y, np.full_like(t, 0.02), np.zeros((len(t), 3))])
    r = retarget(path, room_m=None, speed_m_s=10.0, turn_rad=math.pi)
    c = r.core
    turn = np.array([[0.0, -1.0], [1.0, 0.0]])  # the frame's x is the box's y
    lo = np.array([-0.075, -0.0225]) + FOLLOW.top_margin_m
    hi = np.array([0.075, 0.0225]) - FOLLOW.top_margin_m
    before = r.positions_m[c:, :2] @ turn.T
    assert np.ptp(before[:, 1]) > hi[1] - lo[1]  # the demonstrated core leaves the cucumber
    b = boxed(r, turn, np.zeros(2), lo, hi)
    q = b.positions_m[c:, :2] @ turn.T
    assert np.all(q >= lo - 1e-12) and np.all(q <= hi + 1e-12)
    assert np.ptp(q[:, 0]) == pytest.approx(np.ptp(before[:, 0]))  # the strokes along it are kept
    assert np.allclose(b.positions_m[:, 2], r.positions_m[:, 2])  # heights untouched
    assert np.allclose(b.positions_m[0], r.positions_m[0])  # the way in starts where it did
    # held at its low end: the core goes as far to the other end as it fits, its strokes kept
    f = boxed(r, turn, np.zeros(2), lo, hi, far=(0, 1.0))
    qf = f.positions_m[c:, :2] @ turn.T
    assert qf[:, 0].max() == pytest.approx(hi[0]) and np.all(qf >= lo - 1e-12)
    assert np.ptp(qf[:, 0]) == pytest.approx(np.ptp(before[:, 0]))
