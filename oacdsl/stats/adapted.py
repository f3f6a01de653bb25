"""What an adaptive run changed, as rows of the run store's ``adaptations`` table (issue 22).

The run's JSON holds each adaptation as ``{"kind", "step", "text", "plan"}``
(:mod:`oacdsl.runtime.adaptive`); the store keeps them in order, the plan as a JSON list of
step labels, so that ``oacc stats`` can show them next to the outcomes.
"""

from __future__ import annotations

import json
from collections.abc import Callable, Mapping, Sequence
from typing import Any

__all__ = ["decoded", "rows_of"]


def rows_of(run_id: str, adaptations: Sequence[Mapping[str, Any]]) -> list[tuple[Any, ...]]:
    """``(run_id, position, kind, step, text, plan)`` per adaptation."""
    rows = []
    for position, a in enumerate(adaptations):
        plan, step = a.get("plan"), a.get("step")
        rows.append((
            run_id,
            position,
            str(a.get("kind", "")),
            step if isinstance(step, int) else None,
            str(a.get("text", "")),
            json.dumps([str(p) for p in plan]) if isinstance(plan, list | tuple) and plan else None,
        ))
    return rows


def decoded(
    description: Any, rows: Sequence[Sequence[Any]], fail: Callable[[str], Exception]
) -> list[dict[str, Any]]:
    """Rows read back as dicts, ``plan`` a list of labels or None (``fail(message)`` gives the
    error to raise for a plan that is not one)."""
    names = [d[0] for d in description]
    out = []
    for values in rows:
        row = dict(zip(names, values, strict=True))
        try:
            plan = json.loads(row["plan"]) if row["plan"] is not None else None
        except (TypeError, ValueError, RecursionError):
            plan = "?"
        if plan is not None and not (isinstance(plan, list) and all(isinstance(p, str) for p in plan)):
            where = f"run {row['run_id']} adaptation {row['position']}"
            raise fail(f"damaged run database: {where}: its plan is not a JSON list of steps")
        row["plan"] = plan
        out.append(row)
    return out
