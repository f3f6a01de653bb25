"""A support with slots (``shape rack(…)``, docs/language.md): compile checks, the slots the
runtime derives and the MuJoCo build (library/kit: KIT Wipe's draining rack). A plate set on
edge into a slot by ``touch``'s demonstrated ``tilt`` is exercised by the Wipe reproduction
(tests/test_kit_reproduce.py) and the composer's tilt by tests/test_kit_compose.py."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from oacdsl.compiler import compile_paths
from oacdsl.compiler.loader import load_library
from oacdsl.runtime.bodies import bodies_for_scene
from oacdsl.runtime.racks import rack_boxes
from oacdsl.runtime.turning import on_edge

ROOT = Path(__file__).resolve().parents[1]


def _codes(tmp_path: Path, text: str) -> list[str]:
    f = tmp_path / "r.oac"
    f.write_text(text)
    return [d.code for d in compile_paths([f]).diagnostics]


def test_a_rack_needs_whole_slots_that_fit_its_width_and_a_floor_below_its_top(tmp_path: Path) -> None:
    ok = "class R { shape rack(length 32cm, width 20cm, height 10cm, slots 4) }\n"
    assert _codes(tmp_path, ok) == []
    assert _codes(tmp_path, ok.replace("slots 4", "slots 4.5")) == ["E033"]
    assert _codes(tmp_path, ok.replace("slots 4", "slots 4cm")) == ["E032"]
    assert _codes(tmp_path, ok.replace(", slots 4", "")) == ["E031"]
    assert _codes(tmp_path, ok.replace("width 20cm", "width 2cm")) == ["E033"]  # 5 walls of 5 mm
    assert _codes(tmp_path, ok.replace("slots 4", "slots 4, floor 10cm")) == ["E033"]


def test_the_kit_draining_rack_has_four_slots_across_its_width_between_five_walls() -> None:
    lib = load_library([ROOT / "library" / "kit"])
    rack = bodies_for_scene(lib, lib.scenes["kit_wipe"])["draining_rack"]
    found = rack.slots
    assert len(found) == 4
    pitch = (0.20 - 0.005) / 4
    assert [s.floor_m[1] for s in found] == pytest.approx([-0.0975 + pitch * (k + 0.5) for k in range(4)])
    assert all(s.normal == (0.0, 1.0, 0.0) and s.floor_m[2] == pytest.approx(0.01) for s in found)
    assert found[0].width_m == pytest.approx(pitch - 0.005) and found[0].depth_m == pytest.approx(0.09)
    boxes = rack_boxes(rack.solids[0].dims)
    assert len(boxes) == 6  # the board and five walls
    # the walls' volume and the board's add up to the solid's (its mass splits by it)
    volume = sum(8 * h[0] * h[1] * h[2] for _, h in boxes)
    assert volume == pytest.approx(rack.solids[0].volume)
    assert rack.radius == pytest.approx(math.hypot(0.16, 0.10)) and rack.height == pytest.approx(0.10)


def test_a_tilt_nearer_a_quarter_turn_than_upright_or_upside_down_is_on_edge() -> None:
    assert on_edge(math.radians(97)) and on_edge(math.radians(60))
    assert not on_edge(math.radians(40)) and not on_edge(math.radians(150)) and not on_edge(0.0)


def test_the_rack_is_built_of_a_board_and_walls_with_slots_between() -> None:
    pytest.importorskip("mujoco", reason="the robot runtime needs the 'robot' extra (mujoco)")
    from oacdsl.runtime.build import build_model
    from oacdsl.runtime.layout import plan_layout

    lib = load_library([ROOT / "library" / "kit"])
    model = build_model(plan_layout(lib, lib.scenes["kit_wipe"])).model
    names = [model.geom(i).name for i in range(model.ngeom)
             if model.geom(i).name.startswith("draining_rack/")]
    assert len(names) == 6
    walls = sorted(float(model.geom(n).pos[1]) for n in names if "wall" in n)
    gaps = np.diff(walls) - 0.005
    assert gaps == pytest.approx([(0.20 - 5 * 0.005) / 4] * 4)

