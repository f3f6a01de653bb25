"""What a worker does with one recording: read, segment, match (and compose), as one row.

:func:`analyse` runs in a Dask worker process (or in the client, for the in-process
baseline); it never raises for a bad recording: every :class:`~oacdsl.errors.OacError`, and
any other exception, becomes an error row naming the stage and the one-line message, so one
broken file never ends a job. The job's client parses the library once and ships it with the
:class:`JobSpec` (pickled, a few kB); a spec without it loads the library from its paths once
per worker process and keeps it (:func:`_library`), keyed by its paths and their modification
times. :func:`analyse_batch` is one task of several recordings: a task per recording costs a
scheduler round trip each, more than reading a small recording.
"""

from __future__ import annotations

import os
import socket
import time
from collections.abc import Sequence
from pathlib import Path
from typing import Any

__all__ = ["PRELOAD", "JobSpec", "analyse", "analyse_batch"]

#: Modules a task imports: imported before the embedded cluster's workers are forked.
PRELOAD = (
    "oacdsl.pipeline.analyse",
    "oacdsl.pipeline.inputs",
    "oacdsl.segmentation.grouping",
    "oacdsl.segmentation.readers",
    "oacdsl.matching.drafts",
    "oacdsl.matching.demonstration",
    "oacdsl.matching.emit",
)

_LIBRARIES: dict[tuple[Any, ...], Any] = {}


class JobSpec:
    """What every task of a job shares (picklable): the library's paths, the scene's name (None:
    found per recording), the AAS parameters as a dict, whether to compose, and the library as
    the client parsed it (None: each worker loads it from the paths)."""

    def __init__(self, library: Sequence[str], scene: str | None, params: dict[str, Any], compose: bool,
                 parsed: Any = None):
        self.library = tuple(str(p) for p in library)
        self.scene = scene
        self.params = dict(params)
        self.compose = compose
        self.parsed = parsed


def _stamp(paths: Sequence[str]) -> tuple[Any, ...]:
    out: list[Any] = []
    for p in paths:
        path = Path(p)
        files = [path] if path.is_file() else sorted(path.rglob("*.oac"))
        out += [(str(f), f.stat().st_mtime_ns) for f in files]
    return tuple(out)


def _library(paths: Sequence[str]) -> Any:
    from oacdsl.pipeline.inputs import open_library

    key = (tuple(paths), _stamp(paths))
    if key not in _LIBRARIES:
        _LIBRARIES.clear()
        _LIBRARIES[key] = open_library([Path(p) for p in paths])
    return _LIBRARIES[key]


def _most_specific(classes: frozenset[str], library: Any) -> str:
    if not classes:
        return "?"
    return sorted(classes, key=lambda c: (-len(library.ancestors(c)), c))[0]


def _change(added: Any, removed: Any, name: Any) -> str:
    parts = [f"+ {' <-> '.join(sorted((name(a), name(b))))}" for a, b in sorted(added)]
    parts += [f"- {' <-> '.join(sorted((name(a), name(b))))}" for a, b in sorted(removed)]
    return ", ".join(parts) or "no change"


def _sub_rows(matches: Sequence[Any], library: Any, scene: Any) -> list[dict[str, Any]]:
    from oacdsl.compiler import print_module
    from oacdsl.matching.drafts import propose_draft
    from oacdsl.model import Module
    from oacdsl.world import NOTHING

    classes = library.instance_classes(scene)
    specific = {i: _most_specific(c, library) for i, c in classes.items()}
    specific[NOTHING] = NOTHING
    rows = []
    for m in matches:
        r = m.result
        chosen = r.chosen
        row: dict[str, Any] = {
            "index": m.index,
            "from_frame": int(m.sub_action.start.frame),
            "to_frame": int(m.sub_action.end.frame),
            "change": _change(r.added, r.removed, str),
            "class_change": _change(r.added, r.removed, lambda x: specific.get(x, x)),
            "oac": chosen.oac.name if chosen is not None else (m.text() if m.split is not None else None),
            "binding": dict(chosen.mapping) if chosen is not None else None,
            "draft": None,
        }
        if chosen is None and m.split is None:
            draft, _ = propose_draft(f"unexplained_{m.index}", r.before, r.after, classes, library.ancestors)
            row["draft"] = print_module(Module(path="draft.oac", decls=(draft,)))
        rows.append(row)
    return rows


def _read(path: str, library: Any, scene_name: str | None) -> tuple[Any, Any, Any]:
    """The grouped recording, the library (with an outside scene file added) and its scene, checked
    as ``oacc match`` checks them (:func:`oacdsl.pipeline.inputs.load_inputs`)."""
    from oacdsl.errors import InputError
    from oacdsl.pipeline.inputs import resolve_scene
    from oacdsl.pipeline.library_scene import check_tracked
    from oacdsl.segmentation.grouping import apply_scene_groups, group_recording
    from oacdsl.segmentation.readers import read_recording

    if not Path(path).exists():
        raise InputError("no such recording file", location=path)
    rec, _ = group_recording(read_recording(path), None)
    library, scene, _ = resolve_scene(library, tuple(rec.instances), scene_name)
    if any(i.markers or i.ignored for i in scene.instances):
        rec = apply_scene_groups(rec, scene)
    check_tracked(tuple(rec.instances), scene, path, "marker groups")
    if not rec.instances:
        raise InputError("the recording has no marker groups to segment", location=path)
    return rec, library, scene


def analyse(path: str, rec_id: str, spec: JobSpec) -> dict[str, Any]:
    """The row of one recording (module doc); ``times_s`` per stage, seconds (wall). For
    benchmarks, not stored in the table: ``cpu_s``, the process's CPU seconds meanwhile (all its
    threads: the task's and the worker's own), and ``stage_cpu_s``, the task's thread's CPU
    seconds per stage."""
    from oacdsl.errors import OacError

    row: dict[str, Any] = {
        "id": rec_id,
        "path": path,
        "status": "ok",
        "error": None,
        "stage": None,
        "worker": f"{socket.gethostname()}:{os.getpid()}",
        "times_s": {},
        "subs": [],
    }
    stage = "read"
    clock, thread_clock = time.perf_counter(), time.thread_time()
    cpu0 = time.process_time()
    row["stage_cpu_s"] = {}

    def lap(name: str) -> None:
        nonlocal clock, thread_clock
        now, thread_now = time.perf_counter(), time.thread_time()
        row["times_s"][name] = now - clock
        row["stage_cpu_s"][name] = thread_now - thread_clock
        clock, thread_clock = now, thread_now

    try:
        from oacdsl.pipeline.analyse import match_stage, segment_stage
        from oacdsl.pipeline.inputs import Inputs, default_name
        from oacdsl.segmentation.params import AasParams

        library = spec.parsed if spec.parsed is not None else _library(spec.library)
        rec, library, scene = _read(path, library, spec.scene)
        params = AasParams(**spec.params)
        # the inputs as oacc match and compose hold them: the same shapes (--contacts geometry),
        # the unmerged segmentation (split keyframes) and the hands' travel (a tie of two hands)
        inputs = Inputs(library, Path(path), scene, path, params, recording=rec)
        name = default_name(path) if spec.compose else None  # never a step of its own composition
        row.update(
            rate_hz=rec.rate_hz, frames=rec.n_frames, duration_s=float(rec.times_s[-1]), scene=scene.name
        )
        lap("read")
        stage = "segment"
        seg = segment_stage(rec, params, inputs.shapes()).segmentation
        row["keyframes"] = len(seg.keyframes)
        lap("segment")
        stage = "match"
        matched = match_stage(seg, library, scene, name, inputs.unmerged(), inputs.travel()).matches
        row["subs"] = _sub_rows(matched, library, scene)
        lap("match")
        if name is not None and all(m.matched for m in matched):
            stage = "compose"
            from oacdsl.matching.composedparams import with_demo_params
            from oacdsl.matching.demonstration import compose_demonstration
            from oacdsl.matching.demoparams import demonstrated_motions
            from oacdsl.matching.emit import render

            comp = compose_demonstration(name, matched, library, scene).composition
            motions = demonstrated_motions(rec, [m.sub_action for m in matched])
            comp = with_demo_params(comp, motions, library, scene)  # as oacc compose's steps carry them
            row["composed"] = render([comp.oac], f"{name}.oac")
            lap("compose")
    except OacError as error:
        row.update(status="error", stage=stage, error=str(error).splitlines()[0][:500])
    except Exception as error:  # a bug, or a reader's unforeseen failure: a row, not the job's end
        row.update(
            status="error", stage=stage, error=f"internal error: {type(error).__name__}: {error}"[:500]
        )
    row["cpu_s"] = time.process_time() - cpu0
    return row


def analyse_batch(items: Sequence[tuple[str, str]], spec: JobSpec) -> list[dict[str, Any]]:
    """The rows of several recordings, ``(path, id)`` each, in order (one task)."""
    return [analyse(path, rec_id, spec) for path, rec_id in items]
