"""Impossible search limits are bad input, not a "no plan within limits" answer."""

from __future__ import annotations

import math

import pytest

from delkit.errors import PlanningError
from planners.epistemic import Limits


@pytest.mark.parametrize("kw", [{"timeout": -1.0}, {"timeout": math.nan}, {"max_expanded": -1},
                                {"max_memory_mb": 0.0}, {"max_memory_mb": -5.0}])
def test_impossible_limits_are_rejected(kw) -> None:
    with pytest.raises(PlanningError, match="impossible"):
        Limits(**kw)


def test_possible_limits_are_kept() -> None:
    lim = Limits(timeout=0.0, max_expanded=0, max_memory_mb=1.0)
    assert (lim.timeout, lim.max_expanded, lim.max_memory_mb) == (0.0, 0, 1.0)
    assert Limits(timeout=None, max_memory_mb=None).timeout is None
