"""An OAC's success measure over many seeds and sampled placements, on Dask (``oacc run --seeds``).

Each run is one task (:func:`run_one`): the client loads the library once and ships it with the
spec (each worker would otherwise parse it once more), a worker executes the OAC with
the run's seed and placements, and returns the ``oacc run --json`` document with ``seed``,
``sample`` and ``places`` added. Sample 0 of a seed is the seed's own layout (as ``oacc run
--seed``); sample k > 0 puts every object where the layout of a seed drawn from ``(seed, k)``
puts it (:func:`sampled_places`), so a run is reproduced by ``oacc run --seed S --place …``. The
client alone writes the outcomes into the run store (one writer), in the order they arrive.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import IO, Any

import numpy as np

__all__ = ["PRELOAD", "RunSpec", "run_many", "run_one", "sampled_places"]

#: Modules a run imports: imported before the embedded cluster's workers are forked.
PRELOAD = ("oacdsl.runtime.executor", "oacdsl.runtime.binding", "oacdsl.runtime.layout")

_LIBRARIES: dict[tuple[str, ...], Any] = {}


class RunSpec:
    """What every run of a job shares (picklable): library paths, the OAC, bindings, scene, fills;
    ``parsed``: the library as the client loaded it (None: each worker loads it once)."""

    def __init__(
        self,
        library: Sequence[str],
        name: str,
        binding: Mapping[str, str],
        scene: str | None,
        fill: Mapping[str, str] | None = None,
        places: Mapping[str, tuple[float, float]] | None = None,
    ):
        self.library, self.name, self.binding = tuple(library), name, dict(binding)
        self.scene, self.fill, self.places = scene, dict(fill or {}), dict(places or {})
        self.parsed: Any = None


def _library(paths: Sequence[str], parsed: Any = None) -> Any:
    from oacdsl.compiler import load_library

    if parsed is not None:
        return parsed
    key = tuple(paths)
    if key not in _LIBRARIES:
        _LIBRARIES[key] = load_library([Path(p) for p in paths])
    return _LIBRARIES[key]


def sampled_places(spec: RunSpec, seed: int, sample: int) -> dict[str, tuple[float, float]]:
    """Placements of sample ``sample`` > 0 of ``seed`` (module doc); empty for sample 0."""
    if sample == 0:
        return {}
    from oacdsl.runtime.binding import choose_scene, liquid_contents
    from oacdsl.runtime.layout import plan_layout

    library = _library(spec.library, spec.parsed)
    oac = library.oacs[spec.name]
    scene = choose_scene(library, oac, spec.scene, spec.binding)
    drawn = int(np.random.SeedSequence([seed, sample]).generate_state(1)[0])
    layout = plan_layout(
        library,
        scene,
        liquid_contents(library, scene, oac, spec.binding) | spec.fill,
        seed=drawn,
        places=spec.places,
    )
    return {p.name: (round(p.x, 4), round(p.y, 4)) for p in layout.placements if p.on is None}


def run_one(spec: RunSpec, seed: int, sample: int) -> dict[str, Any]:
    """One run's ``oacc run --json`` document (module doc); a run that cannot start is a failed
    document with its one-line ``error``, never an exception."""
    from oacdsl.errors import OacError

    try:
        from oacdsl.runtime.executor import execute

        places = {**spec.places, **sampled_places(spec, seed, sample)}
        result = execute(
            _library(spec.library, spec.parsed),
            spec.name,
            spec.binding,
            spec.scene,
            seed,
            fill=spec.fill or None,
            places=places or None,
        )
        doc = result.to_json()
    except OacError as error:
        places, doc = {}, {"oac": spec.name, "success": False, "error": str(error), "steps": []}
    doc.update(seed=seed, sample=sample, places={k: list(v) for k, v in places.items()})
    return doc


def run_many(
    spec: RunSpec,
    seeds: Sequence[int],
    samples: int,
    *,
    workers: int | None = None,
    scheduler: str | None = None,
    worker_wait_s: float | None = None,
    on_result: Callable[[dict[str, Any]], None] | None = None,
    progress: IO[str] | None = None,
) -> list[dict[str, Any]]:
    """Every (seed, sample) run on the cluster; ``on_result`` hears each document as it arrives
    (the caller records it); the documents sorted by seed and sample. With ``scheduler``, its first
    worker is awaited at most ``worker_wait_s`` seconds (default
    :data:`~oacdsl.mining.cluster.WORKER_WAIT_S`)."""
    from dask.distributed import as_completed

    from oacdsl.mining.cluster import WORKER_WAIT_S, client_for, close, share
    from oacdsl.mining.engine import Ticker

    jobs = [(s, k) for s in seeds for k in range(samples)]
    ticker = Ticker(len(jobs), progress, "ran", "runs")
    wait_s = WORKER_WAIT_S if worker_wait_s is None else worker_wait_s
    client, cluster = client_for(workers, scheduler, False, PRELOAD, worker_wait_s=wait_s, progress=progress)
    out = []
    try:
        if spec.parsed is None:  # parsed here while the workers start, not once in each of them
            from copy import copy

            spec = copy(spec)
            spec.parsed = _library(spec.library)
        shared = share(client, spec, "run-spec")
        futures = {client.submit(run_one, shared, s, k, pure=False): (s, k) for s, k in jobs}
        for future in as_completed(futures):
            s, k = futures[future]
            try:
                doc = future.result()
            except Exception as error:  # the worker died
                doc = {
                    "oac": spec.name,
                    "success": False,
                    "steps": [],
                    "seed": s,
                    "sample": k,
                    "error": f"the run failed on its worker: {type(error).__name__}: {error}",
                }
            if on_result is not None:
                on_result(doc)
            out.append(doc)
            ticker.tick(not doc.get("success"))
    finally:
        close(client, cluster)
    return sorted(out, key=lambda d: (d["seed"], d["sample"]))
