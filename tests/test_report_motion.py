"""The report's motion section: demonstrated against executed motion per sub-action."""

import copy
import math
import shutil

import numpy as np
import pytest
from report_fixture import dough_result

from oacdsl.errors import ResultError
from oacdsl.pipeline.motion_compare import _pairs, save_comparison_plot
from oacdsl.report import render_html, validate_result
from oacdsl.segmentation.motion import SubActionMotion
from oacdsl.segmentation.motionfeatures import motion_features


def features(tilt_deg: float, rise: float | None, period: float | None = None) -> dict:
    return {"duration_s": 3.0, "path_length_m": 0.45, "extent_m": [0.38, 0.1, 0.02], "core_s": [0.0, 3.0],
            "period_s": period, "cycles": 3.4 if period else None, "radius_m": 0.016,
            "tilt_max_rad": math.radians(tilt_deg), "tilt_time_s": 0.6, "tilt_rise_s": rise}


@pytest.fixture(scope="module")
def base(tmp_path_factory):
    out = tmp_path_factory.mktemp("base")
    return out, dough_result(out, with_pictures=False)


def with_motion(result: dict, plot: str | None = None) -> dict:
    doc = copy.deepcopy(result)
    doc["motion"] = {"sub_actions": [
        {"index": 1, "oac": "pour", "params": {"tilt": math.radians(110), "duration": 0.81},
         "moved": "red_cup", "target": None, "demonstrated": features(110.2, 0.65), "robot_index": 1,
         "robot_moved": "red_cup", "robot_target": None, "executed": features(112.4, 0.67)},
        {"index": 7, "oac": "mix", "moved": "mixer", "target": "orange_bowl",
         "demonstrated": features(3, None, 0.5), "robot_index": None, "executed": None},
    ]}
    if plot:
        doc["motion"]["plot"] = plot
    return doc


def test_the_table_shows_demonstrated_and_executed_features(base):
    out, result = base
    page, warnings = render_html(with_motion(result), out)
    section = page[page.index('<section id="motion">'):]
    section = section[: section.index("</section>")]
    assert "Demonstrated and executed motion" in section
    assert "110° / 112°" in section and "0.65 s / 0.67 s" in section  # tilt, tilt rise
    assert "duration 0.81, tilt 110°" in section  # the parameters the step was given
    assert "0.50 s / –" in section and "no aligned robot sub-action" in section
    assert "mixer → orange_bowl" in section and "red_cup → world" in section


def test_without_a_comparison_the_section_says_so(base):
    out, result = base
    page, _ = render_html(result, out)
    assert "No comparison: the robot was not verified." in page


def test_the_picture_is_embedded(base, tmp_path):
    out, result = base
    shutil.copytree(out, tmp_path / "out")
    t = np.arange(0, 2, 0.1)
    T = np.tile(np.eye(4), (len(t), 1, 1))
    T[:, 0, 3] = 0.02 * np.cos(2 * np.pi * t / 0.5)
    T[:, 1, 3] = 0.02 * np.sin(2 * np.pi * t / 0.5)
    f = motion_features(t, T)
    m = SubActionMotion(2, 0, len(t) - 1, "right_hand", "spoon", "cup", "kept", t, T, f, 0.0)
    (tmp_path / "out" / "figures").mkdir(exist_ok=True)
    save_comparison_plot([(m, m), (m, None)], tmp_path / "out" / "figures" / "motion.png")
    page, warnings = render_html(with_motion(result, "figures/motion.png"), tmp_path / "out")
    section = page[page.index('<section id="motion">'):]
    assert 'src="data:image/png;base64,' in section[: section.index("</section>")] and not warnings


def test_a_bad_motion_part_is_refused(base):
    _, result = base
    doc = with_motion(result)
    doc["motion"]["sub_actions"][0]["executed"]["tilt_max_rad"] = -1.0
    with pytest.raises(ResultError, match="motion.sub_actions.0.executed.tilt_max_rad"):
        validate_result(doc)


def test_pairs_follow_the_alignment():
    v = {"demonstration": [{"index": 1}, {"index": 2}, {"index": 3}],
         "robot": [{"index": 1}, {"index": 2}, {"index": 3}, {"index": 4}],
         "alignment": [{"op": "match", "demonstration": 0, "robot": 0},
                       {"op": "extra", "demonstration": None, "robot": 1},
                       {"op": "match", "demonstration": 1, "robot": 2},
                       {"op": "missing", "demonstration": 2, "robot": None}]}
    assert _pairs(v) == {0: 0, 1: 2}


def test_a_run_stopped_early_leaves_out_the_steps_it_never_executed(base):
    # the sub-actions of steps after a failed one point at no execution (else result.json
    # would not validate and the report of a failed run would be lost)
    from oacdsl.pipeline.result import ResultRecord
    from oacdsl.pipeline.stages import _unexecuted_steps

    _, result = base
    record = ResultRecord(created_utc="", oacdsl_version="", demonstration=result["demonstration"])
    match = copy.deepcopy(result["match"])
    for k, sub in enumerate(match["sub_actions"]):
        sub["step"] = k
    record.put("match", match)
    _unexecuted_steps(record, 2)
    kept = [s.get("step") for s in record.docs["match"]["sub_actions"]]
    assert kept[:3] == [0, 1, None] and set(kept[2:]) == {None}
    _unexecuted_steps(record, 99)  # all executed: nothing changes
    assert [s.get("step") for s in record.docs["match"]["sub_actions"]] == kept
