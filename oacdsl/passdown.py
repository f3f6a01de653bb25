"""Skill parameters written on a step that calls a **composed** OAC go down to the one step
inside it whose skill takes them (docs/language.md, "Skill parameters of a step").

``roll_out(h1, p, h2, d) { strokes 4 }``, where ``roll_out`` calls ``roll_pin`` (``execute
roll``) and ``put_down_with_both`` (``execute place_both``): ``strokes`` goes to ``roll_pin``,
the only step inside whose skill takes a parameter of that name, and overrides what that
step, or its OAC's ``execute … { }``, writes (the caller decides, as a step's parameter does
over its OAC's). A name no step inside takes, or that more than one takes, is an error
(E047): write it on the step inside that should take it.

Light (no runtime import): the compiler, the runtime's binding and the composer share it.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

from oacdsl.model import Oac
from oacdsl.skills import SIGNATURES

__all__ = ["Inner", "inner_steps", "receivers"]

_MAX_DEPTH = 16


@dataclass(frozen=True)
class Inner:
    """A primitive step inside a composed OAC: its OAC, its position among the composed OAC's
    primitive steps (the runtime's order: depth first, as written) and the names of the skill
    parameters written on the calls that lead to it (inside the composed OAC)."""

    oac: Oac
    index: int
    written: frozenset[str]

    def takes(self, name: str) -> bool:
        """Whether this step's skill has a parameter ``name``."""
        sig = SIGNATURES.get(self.oac.skill or "")
        return sig is not None and any(p.name == name for p in sig.params)


def inner_steps(oacs: Mapping[str, Oac], oac: Oac) -> list[Inner]:
    """The primitive steps of composed ``oac`` in the order they run (an unknown OAC or a
    cycle ends the walk there: the compiler reports those, E013 and E019)."""
    out: list[Inner] = []

    def walk(current: Oac, written: frozenset[str], seen: frozenset[str]) -> None:
        if len(seen) > _MAX_DEPTH:
            return
        for call in current.steps or ():
            callee = oacs.get(call.oac)
            if callee is None or callee.name in seen:
                continue
            names = written | {p.name for p in call.skill_params}
            if callee.composed:
                walk(callee, names, seen | {callee.name})
            else:
                out.append(Inner(callee, len(out), names))

    walk(oac, frozenset(), frozenset({oac.name}))
    return out


def receivers(oacs: Mapping[str, Oac], oac: Oac, name: str) -> list[Inner]:
    """The primitive steps inside composed ``oac`` whose skill takes a parameter ``name``."""
    return [s for s in inner_steps(oacs, oac) if s.takes(name)]
