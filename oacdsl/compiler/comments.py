"""Attach the comments of a file to the model nodes they belong to.

The lexer hands comments over separately (they are ignored by the grammar).
Rules, in words:

* comments above the first declaration that are separated from it by a blank
  line are the file's header (``Module.comments``);
* a comment alone on its line belongs to the next node: the next declaration,
  or inside a declaration the next instance, parameter, atom or step; when no
  node follows inside the declaration it joins the declaration's own leading
  comments; after the last declaration it is the module's ``trailing``;
* a comment after code on its line is the ``note`` of the node that ends last
  on that line before it (an atom, an instance, a declaration, …); when none
  ends there (``scene kitchen {  # …``) it is treated like a comment alone on
  its line.

Comment text is stored without the ``#`` and without one following space, and
without trailing blanks; the printer writes ``# `` + text.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

from oacdsl.model import Decl, Node, Oac, Scene

__all__ = ["Comment", "attach_comments", "comment_text"]


@dataclass(frozen=True)
class Comment:
    """One ``#`` comment: its position, whether code precedes it, its text."""

    line: int
    column: int
    own_line: bool
    text: str


def comment_text(raw: str) -> str:
    """``"#  foo  "`` → ``" foo"``: drop ``#`` and one space, strip the end."""
    body = raw[1:] if raw.startswith("#") else raw
    if body.startswith(" "):
        body = body[1:]
    return body.rstrip()


@dataclass
class _Slot:
    comments: list[str] = field(default_factory=list)
    note: str | None = None


def _start(node: Node) -> tuple[int, int]:
    s = node.span
    return (s.line, s.column) if s is not None else (0, 0)


def _end(node: Node) -> tuple[int, int]:
    s = node.span
    return (s.end_line, s.end_column) if s is not None else (0, 0)


def _children(decl: Decl) -> list[Node]:
    nodes: list[Node] = []
    if isinstance(decl, Scene):
        nodes = [*decl.instances, *decl.places, *decl.fills]
    elif isinstance(decl, Oac):
        nodes = [*decl.params, *decl.pre, *decl.effect, *(decl.steps or ())]
    return sorted((n for n in nodes if n.span is not None), key=_start)


def _trivia_update(node: Node, slot: _Slot | None) -> dict[str, object]:
    update: dict[str, object] = {}
    if slot is not None and slot.comments:
        update["comments"] = (*node.comments, *slot.comments)
    if slot is not None and slot.note is not None:
        update["note"] = slot.note
    return update


def _rebuild(decl: Decl, slots: dict[int, _Slot]) -> Decl:
    def fix(node: Node) -> Node:
        update = _trivia_update(node, slots.get(id(node)))
        return node.model_copy(update=update) if update else node

    update = _trivia_update(decl, slots.get(id(decl)))
    if isinstance(decl, Scene):
        update["instances"] = tuple(fix(i) for i in decl.instances)
        update["places"] = tuple(fix(p) for p in decl.places)
        update["fills"] = tuple(fix(f) for f in decl.fills)
    elif isinstance(decl, Oac):
        update["params"] = tuple(fix(p) for p in decl.params)
        update["pre"] = tuple(fix(a) for a in decl.pre)
        update["effect"] = tuple(fix(a) for a in decl.effect)
        if decl.steps is not None:
            update["steps"] = tuple(fix(c) for c in decl.steps)
    return decl.model_copy(update=update) if update else decl


def _place_inner(comment: Comment, decl: Decl, children: list[Node], slots: dict[int, _Slot]) -> None:
    pos = (comment.line, comment.column)
    if not comment.own_line:
        ending = [n for n in children if _end(n)[0] == comment.line and _end(n) <= pos]
        if ending:
            last = max(_end(n) for n in ending)
            owner = next(n for n in ending if _end(n) == last)
            slot = slots.setdefault(id(owner), _Slot())
            if slot.note is None:
                slot.note = comment.text
                return
    following = next((n for n in children if _start(n) > pos), None)
    target = following if following is not None else decl
    slots.setdefault(id(target), _Slot()).comments.append(comment.text)


def attach_comments(
    decls: Sequence[Decl], comments: Sequence[Comment]
) -> tuple[list[Decl], tuple[str, ...], tuple[str, ...]]:
    """The declarations with comments attached, the file's header comments, its trailing comments."""
    if not comments:
        return list(decls), (), ()
    slots: dict[int, _Slot] = {}
    pending = sorted(comments, key=lambda c: (c.line, c.column))
    k = 0
    previous: Decl | None = None
    for decl in decls:
        start, end = _start(decl), _end(decl)
        children: list[Node] | None = None
        while k < len(pending) and (pending[k].line, pending[k].column) < end:
            c = pending[k]
            k += 1
            if (c.line, c.column) < start:
                if not c.own_line and previous is not None and c.line == _end(previous)[0]:
                    slot = slots.setdefault(id(previous), _Slot())
                    if slot.note is None:
                        slot.note = c.text
                        continue
                slots.setdefault(id(decl), _Slot()).comments.append(c.text)
            else:
                if children is None:
                    children = _children(decl)
                _place_inner(c, decl, children, slots)
        previous = decl
    trailing: list[str] = []
    for c in pending[k:]:
        if not c.own_line and previous is not None and c.line == _end(previous)[0]:
            slot = slots.setdefault(id(previous), _Slot())
            if slot.note is None:
                slot.note = c.text
                continue
        trailing.append(c.text)
    out = [_rebuild(d, slots) if _touched(d, slots) else d for d in decls]
    header: tuple[str, ...] = ()
    if decls:
        out[0], header = _split_header(out[0], [c for c in pending if (c.line, c.column) < _start(decls[0])])
    return out, header, tuple(trailing)


def _split_header(first: Decl, before: list[Comment]) -> tuple[Decl, tuple[str, ...]]:
    """Comments above the first declaration and separated from it by a blank line head the file."""
    own = [c for c in before if c.own_line]
    if not own:
        return first, ()
    lines = [c.line for c in own] + [_start(first)[0]]
    gaps = [i for i in range(len(own)) if lines[i + 1] > lines[i] + 1]
    if not gaps:
        return first, ()
    cut = gaps[-1] + 1
    header = tuple(c.text for c in own[:cut])
    return first.model_copy(update={"comments": first.comments[cut:]}), header


def _touched(decl: Decl, slots: dict[int, _Slot]) -> bool:
    if id(decl) in slots:
        return True
    return any(id(n) in slots for n in _children(decl))
