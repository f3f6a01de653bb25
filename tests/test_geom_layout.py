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


KNIFE_LIBRARY = """
class Hand { shape hand }
class Table { shape table }
class Board {
    shape box(length 40cm, width 20cm, height 1.5cm)
    markers (19cm, 9cm, 4cm), (-19cm, -9cm, 3.5cm), (-19cm, 9cm, 4.5cm), (5cm, -10cm, 3cm)
}
class Knife {
    shape box(length 25cm, width 2.5cm, height 1.5cm)
    markers (-10cm, 0, 1cm), (-6cm, 0, 1.2cm), (-8cm, 1.2cm, 8mm), (4cm, -1cm, 1cm)
}
scene cutting {
    board : Board
    knife : Knife
    left_hand, right_hand : Hand
    table : Table environment
    layout demonstrated
}
"""


def test_a_knife_lying_on_a_board_stands_on_it_by_the_shapes_not_by_the_marker_means(tmp_path):
    """The board's markers on 2-3 cm stalks stand higher than a flat knife's, whose markers sit
    on its blade: by marker means the knife is below the board's middle (beside it), by the
    posed bases it lies on the board's top."""
    from _geom_scenes import TABLE_Z, finish, hand, rigid

    from oacdsl.segmentation.shapes import scene_shapes

    oac = tmp_path / "cutting.oac"
    oac.write_text(KNIFE_LIBRARY, encoding="utf-8")
    library = load_library([oac])
    scene = library.scenes["cutting"]
    shapes = scene_shapes(library, scene)
    frames = 40
    board0 = np.tile([0.5, 0.0, TABLE_Z], (frames, 1))
    knife0 = np.tile([0.52, 0.03, TABLE_Z + 0.015], (frames, 1))
    rec = finish({
        "board": rigid(shapes["board"], board0),
        "knife": rigid(shapes["knife"], knife0, np.full(frames, 0.4)),
        "right_hand": hand(np.tile([0.5, -0.4, 1.05], (frames, 1)), (0, 0, 1), (1, 0, 0)),
        "left_hand": hand(np.tile([0.5, 0.4, 1.05], (frames, 1)), (0, 0, 1), (1, 0, 0)),
    })
    by_markers = demonstrated_positions(rec, scene)
    by_shapes = demonstrated_positions(rec, scene, library)
    assert by_markers["knife"][2] < by_markers["board"][2]  # its markers lower than the board's
    assert by_shapes["knife"][2] - by_shapes["board"][2] == pytest.approx(0.015, abs=0.002)
    assert plan_layout(library, scene, demonstrated=by_markers).placement("knife").on is None
    assert plan_layout(library, scene, demonstrated=by_shapes).placement("knife").on == "board"
