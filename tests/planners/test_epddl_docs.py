"""Runs every `>>>` example of docs/epddl.md (doctest, from the repository root so that the ``specs/`` paths
resolve), so that the EPDDL page cannot drift from the code."""

from __future__ import annotations

import doctest
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
PAGE = ROOT / "docs" / "epddl.md"


def test_epddl_page_examples_run(monkeypatch) -> None:
    monkeypatch.chdir(ROOT)
    result = doctest.testfile(str(PAGE), module_relative=False, optionflags=doctest.ELLIPSIS
                              | doctest.NORMALIZE_WHITESPACE, verbose=False, raise_on_error=False)
    assert result.attempted > 20
    assert result.failed == 0, f"{result.failed} example(s) of {PAGE.name} failed (see the output above)"
