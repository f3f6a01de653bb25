"""``reproduce``: from a demonstration to a verified robot execution and its report.

Stages, each timed by :class:`~oacdsl.progress.Progress`: segment → match → compose →
execute → verify → record → report. Inputs are checked first (:func:`load_inputs`),
before anything is written. The outputs are built in a hidden folder inside ``out``
and published in one step at the end (:mod:`oacdsl.pipeline.publish`: ``out/runs/<id>/``
and the link ``out/current``; ``report.html``, ``result.json``, ``NAME.oac``, ``figures``
link to it), so ``out`` never shows half a report or entries of two runs. A stage that fails (no OAC
matches a sub-action, the robot drops a cup) stops the stages that need it and the
report says so, with a red verdict; the run store records every execution.

The stages are in :mod:`oacdsl.pipeline.stages`, the verdict in :mod:`oacdsl.pipeline.verdict`.
"""

from __future__ import annotations

import shutil
from collections.abc import Callable
from dataclasses import dataclass, field
from datetime import datetime, timezone
from pathlib import Path
from typing import Any

from oacdsl.errors import InputError
from oacdsl.pipeline.inputs import Inputs
from oacdsl.pipeline.result import ResultRecord
from oacdsl.pipeline.stages import run_stages
from oacdsl.pipeline.verdict import verdict as _verdict
from oacdsl.progress import Progress
from oacdsl.runtime.overrides import SceneOverrides

__all__ = ["STAGES", "Outcome", "reproduce"]

STAGES = ("segment", "match", "compose", "execute", "verify", "record", "report")


@dataclass
class Outcome:
    """What :func:`reproduce` produced: the exit status, the result document, the files."""

    exit_code: int
    result: dict[str, Any]
    files: list[Path] = field(default_factory=list)
    warnings: list[str] = field(default_factory=list)



def reproduce(
    inputs: Inputs,
    *,
    name: str,
    out: Path,
    db: Path | None,
    seed: int | None = None,
    render: bool = True,
    force: bool = False,
    quiet: bool = False,
    command: str | None = None,
    warn: Callable[[str], None] | None = None,
    overrides: SceneOverrides | None = None,
    demo_params: bool = True,
) -> Outcome:
    """Run every stage on checked ``inputs`` and write the report into ``out`` (see the module
    docstring). ``db``: the run store (None: do not record); ``overrides``: the command line's
    --place/--fill/--layout over the scene's initial state; ``demo_params``: steps carry the skill
    parameters of the demonstrated motion (``--no-demo-params``: the paper's plain steps)."""
    from oacdsl import __version__

    progress = Progress(list(STAGES), quiet=quiet)
    warnings: list[str] = []

    def note_warning(text: str) -> None:
        warnings.append(text)
        if warn is not None:
            warn(text)

    for text in inputs.warnings:  # learned files left out of the library (they no longer compile)
        note_warning(text)
    from oacdsl.atomic import remove_stale_temporaries
    from oacdsl.matching.emit import LEARNED
    from oacdsl.pipeline.publish import clean_stale, make_staging, publish

    library_root = inputs.library_path if inputs.library_path.is_dir() else inputs.library_path.parent
    remove_stale_temporaries(library_root / LEARNED)  # what killed runs left behind
    clean_stale(out)
    try:
        staging = make_staging(out)
    except OSError as error:
        why = error.strerror or str(error)
        raise InputError(f"cannot write the report here: {why}", location=str(out)) from None
    try:
        figures = staging / "figures"
        figures.mkdir()
        record = ResultRecord(
            created_utc=datetime.now(timezone.utc).replace(microsecond=0).isoformat(),
            oacdsl_version=__version__,
            demonstration={
                "recording": inputs.source,
                "scene": inputs.scene.name,
                "library": [str(p) for p in inputs.library_paths or (inputs.library_path,)],
                "seed": seed,
                "command": command,
                **({"scene_overrides": overrides.to_json()} if overrides and overrides.to_json() else {}),
            },
        )
        late: list[Callable[[], None]] = []  # the report's pictures of earlier stages
        failure = run_stages(
            inputs,
            record,
            progress,
            staging,
            name=name,
            seed=seed,
            render=render,
            force=force,
            db=db,
            warn=note_warning,
            overrides=overrides,
            demo_params=demo_params,
            late=late,
        )
        with progress.stage("report"):
            from oacdsl.report import write_report

            for draw in late:
                draw()
            verdict = _verdict(record, failure, name)
            result = record.to_json(verdict, progress.records(), warnings)

            report = write_report(result, staging, source="result")
            for w in report.warnings:
                note_warning(w)
            try:
                files = publish(staging, out)
            except OSError as error:
                raise InputError(
                    f"cannot move the report into place: {error.strerror or error}", location=str(out)
                ) from None
        code = 0 if result["verdict"]["success"] else max(failure[1].exit_code if failure else 1, 1)
        return Outcome(code, result, files, warnings)
    finally:
        shutil.rmtree(staging, ignore_errors=True)

