"""Names of the skills the robot runtime provides.

This list is light on purpose: ``oacc compile`` checks ``execute SKILL`` against
it without importing MuJoCo or placo. The runtime registers one implementation
per name (:mod:`oacdsl.runtime.skills`), and a test checks the two agree.
"""

from __future__ import annotations

#: skill name → one-line description (shown by ``oacc compile`` hints).
SKILLS: dict[str, str] = {
    "reach_and_grasp": "approach an object along its grasp's approach direction and close the hand",
    "place": "lower the held object until the wrist force sensor feels the support, then open the hand",
    "pour": "tilt the held container over a target container until its content has left",
    "mix": "put the held tool into a container and stir",
    "wipe": "press the held tool onto a surface and move it to and fro",
}
