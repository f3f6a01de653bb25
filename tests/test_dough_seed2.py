"""The bundled dough on seed 2's places, reproduced whole (slow): the pours keep the cups off the
bowl's rim as their tilt begins (each step raised by what the arm's measured lag needs), and the
mixer, circling pressed on the bowl's floor with a force regulated on the wrist's, never loses
that floor for 0.1 s (the verifier would read it as a contact lost and made again)."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

pytest.importorskip("mujoco", reason="the robot runtime needs the 'robot' extra (mujoco)")
pytest.importorskip("placo", reason="the robot runtime needs the 'robot' extra (placo)")

from _dough_runs import reproduce_dough  # noqa: E402


def longest_loss_frames(contacts: dict, a: str, b: str) -> int:
    """The longest run of frames, between the first and the last contact of ``a`` and ``b`` in a
    run's ``execution.contacts.json``, without that contact (all its frames: never in contact)."""
    pair = sorted((a, b))
    changes, spans = contacts["changes"], []
    for i, change in enumerate(changes):
        end = changes[i + 1]["frame"] if i + 1 < len(changes) else contacts["frames"]
        spans.append((change["frame"], end, pair in [sorted(r) for r in change["relations"]]))
    on = [k for k, (_, _, touching) in enumerate(spans) if touching]
    if not on:
        return int(contacts["frames"])
    longest, run = 0, 0
    for start, end, touching in spans[on[0] : on[-1] + 1]:
        run = 0 if touching else run + end - start
        longest = max(longest, run)
    return longest


@pytest.mark.slow
def test_dough_on_seed_2_is_faithful_and_the_mixer_keeps_the_floor(tmp_path: Path) -> None:
    # before: the red cup came down on the bowl's rim for 0.3 s as its tilt began (the arm lags
    # its goal 1.5-2 cm at the demonstrated pace), and that touch cut the span its tilt is
    # measured over: 74 deg against the demonstrated 109 (motion.2.tilt); pressed a fixed 2 mm,
    # the mixer floated off the floor for 10-14 frames once or twice per run
    verdict, out = reproduce_dough(tmp_path, seed=2)
    assert verdict["success"] and verdict["faithful"], verdict.get("summary")
    contacts = json.loads((out / "execution.contacts.json").read_text())
    assert contacts["rate_hz"] == 100.0
    assert longest_loss_frames(contacts, "mixer", "orange_bowl") < 10
