"""The synthetic demonstrations of the evaluation tasks (``tests/_task_demos.py``), recorded like
a capture and taken through the standard takes, compose as the clean demonstration does
(``benchmarks/evaltakes.py``; issues 19 and 20: the project is measured on recordings and
variations it has not seen, and a demonstration that only works noise-free measures nothing).

A case that does not compose the same would be listed in :data:`KNOWN` with why, as a strict
expected failure (a change that mends one fails here until it is taken off the list and
docs/kit.md's table is updated); none is.
"""

from __future__ import annotations

from functools import cache
from pathlib import Path

import _task_demos as demos
import evaltakes
import numpy as np
import pytest
import takes as bench

from oacdsl.segmentation.readers import write_recording
from oacdsl.segmentation.takes import IDENTITY, STANDARD_TAKES

#: (task, take or "capture") → why it composes to other steps than the clean demonstration (none
#: since an object at rest on top of another touches it, :mod:`oacdsl.segmentation.stacking`: the
#: lid on the bottle, whose markers are 77-88 mm from the bottle's, was touching by the static
#: 80 mm rule only).
KNOWN: dict[tuple[str, str], str] = {}


def test_a_capture_moves_markers_onto_stalks_adds_noise_and_a_gap():
    clean, kit = demos.transfer_demo(), demos.transfer_demo(demos.KIT_LIKE)
    assert kit.marker_names == clean.marker_names and kit.positions_m.shape == clean.positions_m.shape
    gaps = np.isnan(kit.positions_m[..., 0])
    assert not np.isnan(clean.positions_m).any()
    assert 0 < gaps.sum() == round(demos.KIT_LIKE.gap_s * demos.RATE_HZ) and gaps.any(axis=0).sum() == 1
    # the knife's markers, on its axis in MARKERS, stand off it by the stalk lengths
    placed = demos.MARKERS["knife_black"]
    local = demos.KIT_LIKE.stalks("knife_black", placed)
    off_axis = np.linalg.norm(local[:, :2], axis=1) - np.linalg.norm(placed[:, :2], axis=1)
    assert np.all((off_axis >= 0.01 - 1e-9) & (off_axis <= 0.025 + 1e-9))
    assert np.array_equal(demos.KIT_LIKE.stalks("crate", demos.MARKERS["crate"]), demos.MARKERS["crate"])
    # the hands' markers: only the noise (0.3 mm) apart
    hand = [i for i, n in enumerate(clean.marker_names) if n.startswith("right_hand")]
    diff = (kit.positions_m[:, hand] - clean.positions_m[:, hand])[~gaps[:, hand]]
    assert np.nanstd(diff) == pytest.approx(demos.KIT_LIKE.noise_m, rel=0.1)
    ten = demos.transfer_demo(demos.KIT_10HZ)
    assert ten.rate_hz == 10.0 and ten.n_frames == 121


@cache
def _clean(task: str, folder: Path) -> bench.Outcome:
    return bench.compose_file(demos.write(task, folder), evaltakes.libraries(folder))


def _cases() -> list:  # type: ignore[type-arg]
    out = []
    for task in demos.TASKS:
        for take in ("capture", *STANDARD_TAKES):
            known = KNOWN.get((task, take))
            marks = [pytest.mark.xfail(strict=True, reason=known)] if known else []
            out.append(pytest.param(task, take, marks=marks, id=f"{task}-{take}"))
    return out


def test_every_known_failure_names_a_task_and_a_take():
    assert {t for t, _ in KNOWN} <= set(demos.TASKS) and {k for _, k in KNOWN} <= {"capture", *STANDARD_TAKES}


@pytest.mark.slow
@pytest.mark.parametrize("task, take", _cases())
def test_a_take_of_a_captured_demonstration_composes_to_the_clean_steps(task, take, tmp_path_factory):
    folder = tmp_path_factory.getbasetemp() / "evaltakes"
    folder.mkdir(exist_ok=True)
    clean = _clean(task, folder)
    assert clean.status == "composed", f"{task}: the clean demonstration does not compose: {clean.detail}"
    rec = demos.TASKS[task][0](demos.KIT_LIKE)
    if take == "capture":
        outcome, hands = bench.compose_file(write_recording(rec, folder / f"{task}.c3d"),
                                            evaltakes.libraries(folder)), dict(IDENTITY)
    else:
        outcome, hands = bench.run_take(rec, take, evaltakes.libraries(folder), f"-{task}.c3d", folder)
    assert outcome.status == "composed", f"{task} {take}: {outcome.status}: {outcome.detail}"
    status, detail = bench.compare(clean, outcome, hands or dict(IDENTITY))
    assert status in ("same", "same*"), f"{task} {take}: {detail}"


@pytest.mark.slow
def test_the_captured_close_keeps_the_lid_on_the_bottle_on_the_robot(tmp_path):
    """The synthetic Close, captured as KIT records (``KIT_LIKE``), seed 1: the lid is held 6°
    tilted, and judged by its bounding box it was pressed on the bottle while it hung 0.1-0.4 mm
    above it for 0.66 s (two extra changes, not verified); measured between the shapes, it is
    lowered onto the bottle (``rotate._above``), verified and faithful."""
    pytest.importorskip("mujoco", reason="the robot runtime needs the 'robot' extra (mujoco)")
    pytest.importorskip("placo", reason="the robot runtime needs the 'robot' extra (placo)")
    mark, why = evaltakes.robot_run("Close", "capture", demos.KIT_LIKE, 1, tmp_path)
    assert mark == "V", why


@pytest.mark.slow
@pytest.mark.parametrize("task", list(demos.TASKS))
def test_contacts_from_geometry_compose_each_demonstration_as_its_markers_do(task, tmp_path):
    """``--contacts geometry``: the clean demonstration composes to the steps it composes to by
    markers, and so does its KIT-like capture. The right hand's grasps of the block (Stack), the
    mug (HandOver) and the knife (Transfer) were lost before a carried object counted as held
    whatever the gap from the hand's volume (9-23 mm here, the tolerance 4.7 mm)."""
    libs = evaltakes.libraries(tmp_path)
    path = demos.write(task, tmp_path)
    by_markers = bench.compose_file(path, libs)
    by_shapes = bench.compose_file(path, libs, "geometry")
    assert by_shapes.status == "composed", f"{task}: {by_shapes.status}: {by_shapes.detail}"
    assert bench.compare(by_markers, by_shapes, dict(IDENTITY))[0] == "same"
    captured = write_recording(demos.TASKS[task][0](demos.KIT_LIKE), tmp_path / "captured.c3d")
    outcome = bench.compose_file(captured, libs, "geometry")
    assert outcome.status == "composed", f"{task} captured: {outcome.status}: {outcome.detail}"
    assert bench.compare(by_shapes, outcome, dict(IDENTITY))[0] == "same"
