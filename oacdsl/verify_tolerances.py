"""The verifier's thresholds, in one record (docs/verify.md).

Every number by which ``oacc verify`` judges an execution against its demonstration is a
field of :class:`VerifyTolerances`, with its unit in the name. The runtime's skills never
import or imitate these: a verdict that a skill can be tuned to is not a measurement.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass
from typing import Any

__all__ = ["DEFAULT_TOLERANCES", "VerifyTolerances"]


@dataclass(frozen=True)
class VerifyTolerances:
    """Thresholds of the three checks (relations, end state, motion); SI units."""

    # --- relations -------------------------------------------------------------------------
    #: Edit distance between the two sequences of world-state changes that still passes.
    relations_distance: int = 0
    #: A simulated contact (or its end) counts once it has held this long, seconds: MuJoCo's
    #: contacts flicker for a step or two when a body bounces or slides.
    contact_hold_s: float = 0.05
    #: A simulated contact that lifts off for less than this and comes back is held on,
    #: seconds: a stirring or wiping tool rises off its target for a moment between two
    #: touches, which the demonstration's AAS (150 mm, markers off the surfaces) never sees.
    contact_gap_s: float = 0.5
    #: Simulated changes closer than this are one keyframe, seconds (the demonstration's
    #: default merge window; the split rule pairs a demonstrated change with several).
    contact_merge_s: float = 0.3

    # --- end state -------------------------------------------------------------------------
    #: Orientation classes by the tilt of the object's start "up" axis at the end, radians:
    #: upright below this, upside down above π minus this, on its side in between. A
    #: description in the text only (oacdsl/verify_orientation.py), no rule.
    upright_max_rad: float = math.radians(45.0)
    #: The end tilts of demonstration and execution may differ by this much, radians; and
    #: an elongated object's start poses differ when its long axis's start tilts do.
    tilt_rad: float = math.radians(35.0)
    #: A marker constellation is elongated (its long axis judged) when its largest principal
    #: extent is at least this times the second: the KIT tools' are 5.5-9.8 times (salad
    #: servers 181 x 25 and 175 x 22 mm, knife 312 x 35, ladle 192 x 35, tablespoon 121 x 12,
    #: the dough's mixer 178 x 20), every other tracked object's (cups, bowls, boards,
    #: sponges, hands) at most 2.3 times; a plate's four markers 4.6 times (208 x 46 mm).
    elongated_ratio: float = 3.0
    #: An object's lowest marker within this of the table level (the lowest point of any
    #: tracked object at the first frame) rests on the table, metres.
    table_band_m: float = 0.06
    #: Lower than the table level by more than this: it fell off the table, metres.
    fell_m: float = 0.15
    #: A supporting object's footprint: the horizontal radius of its markers plus this, metres.
    footprint_margin_m: float = 0.03
    #: The demonstration moved an object at least this far (start → end, horizontally) for
    #: "put elsewhere" to be judged, metres.
    moved_min_m: float = 0.08
    #: ... and the execution must move it at least this share of the demonstrated distance;
    #: ending closer to its start is "returned to where it was picked up".
    moved_share: float = 0.3

    # --- motion (faithful) -----------------------------------------------------------------
    #: A demonstrated feature is reliable only where the rigid fits' median residual is
    #: below this, metres (the moved object's and its target's).
    reliable_residual_m: float = 0.015
    #: An oscillation (strokes, circles) is judged where the demonstration shows at least
    #: this many cycles; the execution needs at least ``cycles_share`` of them.
    min_cycles: float = 2.0
    cycles_share: float = 0.4
    #: The execution's oscillation radius within this factor of the demonstration's.
    amplitude_factor: float = 3.0
    #: Where the execution's span, read whole, shows no oscillation, it is looked for in each
    #: run of stretches in which the moved object keeps moving relative to its target: a
    #: pause, the object slower than ``still_speed_m_s`` for ``still_pause_s`` or longer (an
    #: arm's stop between two moves), ends a stretch. A robot's span can hold its own setting
    #: down and a rest before its hands let go, longer than its circles (KIT Mix x0.5 and
    #: mirrored, docs/verify.md); its six paths there read 1.5-5.4 cycles for any of 10-20 mm/s
    #: and 0.05-0.3 s.
    still_speed_m_s: float = 0.01
    still_pause_s: float = 0.1
    #: A turn about the target's axis is judged where the demonstration turns at least
    #: this much, radians; the execution needs ``turn_share`` of it, the same way round.
    min_turn_rad: float = math.radians(60.0)
    turn_share: float = 0.5
    #: A tilt is judged where the demonstration tilts the object at least this much relative
    #: to its target, radians; the execution must reach it less ``tilt_reached_rad``.
    min_tilt_rad: float = math.radians(45.0)
    tilt_reached_rad: float = math.radians(35.0)

    def to_json(self) -> dict[str, Any]:
        return {k: (round(v, 6) if isinstance(v, float) else v) for k, v in asdict(self).items()}


DEFAULT_TOLERANCES = VerifyTolerances()
