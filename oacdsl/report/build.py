"""Helpers that turn the pipeline's objects into parts of the result dict (docs/report.md)."""

from __future__ import annotations

import os
from collections.abc import Mapping
from typing import Any

from oacdsl.model import Oac
from oacdsl.world import NOTHING

__all__ = ["bound_conditions", "reliability_doc"]


def _pair(a: str, b: str) -> list[str]:
    if b == NOTHING or a == NOTHING:
        return [a if b == NOTHING else b, NOTHING]
    return sorted([a, b])


def bound_conditions(oac: Oac, binding: Mapping[str, str]) -> dict[str, list[list[str]]]:
    """An OAC's preconditions and effects with its variables replaced by the bound instances.

    Returns ``{"pre", "pre_not", "effect", "effect_not"}`` lists of relations (pairs sorted,
    ``[x, "nothing"]`` for statements about one instance): the fields a match entry of the
    result may carry so that the report shows the constraints, as the paper's Fig. 4 does.
    A name that is not a variable of the OAC (an instance written directly) stays as it is.
    """
    out: dict[str, list[list[str]]] = {"pre": [], "pre_not": [], "effect": [], "effect_not": []}
    for part, atoms in (("pre", oac.pre), ("effect", oac.effect)):
        for atom in atoms:
            a, b = binding.get(atom.left, atom.left), binding.get(atom.right, atom.right)
            out[f"{part}_not" if atom.negated else part].append(_pair(a, b))
    for key in out:
        out[key].sort()
    return out


def reliability_doc(db: str | os.PathLike[str]) -> dict[str, Any] | None:
    """The result's ``reliability`` part read from the run store at ``db`` (None when it has no file)."""
    from oacdsl.stats import RunStore, summarise

    if not RunStore.exists(db) or os.path.getsize(db) == 0:
        return None
    with RunStore(db, create=False) as store:
        rows = store.rows()
    return {"db": str(db), "oacs": [r.to_json() for r in summarise(rows)]}
