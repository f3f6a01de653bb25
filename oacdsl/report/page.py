"""The report page: ``report.html`` (self-contained) and ``result.json``, from one result dict."""

from __future__ import annotations

import json
import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from oacdsl.atomic import write_atomic
from oacdsl.errors import InputError
from oacdsl.report.demonstration import composed_section, keyframes_section, segment_section
from oacdsl.report.execution import execution_section, reliability_section, verification_section
from oacdsl.report.html import Images, esc
from oacdsl.report.motion import motion_section
from oacdsl.report.overview import footer, header, title_of
from oacdsl.report.schema import SCHEMA_VERSION, validate_result
from oacdsl.report.style import CSS

__all__ = ["Report", "render_html", "write_report"]


@dataclass(frozen=True)
class Report:
    """What :func:`write_report` wrote; ``warnings`` lists pictures it could not embed."""

    html: Path
    json: Path
    warnings: list[str] = field(default_factory=list)


def render_html(
    result: dict[str, Any], base_dir: str | os.PathLike[str] | None = None, *, source: str = "result"
) -> tuple[str, list[str]]:
    """The page for ``result`` (validated first) and the warnings about pictures.

    Image paths in the result are resolved against ``base_dir`` (the report's folder); ``source``
    names the result in error messages.
    """
    r = validate_result(result, source=source)
    images = Images(Path(base_dir) if base_dir is not None else None)
    body = "".join([
        header(r),
        segment_section(r, images),
        keyframes_section(r, images),
        composed_section(r, images),
        execution_section(r, images),
        verification_section(r, images),
        motion_section(r, images),
        reliability_section(r),
        footer(r),
    ])
    page = (
        '<!DOCTYPE html>\n<html lang="en"><head><meta charset="utf-8">'
        '<meta name="viewport" content="width=device-width, initial-scale=1">'
        f'<meta name="generator" content="oacdsl {esc(r.oacdsl_version or "")}">'
        f"<title>{esc(title_of(r))} · oacdsl report</title><style>{CSS}</style></head>"
        f"<body><main>{body}</main></body></html>\n"
    )
    return page, images.warnings


def write_report(
    result: dict[str, Any], out_dir: str | os.PathLike[str], *, source: str = "result"
) -> Report:
    """Write ``out_dir/result.json`` and ``out_dir/report.html`` (each atomically) from ``result``.

    ``result`` follows the schema in :mod:`oacdsl.report.schema` (docs/report.md). Pictures it
    references (paths relative to ``out_dir``) are embedded into the page as data URIs, so the
    page can be mailed or archived alone. ``source`` names the result in error messages.
    Raises :class:`~oacdsl.errors.InputError` when ``result`` does not fit the schema, cannot be
    written as JSON, or the files cannot be written.
    """
    out = Path(out_dir)
    doc = result if "schema_version" in result else {"schema_version": SCHEMA_VERSION, **result}
    page, warnings = render_html(doc, out, source=source)
    try:
        text = json.dumps(doc, indent=2, ensure_ascii=False, allow_nan=False) + "\n"
    except (TypeError, ValueError) as e:
        where = str(out / "result.json")
        raise InputError(f"the result cannot be written as JSON: {e}", location=where) from None
    try:
        json_path = write_atomic(out / "result.json", text)
        html_path = write_atomic(out / "report.html", page)
    except OSError as e:
        raise InputError(f"cannot write the report: {e.strerror or e}", location=str(out)) from None
    return Report(html_path, json_path, warnings)
