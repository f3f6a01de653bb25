"""MuJoCo's OpenGL backend, chosen in one place before MuJoCo is imported.

MuJoCo reads ``MUJOCO_GL`` once, when it is imported; ``oacc run`` and ``oacc
reproduce`` settle it here first (the command line is the one part of oacdsl that
sets the environment; :mod:`oacdsl.runtime.render` only reads it).
"""

from __future__ import annotations

import os
import sys

__all__ = ["MISSING", "NONE_FOUND", "prepare_backend"]

#: The note when ``MUJOCO_GL`` names a backend whose library is not installed (then ``disable``).
MISSING = "MUJOCO_GL={} but its library is not installed"
#: The note when ``MUJOCO_GL`` is unset and neither EGL nor OSMesa is installed.
NONE_FOUND = "no offscreen OpenGL backend (EGL or OSMesa)"


def prepare_backend(render: bool) -> str | None:
    """Settle ``MUJOCO_GL``; a note (:data:`MISSING`, :data:`NONE_FOUND`) when pictures are unlikely.

    Set to a backend whose library is missing, it becomes ``disable``. Unset and
    ``render`` wanted, it becomes the first offscreen backend installed (EGL, then
    OSMesa). Nothing changes once MuJoCo is imported.
    """
    if "mujoco" in sys.modules:
        return None
    from oacdsl.runtime.render import backend_available, choose_backend

    chosen = os.environ.get("MUJOCO_GL")
    if chosen and not backend_available(chosen):
        os.environ["MUJOCO_GL"] = "disable"
        return MISSING.format(chosen)
    if not chosen and render:
        backend = choose_backend()
        if backend is None:
            return NONE_FOUND
        os.environ["MUJOCO_GL"] = backend
    return None
