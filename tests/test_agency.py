"""A tie the world states cannot break (which hand brought its object to the other's), broken by
how far the hands moved (oacdsl/matching/agency.py)."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

from oacdsl.compiler import load_library
from oacdsl.matching import Matcher
from oacdsl.matching.agency import by_motion, hand_travel
from oacdsl.segmentation.recording import Recording
from oacdsl.world import WorldState

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))


@pytest.fixture(scope="module")
def library():
    return load_library([ROOT / "library" / "kit", ROOT / "library" / "examples"])


def _kit_only(library) -> list[str]:
    """The OACs of library/examples: left out, so that only the KIT library's generic ones match."""
    kit = load_library([ROOT / "library" / "kit"])
    return [n for n in library.oacs if n not in kit.oacs]


def _peeling(library):
    scene = library.scenes["peeling"]
    tracked = sorted(i.name for i in scene.tracked())
    before = WorldState.of(tracked, [("left_hand", "cucumber"), ("right_hand", "peeler")])
    after = WorldState.of(tracked, [("left_hand", "cucumber"), ("right_hand", "peeler"),
                                    ("cucumber", "peeler")])
    return Matcher.from_library(library, scene, exclude=_kit_only(library)), before, after


def test_the_hand_that_moved_farther_breaks_the_tie(library):
    matcher, before, after = _peeling(library)
    result = matcher.match(before, after)
    assert result.ambiguous and result.chosen.text() == "touch(h=left_hand, o=cucumber, t=peeler)"
    moved = {"right_hand": 0.39, "left_hand": 0.02}
    decided = by_motion(result, {"left_hand", "right_hand"}, lambda i, a, b: moved[i], 0, 100)
    assert decided.chosen.text() == "touch(h=right_hand, o=peeler, t=cucumber)"
    assert not decided.ambiguous and decided.by_motion
    assert "the demonstration's motion decides" in decided.reason
    assert "right_hand 0.39 m" in decided.reason and "left_hand 0.02 m" in decided.reason
    # hands that moved alike decide nothing: still the tie, as before
    same = by_motion(result, {"left_hand", "right_hand"}, lambda i, a, b: 0.2, 0, 100)
    assert same is result


def test_a_match_that_is_no_tie_is_left_as_it_is(library):
    scene = library.scenes["peeling"]
    tracked = sorted(i.name for i in scene.tracked())
    result = Matcher.from_library(library, scene).match(
        WorldState.of(tracked, [("left_hand", "cucumber"), ("right_hand", "peeler")]),
        WorldState.of(tracked, [("left_hand", "cucumber"), ("right_hand", "peeler"), ("cucumber", "peeler")]))
    assert result.chosen.oac.name == "peel" and not result.ambiguous
    assert by_motion(result, {"left_hand", "right_hand"}, lambda i, a, b: {"left_hand": 1.0}.get(i, 0.0),
                     0, 100) is result


def test_hand_travel_is_the_markers_path_and_ignores_a_gap():
    frames = 5
    pos = np.zeros((frames, 3, 3))
    pos[:, :, 0] = np.arange(frames)[:, None] * 0.1  # every marker 10 cm a frame along x
    pos[2, 0] = np.nan  # one marker unseen in one frame
    pos[:, 2] = np.nan  # one never seen
    rec = Recording("t", 100.0, np.arange(frames) / 100.0, ("a", "b", "c"), pos, {"hand": (0, 1, 2)})
    travel = hand_travel(rec)
    assert travel("hand", 0, 4) == pytest.approx(0.3)  # median of 0.2 (marker a, gap) and 0.4 (b)
    assert travel("hand", 1, 2) == pytest.approx(0.1)
    assert travel("hand", 3, 3) == 0.0 and travel("cup", 0, 4) == 0.0


def test_the_synthetic_peel_composes_with_the_hand_that_moved(tmp_path: Path):
    """The synthetic Peel (tests/_task_demos.py) with only the KIT library's OACs: the peeler,
    brought by the right hand, comes onto the cucumber the left hand holds still."""
    import _task_demos as demos

    from oacdsl.matching.demonstration import match_segmentation
    from oacdsl.pipeline import load_inputs
    from oacdsl.segmentation import AasParams

    libraries = [ROOT / "library" / "kit", ROOT / "library" / "examples"]
    inputs = load_inputs(demos.write("Peel", tmp_path), libraries, None, AasParams())
    matcher = Matcher.from_library(inputs.library, inputs.scene, exclude=_kit_only(inputs.library))
    plain = match_segmentation(inputs.segmented(), matcher, unmerged=inputs.unmerged())
    moved = match_segmentation(inputs.segmented(), matcher, unmerged=inputs.unmerged(),
                               travel=inputs.travel())
    assert [m.text() for m in plain][2] == "touch(h=left_hand, o=cucumber, t=peeler)"
    assert plain[2].result.ambiguous
    assert [m.text() for m in moved] == ["grasp(h=left_hand, o=cucumber)", "grasp(h=right_hand, o=peeler)",
                                         "touch(h=right_hand, o=peeler, t=cucumber)"]
    assert not any(m.result.ambiguous for m in moved)
