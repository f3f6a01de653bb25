"""Where the motion check reads a pair's motion when a demonstrated keyframe merges its change
with another (``oacdsl/verify_spans.py``), on KIT Wipe at twice the speed: the person's sponge
leaving the plate and the plate reaching the rack 0.15 s later are one keyframe (10 Hz), a
robot lifts the sponge and then carries the plate to the rack for seconds. The take reads as
the original; an execution that wipes and then carries the plate verifies and is faithful
whether the demonstration's keyframe is merged or not; one that does not wipe but shakes the
plate under the lifted sponge still fails."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path
from typing import Any

import _verify_takes as corrupt
import numpy as np
import pytest
from _mocap import mocap_file

from oacdsl.matching.transient import agents_of, stable_segmentation
from oacdsl.pipeline import load_inputs
from oacdsl.segmentation import AasParams, segment, takes
from oacdsl.segmentation.poses import fit_poses, relative
from oacdsl.segmentation.recording import Recording
from oacdsl.segmentation.result import Keyframe, Segmentation
from oacdsl.verify_contacts import SimContacts
from oacdsl.verify_execution import VerifyOutcome, verify_execution
from oacdsl.verify_spans import pair_frames
from oacdsl.world import relation

ROOT = Path(__file__).resolve().parents[1]
WIPE = "kit_bimanual/Wipe_files_motions_3091_Wipe1_pl_sp_front_angle_03.mmm.xml"
WIPING = relation("plate_dish", "sponge_small")
INTO_RACK = relation("draining_rack", "plate_dish")


def _inputs() -> Any:
    return load_inputs(mocap_file(WIPE), ROOT / "library" / "kit", None, AasParams())


def _verify(inputs: Any, demo: Recording, execution: Recording, **kw: Any) -> VerifyOutcome:
    return verify_execution(demo, execution, scene=inputs.scene, library=inputs.library, params=inputs.params,
                            **kw)


def _motion(o: VerifyOutcome) -> dict[str, tuple[str, str]]:
    return {c.name: (c.demonstration, c.execution) for c in o.checks if c.kind == "motion"}


def _own_frame(rec: Recording, params: AasParams, pair: tuple[str, str], made: bool) -> int:
    kfs = segment(rec, replace(params, merge_s=0.0)).keyframes
    return next(b.frame for a, b in zip(kfs, kfs[1:], strict=False)
                if (pair in b.state.relations) == made and (pair in a.state.relations) != made)


def test_twice_as_fast_the_wiping_reads_as_the_original() -> None:
    """At ×2 the keyframe ending the wiping also holds the plate's arrival in the rack; read to
    it, the sponge "tilts" 61° against the plate, gained after the sponge left it (more than
    25 cm from it, the plate turning on edge toward the rack); read while the sponge is on the
    plate, as in the original, the ×2 take's features are the original's."""
    inputs = _inputs()
    original = inputs.recording
    fast = takes.stretched(original, 0.5)
    merged = segment(fast, inputs.params).keyframes
    end = next(k for k in merged if WIPING not in k.state.relations and INTO_RACK in k.state.relations)
    assert end.frame in [k.frame for k in merged]  # one keyframe: − plate–sponge, + rack–plate
    left = _own_frame(fast, inputs.params, WIPING, made=False)
    assert left < end.frame
    start = _own_frame(fast, inputs.params, WIPING, made=True)
    posed = fit_poses(fast)
    T = relative(posed["plate_dish"].T_world_object, posed["sponge_small"].T_world_object)
    tilt = np.degrees(np.arccos(np.clip(T[:, 2, 2], -1.0, 1.0)))
    assert tilt[start : end.frame + 1].max() - tilt[start] > 45.0  # read to the merged keyframe
    assert tilt[start:left].max() - tilt[start] < 25.0  # while the sponge is on the plate
    assert np.linalg.norm(T[left:end.frame + 1, :3, 3], axis=1).min() > 0.25
    same, twice = _verify(inputs, original, original), _verify(inputs, fast, fast)
    assert same.faithful and twice.faithful
    assert _motion(twice) == _motion(same) == {"motion.4.cycles": ("2.6 cycles, radius 53 mm",) * 2}


def _robot_like(demo: Recording, params: AasParams, carry_s: float, shake_m: float = 0.0) -> Recording:
    """The demonstration done as a robot does it: up to where the sponge leaves the plate as
    demonstrated, then the sponge alone lifted to where the person's was at the plate's arrival
    (1 s), then the plate (and its hand) carried there over ``carry_s`` — ``shake_m``: swung
    that far to and fro along x three times on the way — then the rest as demonstrated."""
    left = _own_frame(demo, params, WIPING, made=False)
    arrived = _own_frame(demo, params, INTO_RACK, made=True)
    p = demo.positions_m
    dt = 1.0 / demo.rate_hz
    sponge = [i for n in ("sponge_small", "right_hand") for i in demo.groups[n]]
    plate = [i for n in ("plate_dish", "left_hand") for i in demo.groups[n]]
    frames = [p[: left]]
    n = round(1.0 / dt)
    w = np.linspace(0.0, 1.0, n + 1)[1:, None, None]
    lift = np.repeat(p[left - 1][None], n, axis=0)
    lift[:, sponge] = (1 - w) * p[left - 1][sponge] + w * p[arrived][sponge]
    frames.append(lift)
    n = round(carry_s / dt)
    w = np.linspace(0.0, 1.0, n + 1)[1:, None, None]
    carry = np.repeat(lift[-1][None], n, axis=0)
    carry[:, plate] = (1 - w) * p[left - 1][plate] + w * p[arrived][plate]
    carry[:, plate, 0] += shake_m * np.sin(2 * np.pi * 3 * w[..., 0])
    frames.append(carry)
    frames.append(p[arrived:])
    positions = np.concatenate(frames)
    return replace(demo, positions_m=positions, times_s=np.arange(len(positions)) * dt)


def _contacts(rec: Recording, params: AasParams) -> SimContacts:
    """The execution's relations as a simulation reports them (each change on its frame)."""
    kfs = segment(rec, replace(params, merge_s=0.0)).keyframes
    return SimContacts(rec.rate_hz, rec.n_frames, rec.instances,
                       tuple((k.frame, k.state.relations) for k in kfs), {})


def _demo_segmentation(demo: Recording, inputs: Any, merged: bool) -> Segmentation:
    """The demonstration's keyframes, the wiping's end and the plate's arrival merged into one
    keyframe (as at 10 Hz and twice the speed) or not (as a finer segmentation may find them)."""
    agents = agents_of(inputs.library.instance_classes(inputs.scene))
    raw = stable_segmentation(segment(demo, replace(inputs.params, merge_s=0.0)), agents.__contains__)[0]
    kfs: list[Keyframe] = list(raw.keyframes)
    i = next(i for i, k in enumerate(kfs)
             if WIPING in kfs[i - 1].state.relations and WIPING not in k.state.relations)
    assert INTO_RACK in kfs[i + 1].state.relations and INTO_RACK not in kfs[i].state.relations
    if merged:
        del kfs[i]
    return replace(raw, keyframes=tuple(kfs))


@pytest.mark.parametrize("merged", [True, False])
def test_a_robot_that_lifts_the_sponge_then_carries_the_plate(merged: bool) -> None:
    inputs = _inputs()
    demo = takes.stretched(inputs.recording, 0.5)
    seg = _demo_segmentation(demo, inputs, merged)
    run = _robot_like(demo, inputs.params, carry_s=4.0)
    o = _verify(inputs, demo, run, contacts=_contacts(run, inputs.params), demo_segmentation=seg)
    assert o.relations.counts()["split"] == (1 if merged else 0)
    assert o.verified and o.faithful, [(c.name, c.detail) for c in o.failed()]
    assert _motion(o)["motion.4.cycles"][1].startswith("2.6 cycles")


@pytest.mark.parametrize("merged", [True, False])
def test_no_wiping_but_the_plate_shaken_under_the_lifted_sponge_fails(merged: bool) -> None:
    """The strokes straightened, and the plate swung to and fro on its way to the rack, the
    sponge held above it: the sponge moves to and fro relative to the plate only when it no
    longer touches it, which is no wiping."""
    inputs = _inputs()
    demo = takes.stretched(inputs.recording, 0.5)
    seg = _demo_segmentation(demo, inputs, merged)
    start = _own_frame(demo, inputs.params, WIPING, made=True)
    left = _own_frame(demo, inputs.params, WIPING, made=False)
    flat = corrupt.straightened(demo, ["sponge_small", "right_hand"], start, left)
    run = _robot_like(flat, inputs.params, carry_s=4.0, shake_m=0.06)
    o = _verify(inputs, demo, run, contacts=_contacts(run, inputs.params), demo_segmentation=seg)
    assert o.verified
    assert not o.faithful and "motion.4.cycles" in [c.name for c in o.failed()], _motion(o)


def test_pair_frames() -> None:
    """The pair's own change in the keyframes without merging; a span that breaks the relation
    read up to the last frame in which it holds; to the merged keyframe when the pair's break
    came first and the target did not go on to other work (a robot that lost touch first may
    still work over its target)."""
    on, off, rack = frozenset({("a", "b")}), frozenset(), frozenset({("b", "c")})
    unmerged = [(0, off), (5, on), (20, off), (22, rack)]  # a leaves b, then b goes onto c

    def frames(a: int, b: int, relation_: str, merged: tuple[bool, bool], found: Any = lambda: unmerged,
               agents: frozenset[str] = frozenset()) -> tuple[int, int]:
        return pair_frames(a, b, 0, "a", "b", relation_, merged, found, agents)

    assert frames(5, 22, "broken", (False, True)) == (5, 19)
    assert frames(5, 22, "broken", (False, False)) == (5, 21)
    assert frames(5, 22, "kept", (False, True)) == (5, 22)
    assert frames(7, 22, "broken", (True, True)) == (5, 19)
    assert frames(5, 22, "broken", (False, True), list) == (5, 22)  # none found: as merged
    assert frames(5, 22, "broken", (False, True), agents=frozenset({"c"})) == (5, 22)  # c: a hand
    tool = [(0, off), (5, on), (20, off), (22, frozenset({("a", "c")}))]  # a leaves b for c
    assert frames(5, 22, "broken", (False, True), lambda: tool) == (5, 22)
    last = [(0, on | {("b", "h")}), (20, on), (22, off)]  # a hand lets go of b, then a leaves it
    assert frames(5, 22, "broken", (False, True), lambda: last) == (5, 21)
