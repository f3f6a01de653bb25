"""E051: the steps of a ``together { … }`` block must not depend on each other.

Steps in one block may run together, in any order, so none may change what another needs
or changes (:mod:`oacdsl.together`, the rule the composer groups steps by): ``grasp(h, c)``
and ``pour(h, c, l, b)`` cannot share a block, since the pour needs ``h <-> c``, which the
grasp makes.
"""

from __future__ import annotations

from oacdsl.compiler.context import Context
from oacdsl.compiler.diagnostics import Note
from oacdsl.model import Call, Oac, step_groups
from oacdsl.together import StepConds, bound, conflict, text

__all__ = ["check_together"]


def _call(call: Call) -> str:
    return f"{call.oac}({', '.join(call.args)})"


def check_together(ctx: Context) -> None:
    oacs = ctx.library.oacs
    for module in ctx.modules:
        for oac in (d for d in module.decls if isinstance(d, Oac)):
            for group in step_groups(oac.steps or ()):
                conds: list[tuple[Call, StepConds]] = []
                for call in group:
                    callee = oacs.get(call.oac)
                    if callee is None or len(callee.params) != len(call.args):
                        continue  # E013, E014
                    binding = {p.name: a for p, a in zip(callee.params, call.args, strict=True)}
                    conds.append((call, (bound(callee.pre, binding), bound(callee.effect, binding))))
                _check_group(ctx, conds)


def _check_group(ctx: Context, conds: list[tuple[Call, StepConds]]) -> None:
    for j, (call, step) in enumerate(conds):
        for earlier, other in conds[:j]:
            found = conflict(other, step)
            if found is None:
                continue
            effect, condition = found
            ctx.add(
                "E051",
                f"steps '{_call(earlier)}' and '{_call(call)}' of one together block depend on each"
                f" other: the effect '{text(effect)}' of one concerns '{text(condition)}' of the"
                " other; write them one after the other, outside the block",
                call.span,
                Note(f"'{_call(earlier)}' is here", earlier.span),
            )
            break
