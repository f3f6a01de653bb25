"""The robot runtime: ARMAR-III in MuJoCo with placo whole-body IK (optional extra ``robot``).

``from oacdsl.runtime import execute, MarkerRecorder`` loads MuJoCo and placo on first
use; importing this package alone does not (the light modules — :mod:`.armar3`,
:mod:`.binding`, :mod:`.intent`, :mod:`.results` — work without them).
"""

from __future__ import annotations

import importlib
from typing import Any

__all__ = ["execute", "prepare", "RunResult", "StepResult", "CallResult", "MarkerRecorder", "render_png"]

_LAZY = {
    "execute": "oacdsl.runtime.executor",
    "prepare": "oacdsl.runtime.executor",
    "RunResult": "oacdsl.runtime.results",
    "StepResult": "oacdsl.runtime.results",
    "CallResult": "oacdsl.runtime.results",
    "MarkerRecorder": "oacdsl.runtime.recorder",
    "render_png": "oacdsl.runtime.render",
}


def __getattr__(name: str) -> Any:
    if name in _LAZY:
        return getattr(importlib.import_module(_LAZY[name]), name)
    raise AttributeError(f"module 'oacdsl.runtime' has no attribute {name!r}")
