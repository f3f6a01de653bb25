"""Small HTML building blocks for the report: escaping, images, relations, OAC calls, code."""

from __future__ import annotations

import base64
import html
import re
from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path

from oacdsl.world import NOTHING

__all__ = [
    "LINK_SCHEMES",
    "Images",
    "badge",
    "call",
    "esc",
    "highlight_oac",
    "rel",
    "rel_list",
    "safe_link",
    "seconds",
    "holds",
]

_MIME = {
    ".png": "image/png",
    ".jpg": "image/jpeg",
    ".jpeg": "image/jpeg",
    ".gif": "image/gif",
    ".svg": "image/svg+xml",
    ".webp": "image/webp",
}


#: URL schemes a link of the page may use; anything else (javascript:, data:, …) is not linked.
LINK_SCHEMES = ("http", "https", "file")


def safe_link(ref: str) -> str | None:
    """``ref`` as an ``href`` when it is a relative path or an http(s)/file URL, else None.

    A relative path is percent-quoted (so ``a:b`` cannot pass for a scheme); control
    characters, which browsers strip before reading the scheme, make any reference unsafe.
    """
    from urllib.parse import quote, urlsplit

    if not ref or any(ord(c) < 0x20 or ord(c) == 0x7F for c in ref) or ref.startswith(("//", "\\")):
        return None
    try:
        parts = urlsplit(ref)
    except ValueError:
        return None
    if parts.scheme:
        return ref if parts.scheme.lower() in LINK_SCHEMES else None
    if ":" in ref.split("/", 1)[0]:
        return None
    return quote(ref, safe="/#?=&%.-_~")


def esc(value: object) -> str:
    """Text made safe for HTML content and attribute values."""
    return html.escape(str(value), quote=True)


def rel(pair: Sequence[str], *, negated: bool = False) -> str:
    """``a ↔ b`` (``not a ↔ b``) as escaped, non-breaking markup."""
    text = f"{'not ' if negated else ''}{pair[0]} ↔ {pair[1]}"
    return f'<span class="rel">{esc(text)}</span>'


def rel_list(pairs: Iterable[Sequence[str]], *, negated: bool = False, empty: str = "—") -> str:
    items = [rel(p, negated=negated) for p in pairs]
    return ", ".join(items) if items else f'<span class="muted">{esc(empty)}</span>'


def call(oac: str, binding: Mapping[str, str]) -> str:
    """``pour(h=left_hand, c=red_cup)`` as escaped text."""
    args = ", ".join(f"{k}={v}" for k, v in binding.items())
    return esc(f"{oac}({args})")


def badge(text: str, kind: str) -> str:
    """A coloured pill; ``kind`` is ok, bad, warn or mute."""
    return f'<span class="badge {kind}">{esc(text)}</span>'


def seconds(value: float | None) -> str:
    if value is None:
        return "—"
    if value < 10:
        return f"{value:.2f} s"
    if value < 600:
        return f"{value:.1f} s"
    return f"{value / 60:.1f} min"


_TOKEN = re.compile(
    r"(?P<cm>#[^\n]*)|(?P<st>\"(?:[^\"\\\n]|\\.)*\")|(?P<op><->)"
    r"|(?P<kw>\b(?:oac|pre|effect|execute|steps|not|class|scene|import|nothing)\b)"
)


def highlight_oac(text: str) -> str:
    """``.oac`` source as escaped HTML with keywords, comments, strings and ``<->`` marked."""
    out, pos = [], 0
    for m in _TOKEN.finditer(text):
        out.append(esc(text[pos : m.start()]))
        kind = m.lastgroup or "kw"
        out.append(f'<span class="{kind}">{esc(m.group())}</span>')
        pos = m.end()
    out.append(esc(text[pos:]))
    return "".join(out)


def holds(pair: Sequence[str], relations: Iterable[Sequence[str]]) -> bool:
    """Does the (possibly ``x ↔ nothing``) statement hold among ``relations``?"""
    rels = {tuple(sorted(p)) for p in relations}
    a, b = pair[0], pair[1]
    if b == NOTHING or a == NOTHING:
        x = a if b == NOTHING else b
        return not any(x in p for p in rels)
    return tuple(sorted((a, b))) in rels


class Images:
    """Turns image references of the result into embedded ``<img>`` tags (data URIs).

    A reference is a path (relative to ``base``, or absolute) or a ``data:image/…`` URI. A missing
    file becomes a visible placeholder and a warning in :attr:`warnings`, never an error: the
    report of a run whose renderer was unavailable still has every other section.
    """

    def __init__(self, base: Path | None) -> None:
        self.base = base
        self.warnings: list[str] = []

    def uri(self, ref: str) -> str | None:
        if ref.startswith("data:image/"):
            return ref
        path = Path(ref)
        if not path.is_absolute() and self.base is not None:
            path = self.base / path
        mime = _MIME.get(path.suffix.lower())
        if mime is None:
            self.warnings.append(f"{ref}: not an image type the page can embed")
            return None
        try:
            data = path.read_bytes()
        except OSError as e:
            self.warnings.append(f"{ref}: {e.strerror or e}")
            return None
        return f"data:{mime};base64,{base64.b64encode(data).decode('ascii')}"

    def tag(self, ref: str | bytes | None, alt: str, cls: str, *, missing: str = "no picture") -> str:
        """An ``<img>`` for ``ref`` (a reference, or PNG bytes), else a placeholder box."""
        if isinstance(ref, bytes):
            src: str | None = "data:image/png;base64," + base64.b64encode(ref).decode("ascii")
        elif ref:
            src = self.uri(ref)
            if src is None:
                missing = f"picture unavailable: {ref}"
        else:
            src = None
        if src is None:
            return f'<div class="noimg {esc(cls)}">{esc(missing)}</div>'
        return f'<img class="{esc(cls)}" alt="{esc(alt)}" src="{esc(src)}">'
