"""What the ``oacc draft`` tests share: running the command, checking a draft compiles and is canonical."""

from __future__ import annotations

from pathlib import Path

from oacdsl.cli import main
from oacdsl.compiler import compile_sources, parse_text, print_module
from oacdsl.matching.emit import library_files
from oacdsl.model import ObjectClass, Scene

ROOT = Path(__file__).resolve().parents[1]
LIBRARY = ROOT / "library"


def run(capsys, *argv: str) -> tuple[int, str, str]:
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def library_sources(*paths: Path) -> dict[str, str]:
    return {str(f): f.read_text(encoding="utf-8") for p in paths for f in library_files(p)}


def check_draft(text: str, *library: Path) -> tuple[dict[str, ObjectClass], Scene]:
    """The draft compiles (with ``library``) and is canonical; its classes and its scene."""
    result = compile_sources({**library_sources(*library), "draft.oac": text})
    assert result.ok, [d.header() for d in result.errors]
    module = parse_text(text, "draft.oac")
    assert print_module(module) == text  # oacc fmt --check accepts it
    classes = {d.name: d for d in module.decls if isinstance(d, ObjectClass)}
    (scene,) = [d for d in module.decls if isinstance(d, Scene)]
    return classes, scene


def dims(cls: ObjectClass) -> dict[str, float]:
    """The first shape's sizes, metres."""
    from oacdsl.geometry import si

    assert cls.geometry is not None and cls.geometry.shapes
    return {d.name: si(d.value, "length") for d in cls.geometry.shapes[0].dims}
