"""recording_from_points: per-frame points of named groups (e.g. from a simulation) → Recording."""

import numpy as np
import pytest

from oacdsl.errors import RecordingError
from oacdsl.segmentation.points import recording_from_points


def test_groups_become_instances_with_prefixed_marker_names():
    rng = np.random.default_rng(1)
    cup = rng.normal(size=(50, 3, 3))
    hand = rng.normal(size=(50, 2, 3))
    hand[10:14, 1] = np.nan
    rec = recording_from_points({"hand": hand, "cup": cup}, 100.0, source="sim", labels={"hand": ["a", "b"]})
    assert rec.instances == ("cup", "hand")
    assert rec.marker_names == ("hand:a", "hand:b", "cup:m1", "cup:m2", "cup:m3")
    assert rec.n_frames == 50 and rec.rate_hz == 100.0 and rec.source == "sim"
    np.testing.assert_allclose(rec.times_s[:3], [0.0, 0.01, 0.02])
    np.testing.assert_array_equal(rec.group_positions("cup"), cup)
    np.testing.assert_array_equal(rec.group_positions("hand"), hand)  # NaN gaps kept (equal_nan by default)
    assert np.isnan(rec.group_positions("hand")[10:14, 1]).all()


def test_single_point_groups_and_first_frame():
    rec = recording_from_points({"ball": np.zeros((3, 1, 3))}, 30.0, first_frame=704)
    assert rec.groups == {"ball": (0,)} and rec.first_frame == 704
    assert rec.times_s[-1] == pytest.approx(2 / 30)


@pytest.mark.parametrize(
    ("groups", "rate", "labels", "message"),
    [
        ({}, 100.0, None, "no point groups"),
        ({"a": np.zeros((5, 2, 3)), "b": np.zeros((4, 1, 3))}, 100.0, None, "group 'b' has 4 frames"),
        ({"a": np.zeros((5, 2))}, 100.0, None, "expected \\(frames, k ≥ 1, 3\\)"),
        ({"a": np.zeros((5, 0, 3))}, 100.0, None, "expected \\(frames, k ≥ 1, 3\\)"),
        ({"a": np.full((5, 1, 3), np.inf)}, 100.0, None, "infinite"),
        ({"a": np.zeros((5, 1, 3))}, 0.0, None, "frame rate must be positive"),
        ({"a": np.zeros((5, 2, 3))}, 100.0, {"a": ["x"]}, "1 labels for 2 points"),
        ({"a": np.zeros((5, 2, 3))}, 100.0, {"a": ["x", "x"]}, "not unique"),
        ({"a": np.zeros((0, 1, 3))}, 100.0, None, "no frames"),
    ],
)
def test_bad_points_are_one_line_recording_errors(groups, rate, labels, message):
    with pytest.raises(RecordingError, match=message) as info:
        recording_from_points(groups, rate, source="sim.npz", labels=labels)
    assert str(info.value).startswith("sim.npz: ") and "\n" not in str(info.value)
