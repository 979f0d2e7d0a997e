"""Runs every `>>>` example of docs/guide.md (doctest), so the user guide cannot drift from the code."""

from __future__ import annotations

import doctest
from pathlib import Path

import pytest

GUIDE = Path(__file__).resolve().parents[2] / "docs" / "guide.md"


def test_user_guide_examples_run():
    if not GUIDE.exists():
        pytest.skip("docs/guide.md not present")
    result = doctest.testfile(str(GUIDE), module_relative=False, optionflags=doctest.ELLIPSIS
                              | doctest.NORMALIZE_WHITESPACE, verbose=False, raise_on_error=False)
    assert result.attempted > 30
    assert result.failed == 0, f"{result.failed} example(s) of {GUIDE.name} failed (see the output above)"
