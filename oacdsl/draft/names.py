"""Names of a draft: instance names from marker groups, class names from instance names.

An instance is called as its marker group when that is a name of the language (letters,
digits, ``_``, not a keyword); otherwise a cleaned name that lists the group's markers
explicitly (``my_box : MyBox markers ("my box:m1", …)``). A class is the instance's
name in CamelCase (``cup_small`` → ``CupSmall``), made unique.
"""

from __future__ import annotations

import re
from collections.abc import Collection

__all__ = ["camel_case", "instance_name", "library_class_for", "library_classes_alike", "unique"]


def _is_name(text: str) -> bool:
    from oacdsl.compiler.grammar import keywords, name_pattern

    return bool(name_pattern().fullmatch(text)) and text not in keywords()


def unique(base: str, taken: Collection[str]) -> str:
    """``base``, or ``base2``, ``base3`` … — the first not in ``taken``."""
    if base not in taken:
        return base
    n = 2
    while f"{base}{n}" in taken:
        n += 1
    return f"{base}{n}"


def instance_name(group: str, taken: Collection[str]) -> tuple[str, bool]:
    """The instance name of marker group ``group`` and whether it differs from the group's
    (then the scene must list the group's markers)."""
    if _is_name(group) and group not in taken:
        return group, False
    cleaned = re.sub(r"\W+", "_", group.encode("ascii", "ignore").decode()).strip("_").lower() or "object"
    if cleaned[0].isdigit() or not _is_name(cleaned):
        cleaned = f"object_{cleaned}"
    return unique(cleaned, taken), True


def camel_case(name: str) -> str:
    """``cup_small`` → ``CupSmall``, ``box2`` → ``Box2``, ``_3d`` → ``Object3d``."""
    parts = [p for p in re.split(r"_+", name) if p]
    text = "".join(p[:1].upper() + p[1:] for p in parts) or "Object"
    return text if text[0].isalpha() else f"Object{text}"


def _words(text: str) -> set[str]:
    """Lower-case words of a group name (``cutting_board_small``) or a class (``CuttingBoard``)."""
    spaced = re.sub(r"(?<=[a-z0-9])(?=[A-Z])", "_", text)
    return {w.lower() for w in re.split(r"[^A-Za-z]+", spaced) if w}


def library_class_for(group: str, candidates: Collection[str]) -> tuple[str | None, list[str]]:
    """The library class whose name's words are all words of marker group ``group``
    (``cutting_board_small`` → ``CuttingBoard``, ``knife_black`` → ``Knife``), the one with the
    most words when several are, and the candidates tied with it (then none is chosen)."""
    words = _words(group)
    fitting = [c for c in candidates if _words(c) and _words(c) <= words]
    if not fitting:
        return None, []
    most = max(len(_words(c)) for c in fitting)
    best = sorted(c for c in fitting if len(_words(c)) == most)
    return (best[0], []) if len(best) == 1 else (None, best)


def library_classes_alike(group: str, candidates: Collection[str]) -> list[str]:
    """The library classes that share a word with marker group ``group`` but are not all in it
    (``board`` and ``CuttingBoard``), sorted: perhaps the same object, named otherwise."""
    words = _words(group)
    return sorted(c for c in candidates if _words(c) & words and not _words(c) <= words)
