"""The runtime's skills, one per name of :data:`oacdsl.skills.SKILLS`."""

from __future__ import annotations

from oacdsl.runtime.skills.base import Skill, SkillContext
from oacdsl.runtime.skills.bimanual import grasp_both, place_both
from oacdsl.runtime.skills.follow import follow
from oacdsl.runtime.skills.grasp import reach_and_grasp
from oacdsl.runtime.skills.hold import hold, retreat
from oacdsl.runtime.skills.hold_up import hold_up
from oacdsl.runtime.skills.lift import lift
from oacdsl.runtime.skills.mix import mix
from oacdsl.runtime.skills.mix_both import mix_both
from oacdsl.runtime.skills.place import place
from oacdsl.runtime.skills.pour import pour
from oacdsl.runtime.skills.roll import roll
from oacdsl.runtime.skills.saw import saw
from oacdsl.runtime.skills.stir import stir
from oacdsl.runtime.skills.stroke import stroke
from oacdsl.runtime.skills.take_out import take_out
from oacdsl.runtime.skills.tip_out import tip_out
from oacdsl.runtime.skills.touch import touch
from oacdsl.runtime.skills.twist import twist
from oacdsl.runtime.skills.wipe import wipe

__all__ = ["IMPLEMENTATIONS", "Skill", "SkillContext"]

#: skill name → implementation; a test checks the keys equal :data:`oacdsl.skills.SKILLS`'s.
IMPLEMENTATIONS: dict[str, Skill] = {
    "reach_and_grasp": reach_and_grasp,
    "place": place,
    "pour": pour,
    "mix": mix,
    "mix_both": mix_both,
    "wipe": wipe,
    "hold": hold,
    "hold_up": hold_up,
    "touch": touch,
    "retreat": retreat,
    "lift": lift,
    "grasp_both": grasp_both,
    "place_both": place_both,
    "stir": stir,
    "take_out": take_out,
    "tip_out": tip_out,
    "twist": twist,
    "stroke": stroke,
    "roll": roll,
    "saw": saw,
    "follow": follow,
}
