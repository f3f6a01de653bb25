"""reproduce's result: a typed record whose parts are checked against the schema as they are set."""

from __future__ import annotations

import pytest

from oacdsl.errors import OacError
from oacdsl.pipeline.result import ResultRecord
from oacdsl.report.schema import validate_result

RUN = {"oac": "dough", "success": False, "error": "the cup slipped", "metrics": {"balls_total": 4},
       "steps": [{"oac": "grasp", "binding": {"h": "right_hand"}, "success": False}]}


def _record() -> ResultRecord:
    return ResultRecord("2026-01-01T00:00:00+00:00", "0", {"recording": "dough.c3d", "scene": "kitchen"})


def test_a_part_is_checked_when_it_is_set_and_read_back_typed():
    record = _record()
    with pytest.raises(OacError, match=r"result.json would not match its schema: run.steps.0.success: "):
        record.put("run", {**RUN, "steps": [{"oac": "grasp", "binding": {}, "success": "perhaps"}]})
    assert "run" not in record
    record.put("run", RUN)
    assert record.run is not None and record.run.error == "the cup slipped"
    assert not record.run.steps[0].success
    assert record.verification is None
    with pytest.raises(OacError, match="demonstration.recording: Field required"):
        ResultRecord("t", "0", {"scene": "kitchen"})


def test_the_document_keeps_the_parts_in_schema_order_and_is_valid():
    record = _record()
    record.put("reliability", None)  # no run store file yet: null, as before
    record.put("run", RUN)
    verdict = {"success": False, "summary": "The robot did not complete dough.", "failed_stage": "execute"}
    doc = record.to_json(verdict, [{"name": "execute", "status": "failed"}], ["a warning"])
    assert list(doc) == ["schema_version", "created_utc", "oacdsl_version", "demonstration", "run",
                         "reliability", "verdict", "stages", "warnings"]
    assert doc["run"] is RUN and validate_result(doc).run is not None
    with pytest.raises(OacError, match="verdict.success"):
        record.to_json({"summary": "?"}, [], [])
