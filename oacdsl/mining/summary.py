"""The summary page of a mining job: ``summary.html`` in its folder, one self-contained page.

Sections: the counts (recordings, analysed, failed, sub-actions, explained); **OAC
frequencies** (how many sub-actions each OAC explains, in how many recordings); **unexplained
sub-actions** grouped by their change lifted to classes (``+ Hand <-> SmallCup``) with their
count, an example recording and a drafted OAC for the group (the draft of its first
sub-action, :func:`oacdsl.matching.drafts.propose_draft`); **errors**, one line per recording
that could not be analysed (its stage and message); **time per stage** (total and median over
the recordings, seconds). The page is written atomically.
"""

from __future__ import annotations

import statistics
from collections import Counter, defaultdict
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from oacdsl.atomic import write_atomic
from oacdsl.mining.table import MineTable
from oacdsl.report.html import esc

__all__ = ["SUMMARY_NAME", "summarise", "write_summary"]

#: The file name of the page in the job's folder.
SUMMARY_NAME = "summary.html"

_STYLE = """body{font:15px/1.45 system-ui,sans-serif;margin:2em auto;max-width:70em;padding:0 1em;color:#222}
table{border-collapse:collapse;margin:.5em 0 1.5em}td,th{padding:.25em .8em;border-bottom:1px solid #ddd;
text-align:left;vertical-align:top}th{background:#f4f4f4}td.n{text-align:right;font-variant-numeric:tabular-nums}
pre{background:#f7f7f7;padding:.6em;margin:0;font-size:13px;overflow-x:auto}.err{color:#a00}"""


def summarise(table: MineTable) -> dict[str, Any]:
    """The page's figures as data (``oacc mine --json`` prints them)."""
    recordings = table.recordings()
    ok = [r for r in recordings if r["status"] == "ok"]
    subs = list(table.sub_actions())
    freq: Counter[str] = Counter(s["oac"] for s in subs if s["oac"] is not None)
    where: dict[str, set[str]] = defaultdict(set)
    groups: dict[str, list[dict[str, Any]]] = defaultdict(list)
    for s in subs:
        if s["oac"] is not None:
            where[s["oac"]].add(s["path"])
        else:
            groups[s["class_change"]].append(s)
    stages = {}
    for stage in ("read", "segment", "match", "compose"):
        values = [r[f"{stage}_s"] for r in ok if r[f"{stage}_s"] is not None]
        if values:
            stages[stage] = {"total_s": sum(values), "median_s": statistics.median(values), "n": len(values)}
    return {
        "recordings": len(recordings),
        "analysed": len(ok),
        "failed": len(recordings) - len(ok),
        "sub_actions": len(subs),
        "explained": sum(freq.values()),
        "oacs": [
            {"oac": o, "sub_actions": n, "recordings": len(where[o])}
            for o, n in sorted(freq.items(), key=lambda kv: (-kv[1], kv[0]))
        ],
        "unexplained": [
            {"change": c, "count": len(g), "example": g[0]["path"], "draft": g[0]["draft"]}
            for c, g in sorted(groups.items(), key=lambda kv: (-len(kv[1]), kv[0]))
        ],
        "errors": [
            {"path": r["path"], "stage": r["stage"], "error": r["error"]}
            for r in recordings
            if r["status"] != "ok"
        ],
        "stages": stages,
    }


def _page(doc: dict[str, Any], library: Sequence[str]) -> str:
    out = [
        "<!doctype html><html lang=en><meta charset=utf-8><title>oacc mine</title>",
        f"<style>{_STYLE}</style><h1>Mining {doc['recordings']} recordings</h1>",
        f"<p>Library: {esc(', '.join(library))}. {doc['analysed']} analysed, "
        f"<span class=err>{doc['failed']} could not be analysed</span>; {doc['sub_actions']} sub-actions,"
        f" {doc['explained']} explained by an OAC, {doc['sub_actions'] - doc['explained']} unexplained.</p>",
        "<h2>OAC frequencies</h2><table><tr><th>OAC<th>sub-actions<th>recordings",
    ]
    out += [
        f"<tr><td>{esc(o['oac'])}<td class=n>{o['sub_actions']}<td class=n>{o['recordings']}"
        for o in doc["oacs"]
    ] or ["<tr><td colspan=3>none"]
    out.append(
        "</table><h2>Unexplained sub-actions, by change</h2><table><tr><th>change (classes)<th>count"
        "<th>a drafted OAC (review it: it executes the placeholder skill TODO)"
    )
    out += [
        f"<tr><td>{esc(u['change'])}<br><small>e.g. {esc(u['example'])}</small><td class=n>{u['count']}"
        f"<td><pre>{esc(u['draft'] or '')}</pre>"
        for u in doc["unexplained"]
    ] or ["<tr><td colspan=3>none"]
    out.append(
        "</table><h2>Recordings that could not be analysed</h2><table><tr><th>recording<th>stage<th>error"
    )
    out += [
        f"<tr><td>{esc(e['path'])}<td>{esc(e['stage'])}<td class=err>{esc(e['error'])}" for e in doc["errors"]
    ] or ["<tr><td colspan=3>none"]
    out.append("</table><h2>Time per stage</h2><table><tr><th>stage<th>total<th>median per recording")
    out += [
        f"<tr><td>{esc(k)}<td class=n>{v['total_s']:.2f} s<td class=n>{v['median_s'] * 1000:.1f} ms"
        for k, v in doc["stages"].items()
    ] or ["<tr><td colspan=3>none"]
    out.append("</table></html>\n")
    return "\n".join(out)


def write_summary(table: MineTable, folder: Path, *, library: Sequence[str]) -> Path:
    """Write ``summary.html`` into ``folder`` from ``table``; its path."""
    return write_atomic(folder / SUMMARY_NAME, _page(summarise(table), library))
