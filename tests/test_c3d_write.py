"""The numpy C3D writer: the same file content as ezc3d's writer, read back the same."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from oacdsl.segmentation.readers import read_c3d, write_c3d
from oacdsl.segmentation.readers.c3d import _labels_for_writing
from oacdsl.segmentation.recording import Recording


def ezc3d_write(recording: Recording, path: Path) -> None:
    """The writer this module replaced (ezc3d), as the reference."""
    import ezc3d

    labels = _labels_for_writing(recording)
    f, m = recording.n_frames, len(recording.marker_names)
    gap = ~np.all(np.isfinite(recording.positions_m), axis=-1)
    points = np.ones((4, m, f))
    points[:3] = np.where(gap[..., None], 0.0, recording.positions_m * 1000.0).transpose(2, 1, 0)
    c3d = ezc3d.c3d()
    c3d["parameters"]["POINT"]["RATE"]["value"] = [float(recording.rate_hz)]
    c3d["parameters"]["POINT"]["LABELS"]["value"] = tuple(labels)
    c3d["parameters"]["POINT"]["UNITS"]["value"] = ["mm"]
    c3d["data"]["points"] = points
    c3d["data"]["meta_points"] = {"residuals": np.where(gap.T, -1.0, 0.0)[None],
                                  "camera_masks": np.zeros((7, m, f), dtype=bool)}
    c3d["header"]["points"]["first_frame"] = int(recording.first_frame)
    groups = list(recording.groups)
    if groups:
        c3d.add_parameter("SUBJECTS", "USED", [len(groups)])
        c3d.add_parameter("SUBJECTS", "USES_PREFIXES", [1])
        c3d.add_parameter("SUBJECTS", "NAMES", groups)
        c3d.add_parameter("SUBJECTS", "LABEL_PREFIXES", [f"{g}:" for g in groups])
    c3d.write(str(path))


def synthetic(frames: int, markers: int, first_frame: int = 0, rate_hz: float = 120.0) -> Recording:
    rng = np.random.default_rng(markers)
    pos = rng.normal(scale=0.8, size=(frames, markers, 3))
    pos[3:9, 0] = np.nan  # a gap
    pos[:, markers - 1] = np.nan  # a marker never seen
    pos[5, 2, 1] = np.nan  # one coordinate missing: the whole point is a gap
    names = [f"m{i}" for i in range(markers)]
    half = markers // 2
    groups = {"cup": tuple(range(1, half)), "right_hand": tuple(range(half, markers - 1))}
    return Recording("synthetic", rate_hz, np.arange(frames) / rate_hz, names, pos, groups, first_frame)


def same(a: Recording, b: Recording) -> None:
    assert a.marker_names == b.marker_names
    assert {g: tuple(i) for g, i in a.groups.items()} == {g: tuple(i) for g, i in b.groups.items()}
    assert (a.rate_hz, a.first_frame, a.n_frames) == (b.rate_hz, b.first_frame, b.n_frames)
    np.testing.assert_array_equal(a.positions_m, b.positions_m)  # bit for bit, NaN where NaN


def parameters(path: Path) -> dict[tuple[str, str], list]:
    import ezc3d

    params = ezc3d.c3d(str(path))["parameters"]
    out = {}
    for group in params:
        if group in ("ROTATION", "EZC3D") or not isinstance(params[group], dict):
            continue  # ezc3d's own groups, left out (so the data starts at another block)
        for name, p in params[group].items():
            if isinstance(p, dict) and "value" in p and (group, name) != ("POINT", "DATA_START"):
                v = p["value"]
                out[(group, name)] = [str(x).strip() if isinstance(x, str) else float(x) for x in np.ravel(v)]
    return out


@pytest.mark.parametrize(("frames", "markers", "first"), [(40, 7, 0), (25, 300, 12), (10, 600, 0)])
def test_the_same_recording_and_parameters_as_ezc3d_writes(
    tmp_path: Path, frames: int, markers: int, first: int
) -> None:
    rec = synthetic(frames, markers, first)
    ours, theirs = write_c3d(rec, tmp_path / "ours.c3d"), tmp_path / "theirs.c3d"
    ezc3d_write(rec, theirs)
    back = read_c3d(ours)
    same(back, read_c3d(theirs))
    assert parameters(ours) == parameters(theirs)
    assert ours.read_bytes()[-(frames * markers * 16):] == theirs.read_bytes()[-(frames * markers * 16):]
    assert len(back.marker_names) == markers and np.isnan(back.positions_m[3:9, 0]).all()
    expect = (rec.positions_m * 1000.0).astype(np.float32).astype(np.float64) * 0.001  # the reader: × m/mm
    np.testing.assert_array_equal(back.positions_m[:, :-1][~np.isnan(rec.positions_m[:, :-1]).any(-1)],
                                  expect[:, :-1][~np.isnan(rec.positions_m[:, :-1]).any(-1)])
    if markers > 255:
        assert ("POINT", "LABELS2") in parameters(ours)


def test_no_groups_and_a_rate_that_is_not_whole(tmp_path: Path):
    rec = synthetic(10, 4, rate_hz=59.94)
    bare = Recording("x", rec.rate_hz, rec.times_s, rec.marker_names, rec.positions_m, {})
    ezc3d_write(bare, tmp_path / "theirs.c3d")
    same(read_c3d(write_c3d(bare, tmp_path / "ours.c3d")), read_c3d(tmp_path / "theirs.c3d"))


@pytest.mark.mocap
def test_the_bundled_demonstration_as_ezc3d_writes_it(tmp_path: Path):
    from oacdsl.pipeline.inputs import bundled_recording

    rec = bundled_recording()[0]
    ezc3d_write(rec, tmp_path / "theirs.c3d")
    same(read_c3d(write_c3d(rec, tmp_path / "ours.c3d")), read_c3d(tmp_path / "theirs.c3d"))


def test_more_frames_than_a_16_bit_parameter_holds(tmp_path: Path):
    rec = synthetic(40_000, 5, rate_hz=1000.0)  # POINT:FRAMES unsigned, as ezc3d writes it
    ezc3d_write(rec, tmp_path / "theirs.c3d")
    back = read_c3d(write_c3d(rec, tmp_path / "ours.c3d"))
    assert back.n_frames == 40_000
    same(back, read_c3d(tmp_path / "theirs.c3d"))


def test_more_frames_than_the_parameter_holds_are_refused(tmp_path: Path):
    from oacdsl.errors import RecordingError

    with pytest.raises(RecordingError, match="70000 frames"):
        write_c3d(synthetic(70_000, 5, rate_hz=1000.0), tmp_path / "long.c3d")
    assert not list(tmp_path.iterdir())
