"""Runs every `>>>` example of docs/diff-draw-belief.md (doctest, from the repository root so that the
``specs/`` paths resolve), so that the page cannot drift from the code."""

from __future__ import annotations

import doctest
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
PAGE = ROOT / "docs" / "diff-draw-belief.md"


def test_diff_draw_belief_page_examples_run(monkeypatch):
    if not PAGE.exists():
        pytest.skip("docs/diff-draw-belief.md not present")
    monkeypatch.chdir(ROOT)
    result = doctest.testfile(str(PAGE), module_relative=False, optionflags=doctest.ELLIPSIS
                              | doctest.NORMALIZE_WHITESPACE, verbose=False, raise_on_error=False)
    assert result.attempted > 20
    assert result.failed == 0, f"{result.failed} example(s) of {PAGE.name} failed (see the output above)"
