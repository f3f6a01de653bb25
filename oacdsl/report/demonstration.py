"""Report sections about the demonstration: segmentation, the Fig.-4 table, the composed OAC."""

from __future__ import annotations

from collections.abc import Sequence

from oacdsl.report.figures import relation_timeline_png, world_state_png
from oacdsl.report.html import Images, badge, call, esc, highlight_oac, rel, rel_list, seconds
from oacdsl.report.overview import not_run
from oacdsl.report.schema import KeyframeDoc, MatchDoc, Result, SubActionDoc

__all__ = ["composed_section", "keyframes_section", "segment_section", "steps_of_sub_actions"]

RUNNERS_SHOWN = 4


def _pairs(rels: Sequence[Sequence[str]]) -> set[tuple[str, str]]:
    return {(p[0], p[1]) if p[0] <= p[1] else (p[1], p[0]) for p in rels}


def segment_section(r: Result, images: Images) -> str:
    out = ['<section id="demonstration"><h2>Demonstration</h2>']
    s = r.segment
    if s is None:
        return "".join(out) + not_run(r, "segment", "The segmentation") + "</section>"
    duration = (s.frames - 1) / s.rate_hz if s.rate_hz else 0.0  # first to last frame
    out.append(
        f'<p class="lead">{esc(s.recording)}: {s.frames} frames at {s.rate_hz:g} Hz ({seconds(duration)}),'
        f" {len(s.instances)} tracked instances, segmented by the automatic action segmentation (AAS)"
        f" into {len(s.keyframes)} keyframes, one at every change of the touching relations.</p>"
    )
    if s.parameters:
        chips = "".join(f"<span><b>{esc(k)}</b>{esc(v)}</span>" for k, v in s.parameters.items())
        out.append(f'<div class="chips">{chips}</div>')
    if s.plot:
        out.append(
            "<figure>"
            + images.tag(s.plot, "distances of the relevant marker pairs", "wide")
            + "<figcaption>Distances of the relevant marker pairs over time with the thresholds;"
            " keyframes as vertical lines (cf. the paper's Fig. 3).</figcaption></figure>"
        )
    if s.keyframes:
        png = relation_timeline_png([(k.time_s, k.relations) for k in s.keyframes], duration)
        out.append(
            "<figure>"
            + images.tag(png, "when each relation held", "wide")
            + "<figcaption>When each touching relation held; dotted lines are the keyframes"
            " K0, K1, ….</figcaption></figure>"
        )
    return "".join(out) + "</section>"


def _sub_action_for(subs: list[SubActionDoc], i: int, kfs: list[KeyframeDoc]) -> SubActionDoc | None:
    """The sub-action from keyframe i-1 to i: by frames, else by position."""
    for s in subs:
        if s.from_frame == kfs[i - 1].frame and s.to_frame == kfs[i].frame:
            return s
    return subs[i - 1] if i - 1 < len(subs) else None


def steps_of_sub_actions(r: Result) -> list[int | None]:
    """For each sub-action, the index of the run step that executed it (or None).

    An explicit ``step`` wins; otherwise chosen OACs are paired with run steps in order, by name.
    """
    if r.match is None:
        return []
    out: list[int | None] = []
    steps = r.run.steps if r.run is not None else []
    j = 0
    for s in r.match.sub_actions:
        if s.step is not None:
            out.append(s.step if 0 <= s.step < len(steps) else None)
            continue
        found = None
        if s.chosen is not None and 0 <= s.chosen < len(s.matches):
            name = s.matches[s.chosen].oac
            found = next((k for k in range(j, len(steps)) if steps[k].oac == name), None)
            if found is not None:
                j = found + 1
        out.append(found)
    return out


def _constraints(m: MatchDoc) -> str:
    lines = []
    if m.pre is not None or m.pre_not:
        items = [rel(p) for p in (m.pre or [])] + [rel(p, negated=True) for p in m.pre_not]
        lines.append(f'<div class="cons"><b>pre</b>{", ".join(items) or "—"}</div>')
    if m.effect is not None or m.effect_not:
        items = [rel(p) for p in (m.effect or [])] + [rel(p, negated=True) for p in m.effect_not]
        lines.append(f'<div class="cons"><b>effect</b>{", ".join(items) or "—"}</div>')
    return "".join(lines)


def _oac_cell(sub: SubActionDoc | None) -> str:
    if sub is None:
        return '<span class="muted">not matched (matching did not run)</span>'
    parts = (sub.model_extra or {}).get("split")
    if sub.chosen is None and isinstance(parts, list) and parts:  # several sub-actions at once
        items = "".join(
            f"<li><span class=mono>{call(str(p.get('oac')), dict(p.get('binding') or {}))}</span>"
            f" (group {esc(str(p.get('group')))})</li>"
            for p in parts if isinstance(p, dict)
        )
        why = f'<div class="small muted">{esc(sub.explanation)}</div>' if sub.explanation else ""
        return (f'<div class="oacbox">{badge("split", "ok")} parts of one group may run together'
                f"<ol>{items}</ol>{why}</div>")
    if sub.chosen is None or not 0 <= sub.chosen < len(sub.matches):
        why = ""
        if sub.explanation:
            why = f'<div class="err" style="white-space:pre-wrap">{esc(sub.explanation)}</div>'
        return f'<div class="oacbox">{badge("no OAC matched", "bad")}{why}</div>'
    m = sub.matches[sub.chosen]
    box = f'<div class="oacbox"><div class="call">{call(m.oac, m.binding)}</div>{_constraints(m)}'
    if m.note:
        box += f'<div class="small muted">{esc(m.note)}</div>'
    box += "</div>"
    others = [x for k, x in enumerate(sub.matches) if k != sub.chosen]
    if others:
        items = "".join(
            f"<li><span class=mono>{call(x.oac, x.binding)}</span>"
            + (f" — {esc(x.note)}" if x.note else "")
            + "</li>"
            for x in others[:RUNNERS_SHOWN]
        )
        more = f"<div>… and {len(others) - RUNNERS_SHOWN} more</div>" if len(others) > RUNNERS_SHOWN else ""
        box += f'<div class="runners">Also matched ({len(others)}):<ol>{items}</ol>{more}</div>'
    if sub.explanation:
        box += f'<div class="small muted">{esc(sub.explanation)}</div>'
    return box


def _robot_cell(r: Result, images: Images, step: int | None) -> str:
    if r.run is None:
        return '<span class="muted">not executed</span>'
    if step is None:
        return '<span class="muted">no executed step</span>'
    s = r.run.steps[step]
    state = badge("ok", "ok") if s.success else badge("failed", "bad")
    if s.moment:  # the moment the step's prediction came true: what the paper's Fig. 4 shows
        pic = images.tag(s.moment, f"the robot as step {step + 1} makes its change", "frame")
    else:
        pic = images.tag(s.frame, f"the robot after step {step + 1}", "frame", missing="no rendered frame")
    return f'{pic}<div class="small">step {step + 1}: {esc(s.oac)} {state} {seconds(s.duration_s)}</div>'


def keyframes_section(r: Result, images: Images) -> str:
    out = [
        '<section id="keyframes"><h2>Keyframes and matched OACs</h2>',
        '<p class="lead">The paper\'s Fig. 4: each keyframe of the demonstration, its world state as a'
        ' graph (black: relation held on, <span style="color:#d62728">red: new</span>,'
        " grey dashed: ended),"
        " the OAC matched to the sub-action that leads to it with its bound constraints and the other"
        " matches, and the robot executing that OAC (when its prediction came true, else after it).</p>",
    ]
    s = r.segment
    if s is None or not s.keyframes:
        return "".join(out) + not_run(r, "segment", "The keyframes") + "</section>"
    subs = r.match.sub_actions if r.match is not None else []
    step_of = steps_of_sub_actions(r)
    rows = []
    for i, kf in enumerate(s.keyframes):
        before = s.keyframes[i - 1].relations if i else None
        graph = kf.graph or world_state_png(s.instances, kf.relations, before)
        cell_kf = (
            f'<div class="kfn">K{i}</div><div class="small muted">frame {kf.frame} · {kf.time_s:.2f} s</div>'
        )
        if kf.image:
            cell_kf += images.tag(kf.image, f"the demonstration at keyframe {i}", "snap")
        changes = ""
        if before is not None:
            new, gone = _pairs(kf.relations) - _pairs(before), _pairs(before) - _pairs(kf.relations)
            changes = (
                f'<div class="rels">new: {rel_list(sorted(new))}</div>'
                f'<div class="rels">ended: {rel_list(sorted(gone))}</div>'
            )
        cell_graph = images.tag(graph, f"world state at keyframe {i}", "graph") + changes
        if i == 0:
            cell_oac = (
                f'<div class="oacbox"><div class="call">initial world state</div>'
                f'<div class="cons">{rel_list(kf.relations, empty="nothing touches")}</div></div>'
            )
            robot = '<span class="muted">not executed</span>'
            if r.run is not None:
                robot = images.tag(
                    r.run.frame, "the robot before execution", "frame", missing="no rendered frame"
                )
        else:
            sub = _sub_action_for(subs, i, list(s.keyframes)) if subs else None
            cell_oac = _oac_cell(sub)
            k = subs.index(sub) if sub is not None and sub in subs else None
            robot = _robot_cell(r, images, step_of[k] if k is not None and k < len(step_of) else None)
        rows.append(
            f'<tr><td class="kf">{cell_kf}</td><td class="graph">{cell_graph}</td>'
            f'<td>{cell_oac}</td><td class="robot">{robot}</td></tr>'
        )
    out.append(
        '<table class="fig4"><thead><tr><th>keyframe</th><th>world state</th><th>matched OAC and'
        " constraints</th><th>robot</th></tr></thead><tbody>" + "".join(rows) + "</tbody></table>"
    )
    return "".join(out) + "</section>"


def _where(r: Result, step: int | None, keyframe: int | None) -> tuple[str, str]:
    by = "—"
    if r.compose is not None and step is not None and 0 <= step < len(r.compose.steps):
        c = r.compose.steps[step]
        by = f"step {step + 1}: <span class=mono>{call(c.oac, c.binding)}</span>"
    at = "—"
    if keyframe is not None:
        at = f"K{keyframe}"
        if r.segment is not None and 0 <= keyframe < len(r.segment.keyframes):
            kf = r.segment.keyframes[keyframe]
            at += f' <span class="small muted">(frame {kf.frame}, {kf.time_s:.2f} s)</span>'
    return by, at


def composed_section(r: Result, images: Images) -> str:
    out = ['<section id="composed"><h2>Composed OAC</h2>']
    c = r.compose
    if c is None:
        return "".join(out) + not_run(r, "compose", "The composed OAC") + "</section>"
    out.append(
        f'<p class="lead">Algorithm 1 applied per relation: a precondition of a step belongs to'
        f" <code>{esc(c.name)}</code> unless an earlier step established it; its effects are the"
        " relations of the final world state that were not in the initial one, and the ones that"
        " ended are kept as negative effects.</p>"
    )
    if c.text:
        out.append(f"<pre>{highlight_oac(c.text.rstrip())}</pre>")
    if c.file:
        out.append(f'<p class="small muted">Written to <code>{esc(c.file)}</code>.</p>')
    rows = []
    for kind, pairs in (("pre", c.pre), ("effect", c.effect), ("ended", c.ended)):
        for p in pairs:
            prov = next(
                (x for x in c.provenance if x.kind == kind and _pairs([x.relation]) == _pairs([p])), None
            )
            by, at = _where(r, prov.step if prov else None, prov.keyframe if prov else None)
            note = f'<div class="small muted">{esc(prov.note)}</div>' if prov and prov.note else ""
            rows.append(
                f"<tr><td>{esc(kind)}</td><td>{rel(p, negated=kind == 'ended')}</td>"
                f"<td>{by}{note}</td><td>{at}</td></tr>"
            )
    out.append(
        "<h3>Preconditions and effects, with provenance</h3><table><thead><tr><th>kind</th>"
        "<th>relation</th><th>from</th><th>keyframe</th></tr></thead><tbody>"
        + "".join(rows)
        + "</tbody></table>"
    )
    steps = "".join(f"<li><span class=mono>{call(s.oac, s.binding)}</span></li>" for s in c.steps)
    out.append(f"<h3>Steps</h3><ol>{steps}</ol>")
    return "".join(out) + "</section>"
