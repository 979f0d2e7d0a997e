"""S-expressions with line numbers for the EPDDL (2026) reader.

EPDDL is Lisp-shaped, with two extra bracket pairs for modalities: ``[i] φ`` / ``[C. G] φ`` (boxes) and
``<i> φ`` / ``<Kw. i> φ`` (diamonds). :func:`read` turns a text into :class:`Node` trees whose ``kind`` is
``"("``, ``"["`` or ``"<"``; atoms are :class:`Sym` (a ``str`` that remembers its line). ``;`` starts a
comment. Hand-written (a dozen lines of regular expression and a stack): a lark grammar would add start-up
time for no gain on this token set.
"""

from __future__ import annotations

import re

from delkit.errors import ParseError

__all__ = ["Sym", "Node", "read"]

_TOKEN = re.compile(r"[()\[\]<>|]|[^\s()\[\]<>|;]+|;[^\n]*")  # whitespace is skipped, not matched
_CLOSE = {"(": ")", "[": "]", "<": ">"}


class Sym(str):
    """An atom (identifier, ``?variable``, ``:keyword``, ``|``) with the line it is on."""

    __slots__ = ("line",)
    line: int

    def __new__(cls, text: str, line: int) -> Sym:
        s = super().__new__(cls, text)
        s.line = line
        return s


class Node(list):
    """A bracketed list; ``kind`` is its opening bracket, ``line`` the line it starts on."""

    __slots__ = ("kind", "line")

    def __init__(self, kind: str, line: int) -> None:
        super().__init__()
        self.kind = kind
        self.line = line

    def head(self) -> str | None:
        return self[0] if self and isinstance(self[0], Sym) else None

    __hash__ = object.__hash__  # identity; used as a cache key

    def __eq__(self, other: object) -> bool:
        return self is other


def read(text: str, source: str) -> list[Node | Sym]:
    """All top-level forms of ``text``."""
    out: list = []
    stack: list[Node] = []
    cur: list = out
    sym = _sym
    new = list.__new__
    findall = _TOKEN.findall
    for line, ln in enumerate(text.split("\n"), 1):
        for tok in findall(ln):
            c = tok[0]
            if c == ";":
                break
            if c in _CLOSE:
                node = new(Node)  # Node(c, line) without the Python-level __init__
                node.kind = c
                node.line = line
                cur.append(node)
                stack.append(node)
                cur = node
            elif c in ")]>":
                if not stack:
                    raise ParseError(f"unbalanced {tok!r}", source=source, line=line)
                node = stack.pop()
                if _CLOSE[node.kind] != c:
                    raise ParseError(f"{tok!r} closes {node.kind!r} opened on line {node.line}", source=source,
                                     line=line)
                cur = stack[-1] if stack else out
            else:
                cur.append(sym(tok, line))
    if stack:
        raise ParseError(f"{stack[-1].kind!r} opened here is never closed", source=source, line=stack[-1].line)
    return out


def _sym(text: str, line: int) -> Sym:
    s = str.__new__(Sym, text)
    s.line = line
    return s
