"""Report section: the demonstration's object motion next to the robot's, per sub-action."""

from __future__ import annotations

import math

from oacdsl.report.html import Images, esc
from oacdsl.report.schema import MotionFeaturesDoc, MotionRow, Result

__all__ = ["FEATURES", "motion_section"]

#: (column, how a value is shown): the features compared, SI in result.json.
FEATURES: tuple[tuple[str, str], ...] = (
    ("tilt", "tilt_max_rad"),
    ("tilt rise", "tilt_rise_s"),
    ("period", "period_s"),
    ("cycles", "cycles"),
    ("radius", "radius_m"),
    ("extent", "extent_m"),
    ("path", "path_length_m"),
    ("duration", "duration_s"),
)


def _value(f: MotionFeaturesDoc | None, key: str) -> str:
    if f is None:
        return "–"
    v = f.extent_m[0] if key == "extent_m" and f.extent_m else getattr(f, key, None)
    if v is None:
        return "–"
    if key.endswith("_rad"):
        return f"{math.degrees(v):.0f}°"
    if key.endswith("_m"):
        return f"{v * 1000:.0f} mm"
    if key.endswith("_s"):
        return f"{v:.2f} s"
    return f"{v:.1f}"


def _params(row: MotionRow) -> str:
    if not row.params:
        return ""
    shown = []
    for name, v in sorted(row.params.items()):
        text = f"{math.degrees(v):.0f}°" if name == "tilt" else f"{v:g}"
        shown.append(f"{name} {text}")
    return '<div class="muted">' + esc(", ".join(shown)) + "</div>"


def motion_section(r: Result, images: Images) -> str:
    out = ['<section id="motion"><h2>Demonstrated and executed motion</h2>',
           '<p class="lead">Per sub-action, the moved object\'s path in its target\'s frame'
           " (the world's when it works on nothing): the demonstration's from its markers, the robot's"
           " from its own virtual markers through the same rigid fit and features. Each cell:"
           " demonstration / robot; under the OAC, the skill parameters its step was given from the"
           " demonstration (SI; tilt in degrees).</p>"]
    m = r.motion
    if m is None:
        return "".join(out) + '<p class="muted">No comparison: the robot was not verified.</p></section>'
    head = "".join(f"<th>{esc(name)}</th>" for name, _ in FEATURES)
    rows = []
    for row in m.sub_actions:
        where = f"{row.moved or '–'} → {row.target or 'world'}"
        cells = "".join(
            f"<td>{esc(_value(row.demonstrated, key))} / {esc(_value(row.executed, key))}</td>"
            for _, key in FEATURES)
        none = ' <span class="muted">(no aligned robot sub-action)</span>'
        robot = "" if row.robot_index is not None else none
        rows.append(f"<tr><td class=num>{row.index}</td><td>{esc(row.oac or '–')}{_params(row)}</td>"
                    f"<td>{esc(where)}{robot}</td>{cells}</tr>")
    out.append('<table class="motion"><thead><tr><th class=num>#</th><th>OAC</th><th>moved → frame</th>'
               f"{head}</tr></thead><tbody>" + "".join(rows) + "</tbody></table>")
    if m.plot:
        out.append("<figure>" + images.tag(m.plot, "demonstrated and executed motion", "wide")
                   + "<figcaption>Left: the demonstration; right: the robot (dark → light: start → end;"
                   " thick: the dwelling core; star: the largest tilt).</figcaption></figure>")
    return "".join(out) + "</section>"
