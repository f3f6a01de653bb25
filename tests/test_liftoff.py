"""Lifted off (``oacdsl.segmentation.liftoff``): an object that rested on top of another stops
touching it when it is lifted off, however near it is then held, and touches it again only when
put back onto it.

Hand-made recordings: a lid rests on its bottle, is turned on it by the left hand while the right
hand holds the bottle, is lifted a few centimetres (well within the tool reach of 150 mm) and held
there, then put back, or put down beside the bottle; and the synthetic Open of
``tests/_task_demos.py`` turned 535°, whose lid ends 146 mm from the bottle's markers.
"""

from __future__ import annotations

import numpy as np
import pytest
from _aas_helpers import closest_m, on_spans, path, recording, still, summary
from _task_demos import CLEAN, KIT_10HZ, KIT_LIKE, MARKERS, _spin_s, turned
from segeval.reference import segment_reference

from oacdsl.segmentation import AasParams, segment
from oacdsl.segmentation.adaptive import AdaptiveDetector, AdaptiveSettings
from oacdsl.segmentation.liftoff import LiftOff, cut_at_lift_offs, lift_offs, over_frames
from oacdsl.segmentation.pairs import PairTable
from oacdsl.segmentation.stacking import inside_hull
from oacdsl.segmentation.takes import STANDARD_TAKES

RATE = 100.0
N = 1100
BOTTLE = MARKERS["bottle"]  # 18 cm tall, markers on its body; the lid's on its top, 77 mm from them
LID = MARKERS["lid"] + (0.0, 0.0, 0.181)
HAND = np.array([[0.0, 0.0, 0.0], [0.04, 0.0, 0.0], [0.0, 0.03, 0.01], [0.12, 0.05, 0.0], [0.15, 0.04, 0.02]])
BASE = np.array([0.1, 0.4, 0.75])
LIFT = (620, 700)  # frames: the lid rises from the bottle's top
LIFT_M = 0.04  # how far: the lid's markers end 115 mm from the bottle's, within the tool reach
AWAY = (850, 930)  # frames: then put back onto the bottle, or down beside it
BESIDE = np.array([0.12, 0.0, -0.18])  # on the table beside the bottle, 2.5 cm from it
CLOSE_BESIDE = np.array([0.095, 0.0, -0.18])  # 1.5 cm from it: markers within the rest's distance
PAIR = ("bottle", "lid")


def _turned(layout: np.ndarray, angle_rad: np.ndarray) -> np.ndarray:
    c, s = np.cos(angle_rad)[:, None], np.sin(angle_rad)[:, None]
    out = np.repeat(layout[None], angle_rad.size, axis=0)
    out[..., 0] = c * layout[:, 0] - s * layout[:, 1]
    out[..., 1] = s * layout[:, 0] + c * layout[:, 1]
    return out


def scene(then: str = "hold", beside: np.ndarray = BESIDE) -> dict[str, np.ndarray]:
    """The lid rests on the bottle; the right hand holds the bottle from 1 s; the left hand takes
    the lid (2 s), turns it 240° on the bottle (2.5-5.5 s), lifts it ``LIFT_M`` (6.2-7 s) and holds
    it; ``then`` (8.5-9.3 s): ``hold`` it up, put it ``back`` on the bottle, or put it ``beside``
    the bottle on the table (at ``beside`` from the lid's place on it); the hand keeps holding it."""
    frames = np.arange(N)
    angle = np.interp(frames, [250, 550], [0.0, np.radians(240.0)])
    up = (0.0, 0.0, LIFT_M)
    end = {"hold": up, "back": (0.0, 0.0, 0.0), "beside": tuple(beside)}[then]
    aside = ((AWAY[0] + AWAY[1]) // 2, (beside[0], 0.0, LIFT_M))  # beside: first aside, then down
    via = [aside] if then == "beside" else []
    offset = path(N, [(0, (0.0, 0.0, 0.0)), (LIFT[0], (0.0, 0.0, 0.0)), (LIFT[1], up), (AWAY[0], up), *via,
                      (AWAY[1], end)])
    lid = BASE + _turned(LID, angle) + offset[:, None, :]
    grip = BASE + (0.0, 0.0, 0.25)
    reach = path(N, [(0, (-0.25, 0.0, 0.85)), (200, tuple(grip))])
    left = np.where(frames[:, None] < 200, reach, grip + offset)[:, None, :] + _turned(HAND * 0.6, angle)
    right = path(N, [(0, (0.35, 0.0, 0.85)), (100, tuple(BASE + (0.12, 0.0, 0.06)))])
    return {"bottle": BASE + still(N, (0, 0, 0))[:, None, :] + BOTTLE, "lid": lid,
            "left_hand": left, "right_hand": right[:, None, :] + HAND * (-1, 1, 1)}


def run(rec, settings: AdaptiveSettings | None = None) -> list:
    params = AasParams()
    return summary(segment(rec, params, detector=AdaptiveDetector(params.resolved(rec.rate_hz), settings)))


def test_the_lid_held_up_stays_within_the_tool_reach():
    near = closest_m(scene(), "lid", "bottle")
    assert near[AWAY[0]] < AasParams().distance_m * 0.8  # lifted, but within any tool reach


def test_a_lid_lifted_and_held_near_its_bottle_leaves_it():
    (span,) = on_spans(run(recording(scene())), PAIR)
    assert span[0] == 0 and span[1] is not None and LIFT[0] <= span[1] <= LIFT[1], span


def test_a_lid_put_back_touches_again_and_one_put_beside_does_not():
    back = on_spans(run(recording(scene("back"))), PAIR)
    assert len(back) == 2 and LIFT[0] <= back[0][1] <= LIFT[1], back
    assert AWAY[0] <= back[1][0] <= AWAY[1] + 10 and back[1][1] is None, back
    beside = scene("beside")
    near = closest_m(beside, "lid", "bottle")
    assert near[-1] < AasParams().distance_m * 0.8  # within any tool reach
    assert near[AWAY[0]:].min() < 0.08  # passing by as near as it rested on it (77 mm)
    (span,) = on_spans(run(recording(beside)), PAIR)
    assert LIFT[0] <= span[1] <= LIFT[1], span


def test_a_lid_set_down_within_the_rest_distance_beside_its_bottle_does_not_touch_it():
    """Side by side on the table, neither on the other, nothing moving them together: the
    distance learned from the rest on top (the paper's rule at it) does not make them touch."""
    beside = scene("beside", CLOSE_BESIDE)
    rec = recording(beside)
    detector = AdaptiveDetector(AasParams().resolved(rec.rate_hz))
    seg = segment(rec, AasParams(), detector=detector)
    table = PairTable.of(rec)
    q = next(q for q, (i, j) in enumerate(table.instance_pairs)
             if {table.instances[i], table.instances[j]} == {"bottle", "lid"})
    near = closest_m(beside, "lid", "bottle")
    assert (near[AWAY[1] + 20 :] < detector._inner._pair_d[table.block == q].max()).all()
    (span,) = on_spans(summary(seg), PAIR)
    assert span[0] == 0 and LIFT[0] <= span[1] <= LIFT[1], span
    (again,) = on_spans(run(recording(scene("back", CLOSE_BESIDE))), PAIR)[1:]  # put back on top: touches
    assert AWAY[0] <= again[0] <= AWAY[1] + 10 and again[1] is None, again


@pytest.mark.parametrize("take", sorted(STANDARD_TAKES))
def test_every_standard_take_sees_the_lift_off(take):
    rec = recording(scene())
    other, _ = STANDARD_TAKES[take](rec)
    (span,) = on_spans(run(other), PAIR)
    factor = other.times_s[-1] / rec.times_s[-1]  # a slower or faster take: times scale
    lift_s = (LIFT[0] / RATE * factor, LIFT[1] / RATE * factor)
    assert span[0] == 0 and span[1] is not None, (take, span)
    assert lift_s[0] <= other.times_s[span[1]] <= lift_s[1], (take, span)


@pytest.mark.parametrize("capture", [CLEAN, KIT_LIKE, KIT_10HZ], ids=["clean", "kit", "kit10"])
def test_the_synthetic_open_turned_535_degrees_lets_go_of_the_bottle(capture):
    """Its lid, lifted 8 cm, ends 146 mm from the bottle's markers: within the tool reach."""
    rec = turned("Open", 535)(capture)
    seg = segment(rec, AasParams(mode="adaptive"))
    on = [("bottle", "lid") in k.state.sorted_relations() for k in seg.keyframes]
    kfs = seg.keyframes
    off = [k.time_s for k, was, now in zip(kfs[1:], on[:-1], on[1:], strict=True) if was and not now]
    lift_s = 8.6 + _spin_s(535) - 4.0  # the lift lasts 1 s from here
    assert len(off) == 1 and lift_s <= off[0] <= lift_s + 0.6, off


def test_the_per_frame_reference_agrees():
    from oacdsl.segmentation.takes import resampled

    rec = resampled(recording(scene("back")), 30.0)
    params = AasParams(mode="adaptive")
    fast = segment(rec, params)
    assert fast.keyframes == segment_reference(rec, params).keyframes


def _pair_rec(lid_z_m: np.ndarray) -> tuple:
    """A still bottle and a lid above it at heights ``lid_z_m`` (F,) over its rest, the pair table."""
    n = lid_z_m.size
    lid = BASE + LID + np.stack([np.zeros(n), np.zeros(n), lid_z_m], axis=1)[:, None, :]
    tracks = {"bottle": BASE + still(n, (0, 0, 0))[:, None, :] + BOTTLE, "lid": lid}
    rec = recording(tracks)
    return rec, PairTable.of(rec), closest_m(tracks, "lid", "bottle")


def test_a_rest_that_ends_without_a_rise_is_not_lifted_off():
    z = np.interp(np.arange(200), [100, 150], [0.0, 0.05])
    rec, table, _ = _pair_rec(z)
    rests = {0: ([(0, 100)], 0.09)}  # the rest's contact ends at frame 100
    (lift,) = lift_offs(rec, table, rests, 50, 0.15)[0]
    assert lift.frame == 100 and table.instances[lift.top] == "lid" and table.instances[lift.base] == "bottle"
    flat, table, _ = _pair_rec(np.zeros(200))  # the markers turned out of reach, the lid not raised
    assert lift_offs(flat, table, rests, 50, 0.15) == {}
    small, table, _ = _pair_rec(np.interp(np.arange(200), [100, 150], [0.0, 0.01]))  # 10 mm: within
    assert lift_offs(small, table, rests, 50, 0.15) == {}  # the 0.09 × 0.15 / 1.15 = 11.7 mm allowed


def test_a_cut_tool_contact_resumes_only_back_on_top():
    z = np.interp(np.arange(300), [100, 150, 200, 250], [0.0, 0.06, 0.06, 0.0])
    rec, table, near = _pair_rec(z)
    lift = LiftOff(120, float(near[0]) * 1.15, table.instances.index("lid"), table.instances.index("bottle"))
    back = 120 + int(np.flatnonzero(near[120:] <= lift.threshold)[0])  # within the rest's distance again
    assert 200 < back < 250
    assert cut_at_lift_offs([(50, 300)], [lift], near, 20, rec.positions_m, table) == [(50, 120), (back, 300)]
    assert cut_at_lift_offs([(50, 300)], [lift], near, 80, rec.positions_m, table) == [(50, 120)]  # too short
    new = cut_at_lift_offs([(130, 300)], [lift], near, 20, rec.positions_m, table)
    assert new == [(130, 300)]  # begun after the lift: a new arrival
    aside = rec.positions_m.copy()
    aside[:, list(rec.groups["lid"])] += (0.2, 0.0, 0.0)  # back down, but beside the bottle
    assert cut_at_lift_offs([(50, 300)], [lift], near, 20, aside, table) == [(50, 120)]


def test_the_per_frame_reference_agrees_beside():
    from oacdsl.segmentation.takes import resampled

    rec = resampled(recording(scene("beside", CLOSE_BESIDE)), 30.0)
    params = AasParams(mode="adaptive")
    assert segment(rec, params).keyframes == segment_reference(rec, params).keyframes


def test_over_frames_is_the_hull_test_of_every_frame_at_once():
    """The vectorised footprint test decides as the per-frame convex hull test, with markers
    unseen, collinear or repeated, and a centre on the hull's corner."""
    rng = np.random.default_rng(7)
    frames = 400
    positions = rng.uniform(-0.1, 0.1, size=(frames, 8, 3))
    positions[rng.random((frames, 8)) < 0.15] = np.nan  # unseen markers
    positions[::17, 4:8, 1] = positions[::17, 4:8, 0]  # the base's markers on a line
    positions[::23, 5] = positions[::23, 4]  # two base markers at one place
    positions[::29, 0:4, :2] = positions[::29, 4:5, :2]  # the centre on a corner
    table = PairTable.of(recording({"top": positions[:, 0:4], "base": positions[:, 4:8]}))
    top, base = table.instances.index("top"), table.instances.index("base")
    got = over_frames(positions, table, top, base, np.arange(frames))
    want = []
    for f in range(frames):
        a, b = positions[f, 0:4], positions[f, 4:8]
        a, b = a[np.isfinite(a).all(axis=1)], b[np.isfinite(b).all(axis=1)]
        want.append(a.shape[0] > 0 and inside_hull(a[:, :2].mean(axis=0), b[:, :2]))
    assert got.tolist() == want
    assert 0 < sum(want) < frames
