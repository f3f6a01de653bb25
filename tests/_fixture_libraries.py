"""Libraries a new user wrote from the docs alone (``tests/fixtures/newuser*``), as their tests use
them: copied with ``library/kit`` into a temporary folder, and a demonstration matched and
composed with them."""

from __future__ import annotations

import shutil
from pathlib import Path

from oacdsl.segmentation import AasParams

ROOT = Path(__file__).resolve().parents[1]
KIT = ROOT / "library" / "kit"


def library_copies(fixtures: Path, tmp: Path) -> list[Path]:
    """Copies of ``fixtures`` and of ``library/kit`` in ``tmp``, without their ``learned`` and
    ``drafts`` folders (compose writes into the first)."""
    ignore = shutil.ignore_patterns("learned", "drafts")
    shutil.copytree(fixtures, tmp / fixtures.name, ignore=ignore)
    shutil.copytree(KIT, tmp / "kit", ignore=ignore)
    return [tmp / fixtures.name, tmp / "kit"]


def composed_steps(demo: Path, libraries: list[Path], scene: str, *, given: bool = True,
                   name: str = "task") -> list[str]:
    """The steps ``demo`` composes to with ``libraries``, each ``oac(argument, …)``; every
    sub-action must match (strict). ``given``: the scene is named to the loader; otherwise the
    loader chooses it from the recording and it must be ``scene``."""
    from oacdsl.matching.demonstration import compose_demonstration, match_segmentation
    from oacdsl.matching.matcher import Matcher
    from oacdsl.pipeline import load_inputs

    inputs = load_inputs(demo, libraries, scene if given else None, AasParams())
    assert inputs.scene.name == scene
    matcher = Matcher.from_library(inputs.library, inputs.scene, mode="strict")
    matches = match_segmentation(inputs.segmented(), matcher, unmerged=inputs.unmerged(),
                                 travel=inputs.travel())
    assert all(m.matched for m in matches), [m.explanation for m in matches if not m.matched]
    composed = compose_demonstration(name, matches, inputs.library, inputs.scene)
    return [f"{s.oac.name}({', '.join(dict(s.binding).values())})" for s in composed.composition.steps]
