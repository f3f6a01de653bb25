"""Where the inputs come from when none are given: the source tree, the bundled dough
demonstration (``data/dough.c3d``, else generated from its seed), the default library, and a
name for the composed OAC from a recording's file name (see :mod:`oacdsl.pipeline.inputs`)."""

from __future__ import annotations

import re
import unicodedata
from pathlib import Path

from oacdsl.segmentation.recording import Recording

__all__ = ["BUNDLED_NAME", "bundled_recording", "default_library", "default_name", "source_root"]

#: The bundled demonstration, relative to the source tree.
BUNDLED_NAME = "data/dough.c3d"


def source_root() -> Path | None:
    """The source tree the package runs from (a checkout or an editable install), else None."""
    root = Path(__file__).resolve().parents[2]
    return root if (root / "pyproject.toml").is_file() and (root / "oacdsl").is_dir() else None


def bundled_recording() -> tuple[Recording, str]:
    """The bundled dough demonstration and where it came from (the file, or ``synth:dough``)."""
    root = source_root()
    path = root / BUNDLED_NAME if root is not None else None
    if path is not None and path.is_file():
        from oacdsl.segmentation.readers import read_recording

        return read_recording(path), _shown(path)
    from oacdsl.segmentation.synth import DEFAULT_SEED, dough_demonstration

    return dough_demonstration(DEFAULT_SEED).recording, f"synth:dough (seed {DEFAULT_SEED}, generated)"


def _shown(path: Path) -> str:
    """``path`` relative to the working folder when it lies inside it."""
    try:
        return str(path.resolve().relative_to(Path.cwd().resolve()))
    except ValueError:
        return str(path)


def default_library() -> Path:
    """``library/`` in the working folder, else the source tree's ``library/``."""
    here = Path("library")
    root = source_root()
    if here.is_dir() or root is None or not (root / "library").is_dir():
        return here
    return root / "library"


def default_name(source: str) -> str:
    """A name for the composed OAC from the recording's file name: ``Pour-01.c3d`` → ``pour_01``,
    ``Crêpe.c3d`` → ``crepe`` (ASCII letters, digits and ``_``; at most 200 characters)."""
    stem = Path(source.split(" ")[0].split(":")[-1]).name
    for suffix in (".mmm.xml", ".xml", ".c3d", ".tsv", ".csv", ".json"):
        if stem.lower().endswith(suffix):
            stem = stem[: -len(suffix)]
            break
    ascii_stem = unicodedata.normalize("NFKD", stem.lower()).encode("ascii", "ignore").decode("ascii")
    name = re.sub(r"[^a-z0-9]+", "_", ascii_stem).strip("_") or "demonstration"
    name = name if name[0].isalpha() else f"demo_{name}"
    return name[:200].rstrip("_")  # an ASCII identifier, and NAME.oac a file name of any file system
