"""``layout demonstrated`` with the library's shapes: a lid found on its bottle by the height of the bases."""

import numpy as np
import pytest
from _geom_scenes import bottle_and_lid

pytest.importorskip("mujoco", reason="the robot runtime needs the 'robot' extra (mujoco)")

from oacdsl.compiler import load_library  # noqa: E402
from oacdsl.runtime.demo_layout import demonstrated_positions  # noqa: E402
from oacdsl.runtime.layout import plan_layout  # noqa: E402

LIBRARY = """
class Hand { shape hand }
class Table { shape table }
class Bottle {
    shape cylinder(radius 4cm, height 20cm)
    markers (4cm, 0, 17cm), (-4cm, 0, 15cm), (0, 4cm, 18cm), (0, -4cm, 13cm)
}
class Lid {
    shape cylinder(radius 1.7cm, height 2.5cm)
    markers (3cm, 0, 3cm), (-2cm, 2cm, 3.5cm), (0, -3cm, 2.5cm), (0, 0, 5cm)
}
scene opening {
    bottle : Bottle
    lid : Lid
    left_hand, right_hand : Hand
    table : Table environment
    layout demonstrated
}
"""


def test_a_lid_on_its_bottle_stands_on_it_by_the_shapes_not_by_the_marker_means(tmp_path):
    oac = tmp_path / "opening.oac"
    oac.write_text(LIBRARY, encoding="utf-8")
    library = load_library([oac])
    scene = library.scenes["opening"]
    rec, _ = bottle_and_lid()
    by_markers = demonstrated_positions(rec, scene)
    by_shapes = demonstrated_positions(rec, scene, library)
    # the bottle's markers sit near its top, 2-7 cm below the lid's: their means say "beside"
    assert by_markers["lid"][2] - by_markers["bottle"][2] < 0.10
    assert by_shapes["lid"][2] - by_shapes["bottle"][2] == pytest.approx(0.20, abs=0.002)
    np.testing.assert_allclose(by_shapes["bottle"][:2], by_markers["bottle"][:2])  # xy: the markers' mean
    assert plan_layout(library, scene, demonstrated=by_markers).placement("lid").on is None
    stacked = plan_layout(library, scene, demonstrated=by_shapes)
    assert stacked.placement("lid").on == "bottle"
