"""Matching sub-actions to OACs and composing a new OAC from the matched sequence.

``Matcher`` / ``match_sub_action`` link a sub-action (world state before, after)
to the OACs of a library under bindings of their variables; ``apply_effects``
applies bound effects to a world state. See docs/matching.md.
"""

from oacdsl.matching.conditions import apply_effects, bind_atom, bind_atoms, holds, why_not
from oacdsl.matching.matcher import MODES, Matcher, match_sub_action
from oacdsl.matching.results import Match, MatchResult, Mode, NearMiss
from oacdsl.model import atom_text  # the one text of an atom, for messages

__all__ = [
    "MODES",
    "Match",
    "MatchResult",
    "Matcher",
    "Mode",
    "NearMiss",
    "apply_effects",
    "atom_text",
    "bind_atom",
    "bind_atoms",
    "holds",
    "match_sub_action",
    "why_not",
]
