"""Where the demonstration sets objects down (``oacdsl/runtime/demo_places.py``), mapped onto the
robot's table as ``layout demonstrated`` maps the first frame, for ``place`` (issue 19)."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).parent))

import _task_demos as demos  # noqa: E402

from oacdsl.runtime.demo_layout import first_frame_positions, map_into_reach, table_map  # noqa: E402
from oacdsl.runtime.demo_places import set_down_places  # noqa: E402

HANDS = ["left_hand", "right_hand"]


def test_the_handed_over_mug_is_set_down_where_the_left_hand_put_it():
    rec = demos.handover_demo()
    places = set_down_places(rec, list(rec.groups), HANDS)
    assert list(places) == ["mug"]  # the hands are no objects; held up in the middle is no place
    (only,) = places["mug"]
    assert only[:2] == pytest.approx([-0.24, 0.40], abs=0.005)


def test_a_tool_held_still_on_what_it_works_is_not_set_down_there():
    """Transfer: the knife rests on the board at the end of each push, held: not a set-down
    place with the hands known, one without them (the rule is what keeps it out)."""
    rec = demos.transfer_demo()
    assert "knife_black" not in set_down_places(rec, list(rec.groups), HANDS)
    assert "knife_black" in set_down_places(rec, ["knife_black"])


def test_set_on_something_higher_is_no_place_on_the_table():
    rec = demos.stack_demo()  # the block ends on the crate: higher than it started
    assert set_down_places(rec, list(rec.groups), HANDS) == {}


def test_the_table_map_is_the_layouts_own_before_pushing_apart():
    objects = {"a": np.array([0.2, 0.4, 0.8]), "b": np.array([-0.3, 0.5, 0.8])}
    hands = {"r": np.array([0.3, 0.0, 0.9]), "l": np.array([-0.3, 0.0, 0.9])}
    radii = {"a": 0.04, "b": 0.04}
    mapping = table_map(objects, hands, radii)
    laid = map_into_reach(objects, hands, radii, gap_m=0.0)
    for name, p in objects.items():
        assert mapping(p) == pytest.approx(laid[name], abs=1e-9)


@pytest.mark.parametrize("seed", [None, 1, 2])
def test_the_set_down_place_is_mapped_with_the_layout_and_its_seed(seed):
    """The mug, handed over from the robot's right to its left, is to be set down 0.46 m to the
    left of where it stands on the robot's table (scale 1 here), whatever the seed's shift."""
    from test_kit_general import library

    from oacdsl.runtime.layout import plan_layout

    lib = library()
    scene = lib.scenes["handing"]
    rec = demos.handover_demo()
    first = first_frame_positions(rec, ["mug", *HANDS])
    places = set_down_places(rec, ["mug", *HANDS], HANDS)
    layout = plan_layout(lib, scene, seed=seed, layout="demonstrated", demonstrated=first, set_downs=places)
    mug = layout.placement("mug")
    assert mug.y < 0  # the person took it on their right
    (target,) = layout.set_downs["mug"]
    assert np.subtract(target, (mug.x, mug.y)) == pytest.approx([0.02, 0.46], abs=0.01)
    # the scene's own places: no demonstrated layout, nothing mapped
    assert plan_layout(lib, scene, seed=seed, demonstrated=first, set_downs=places).set_downs == {}
