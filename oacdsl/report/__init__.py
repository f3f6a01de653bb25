"""The reproduction report: one self-contained HTML page and its data, ``result.json``.

``write_report(result, out_dir)`` validates ``result`` against the schema of
:mod:`oacdsl.report.schema` (docs/report.md) and writes ``report.html`` (inline CSS,
pictures embedded as data URIs, no JavaScript, no network) and ``result.json``.
:mod:`oacdsl.report.figures` draws the pictures the pipeline may add.
"""

from oacdsl.atomic import write_atomic
from oacdsl.report.build import bound_conditions, reliability_doc
from oacdsl.report.page import Report, render_html, write_report
from oacdsl.report.schema import SCHEMA_VERSION, Result, validate_result

__all__ = [
    "SCHEMA_VERSION",
    "Report",
    "Result",
    "bound_conditions",
    "reliability_doc",
    "render_html",
    "validate_result",
    "write_atomic",
    "write_report",
]
