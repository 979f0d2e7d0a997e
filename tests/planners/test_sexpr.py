"""The EPDDL s-expression reader (planners.lang.sexpr): the same trees (text, kind and line of every node and
atom) and the same errors as a plain regular-expression tokeniser, on plank's files and on random texts made of
brackets, comments, words and every kind of white space."""

from __future__ import annotations

import re

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from delkit.errors import ParseError
from planners.lang import shared_benchmarks
from planners.lang.sexpr import Node, Sym, read

_TOKEN = re.compile(r"[()\[\]<>|]|[^\s()\[\]<>|;]+|;[^\n]*")
_CLOSE = {"(": ")", "[": "]", "<": ">"}


def _reference(text: str, source: str) -> list:
    """The reader's specification: tokens by regular expression, line by line; (kind, line, children) trees
    and (text, line) atoms."""
    out: list = []
    stack: list = []
    for line, ln in enumerate(text.split("\n"), 1):
        for tok in _TOKEN.findall(ln):
            if tok[0] == ";":
                break
            if tok in _CLOSE:
                node = (tok, line, [])
                (stack[-1][2] if stack else out).append(node)
                stack.append(node)
            elif tok in ")]>":
                if not stack:
                    raise ParseError(f"unbalanced {tok!r}", source=source, line=line)
                node = stack.pop()
                if _CLOSE[node[0]] != tok:
                    raise ParseError(f"{tok!r} closes {node[0]!r} opened on line {node[1]}", source=source,
                                     line=line)
            else:
                (stack[-1][2] if stack else out).append((tok, line))
    if stack:
        raise ParseError(f"{stack[-1][0]!r} opened here is never closed", source=source, line=stack[-1][1])
    return out


def _plain(x) -> tuple:
    if isinstance(x, Node):
        return (x.kind, x.line, [_plain(y) for y in x])
    assert type(x) is Sym
    return (str(x), x.line)


def _outcome(fn, text: str):
    try:
        got = fn(text, "f.epddl")
    except ParseError as exc:
        return ("error", str(exc))
    return [_plain(x) for x in got] if fn is read else got


_PIECES = st.sampled_from(["(", ")", "[", "]", "<", ">", "|", ";", "; c (", "\n", " ", "\t", "\r", "\x0b", "\x1c",
                           "\u00a0", "\u2028", "\u3000", "a", "?x", ":and", "C.", "Kw.", "-", "é", "0"])


@settings(max_examples=400, deadline=None)
@given(st.lists(_PIECES, max_size=40).map("".join))
def test_random_texts_read_as_the_regular_expression_reader(text: str) -> None:
    assert _outcome(read, text) == _outcome(_reference, text)


@pytest.mark.skipif(shared_benchmarks() is None, reason="../shared/benchmarks is not available")
def test_plank_files_read_as_the_regular_expression_reader() -> None:
    files = sorted((shared_benchmarks() / "epddl2026").rglob("*.epddl"))
    assert len(files) > 20
    for f in files:
        text = f.read_text()
        assert _outcome(read, text) == _outcome(_reference, text), f
