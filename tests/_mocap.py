"""Where the third-party recordings are (``../shared/mocap``), and how tests skip without them."""

from __future__ import annotations

from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


def _shared() -> Path | None:
    for candidate in (ROOT.parent / "shared", ROOT.parents[1] / "shared"):
        if candidate.is_dir():
            return candidate
    return None


SHARED = _shared()
MOCAP = SHARED / "mocap" if SHARED else None


def mocap_file(relative: str) -> Path:
    """The path of a file under ``shared/mocap``; skips the test when it is absent."""
    if MOCAP is None or not MOCAP.is_dir():
        pytest.skip(f"third-party recordings absent: no shared/mocap next to {ROOT} or its parent")
    path = MOCAP / relative
    if not path.exists():
        pytest.skip(f"third-party recording absent: {path}")
    return path
