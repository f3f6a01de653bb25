"""The bundled dough reproduced whole on one seed's places, in a temporary copy of ``library/``
(the slow tests of particular seeds share it)."""

from __future__ import annotations

import shutil
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[1]


def reproduce_dough(tmp_path: Path, seed: int) -> tuple[dict[str, Any], Path]:
    """Reproduce the bundled dough on ``seed`` without pictures; its verdict and the run's folder."""
    from oacdsl.pipeline import load_inputs, reproduce
    from oacdsl.segmentation import AasParams

    library = tmp_path / "library"
    shutil.copytree(ROOT / "library", library, ignore=shutil.ignore_patterns("learned", "drafts"))
    inputs = load_inputs(None, library, None, AasParams())
    out = tmp_path / "out"
    outcome = reproduce(
        inputs, name="dough", out=out, db=None, seed=seed, render=False, quiet=True, force=True
    )
    return outcome.result["verdict"], out
