"""The adaptive touch detector (mode ``adaptive``): co-motion, learned per-pair distances."""

from __future__ import annotations

import warnings

import numpy as np
import pytest
from _aas_helpers import path, recording, still, summary

from oacdsl.errors import SegmentationError
from oacdsl.segmentation import AasParams, segment
from oacdsl.segmentation.adaptive import AdaptiveDetector, AdaptiveSettings
from oacdsl.segmentation.combine import StateCombiner
from oacdsl.segmentation.recording import Recording

F = 500
RATE = 100.0
# marker layouts, metres: a cup's four corners, the back of a hand 9 cm above what it holds
CUP_MARKERS = np.array([[0.03, 0.03, 0.0], [-0.03, 0.03, 0.0], [0.03, -0.03, 0.05], [-0.03, -0.03, 0.05]])
HAND_MARKERS = np.array([[0.0, 0.0, 0.0], [0.04, 0.0, 0.0], [0.0, 0.03, 0.01]])
GRIP = np.array([0.0, 0.0, 0.14])  # hand origin above the cup origin while holding: 9 cm marker gap


def cluster(centre: np.ndarray, layout: np.ndarray) -> np.ndarray:
    return centre[:, None, :] + layout[None, :, :]


def carry_scene() -> dict[str, np.ndarray]:
    """The hand reaches the cup (frame 100), lifts and carries it (150–300), sets it down, leaves (350)."""
    start, goal = (0.5, 0.0, 0.0), (0.9, 0.2, 0.0)
    cup = path(F, [(0, start), (150, start), (300, goal)])
    held, placed = tuple(np.add(start, GRIP)), tuple(np.add(goal, GRIP))
    hand = path(F, [(0, (0.0, -0.3, 0.4)), (100, held), (150, held), (300, placed), (350, placed),
                    (450, (1.2, 0.5, 0.6))])
    return {"cup": cluster(cup, CUP_MARKERS), "hand": cluster(hand, HAND_MARKERS)}


def adaptive(rec: Recording, **kwargs: float) -> list:
    params = AasParams(mode="adaptive", merge_s=0.0, **kwargs)
    return summary(segment(rec, params))


def test_carried_object_touches_from_grasp_to_release():
    rec = recording(carry_scene())
    kfs = adaptive(rec)
    assert [k[1] for k in kfs] == [[], [("cup", "hand")], []]
    grasp, release = kfs[1][0], kfs[2][0]
    assert 90 <= grasp <= 110 and 345 <= release <= 365  # the hand arrives at 100, leaves after 350
    # the paper's rule at a distance that suits other objects (6 cm) never sees this grip (9 cm)
    assert summary(segment(rec, AasParams(distance_m=0.06, mode="paper"))) == [(0, [])]


def test_hand_resting_beside_an_object_is_not_touching():
    scene = carry_scene()
    # a bowl 12 cm from where the hand comes to rest at the end (frames 450-499)
    bowl = still(F, (1.2, 0.5 + 0.03 + 0.12 + 0.015, 0.61))
    scene["bowl"] = cluster(bowl, CUP_MARKERS * 0.5)
    rec = recording(scene)
    relations = {r for _, rs in adaptive(rec) for r in rs}
    assert ("bowl", "hand") not in relations and ("cup", "hand") in relations
    # the paper's rule at its default 15 cm calls the resting hand a touch
    assert ("bowl", "hand") in summary(segment(rec, AasParams(mode="paper")))[-1][1]


def test_object_held_by_the_other_hand_is_not_touched():
    # left hand holds the cup, the right hand holds a jug against it: all four move as one
    scene = carry_scene()
    cup = scene["cup"].mean(axis=1) - CUP_MARKERS.mean(axis=0)
    jug = cup + np.array([0.0, 0.16, 0.0])  # 10 cm from the cup's markers, 13 cm from the hand's
    scene["jug"] = cluster(jug, CUP_MARKERS)
    scene["other_hand"] = cluster(jug + GRIP, HAND_MARKERS)
    relations = {r for _, rs in adaptive(recording(scene)) for r in rs}
    assert ("cup", "hand") in relations and ("jug", "other_hand") in relations
    assert ("hand", "jug") not in relations and ("cup", "other_hand") not in relations


def test_a_gap_during_the_carry_does_not_break_the_touch():
    scene = carry_scene()
    scene["cup"][180:260, 1:] = np.nan  # three of four cup markers occluded mid-carry
    scene["hand"][200:215] = np.nan  # and the whole hand for 0.15 s
    assert [k[1] for k in adaptive(recording(scene))] == [[], [("cup", "hand")], []]


def test_chunked_equals_single_pass_with_gaps():
    rng = np.random.default_rng(5)
    scene = carry_scene()
    scene["cup"] = scene["cup"] + rng.normal(0, 0.0005, scene["cup"].shape)  # 0.5 mm noise
    scene["cup"][rng.random(scene["cup"].shape[:2]) < 0.03] = np.nan
    rec = recording(scene)
    params = AasParams(mode="adaptive")
    whole = segment(rec, params)
    for chunk in (7, 64, 333):
        assert segment(rec, params, chunk_frames=chunk).keyframes == whole.keyframes


def test_same_touch_at_10_hz_and_100_hz():
    rec100 = recording(carry_scene())
    rec10 = recording({k: v[::10] for k, v in carry_scene().items()}, rate_hz=10.0)
    t100 = [k.time_s for k in segment(rec100, AasParams(mode="adaptive", merge_s=0)).keyframes]
    t10 = [k.time_s for k in segment(rec10, AasParams(mode="adaptive", merge_s=0)).keyframes]
    assert len(t100) == len(t10) == 3
    assert np.allclose(t100, t10, atol=0.25)


def test_settings_are_checked_and_usable_directly():
    with pytest.raises(SegmentationError, match="rigid_ratio must be positive"):
        AdaptiveSettings(rigid_ratio=0)
    rec = recording(carry_scene())
    params = AasParams(mode="adaptive", merge_s=0).resolved(RATE)
    # nothing moves at 10 m/s, so there is no co-motion: only the static rule (here 5 cm) remains
    strict = AdaptiveDetector(params, AdaptiveSettings(move_speed_m_s=10.0, static_distance_m=0.05))
    assert summary(segment(rec, params, detector=strict)) == [(0, [])]


def test_unknown_mode_lists_adaptive():
    with pytest.raises(SegmentationError, match="adaptive"):
        segment(recording(carry_scene()), AasParams(mode="adaptiv"))


def test_invariant_to_marker_order_and_a_rigid_motion_of_the_scene():
    rng = np.random.default_rng(11)
    scene = carry_scene()
    scene["cup"] = scene["cup"] + rng.normal(0, 0.0003, scene["cup"].shape)
    rec = recording(scene)
    base = segment(rec, AasParams(mode="adaptive")).keyframes
    perm = rng.permutation(len(rec.marker_names))
    inverse = np.argsort(perm)
    groups = {g: tuple(int(inverse[i]) for i in idx) for g, idx in rec.groups.items()}
    angle = 0.7
    rot = np.array([[np.cos(angle), -np.sin(angle), 0], [np.sin(angle), np.cos(angle), 0], [0, 0, 1]])
    moved = rec.positions_m[:, perm] @ rot.T + np.array([3.0, -2.0, 0.5])
    names = tuple(rec.marker_names[i] for i in perm)
    other = Recording("moved", rec.rate_hz, rec.times_s, names, moved, groups)
    assert segment(other, AasParams(mode="adaptive")).keyframes == base


def _extend_per_frame(dmin: np.ndarray, a: int, b: int, threshold: float, bridge: int) -> tuple[int, int]:
    """Step 3 frame by frame: walk outwards from [a, b) while within threshold, unknown, or bridged."""
    n = dmin.size

    def beyond(i: int) -> bool:
        if not dmin[i] > threshold:  # NaN: unknown, not beyond
            return False
        s = i
        while s > 0 and dmin[s - 1] > threshold:
            s -= 1
        e = i + 1
        while e < n and dmin[e] > threshold:
            e += 1
        return not (e - s <= bridge and s > 0 and e < n)

    start = a
    while start > 0 and not beyond(start - 1):
        start -= 1
    end = b
    while end < n and not beyond(end):
        end += 1
    while end < n:  # a let-go: the first leave followed by moving apart, not a brief return
        r = end
        while r > b and not dmin[r - 1] > threshold:
            r -= 1  # [r, end): the return before the leave
        if r <= b or end - r > bridge:
            break
        s = r
        while s > 0 and dmin[s - 1] > threshold:
            s -= 1  # [s, r): the bridged excursion before it
        if s < b:
            break
        end = s
    return start, end


def test_episode_extension_matches_a_per_frame_walk():
    from oacdsl.segmentation.episodes import extend_episode

    rng = np.random.default_rng(7)
    for _ in range(3000):
        n = int(rng.integers(1, 30))
        dmin = rng.random(n).astype(np.float32)
        dmin[rng.random(n) < 0.2] = np.nan
        a = int(rng.integers(0, n))
        b = int(rng.integers(a + 1, n + 1))
        threshold, bridge = float(rng.random()), int(rng.integers(0, 4))
        expected = _extend_per_frame(dmin, a, b, threshold, bridge)
        assert extend_episode(dmin, a, b, threshold, bridge) == expected


def test_a_let_go_with_a_brief_return_ends_at_the_first_leave():
    """The hand opens, leaves the grip's distance for a frame, passes back within it for a frame and
    leaves (KIT Stir's spoon at ×0.6 speed): the let-go is the first leave, which the bridge alone
    would join to the return. A leave followed by a return that lasts is still bridged, and so is
    the grasp's flicker before the episode (only the let-go is moved)."""
    from oacdsl.segmentation import episodes as cm

    held, out, thr = 0.037, 0.06, 0.043
    let_go = np.array([out] * 5 + [held] * 10 + [out, held] + [out] * 5, dtype=np.float32)
    assert cm._extend_in(let_go, 7, 10, thr, bridge=1) == (5, 15)
    assert cm.extend_episode(let_go, 7, 10, thr, bridge=1) == (5, 15)
    assert cm._extend_in(let_go, 7, 10, thr, bridge=0) == (5, 15)
    lasting = np.array([out] * 5 + [held] * 10 + [out, held, held] + [out] * 5, dtype=np.float32)
    assert cm._extend_in(lasting, 7, 10, thr, bridge=1) == (5, 18)
    flicker = np.array([out] * 5 + [held, out] + [held] * 10 + [out] * 5, dtype=np.float32)
    assert cm._extend_in(flicker, 9, 12, thr, bridge=1) == (5, 17)


def _alike_scene(far_m: float, near_m: float) -> Recording:
    """Two objects (no hands): b rests ``far_m`` from a (closest markers), the two move together
    (frames 100-150), b comes to ``near_m`` of a (150-200), the two move together again (200-300),
    b leaves (350-420)."""
    off = 0.06  # the layouts' closest markers are 6 cm inside their centres' offset
    a = path(F, [(0, (0, 0, 0)), (100, (0, 0, 0)), (150, (0.3, 0, 0)), (200, (0.3, 0, 0)),
                 (300, (0.7, 0, 0))])
    b = path(F, [(0, (0, far_m + off + 0.2, 0)), (60, (0, far_m + off, 0)), (100, (0, far_m + off, 0)),
                 (150, (0.3, far_m + off, 0)), (200, (0.3, near_m + off, 0)), (300, (0.7, near_m + off, 0)),
                 (350, (0.7, near_m + off, 0)), (420, (0.7, near_m + off + 0.3, 0))])
    return recording({"a": cluster(a, CUP_MARKERS), "b": cluster(b, CUP_MARKERS)})


def test_co_motion_far_beyond_the_pairs_closest_is_no_grip():
    """Two things moving alike 130 mm apart (within d), and later 40 mm apart: the far co-motion,
    more than FAR_RATIO times the pair's closest, is two hands moving alike (KIT Stir's spoon
    brought towards the cup), not a grip; at 140 mm with a closest of 90 mm it is one (Scoop's cup
    held up to the ladle)."""
    from oacdsl.segmentation.episodes import FAR_RATIO

    assert 0.13 > FAR_RATIO * 0.04 and 0.14 < FAR_RATIO * 0.09
    kfs = summary(segment(_alike_scene(0.13, 0.04), AasParams(mode="adaptive", merge_s=0.0)))
    assert [r for _, r in kfs] == [[], [("a", "b")], []] and 185 <= kfs[1][0] <= 200  # b arrives at 200
    kfs = summary(segment(_alike_scene(0.14, 0.09), AasParams(mode="adaptive", merge_s=0.0)))
    assert [r for _, r in kfs] == [[], [("a", "b")], []] and 55 <= kfs[1][0] <= 65  # b comes to rest at 60


def test_co_motion_beyond_d_counts_within_twice_the_pairs_closest():
    """The scan finds co-motion up to d × (1 + margin), and an episode beyond d counts when the pair
    co-moves within d too and it lies within FAR_RATIO times the closest (a take 15 % larger of
    KIT Scoop: the cup held up to the ladle 165-171 mm away, d 163.5 mm)."""
    from oacdsl.segmentation.episodes import near_episodes

    d = np.array([0.165] * 3 + [0.12] * 3 + [0.10] * 3 + [0.30] * 3, dtype=np.float32)
    eps = [(0, 3), (6, 9), (9, 12)]
    assert [(a, b) for a, b, _ in near_episodes(d, eps, 0.15)] == [(0, 3), (6, 9)]
    assert near_episodes(d, [(0, 3)], 0.15) == []  # nothing within d: no grip at all
    assert [(a, b) for a, b, _ in near_episodes(d, [(0, 3), (3, 6)], 0.15)] == [(0, 3), (3, 6)]


def test_windowed_extend_equals_the_whole_recording_pass(monkeypatch: pytest.MonkeyPatch) -> None:
    """extend_episode looks at a window around the episode first; it must grow exactly as the pass over
    the whole recording does (short windows: runs cut at the window's edges, bridges, gaps)."""
    from oacdsl.segmentation import episodes as cm

    rng = np.random.default_rng(3)
    for _ in range(500):
        n = int(rng.integers(1, 300))
        monkeypatch.setattr(cm, "_EXTEND_WINDOW", int(rng.integers(1, 40)))
        dmin = np.repeat((rng.random(n // 6 + 1) * 0.2).astype(np.float32), 6)[:n]  # metres
        dmin[rng.random(n) < 0.05] = np.nan
        a = int(rng.integers(0, n))
        b = int(rng.integers(a + 1, n + 1))
        threshold, bridge = float(rng.random() * 0.2), int(rng.integers(0, 12))
        assert cm.extend_episode(dmin, a, b, threshold, bridge) == cm._extend_in(
            dmin, a, b, threshold, bridge)


def test_instance_speed_median_by_network_equals_the_sorted_median() -> None:
    """The scan's instance speeds: the min/max networks give nanmedian0's values, gaps, ties and all."""
    from oacdsl.segmentation.medians import median_rows as _median_rows
    from oacdsl.segmentation.medians import nanmedian0 as _nanmedian0

    rng = np.random.default_rng(11)
    for k in range(0, 11):  # up to 8 markers by the network, more by sorting
        for gaps in (0.0, 0.05, 0.5, 1.0):
            x = rng.random((k, 200))
            x[rng.random(x.shape) < gaps] = np.nan
            x[:, :5] = 0.25  # ties
            assert np.array_equal(_median_rows(x), _nanmedian0(x), equal_nan=True)


def test_sorted_median_equals_nanmedian_with_and_without_gaps() -> None:
    """_nanmedian0 (the scan's distance-change and speed medians) reads the middle rows when no
    value is missing, and counts per column otherwise: both are np.nanmedian's values."""
    from oacdsl.segmentation.medians import nanmedian0 as _nanmedian0

    rng = np.random.default_rng(5)
    for k in (1, 2, 5, 16, 25):
        for gaps in (0.0, 0.1, 1.0):
            x = rng.random((k, 300)).astype(np.float32)
            x[rng.random(x.shape) < gaps] = np.nan
            x[:, :3] = np.float32(0.5)  # ties
            with warnings.catch_warnings():
                warnings.simplefilter("ignore", RuntimeWarning)  # all-NaN columns
                expected = np.nanmedian(x, axis=0)
            got = _nanmedian0(x)
            assert got.dtype == np.float32
            assert np.array_equal(got, expected.astype(np.float32), equal_nan=True)


def test_episode_median_equals_nanmedian() -> None:
    """_nanmedian1d (an episode's closest distance) is float(np.nanmedian(x)) of float32 values."""
    from oacdsl.segmentation.episodes import _nanmedian1d

    rng = np.random.default_rng(9)
    for _ in range(2000):
        n = int(rng.integers(1, 60))
        x = (rng.random(n) * 0.2).astype(np.float32)  # metres
        x[rng.random(n) < 0.1] = np.nan
        if rng.random() < 0.2:
            x[: n // 2] = np.float32(0.1)  # ties
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)  # all NaN
            expected = float(np.nanmedian(x))
        got = _nanmedian1d(x)
        assert got == expected or (np.isnan(got) and np.isnan(expected))


def test_squared_distances_are_the_distances_squared_bit_for_bit() -> None:
    """The co-motion scan takes the closest distance as the root of the smallest squared one and
    roots only the frames it needs: the same values as ChunkGeometry.distances."""
    from oacdsl.segmentation.geometry import ChunkGeometry
    from oacdsl.segmentation.pairs import PairTable

    rng = np.random.default_rng(2)
    pos = rng.normal(scale=0.1, size=(97, 9, 3)) + 5.0  # metres, far from the origin
    pos[rng.random(pos.shape[:2]) < 0.1] = np.nan
    rec = Recording("random", RATE, np.arange(97) / RATE, tuple(f"m{i}" for i in range(9)), pos,
                    {"a": (0, 1, 2), "b": (3, 4), "c": (5, 6, 7, 8)})
    table = PairTable.of(rec)
    geometry = ChunkGeometry(rec, table)
    x = geometry.coordinates(0, 97)
    blocks = np.arange(table.n_instance_pairs)
    _, dist = geometry.distances(x, blocks)
    buf, tmp = geometry.scratch(97), geometry.scratch(97)
    for q in blocks:
        rows = dist[table.block_offsets[q]:table.block_offsets[q + 1]]
        sq = geometry.squared(x, int(q), buf, tmp)
        assert np.array_equal(np.sqrt(sq), rows, equal_nan=True)
        closest = np.fmin.reduce(rows, axis=0)
        assert np.array_equal(np.sqrt(np.fmin.reduce(sq, axis=0)), closest, equal_nan=True)


def _combine_loop(det: StateCombiner, pairs, frames, touching, events):  # type: ignore[no-untyped-def]
    """The managed blocks' combined state, change by change (the detector's rule, written out)."""
    table = det.table
    changes: dict[int, list[tuple[int, int, bool, int]]] = {}
    for p, f, v in zip(pairs.tolist(), frames.tolist(), touching.tolist(), strict=True):
        changes.setdefault(int(table.block[p]), []).append((f, 0, v, p))
    for f, kind, v, q in events.tolist():
        changes.setdefault(q, []).append((f, kind, bool(v), -1))
    out = []
    for q, block_changes in changes.items():
        block_changes.sort()
        for k, (f, kind, v, p) in enumerate(block_changes):
            if kind == 0:
                if det.pair_state[p] != v:
                    det.pair_state[p] = v
                    det.paper_count[q] += 1 if v else -1
            else:
                det.flags[q, kind] = v
            if k + 1 < len(block_changes) and block_changes[k + 1][0] == f:
                continue  # the state after all changes of a frame counts
            flags = det.flags[q]
            state = bool((det.paper_count[q] > 0 or flags[1] or flags[2]) and not flags[3])
            if state != det.combined[q]:
                det.combined[q] = state
                out.append((int(det.heads[q]), f, state))
    return sorted(out)


def test_combined_block_state_equals_the_change_by_change_rule() -> None:
    """The adaptive detector combines, per instance pair, the paper rule's marker-pair changes with
    the episode, tool and veto intervals by array operations (``StateCombiner``); the result (and
    the state carried to the next chunk) is the change-by-change rule's, same-frame changes and all."""
    import copy

    from oacdsl.segmentation.pairs import PairTable

    rng = np.random.default_rng(7)
    groups = {"a": (0, 1), "b": (2, 3, 4), "c": (5,), "d": (6, 7)}
    rec = Recording("r", RATE, np.arange(10) / RATE, tuple(f"m{i}" for i in range(8)),
                    np.zeros((10, 8, 3)), groups)
    table = PairTable.of(rec)
    for _ in range(200):
        det = StateCombiner(table)
        n_q = table.n_instance_pairs
        det.pair_state = rng.random(table.n_pairs) < 0.3
        det.paper_count = np.array([det.pair_state[table.block == q].sum() for q in range(n_q)])
        det.flags = rng.random((n_q, 4)) < 0.3
        det.combined = ((det.paper_count > 0) | det.flags[:, 1] | det.flags[:, 2]) & ~det.flags[:, 3]
        twin = copy.deepcopy(det)
        # paper changes: per marker pair alternating states at distinct frames (sorted by pair, frame)
        pairs, frames, touching = [], [], []
        for p in np.flatnonzero(rng.random(table.n_pairs) < 0.5):
            state = bool(det.pair_state[p])
            for f in np.sort(rng.choice(12, size=int(rng.integers(1, 4)), replace=False)):
                state = not state if rng.random() < 0.9 else state  # now and then a repeat
                pairs.append(p), frames.append(f), touching.append(state)
        events = np.array([(int(rng.integers(0, 12)), int(rng.integers(1, 4)), int(rng.integers(0, 2)),
                            int(rng.integers(0, n_q))) for _ in range(int(rng.integers(0, 8)))],
                          dtype=np.intp).reshape(-1, 4)
        args = (np.array(pairs, dtype=np.intp), np.array(frames, dtype=np.intp),
                np.array(touching, dtype=bool))
        heads, got_frames, states = det.combine(*args, events[np.argsort(events[:, 0], kind="stable")])
        got = sorted(zip(heads.tolist(), got_frames.tolist(), states.tolist(), strict=True))
        assert got == _combine_loop(twin, *args, events)
        assert np.array_equal(det.combined, twin.combined)
        assert np.array_equal(det.paper_count, twin.paper_count)
        assert np.array_equal(det.flags, twin.flags)
        assert np.array_equal(det.pair_state, twin.pair_state)


@pytest.mark.parametrize("scan_frames", [4096, 37])
def test_the_scan_measures_the_hands_speeds_as_holding_still_does(monkeypatch, scan_frames):
    """The hold-still rule takes the hands' speeds from the co-motion scan (not measured twice):
    from frame ``lag`` on they are its own, gaps and chunk borders included."""
    from oacdsl.segmentation import scan
    from oacdsl.segmentation.comotion import AdaptiveSettings, comotion
    from oacdsl.segmentation.holding import median_speeds as _speeds
    from oacdsl.segmentation.pairs import PairTable
    from oacdsl.segmentation.poses import RigidFill

    scene = carry_scene()
    scene["hand"][200:215, 1] = np.nan  # a marker of the hand hidden
    scene["cup"][120:130, 0] = np.nan  # and one of the cup (filled by its rigid fit)
    rec = recording(scene)
    table = PairTable.of(rec)
    hand = table.instances.index("hand")
    settings = AdaptiveSettings(lag_s=0.07)
    params = AasParams(mode="adaptive").resolved(rec.rate_hz)
    monkeypatch.setattr(scan, "SCAN_FRAMES", scan_frames)  # chunks of the scan
    found = comotion(rec, table, params, settings, RigidFill(rec, ["cup"]), keep_speeds=[hand])
    lag = settings.frames(settings.lag_s, rec.rate_hz)
    own = _speeds(rec.group_positions("hand"), np.asarray(rec.times_s, dtype=np.float64), lag)
    assert np.array_equal(found.speeds[hand][lag:], own[lag:], equal_nan=True)
    assert found.speeds[hand][0] == own[0]  # frame 0 against frame lag, as the first frames
    assert set(found.speeds) == {hand}
