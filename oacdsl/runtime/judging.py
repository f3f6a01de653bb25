"""What a step leaves judged: the relations it must (its preconditions before it, its predicted
effects after it, a composed step's effects where its last step ends) against those the
simulation reports, and the pairs a result lists. The executor and the adaptive executor
(:mod:`oacdsl.runtime.adaptive`) judge alike; no simulator needed."""

from __future__ import annotations

from oacdsl.runtime.binding import Call, bound_atoms, explain, holds
from oacdsl.runtime.results import CallResult
from oacdsl.world import NOTHING, WorldState

__all__ = ["check", "judge_call", "observed_pairs", "pair"]


def pair(a: str, b: str) -> list[str]:
    """A relation as a result lists it: sorted, ``nothing`` second."""
    if NOTHING in (a, b):
        return [b if a == NOTHING else a, NOTHING]
    return sorted([a, b])


def observed_pairs(state: WorldState, mentioned: set[str]) -> list[list[str]]:
    """The relations of ``state``, and ``[x, nothing]`` for each ``mentioned`` instance that
    touches nothing."""
    pairs = [list(r) for r in state.sorted_relations()]
    pairs += [[x, NOTHING] for x in sorted(mentioned) if state.touches_nothing(x)]
    return pairs


def check(state: WorldState, atoms: list[tuple[str, str, bool]], what: str) -> str | None:
    """``what: …`` with every atom that does not hold in ``state`` explained; None when all hold."""
    failed = [explain(state, a, b, n) for a, b, n in atoms if not holds(state, a, b, n)]
    return f"{what}: {'; '.join(failed)}" if failed else None


def judge_call(call: Call, state: WorldState) -> CallResult:
    """A composed step judged by its own predicted effects in ``state``."""
    effects = bound_atoms(call.oac.effect, call.binding)
    error = check(state, effects, f"{call.oac.name}: predicted effect not observed")
    return CallResult(
        call.oac.name,
        dict(call.binding),
        call.first + 1,
        call.last + 1,
        error is None,
        sorted(pair(a, b) for a, b, n in effects if not n),
        observed_pairs(state, set(call.binding.values())),
        error,
    )
