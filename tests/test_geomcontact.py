"""Contacts from geometry: shapes, their poses, surface gaps, and issue 20's cases against markers."""

import json

import numpy as np
import pytest
from _aas_helpers import path, recording
from _geom_scenes import (
    TABLE_Z,
    bottle_and_lid,
    finish,
    hand,
    knife_on_board,
    model,
    peeler_and_cucumber,
    rigid,
    spoon_in_bowl,
)

from oacdsl.cli import main
from oacdsl.errors import SegmentationError
from oacdsl.segmentation import AasParams, segment
from oacdsl.segmentation.episodes import union_spans
from oacdsl.segmentation.geomcontact import _contact_spans, complement_spans
from oacdsl.segmentation.readers import write_c3d
from oacdsl.segmentation.shapefit import hand_volume, pose_shape, surface_gaps
from oacdsl.segmentation.shapes import MAX_SURFACE_POINTS, Primitive
from oacdsl.segmentation.takes import scaled


def relations(seg):
    """Per keyframe, its set of relations."""
    return [set(k.state.sorted_relations()) for k in seg.keyframes]


def ever(seg, pair):
    return any(pair in r for r in relations(seg))


def both(rec, shapes):
    return (segment(rec, AasParams(), shapes=shapes),
            segment(rec, AasParams(contacts="geometry"), shapes=shapes))


@pytest.mark.parametrize(
    ("prim", "point", "expected"),
    [
        (Primitive("box", (0.2, 0.1, 0.04), (0, 0, 0)), (0.0, 0.0, 0.10), 0.06),
        (Primitive("box", (0.2, 0.1, 0.04), (0, 0, 0)), (0.0, 0.0, 0.02), -0.02),
        (Primitive("box", (0.2, 0.1, 0.04), (0, 0, 0)), (0.13, 0.09, 0.02), 0.05),
        (Primitive("cylinder", (0.05, 0.1, 0), (0, 0, 0.01)), (0.08, 0.0, 0.06), 0.03),
        (Primitive("cylinder", (0.05, 0.1, 0), (0, 0, 0.01)), (0.0, 0.0, 0.15), 0.04),
        (Primitive("cylinder", (0.05, 0.1, 0), (0, 0, 0.01)), (0.0, 0.0, 0.06), -0.05),
        (Primitive("sphere", (0.03, 0.06, 0.06), (0, 0, 0)), (0.0, 0.05, 0.03), 0.02),
        (Primitive("capsule", (0.02, 0.10, 0), (0, 0, 0)), (0.05, 0.0, 0.05), 0.03),
        (Primitive("capsule", (0.02, 0.10, 0), (0, 0, 0)), (0.0, 0.0, 0.13), 0.03),
    ],
)
def test_signed_distance_of_each_primitive(prim, point, expected):
    assert prim.signed_distance(np.array([point]))[0] == pytest.approx(expected, abs=1e-9)


@pytest.mark.parametrize("kind", ["box", "cylinder", "sphere", "capsule"])
def test_surface_points_lie_on_the_surface(kind):
    size = {"box": (0.3, 0.2, 0.05), "sphere": (0.04, 0.08, 0.08)}.get(kind, (0.04, 0.2, 0))
    shape = model([(kind, size, (0.01, 0.0, 0.02))], [])
    pts = shape.surface_points()
    assert 0 < len(pts) <= MAX_SURFACE_POINTS
    assert np.abs(shape.signed_distance(pts)).max() < 1e-9


def test_compound_surface_drops_points_inside_the_other_primitive():
    spoon = model([("cylinder", (0.025, 0.01, 0), (0, 0, 0)),
                   ("cylinder", (0.006, 0.24, 0), (0, 0, 0.01))], [])
    pts = spoon.surface_points()
    assert (spoon.signed_distance(pts) > -1e-6).all()
    assert spoon.extents_m == pytest.approx((0.05, 0.05, 0.25), abs=1e-6)


def test_pose_found_whatever_the_recorded_marker_order():
    shape = model([("box", (0.2, 0.1, 0.05), (0, 0, 0))],
                  [(0.1, 0.05, 0.05), (-0.1, 0.0, 0.05), (0.0, -0.05, 0.02), (0.05, 0.05, 0.0)])
    f = 50
    origin = np.column_stack([np.linspace(0.3, 0.5, f), np.zeros(f), np.full(f, 0.9)])
    yaw = np.linspace(0.0, 1.0, f)
    markers = rigid(shape, origin, yaw)[:, [2, 0, 3, 1]]  # recorded in another order
    posed, why = pose_shape(recording({"box": markers}), "box", shape)
    assert why == "posed" and posed is not None
    assert posed.misfit_m < 1e-9 and posed.noise_m < 1e-9
    np.testing.assert_allclose(posed.T_world_object[:, :3, 3], origin, atol=1e-9)
    assert np.arctan2(posed.T_world_object[-1, 1, 0], posed.T_world_object[-1, 0, 0]) == pytest.approx(1.0)


def test_markers_that_do_not_fit_the_declared_ones_fall_back():
    shape = model([("box", (0.2, 0.1, 0.05), (0, 0, 0))],
                  [(0.1, 0.05, 0.05), (-0.1, 0.0, 0.05), (0.0, -0.05, 0.02), (0.05, 0.05, 0.0)])
    big = model([("box", (0.2, 0.1, 0.05), (0, 0, 0))], list(map(tuple, shape.markers_m * 1.5)))
    rec = recording({"box": rigid(big, np.tile([0.4, 0.0, 0.9], (10, 1)))})
    posed, why = pose_shape(rec, "box", shape)
    assert posed is None and "declared markers fit the recorded ones within" in why
    posed, why = pose_shape(rec, "box", model([("box", (0.2, 0.1, 0.05), (0, 0, 0))], []))
    assert posed is None and why == "0 declared markers for 4 recorded"


def test_contact_spans_bridge_hold_gaps_and_a_hand_resting_from_the_start():
    gap = np.array([0.0, 0.0, 0.0, 1, 1, 0, 0, 0, 1, 1, 1, 1, 0, 1, np.nan, 0.0, 0.0, 0.0])
    assert _contact_spans(gap, 0.5, hold=2, bridge=2, hand=False) == ([(0, 8), (12, 18)], [])
    # a hand within reach from the first frame: that run is left to the markers
    assert _contact_spans(gap, 0.5, hold=2, bridge=2, hand=True) == ([(12, 18)], [(0, 8)])
    assert _contact_spans(gap, 0.5, hold=4, bridge=0, hand=False) == ([], [])  # every run shorter
    nan_inside = np.array([1, 0, 0, np.nan, np.nan, 0, 1, 1, 1.0])
    assert _contact_spans(nan_inside, 0.5, hold=1, bridge=0, hand=False) == ([(1, 6)], [])
    assert union_spans([(5, 8), (0, 2), (1, 3)]) == [(0, 3), (5, 8)]
    assert complement_spans([(0, 3), (5, 8)], 10) == [(3, 5), (8, 10)]


def test_a_hand_holding_a_still_bottle_while_the_other_turns_its_lid():
    rec, shapes = bottle_and_lid()
    markers, geometry = both(rec, shapes)
    assert not ever(markers, ("bottle", "left_hand"))  # nothing moves together: markers miss it
    assert ever(geometry, ("bottle", "left_hand")) and ever(geometry, ("lid", "right_hand"))
    assert ("bottle", "lid") in relations(geometry)[0]
    assert not ever(geometry, ("bottle", "right_hand"))
    assert relations(geometry)[-1] == {("bottle", "lid")}
    assert geometry.parameters["geometry"] == {"bottle": "shape", "left_hand": "hand", "lid": "shape",
                                               "right_hand": "hand"}


def test_a_peeler_touches_the_long_cucumber_not_the_board():
    rec, shapes = peeler_and_cucumber()
    markers, geometry = both(rec, shapes)
    assert ever(markers, ("board", "peeler")) and not ever(markers, ("cucumber", "peeler"))
    assert ever(geometry, ("cucumber", "peeler")) and not ever(geometry, ("board", "peeler"))


def test_a_knife_lying_on_a_board_from_first_frame_to_last_is_seen_lifted():
    rec, shapes = knife_on_board()
    markers, geometry = both(rec, shapes)
    seen = relations(geometry)
    assert ("board", "knife") in seen[0] and ("board", "knife") in seen[-1]
    lifted = [i for i, r in enumerate(seen) if ("knife", "right_hand") in r and ("board", "knife") not in r]
    assert lifted, seen
    # by markers the knife never leaves the board once it touches it
    first = next(i for i, r in enumerate(relations(markers)) if ("board", "knife") in r)
    assert all(("board", "knife") in r for r in relations(markers)[first:])


def test_a_spoon_in_a_bowl_of_a_larger_scene():
    rec, shapes = spoon_in_bowl()
    larger = scaled(rec, 1.15)
    assert ever(segment(rec, AasParams()), ("bowl", "spoon"))
    assert not ever(segment(larger, AasParams()), ("bowl", "spoon"))  # markers beyond 150 mm
    original = relations(segment(rec, AasParams(contacts="geometry"), shapes=shapes))
    grown = relations(segment(larger, AasParams(contacts="geometry"), shapes=shapes))
    assert any(("bowl", "spoon") in r for r in original)
    assert grown == original


def test_without_shapes_every_pair_is_measured_by_markers():
    rec, _ = knife_on_board()
    plain = segment(rec, AasParams())
    geometry = segment(rec, AasParams(contacts="geometry"))
    assert [(k.frame, k.state) for k in geometry.keyframes] == [(k.frame, k.state) for k in plain.keyframes]
    assert geometry.parameters["geometry"]["knife"] == "markers: no measurable shape in the library"
    assert "contacts" not in plain.parameters and geometry.parameters["contacts"] == "geometry"


def test_contacts_parameter_is_checked():
    with pytest.raises(SegmentationError, match="contacts from geometry need mode adaptive, not 'paper'"):
        AasParams(mode="paper", contacts="geometry")
    with pytest.raises(SegmentationError, match="contacts must be one of markers, geometry"):
        AasParams(contacts="surfaces")


LIBRARY = """
class Hand { shape hand }
class Board {
    shape box(length 40cm, width 20cm, height 1.5cm)
    markers (19cm, 9cm, 1.5cm), (-19cm, -9cm, 1.5cm), (-19cm, 9cm, 1.5cm), (5cm, -10cm, 5mm)
}
class Knife {
    shape box(length 25cm, width 2.5cm, height 1.5cm)
    markers (-10cm, 0, 2.5cm), (-6cm, 0, 3cm), (-8cm, 1.2cm, 2cm), (-4cm, -1cm, 1.8cm)
}
scene cutting {
    board : Board
    knife : Knife
    left_hand, right_hand : Hand
}
"""


def test_segment_command_takes_the_shapes_from_the_scene(tmp_path, capsys):
    rec, _ = knife_on_board()
    c3d = write_c3d(rec, tmp_path / "knife.c3d")
    oac = tmp_path / "cutting.oac"
    oac.write_text(LIBRARY, encoding="utf-8")
    code = main(["segment", str(c3d), "--scene", str(oac), "--contacts", "geometry", "--json"])
    out, err = capsys.readouterr()
    assert code == 0, err
    doc = json.loads(out)
    assert doc["parameters"]["geometry"]["knife"] == "shape"
    states = [{tuple(r) for r in k["relations"]} for k in doc["keyframes"]]
    assert ("board", "knife") in states[0] and any(("board", "knife") not in s for s in states[1:])
    for argv, needle in ((["--contacts", "geometry"], "--contacts geometry needs --scene"),
                         (["--scene", str(oac), "--contacts", "geometry", "--mode", "paper"],
                          "--contacts geometry needs --mode adaptive"),
                         (["--scene", str(oac), "--contacts", "surface"],
                          "--contacts: 'surface' is neither")):
        code = main(["segment", str(c3d), *argv])
        err = capsys.readouterr().err
        assert code == 2 and err.count("\n") == 1 and needle in err, err


def test_the_pipeline_passes_the_scene_shapes_when_asked(tmp_path):
    from oacdsl.compiler import load_library
    from oacdsl.pipeline.inputs import Inputs

    oac = tmp_path / "cutting.oac"
    oac.write_text(LIBRARY, encoding="utf-8")
    library = load_library([oac])
    rec, _ = knife_on_board()
    for contacts, knife in (("markers", None), ("geometry", "shape")):
        inputs = Inputs(library, tmp_path, library.scenes["cutting"], "knife", AasParams(contacts=contacts),
                        recording=rec)
        seg = inputs.segmented()
        assert seg.parameters.get("geometry", {}).get("knife") == knife
        unmerged = inputs.unmerged()
        assert unmerged is not None and unmerged().parameters.get("geometry", {}).get("knife") == knife


def test_the_broad_phase_changes_no_decision():
    rec, shapes = peeler_and_cucumber()
    peeler = pose_shape(rec, "peeler", shapes["peeler"])[0]
    hand = hand_volume(rec, "right_hand")
    others = [pose_shape(rec, name, shapes[name])[0] for name in ("cucumber", "board")]
    for other in (*others, hand):
        exact = surface_gaps(peeler, other)
        for tol in (0.005, 0.02):
            bounded = surface_gaps(other, peeler, within_m=tol)
            assert np.array_equal(exact <= tol, bounded <= tol)
            assert (bounded <= exact + 1e-12).all()  # a lower bound where not measured


def test_mining_segments_with_the_scene_shapes_as_match_does(tmp_path):
    """``oacc mine --contacts geometry`` (and ``oacc reproduce``'s segment stage) measured every
    contact by markers: the shapes were never passed. The knife lying on the board is lifted off
    it only when its shape is known."""
    from oacdsl.mining.task import JobSpec, analyse

    oac = tmp_path / "cutting.oac"
    oac.write_text(LIBRARY, encoding="utf-8")
    rec, _ = knife_on_board()
    c3d = write_c3d(rec, tmp_path / "knife.c3d")
    changes = {}
    for contacts in ("markers", "geometry"):
        row = analyse(str(c3d), "knife", JobSpec([str(oac)], None, {"contacts": contacts}, compose=False))
        assert row["status"] == "ok", row["error"]
        changes[contacts] = [s["change"] for s in row["subs"]]
    assert changes["geometry"] == ["+ knife <-> right_hand", "- board <-> knife", "+ board <-> knife",
                                   "- knife <-> right_hand"]
    assert changes["markers"] != changes["geometry"]


def test_a_hand_carrying_an_object_beyond_its_volume_holds_it():
    """A hand whose markers ride 4.5 cm above a block it carries (fingers around the block, not
    modelled): the hand's volume stays beyond the pair's tolerance, yet the two move together, so
    geometry keeps the carry as a contact; before the hand arrives and after it leaves, none."""
    f = 500
    block = model([("box", (0.06, 0.06, 0.06), (0, 0, 0))],
                  [(0.03, 0, 0.05), (-0.03, 0, 0.04), (0, 0.03, 0.055), (0, -0.03, 0.02)])
    start, end = (0.5, 0.0, TABLE_Z), (0.5, 0.25, TABLE_Z)
    b = path(f, [(150, start), (200, (0.5, 0.05, TABLE_Z + 0.1)), (300, (0.5, 0.2, TABLE_Z + 0.1)),
                 (350, end)])
    above = np.array([0.0, 0.0, 0.085])  # the palm 2.5 cm above the block's top, its markers 2 cm higher
    away = (0.5, -0.35, 1.1)
    right = path(f, [(50, away), (140, tuple(start + above)), (360, tuple(end + above)), (450, away)])
    right = np.where((np.arange(f)[:, None] >= 140) & (np.arange(f)[:, None] < 360), b + above, right)
    rec = finish({
        "block": rigid(block, b),
        "right_hand": hand(right, (0, 0, 1), (1, 0, 0)),
        "left_hand": hand(np.tile([0.5, 0.5, 1.0], (f, 1)), (0, 0, 1), (1, 0, 0)),
    })
    shapes = {"block": block}
    posed, _ = pose_shape(rec, "block", shapes["block"])
    gaps = surface_gaps(hand_volume(rec, "right_hand"), posed, within_m=1.0)
    assert np.nanmin(gaps) > 0.015  # never within a hand's tolerance (a few mm)
    markers, geometry = both(rec, shapes)
    pair = ("block", "right_hand")
    assert ever(markers, pair) and ever(geometry, pair)
    held = [k.frame for k in geometry.keyframes if pair in set(k.state.sorted_relations())]
    assert 120 <= held[0] <= 200
    assert relations(geometry)[0] == set() and relations(geometry)[-1] == set()
