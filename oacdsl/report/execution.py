"""Report sections about the robot: execution, closed-loop verification, OAC reliability."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from oacdsl.report.html import Images, badge, call, esc, holds, rel, rel_list, safe_link, seconds
from oacdsl.report.overview import not_run
from oacdsl.report.schema import ChangeDoc, Result, RunStepDoc
from oacdsl.world import NOTHING

__all__ = ["compare_step", "execution_section", "reliability_section", "verification_section"]

Pair = tuple[str, str]


def _key(p: Sequence[str]) -> Pair:
    return (p[0], p[1]) if p[0] <= p[1] else (p[1], p[0])


def compare_step(step: RunStepDoc, previous: Sequence[Sequence[str]] | None) -> list[tuple[Pair, str, str]]:
    """Predicted vs observed relations of one step: (relation, status, note) rows.

    Status ``ok``: a prediction that came true; ``bad``: a prediction that did not; ``warn``: a change
    the OAC did not predict (needs the relations before the step, ``previous``).
    """
    rows: list[tuple[Pair, str, str]] = []
    for p in step.predicted:
        ok = holds(p, step.observed)
        rows.append(
            (
                _key(p) if NOTHING not in p else (p[0], p[1]),
                "ok" if ok else "bad",
                "predicted, observed" if ok else "predicted, not observed",
            )
        )
    for p in step.predicted_not:
        ok = not holds(p, step.observed)
        note = "predicted to end, ended" if ok else "predicted to end, still holds"
        rows.append((_key(p), "ok" if ok else "bad", note))
    if previous is not None:
        now, then = {_key(p) for p in step.observed}, {_key(p) for p in previous}
        told = {_key(p) for p in step.predicted if NOTHING not in p} | {_key(p) for p in step.predicted_not}
        for p in sorted(now - then - told):
            rows.append((p, "warn", "new, not predicted"))
        for p in sorted(then - now - told):
            rows.append((p, "warn", "ended, not predicted"))
    return rows


def _comparison(step: RunStepDoc, previous: Sequence[Sequence[str]] | None) -> str:
    rows = compare_step(step, previous)
    marks = {"ok": "✔", "bad": "✘", "warn": "!"}
    body = "".join(
        f'<tr class="{"" if st == "ok" else st}"><td>{rel(p, negated="to end" in note)}</td>'
        f'<td>{badge(marks[st], st)} <span class="small">{esc(note)}</span></td></tr>'
        for p, st, note in rows
    )
    table = f'<table class="small"><tbody>{body}</tbody></table>'
    if not rows:
        table = '<p class="muted small">no prediction</p>'
    observed = rel_list(sorted({_key(p) for p in step.observed}), empty="nothing touches")
    return table + f'<div class="rels">observed after the step: {observed}</div>'


def execution_section(r: Result, images: Images) -> str:
    out = ['<section id="execution"><h2>Execution</h2>']
    run = r.run
    if run is None:
        return "".join(out) + not_run(r, "execute", "The robot's execution") + "</section>"
    ok = sum(1 for s in run.steps if s.success)
    verdict = badge("success", "ok") if run.success else badge("failed", "bad")
    out.append(
        f'<p class="lead">ARMAR-III in MuJoCo executed <code>{esc(run.oac)}</code>: {ok} of'
        f" {len(run.steps)} steps succeeded {verdict}."
        " After every step the touching relations observed in the simulation are compared with the"
        " OAC's prediction.</p>"
    )
    if not run.success and run.effects_hold:
        why = esc(run.error or "a step failed")
        out.append(f"<p>The composed OAC's effects hold at the end, but the run failed: {why}</p>")
    m = run.metrics
    facts = []
    if "balls_in_bowl" in m and "balls_total" in m:
        facts.append(("balls in the bowl", f"{m['balls_in_bowl']} / {m['balls_total']}"))
    if isinstance(m.get("sim_time_s"), (int, float)):
        facts.append(("simulated time", seconds(float(m["sim_time_s"]))))
    if isinstance(m.get("wall_time_s"), (int, float)):
        facts.append(("wall-clock time", seconds(float(m["wall_time_s"]))))
        if isinstance(m.get("sim_time_s"), (int, float)) and m["wall_time_s"] > 0:
            facts.append(("real-time factor", f"{m['sim_time_s'] / m['wall_time_s']:.1f}×"))
    if run.grasp:
        facts.append(("grasps hold by", run.grasp))
    known = {"balls_in_bowl", "balls_total", "sim_time_s", "wall_time_s"}
    facts += [(k.replace("_", " "), str(v)) for k, v in m.items() if k not in known]
    if facts:
        out.append(_cards(facts))
    out.append(_adaptations(run.model_extra or {}))
    if run.video:
        href = safe_link(run.video)
        if href is None:  # e.g. javascript:…: shown as text, never a live link
            out.append(f"<p>Video: <code>{esc(run.video)}</code> (not linked)</p>")
        else:
            out.append(f'<p>Video: <a href="{esc(href)}">{esc(run.video)}</a></p>')
    rows = []
    previous = run.initial
    for i, s in enumerate(run.steps):
        pic = images.tag(s.frame, f"the robot after step {i + 1}", "frame", missing="no rendered frame")
        shot = "shot"
        if s.moment:  # the moment the prediction came true, and the end of the step, side by side
            shot = "shot two"
            pic = (
                '<div class="pair"><div>'
                + images.tag(s.moment, f"the robot as step {i + 1} makes its change", "frame")
                + '<div class="small muted">prediction comes true</div></div><div>'
                + pic
                + '<div class="small muted">end of the step</div></div></div>'
            )
        state = badge("ok", "ok") if s.success else badge("failed", "bad")
        err = f'<div class="err">{esc(s.error)}</div>' if s.error else ""
        rows.append(
            f'<tr class="{"" if s.success else "bad"}"><td class=num>{i + 1}</td>'
            f'<td class="{shot}">{pic}</td>'
            f'<td><div class="call mono">{call(s.oac, s.binding)}</div>{state}{err}</td>'
            f"<td>{_comparison(s, previous)}</td><td class=num>{seconds(s.duration_s)}</td></tr>"
        )
        previous = s.observed
    out.append(
        "<table><thead><tr><th class=num>#</th><th>the robot</th><th>step</th>"
        "<th>predicted vs observed</th><th class=num>time</th></tr></thead><tbody>"
        + "".join(rows)
        + "</tbody></table>"
    )
    return "".join(out) + "</section>"


def _adaptations(extra: dict[str, Any]) -> str:
    """What an adaptive run skipped and replanned (issue 22), as a list; empty without any."""
    items = []
    for entry in extra.get("adaptations") or []:
        if not isinstance(entry, dict):
            continue
        plan = entry.get("plan") or []
        then = f' <span class="mono">→ {esc(", ".join(str(p) for p in plan))}</span>' if plan else ""
        items.append(f"<li>{esc(str(entry.get('text', '')))}{then}</li>")
    if not items:
        return ""
    return "<p>Adapted to the world at execution time:</p><ul>" + "".join(items) + "</ul>"


def _cards(facts: list[tuple[str, str]]) -> str:
    cards = "".join(
        f'<div class="card"><div class="v">{esc(v)}</div><div class="k">{esc(k)}</div></div>'
        for k, v in facts
    )
    return f'<div class="cards">{cards}</div>'


def _change(c: ChangeDoc | None) -> str:
    if c is None:
        return '<span class="muted">—</span>'
    items = [f'<div class="rel">+ {esc(a)} ↔ {esc(b)}</div>' for a, b in c.added]
    items += [f'<div class="rel muted">− {esc(a)} ↔ {esc(b)}</div>' for a, b in c.removed]
    where = f"K{c.index}" + (f" · frame {c.frame}" if c.frame is not None else "")
    where += f" · {c.time_s:.2f} s" if c.time_s is not None else ""
    oac = (c.model_extra or {}).get("oac")  # the robot's sub-action as matched, when the pipeline says
    matched = f'<div class="small">matched: <span class="mono">{esc(oac)}</span></div>' if oac else ""
    return "".join(items) + matched + f'<div class="small muted">{esc(where)}</div>'


def _checks(extra: dict[str, object]) -> str:
    """The verifier's checks (relations, end state, motion) as a table, its findings and notes."""
    checks = extra.get("checks")
    if not isinstance(checks, list) or not checks:
        return ""
    rows = []
    for c in checks:
        if not isinstance(c, dict):
            continue
        mark = badge("pass", "ok") if c.get("passed") else badge("FAIL", "bad")
        rows.append(f"<tr><td>{mark}</td><td class=mono>{esc(c.get('name', ''))}</td>"
                    f"<td>{esc(c.get('demonstration', ''))}</td><td>{esc(c.get('execution', ''))}</td>"
                    f"<td class=small>{esc(c.get('tolerance', ''))}</td>"
                    f"<td class=small>{esc(c.get('detail', ''))}</td></tr>")
    source = esc(extra.get("relations_source", "aas"))
    out = [f"<p>Checks (docs/verify.md); the robot's relations come from <b>{source}</b>."
           " <i>verified</i> = relations and end state; <i>faithful</i> = also motion.</p>",
           "<table><thead><tr><th></th><th>check</th><th>demonstration</th><th>execution</th>"
           "<th>tolerance</th><th>detail</th></tr></thead><tbody>" + "".join(rows) + "</tbody></table>"]
    for key, head in (("findings", "Segmentation findings (the AAS of the virtual markers against the"
                       " simulation's contacts)"), ("notes", "Not judged")):
        items = extra.get(key)
        if isinstance(items, list) and items:
            out.append(f"<p><b>{esc(head)}:</b></p><ul>" + "".join(f"<li>{esc(x)}</li>" for x in items)
                       + "</ul>")
    return "".join(out)


def verification_section(r: Result, images: Images) -> str:
    out = [
        '<section id="verification"><h2>Closed-loop verification</h2>',
        '<p class="lead">The robot\'s own execution, recorded with virtual markers and segmented by the'
        " same AAS, compared with the demonstration: each keyframe transition is a change (relations added"
        " and removed); the two sequences of changes are aligned with the Levenshtein distance.</p>",
    ]
    v = r.verification
    if v is None:
        return "".join(out) + not_run(r, "verify", "The verification") + "</section>"
    out.append(
        f'<div class="verdict {"ok" if v.verified else "fail"}"><div class="big">'
        f"{'✔' if v.verified else '✘'} {esc(v.verdict)}</div></div>"
    )
    out.append(_checks(v.model_extra or {}))
    facts = [
        ("edit distance", str(v.distance)),
        ("fidelity", f"{100 * v.fidelity:.0f} %"),
        ("demonstration changes", str(len(v.demonstration))),
        ("robot changes", str(len(v.robot))),
    ]
    if v.relation_distance is not None:
        facts.insert(1, ("relation-level distance", str(v.relation_distance)))
    facts.append(("initial states", "equal" if v.initial.equal else "differ"))
    facts.append(("final states", "equal" if v.final.equal else "differ"))
    out.append(_cards(facts))
    for name, st in (("Initial", v.initial), ("Final", v.final)):
        if not st.equal:
            out.append(f'<p><b>{name} world states differ.</b> Demonstration: {rel_list(st.demonstration)};'
                       f" robot: {rel_list(st.robot)}.</p>")
    ops = {"match": ("same", "ok"), "split": ("split", "ok"), "merge": ("merged", "ok"),
           "substitute": ("different", "warn"),
           "missing": ("missing", "bad"), "extra": ("extra", "bad")}
    rows = []
    for i, a in enumerate(v.alignment, 1):
        dl = a.demonstration_last if a.demonstration_last is not None else a.demonstration
        ds = [v.demonstration[k] for k in range(a.demonstration, dl + 1)] if a.demonstration is not None \
            and dl is not None else []
        demo = "<br>".join(_change(x) for x in ds) if ds else _change(None)
        last = a.robot_last if a.robot_last is not None else a.robot
        parts = [v.robot[k] for k in range(a.robot, last + 1)] if a.robot is not None and last is not None \
            else []
        robot = "<br>".join(_change(b) for b in parts) if parts else _change(None)
        text, kind = ops[a.op]
        rows.append(f'<tr class="op-{a.op}"><td class=num>{i}</td><td class="side">{demo}</td>'
                    f'<td class="op">{badge(text, kind)}</td><td class="side">{robot}</td></tr>')
    out.append('<table class="align"><thead><tr><th class=num>#</th><th>demonstration</th><th></th>'
               "<th>robot</th></tr></thead><tbody>" + "".join(rows) + "</tbody></table>")
    if v.plot:
        out.append(
            "<figure>"
            + images.tag(v.plot, "the robot's recording", "wide")
            + "<figcaption>The robot's execution segmented by the AAS.</figcaption></figure>"
        )
    return "".join(out) + "</section>"


def reliability_section(r: Result) -> str:
    out = [
        '<section id="reliability"><h2>OAC reliability</h2>',
        "<p class=\"lead\">The OAC's success measure (Krüger's third element): every execution's outcome"
        " is kept in the run store; the rate's 95 % interval is the Wilson score interval"
        " (band: interval; mark: rate).</p>",
    ]
    rel_doc = r.reliability
    if rel_doc is None or not rel_doc.oacs:
        return "".join(out) + '<p class="muted">No recorded runs.</p></section>'
    rows = []
    for x in rel_doc.oacs:
        bar = (
            f'<div class="bar"><div class="ci" style="left:{100 * x.ci_low:.1f}%;'
            f'width:{100 * (x.ci_high - x.ci_low):.1f}%"></div>'
            f'<div class="pt" style="left:{100 * x.rate:.1f}%"></div></div>'
        )
        fail = esc(x.last_failure) if x.last_failure else '<span class="muted">—</span>'
        when = f'<div class="small muted">{esc(x.last_failure_utc)}</div>' if x.last_failure_utc else ""
        rows.append(
            f"<tr><td class=mono>{esc(x.oac)}</td><td class=num>{x.runs}</td>"
            f"<td class=num>{x.successes}</td><td class=num>{100 * x.rate:.0f} %</td>"
            f'<td style="width:18%">{bar}</td>'
            f'<td class="num small">{100 * x.ci_low:.0f}–{100 * x.ci_high:.0f} %</td>'
            f"<td class=num>{seconds(x.median_duration_s)}</td>"
            f"<td class=small>{fail}{when}</td></tr>"
        )
    out.append(
        "<table><thead><tr><th>OAC</th><th class=num>runs</th><th class=num>ok</th>"
        "<th class=num>rate</th><th></th><th class=num>95 % interval</th>"
        "<th class=num>median time</th><th>last failure</th>"
        "</tr></thead><tbody>" + "".join(rows) + "</tbody></table>"
    )
    if rel_doc.db:
        out.append(
            f'<p class="small muted">Run store: <code>{esc(rel_doc.db)}</code>'
            " (<code>oacc stats</code> shows it).</p>"
        )
    return "".join(out) + "</section>"
