"""oacdsl: reproduce a demonstrated manipulation task on a humanoid robot.

Motion capture → automatic action segmentation → matching against a library of
Object-Action Complexes written in the ``.oac`` language → composition of a new
OAC → execution on ARMAR-III in MuJoCo → verification. See README.md.
"""

from typing import Any

from oacdsl.errors import InputError, LanguageError, OacError, RecordingError, RuntimeFailure, UsageError

__version__ = "0.1.0"

#: The public API (:mod:`oacdsl.api`, docs/api.md), imported when first used so that
#: ``import oacdsl`` stays light.
_API = (
    "Composed",
    "Demonstration",
    "compose",
    "load_demonstration",
    "load_library",
    "match",
    "mine",
    "read_recording",
    "run",
    "segment",
)

__all__ = [
    *_API,
    "InputError",
    "LanguageError",
    "OacError",
    "RecordingError",
    "RuntimeFailure",
    "UsageError",
    "__version__",
]


def __getattr__(name: str) -> Any:
    if name in _API:
        from importlib import import_module

        return getattr(import_module("oacdsl.mining" if name == "mine" else "oacdsl.api"), name)
    raise AttributeError(f"module 'oacdsl' has no attribute {name!r}")
