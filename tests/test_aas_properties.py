"""Properties of the AAS: chunking, the per-frame reference, marker/instance order, rigid motion."""

import numpy as np
from _aas_helpers import grid_scene
from hypothesis import given, settings
from hypothesis import strategies as st
from segeval.reference import segment_reference

from oacdsl.segmentation import AasParams, segment
from oacdsl.segmentation.recording import Recording

# thresholds that no distance or change of a grid scene comes near (see grid_scene)
SAFE = {"distance_m": 0.155, "speed_m_s": 0.001, "mode": "paper"}  # the paper's Eq. 1/2 as printed

seeds = st.integers(0, 2**32 - 1)
params = st.builds(
    lambda n, merge: AasParams(frames=n, merge_s=merge, **SAFE),
    st.integers(1, 5),
    st.sampled_from([0.0, 0.05, 0.3]),
)


def scene(seed: int, frames: int = 160) -> Recording:
    rng = np.random.default_rng(seed)
    return grid_scene(rng, frames, n_inst=int(rng.integers(2, 5)), markers=int(rng.integers(1, 4)))


@settings(max_examples=40, deadline=None)
@given(seeds, params, st.integers(1, 200))
def test_chunked_equals_single_pass(seed, p, chunk):
    rec = scene(seed)
    assert segment(rec, p, chunk_frames=chunk).keyframes == segment(rec, p, chunk_frames=10**6).keyframes


@settings(max_examples=25, deadline=None)
@given(seeds, params, st.integers(1, 100))
def test_vectorised_equals_per_frame_reference(seed, p, chunk):
    rec = scene(seed, frames=120)
    assert segment(rec, p, chunk_frames=chunk).keyframes == segment_reference(rec, p).keyframes


@settings(max_examples=30, deadline=None)
@given(seeds, params, st.randoms(use_true_random=False))
def test_invariant_to_the_order_of_markers_and_instances(seed, p, rnd):
    rec = scene(seed)
    perm = list(range(len(rec.marker_names)))
    rnd.shuffle(perm)
    where = {old: new for new, old in enumerate(perm)}
    names = list(rec.groups)
    rnd.shuffle(names)
    groups = {}
    for name in names:
        idx = [where[i] for i in rec.groups[name]]
        rnd.shuffle(idx)
        groups[name] = tuple(idx)
    shuffled = Recording(rec.source, rec.rate_hz, rec.times_s, tuple(rec.marker_names[i] for i in perm),
                         rec.positions_m[:, perm, :], groups)
    assert segment(shuffled, p).keyframes == segment(rec, p).keyframes


@settings(max_examples=30, deadline=None)
@given(seeds, params, st.integers(0, 2**32 - 1), st.floats(-50.0, 50.0))
def test_invariant_to_a_rigid_motion_of_the_scene(seed, p, rot_seed, offset):
    rec = scene(seed)
    rng = np.random.default_rng(rot_seed)
    q, r = np.linalg.qr(rng.normal(size=(3, 3)))
    rot = q * np.sign(np.diag(r))
    if np.linalg.det(rot) < 0:
        rot[:, 0] = -rot[:, 0]
    moved = rec.positions_m @ rot.T + rng.normal(size=3) * offset
    other = Recording(rec.source, rec.rate_hz, rec.times_s, rec.marker_names, moved, rec.groups)
    assert segment(other, p).keyframes == segment(rec, p).keyframes


def test_grid_scenes_are_not_trivial():
    # the properties above mean something only if the scenes have touches and gaps
    counts = [len(segment(scene(s), AasParams(frames=2, merge_s=0, **SAFE)).keyframes) for s in range(10)]
    assert sum(c > 2 for c in counts) >= 7
