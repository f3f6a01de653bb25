"""Skill parameters name the demonstrated motion feature they come from (SkillParamSpec.source)."""

from __future__ import annotations

import dataclasses
import math

import pytest

from oacdsl.segmentation.motionfeatures import MotionFeatures
from oacdsl.skills import MOTION_FEATURES, SIGNATURES, MotionSource


def test_motion_features_named_exist():
    fields = {f.name for f in dataclasses.fields(MotionFeatures)}
    assert set(MOTION_FEATURES) <= fields
    assert fields - set(MOTION_FEATURES) == {"core_s"}  # a time window, no parameter


def test_existing_skills_name_their_sources():
    src = {(s.name, p.name): p.source for s in SIGNATURES.values() for p in s.params}
    assert src[("pour", "tilt")] == MotionSource("tilt_max_rad", needs="tilt_rise_s", least=math.radians(125))
    assert src[("pour", "duration")] == MotionSource("tilt_rise_s", scale=1.25)
    assert src[("mix", "period")].feature == "period_s"
    assert src[("mix", "radius")] == MotionSource("radius_m", needs="period_s")
    assert src[("mix", "turns")].feature == "cycles"
    assert src[("wipe", "length")] == MotionSource("radius_m", scale=1.41, needs="period_s")
    assert src[("wipe", "strokes")].feature == "cycles"
    assert src[("pour", "height")] is None and src[("place", "force")] is None


@pytest.mark.parametrize("kwargs, message", [
    ({"feature": "tilt"}, "no motion feature 'tilt'; features: cycles, duration_s"),
    ({"feature": "radius_m", "needs": "period"}, "no motion feature 'period'"),
    ({"feature": "radius_m", "axis": 1}, "only extent_m has axes"),
    ({"feature": "extent_m", "axis": 3}, "only extent_m has axes"),
    ({"feature": "period_s", "scale": 0.0}, "a positive number"),
])
def test_bad_source_is_refused(kwargs, message):
    with pytest.raises(ValueError, match=message):
        MotionSource(**kwargs)


def test_describe_names_the_source():
    assert SIGNATURES["wipe"].param("length").describe().endswith(
        "from the demonstration: 1.41 x radius_m (where period_s is found)")
    assert MotionSource("extent_m", scale=0.5).describe() == "0.5 x extent_m[0]"


def test_skills_json_lists_the_source(capsys):
    import json

    from oacdsl.cli import main

    assert main(["skills", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    tilt = next(p for p in doc["pour"]["params"] if p["name"] == "tilt")
    assert tilt["source"] == {"feature": "tilt_max_rad", "scale": 1.0, "axis": 0, "needs": "tilt_rise_s",
                              "least": pytest.approx(math.radians(125))}
    assert next(p for p in doc["place"]["params"])["source"] is None
