"""The verdict of ``reproduce`` (:func:`verdict`): success or the failed stage, and the one
paragraph the report and ``result.json`` print; :func:`untracked_judged`: how the step effects
judged each untracked instance (see :mod:`oacdsl.pipeline.run`)."""

from __future__ import annotations

from typing import Any

from oacdsl.errors import OacError
from oacdsl.pipeline.result import ResultRecord

__all__ = ["untracked_judged", "verdict"]


def verdict(result: ResultRecord, failure: tuple[str, OacError] | None, name: str) -> dict[str, Any]:
    if failure is not None:
        stage, error = failure
        return {"success": False, "summary": f"The {stage} stage failed: {error}", "failed_stage": stage}
    run, v = result.run, result.verification
    if run is not None and not run.success:
        held = "the composed OAC's effects hold, but " if run.effects_hold else ""
        return {
            "success": False,
            "failed_stage": "execute",
            "summary": f"The robot did not complete {name}: {held}{run.error or 'a step failed'}.",
        }
    extra = (v.model_extra or {}) if v is not None else {}
    flags = {"verified": bool(v.verified), "faithful": bool(extra.get("faithful", v.verified))} \
        if v is not None else {}
    failed = [c for c in extra.get("checks", []) if not c["passed"]]
    spilt = _untracked_failed(extra.get("untracked", []))
    if v is not None and v.verified and spilt:
        # the recording cannot show an untracked liquid: the step that last moved it judged it
        # by the simulation (the balls that ended in the target), and it failed
        return {
            "success": False,
            "failed_stage": "verify",
            "verified": False,
            "faithful": False,
            "failed_checks": [c["name"] for c in failed] + [f"untracked.{u['instance']}" for u, _ in spilt],
            "summary": f"The robot executed {name}, but the outcome differs from the demonstration: "
            + "; ".join(f"the untracked {u['instance']}: step {j['step']} {j['oac']} failed"
                        f" ({j.get('error') or 'its effects were not observed'})" for u, j in spilt) + ".",
        }
    if v is not None and not v.verified:
        named = "; ".join(f"{c['name']}: {c['detail']}" for c in failed if c["kind"] != "motion")
        # a motion check decides faithful, not verified; the verifier's verdict counts it, so name it too
        motion = "; ".join(f"{c['name']}: {c['detail']}" for c in failed if c["kind"] == "motion")
        return {
            "success": False,
            "failed_stage": "verify",
            **flags,
            "failed_checks": [c["name"] for c in failed] + [f"untracked.{u['instance']}" for u, _ in spilt],
            "summary": f"The robot executed {name}, but the outcome differs from the demonstration:"
            f" {v.verdict}." + (f" Failed: {named}." if named else "")
            + (f" Not faithful either: {motion}." if motion else "") + _during(run, v) + _repaired(run),
        }
    m = run.metrics if run is not None else {}
    balls = f", {m['balls_in_bowl']} of {m['balls_total']} balls in the bowl" if m.get("balls_total") else ""
    liquid = ""
    for u in (v.model_extra or {}).get("untracked", []) if v is not None else []:
        judged = "; ".join(
            f"step {j['step']} {j['oac']} observed " + ", ".join(" <-> ".join(p) for p in j["relations"])
            for j in u["judged_by"]
        )
        liquid += (f" The untracked {u['instance']} is not in the recording, so not compared: the robot's"
                   f" step effects judged it ({judged or 'no step predicts it'}).")
    n = len(v.demonstration) if v is not None else 0
    source = "its simulated contacts" if extra.get("relations_source") == "simulation contacts" else \
        "its own recording, segmented by the same AAS,"
    unfaithful = ""
    if flags and not flags["faithful"]:
        unfaithful = " Not faithful: " + "; ".join(f"{c['name']}: {c['detail']}" for c in failed) + "."
    ends = " every tracked object ends as demonstrated;" if "checks" in extra else ""
    return {
        "success": True,
        **flags,
        "failed_checks": [c["name"] for c in failed],
        "summary": f"ARMAR-III executed {name} ({len(run.steps) if run else 0} steps{balls}), and"
        f" {source} shows the demonstration's {n} world-state changes in order (edit distance"
        f" {v.distance if v else '–'});{ends} {'faithful' if flags.get('faithful') else 'verified'}."
        f"{unfaithful}{liquid}",
    }


def _repaired(run: Any) -> str:
    """The steps that failed in a run that completed by repairs: often why the outcome differs
    (a lid the twist could not turn, put down and taken again)."""
    failed = [(i, s) for i, s in enumerate(run.steps if run is not None else [], 1) if not s.success]
    if not failed:
        return ""
    why = [f"step {i} {s.oac}({', '.join(s.binding.values())}) failed"
           f" ({s.error or 'its effects were not observed'})" for i, s in failed]
    return " The run completed only by repairs after " + "; ".join(why) + "."


def _during(run: Any, v: Any) -> str:
    """In which executed step each extra change of the robot's happened: its time in the robot's
    recording within the steps' consecutive durations (the recording starts with step 1). A
    change the alignment calls extra is what a step did besides its effects (a hand brushing an
    object on its way): that step is what to change, and the relations check names only the
    change."""
    extra = [v.robot[a.robot] for a in getattr(v, "alignment", None) or []
             if a.op == "extra" and a.robot is not None and v.robot[a.robot].time_s is not None]
    steps = list(run.steps) if run is not None and extra else []
    ends, t = [], 0.0
    for s in steps:
        t += float(s.duration_s)
        ends.append(t)
    notes: list[str] = []
    for change in extra:
        i = next((k for k, end in enumerate(ends) if change.time_s <= end + 1e-9), None)
        if i is None:
            continue
        rel = ", ".join([f"+ {' <-> '.join(p)}" for p in change.added]
                        + [f"− {' <-> '.join(p)}" for p in change.removed])
        step = f"{steps[i].oac}({', '.join(steps[i].binding.values())})"
        notes.append(f"{rel} at {change.time_s:.1f} s, in step {i + 1} {step}")
    return f" The extra changes happened: {'; '.join(notes)}." if notes else ""


def _untracked_failed(untracked: list[dict[str, Any]]) -> list[tuple[dict[str, Any], dict[str, Any]]]:
    """(instance, the step that judged it last) for each untracked instance whose last judging
    step failed (a pour that left too few balls in the target, a repair then went on)."""
    return [(u, u["judged_by"][-1]) for u in untracked
            if u["judged_by"] and not u["judged_by"][-1]["success"]]


def untracked_judged(scene: Any, run_doc: dict[str, Any]) -> list[dict[str, Any]]:
    """How each untracked instance (a liquid the recording does not track) was judged: the
    executed steps whose predicted effects name it (their effect judge observed them in the
    simulation; a step that failed carries its error: when it is the last, the verdict is not
    verified). The closed loop leaves these instances out."""
    out = []
    for inst in scene.untracked():
        judged = [
            {"step": k, "oac": s["oac"], "relations": [p for p in s["predicted"] if inst.name in p],
             "success": s["success"], **({} if s["success"] else {"error": s.get("error")})}
            for k, s in enumerate(run_doc.get("steps", []), 1)
            if any(inst.name in p for p in s["predicted"])
        ]
        out.append({"instance": inst.name, "judged_by": judged})
    return out
