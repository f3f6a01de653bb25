"""The relations check of ``oacc verify`` (docs/verify.md), on top of :mod:`oacdsl.verify`:
its check record, and where a simulated run's AAS and its contacts disagree (findings). The
execution's frames aligned with each demonstrated sub-action: :mod:`oacdsl.verify_spans`."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from oacdsl.segmentation.result import Segmentation
from oacdsl.verify import Verification, verify

__all__ = ["Check", "disagreements", "relations_check"]


@dataclass(frozen=True)
class Check:
    """One judged item: ``kind`` is relations, end_state or motion."""

    name: str
    kind: str
    passed: bool
    demonstration: str
    execution: str
    tolerance: str
    detail: str = ""

    def to_json(self) -> dict[str, Any]:
        return {"name": self.name, "kind": self.kind, "passed": self.passed,
                "demonstration": self.demonstration, "execution": self.execution,
                "tolerance": self.tolerance, "detail": self.detail}


def relations_check(v: Verification, source: str) -> Check:
    """The ``relations`` check of a comparison."""
    c = v.counts()
    detail = ""
    if not v.verified:
        parts = [v.verdict()]
        for s in v.alignment:
            if s.op == "missing" and s.demonstration is not None:
                parts.append(f"missing {v.demonstration[s.demonstration].label()}")
            elif s.op == "extra" and s.robot is not None:
                parts.append(f"extra {v.robot[s.robot].label()}")
            elif s.op == "substitute" and s.robot is not None and s.demonstration is not None:
                made, wanted = v.robot[s.robot].label(), v.demonstration[s.demonstration].label()
                parts.append(f"{made} instead of {wanted}")
        detail = "; ".join(parts)
    split = f" ({c['split']} split)" if c["split"] else ""
    return Check("relations", "relations", v.verified, f"{len(v.demonstration)} changes",
                 f"{len(v.robot)} changes{split}, from {source}", f"edit distance <= {v.tolerance}",
                 detail)


def disagreements(aas: Segmentation, sim: Segmentation, instances: list[str]) -> list[str]:
    """Where the AAS of the markers and the simulation's contacts see different changes."""
    a, s = aas.keyframes, sim.keyframes
    v = verify([k.state for k in s], [k.state for k in a], demonstration_times_s=[k.time_s for k in s],
               robot_times_s=[k.time_s for k in a], instances=instances)
    out = []
    if v.initial[0] != v.initial[1]:
        out.append("the AAS of the virtual markers starts from another world state than the contacts")
    for st in v.alignment:
        if st.op == "missing" and st.demonstration is not None:
            ch = v.demonstration[st.demonstration]
            out.append(f"the AAS misses {ch.label()} (contacts, {ch.time_s or 0:.1f} s)")
        elif st.op == "extra" and st.robot is not None:
            ch = v.robot[st.robot]
            out.append(f"the AAS sees {ch.label()} that the contacts do not ({ch.time_s or 0:.1f} s)")
        elif st.op == "substitute" and st.robot is not None and st.demonstration is not None:
            ch, cs = v.robot[st.robot], v.demonstration[st.demonstration]
            out.append(f"the AAS sees {ch.label()} where the contacts have {cs.label()}"
                       f" ({cs.time_s or 0:.1f} s)")
    return out
