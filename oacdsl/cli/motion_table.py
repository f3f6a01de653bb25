"""The ``oacc segment --motion`` table: one line per sub-action with its demonstrated motion."""

from __future__ import annotations

import math
from collections.abc import Sequence

from oacdsl.segmentation.motion import SubActionMotion

__all__ = ["format_motion_table"]

_HEADER = (
    f"{'#':>3}  {'frames':>9}  {'moved':<22} {'by':<11} {'target (relation)':<32}"
    f" {'path':>7} {'extent':>7} {'period':>13} {'radius':>7} {'tilt':>11} {'turn':>8}"
)


def _row(m: SubActionMotion) -> str:
    frames = f"{m.start_frame}-{m.end_frame}"
    if m.moved is None or m.features is None:
        return f"{m.index + 1:>3}  {frames:>9}  (no hand moves an object with >= 3 markers)"
    f = m.features
    target = f"{m.target} ({m.relation})" if m.target else "world"
    period = f"{f.period_s:.2f}s x{f.cycles:.1f}" if f.period_s is not None and f.cycles else "-"
    tilt = f"{math.degrees(f.tilt_max_rad):.0f}deg {f.tilt_time_s:.1f}s"
    turn_deg = round(math.degrees(f.twist_rad))
    turn = f"{turn_deg:+d}deg" if turn_deg else "0deg"
    return (
        f"{m.index + 1:>3}  {frames:>9}  {m.moved:<22} {m.hand or '-':<11} {target:<32}"
        f" {f.path_length_m * 1e3:>5.0f}mm {f.extent_m[0] * 1e3:>5.0f}mm {period:>13}"
        f" {f.radius_m * 1e3:>5.0f}mm {tilt:>11} {turn:>8}"
    )


def format_motion_table(motions: Sequence[SubActionMotion]) -> str:
    """The readable table (millimetres, seconds, degrees: converted from SI for reading only)."""
    lines = [
        "demonstrated motion per sub-action (object pose by a rigid fit of its markers;"
        " path in the target's frame):",
        _HEADER,
    ]
    lines += [_row(m) for m in motions]
    lines.append(
        "#: the sub-action ending at keyframe # (as oacc match and the verifier number sub-actions);"
        " path: length; extent: along the main axis; period: of the oscillation x cycles;"
        " radius: around its centre; tilt: largest, and time above half of it;"
        " turn: about the target's vertical axis, counterclockwise seen from above positive (a lid"
        " unscrewed; twist's angle)"
    )
    return "\n".join(lines)
