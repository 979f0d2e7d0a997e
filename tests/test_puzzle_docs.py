"""The runnable examples of the docs/puzzles.md sections on GossipKw, Hanabi-style hints and muddy children
planning (each section's ``>>>`` lines are executed; the other sections are not doctests)."""

from __future__ import annotations

import doctest
import re
from pathlib import Path

import pytest

PAGE = Path(__file__).resolve().parents[1] / "docs" / "puzzles.md"


def _section(title: str) -> str:
    text = PAGE.read_text(encoding="utf-8")
    m = re.search(rf"^## {re.escape(title)}\n(.*?)(?=^## )", text, flags=re.S | re.M)
    assert m, f"no section {title!r} in {PAGE.name}"
    return m.group(1)


@pytest.mark.parametrize("title", ["Gossip, knowing whether", "Hanabi-style hints", "Muddy children planning"])
def test_section_examples_run(title: str) -> None:
    parser = doctest.DocTestParser()
    test = parser.get_doctest(_section(title), {}, title, str(PAGE), 0)
    assert test.examples, title
    runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    runner.run(test)
    assert runner.failures == 0, f"{runner.failures} example(s) of {title!r} failed (see the output above)"
