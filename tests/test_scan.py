"""The co-motion scan's shortcuts give the values of the plain computation, bit for bit: instance
boxes straight from the coordinates, coordinates of some instances only, speeds in slabs of frames."""

from __future__ import annotations

import numpy as np
import pytest
from _aas_helpers import recording
from test_adaptive import carry_scene

from oacdsl.segmentation.comotion import AdaptiveSettings
from oacdsl.segmentation.geometry import ChunkGeometry
from oacdsl.segmentation.pairs import PairTable
from oacdsl.segmentation.poses import RigidFill
from oacdsl.segmentation.recording import Recording


def random_walk(seed: int, frames: int = 300, shuffled: bool = False) -> Recording:
    """Instances of 1-6 markers wandering near each other, with gaps; ``shuffled``: their markers
    interleaved in the recording (the pair table's order is then not the recording's)."""
    rng = np.random.default_rng(seed)
    tracks = {}
    for i in range(int(rng.integers(2, 6))):
        centre = np.cumsum(rng.normal(scale=0.01, size=(frames, 3)), axis=0) + rng.random(3) * 0.3
        pos = centre[:, None, :] + rng.normal(scale=0.03, size=(1, int(rng.integers(1, 7)), 3))
        pos[rng.random(pos.shape[:2]) < 0.05] = np.nan
        tracks[f"o{i}"] = pos
    rec = recording(tracks)
    if not shuffled:
        return rec
    perm = rng.permutation(len(rec.marker_names))
    where = {int(old): new for new, old in enumerate(perm)}
    groups = {g: tuple(where[m] for m in idx) for g, idx in rec.groups.items()}
    return Recording(rec.source, rec.rate_hz, rec.times_s, tuple(rec.marker_names[i] for i in perm),
                     rec.positions_m[:, perm], groups)


@pytest.mark.parametrize("seed", range(8))
def test_instance_boxes_from_the_coordinates_equal_those_from_marker_boxes(seed):
    rec = random_walk(seed, shuffled=seed % 2 == 1)
    geometry = ChunkGeometry(rec, PairTable.of(rec))
    x = geometry.coordinates(0, rec.n_frames)
    for block in (1, 3, 8, 1000):
        direct = geometry.lower_bounds(x, block)
        via_markers = geometry.lower_bounds(x, block, boxes=geometry.marker_boxes(x, block))
        assert np.array_equal(direct, via_markers, equal_nan=True)
        assert direct.size == geometry.table.n_instance_pairs and not np.isnan(direct).all()


@pytest.mark.parametrize("seed", range(6))
def test_coordinates_of_some_instances_are_those_of_all(seed):
    rec = random_walk(seed, shuffled=seed % 2 == 1)
    table = PairTable.of(rec)
    geometry = ChunkGeometry(rec, table, RigidFill(rec, list(rec.groups)))
    every = geometry.coordinates(7, 250)
    rng = np.random.default_rng(seed)
    needed = rng.random(len(table.instances)) < 0.5
    some = geometry.coordinates(7, 250, np.full_like(every, 9.0), needed)
    rows = np.concatenate([np.arange(table.marker_offsets[i], table.marker_offsets[i + 1])
                           for i in np.flatnonzero(needed)] + [np.zeros(0, dtype=np.intp)])
    assert np.array_equal(some[:, rows], every[:, rows], equal_nan=True)


@pytest.mark.parametrize(("slab", "chunk"), [(1, 4096), (7, 50), (4096, 33)])
def test_the_scan_does_not_depend_on_its_slabs_of_frames(monkeypatch, slab, chunk):
    """Speeds, closest distances and co-motion frames: the same whatever the slab of frames whose
    speeds are computed at a time (one frame, 7 frames, the whole chunk), gaps filled or not."""
    from oacdsl.segmentation import scan
    from oacdsl.segmentation.comotion import comotion
    from oacdsl.segmentation.params import AasParams

    scene = carry_scene()
    scene["hand"][200:215, 1] = np.nan  # a hand's marker hidden
    scene["cup"][120:130, 0] = np.nan  # a cup's (filled by its rigid fit)
    rec = recording(scene)
    table = PairTable.of(rec)
    params = AasParams(mode="adaptive").resolved(rec.rate_hz)
    settings = AdaptiveSettings(lag_s=0.07)
    keep = list(range(len(table.instances)))
    monkeypatch.setattr(scan, "SCAN_FRAMES", chunk)
    found = {}
    for size in (slab, 10**6):
        monkeypatch.setattr(scan, "_SLAB", size)
        found[size] = comotion(rec, table, params, settings, RigidFill(rec, ["cup"]), keep_speeds=keep)
    a, b = found[slab], found[10**6]
    assert a.learned == b.learned and a.edges == b.edges and a.learned  # the cup is carried
    for q in b.closest:
        assert np.array_equal(a.closest[q], b.closest[q], equal_nan=True)
    for i in keep:
        assert np.array_equal(a.speeds[i], b.speeds[i], equal_nan=True)
