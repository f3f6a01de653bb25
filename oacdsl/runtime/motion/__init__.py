"""The motion layer the skills compose (issue 19): primitives for one hand, a policy for
the other, defaults in one tuning record, and the controller's one control loop.

- :mod:`~oacdsl.runtime.motion.tuning`: :class:`Tuning`, the defaults (SI units).
- :mod:`~oacdsl.runtime.motion.paths`: collision-free ways over the objects on the table.
- :mod:`~oacdsl.runtime.motion.approach`: a grasp's approach keeps clear of the other hand and
  of what it holds.
- :mod:`~oacdsl.runtime.motion.timing`: how many waypoints a repeated path (circles) is cut into.
- :mod:`~oacdsl.runtime.motion.hand`: :class:`Motion` (carry, guarded approach, press, slide,
  rise, hold still, release, withdraw) and :class:`OtherHand` (idle, steady, follow).
- :mod:`~oacdsl.runtime.motion.letgo`: letting go (release, withdraw), the primitives
  :class:`Motion` takes from :class:`~oacdsl.runtime.motion.letgo.LettingGo`.
- :mod:`~oacdsl.runtime.motion.press`: :class:`ForcePress`, a press regulated on the wrist's
  measured force (a tool kept on a surface while it moves along it).
"""

from __future__ import annotations

from oacdsl.runtime.motion.hand import Motion, OtherHand, other_side
from oacdsl.runtime.motion.letgo import withdrawal
from oacdsl.runtime.motion.paths import carry_path, clearance, obstacles, via_height
from oacdsl.runtime.motion.press import ForcePress
from oacdsl.runtime.motion.timing import waypoints_per_cycle
from oacdsl.runtime.motion.tuning import TUNING, Tuning
from oacdsl.runtime.transforms import down, raised

__all__ = [
    "ForcePress",
    "Motion",
    "OtherHand",
    "TUNING",
    "Tuning",
    "carry_path",
    "clearance",
    "down",
    "obstacles",
    "other_side",
    "raised",
    "via_height",
    "waypoints_per_cycle",
    "withdrawal",
]
