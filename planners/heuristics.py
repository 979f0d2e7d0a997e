"""Domain-independent heuristics for epistemic search (over any :class:`planners.epistemic.StateSpace`).

* ``h_gc`` — goal count: the number of top-level goal conjuncts false at the pointed world. Every
  conjunct needs some action to become true, but one action can satisfy several (e.g. an announcement
  heard by three agents), so h_gc is informative but not admissible: used by GBFS.
* ``h_01`` — 0 on goal states, 1 elsewhere: admissible (every non-goal state needs ≥ 1 action), so A*
  with it returns plans of optimal length (it orders the frontier as BFS does, and tests goals on
  expansion).
* ``h_depth`` — h_01 plus dead-end detection: a false propositional goal conjunct over fluents that no
  action changes, senses or announces stays false forever, so h = ∞ (pruned). Admissible; used by A*.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

from delkit.formula import Formula, is_propositional, props_of
from planners.task import Task

__all__ = ["h_gc", "h_01", "h_depth", "make_heuristic"]


def h_gc(space: Any) -> Callable[[Any], float]:
    """Goal-count heuristic of ``space``."""
    return lambda s: float(space.goal_count(s))


def h_01(space: Any) -> Callable[[Any], float]:
    """0 on goal states, 1 elsewhere (admissible)."""
    return lambda s: 0.0 if space.is_goal(s) else 1.0


def _touchable(task: Task) -> set[str]:
    """Fluents some action may change, sense or announce (anything else is fixed forever)."""
    out: set[str] = set()
    for a in task.actions:
        out.update(p for p, _, _ in a.effects)
        for f, _ in a.sensed:
            out.update(props_of(f))
    return out


def h_depth(space: Any) -> Callable[[Any], float]:
    """h_01, and ∞ when a propositional goal conjunct over fluents that no action touches is false (it can
    never become true, so the state is a dead end). Admissible."""
    from planners.epistemic import goal_conjuncts

    task: Task = space.task
    touch = _touchable(task)
    frozen: list[Formula] = [g for g in goal_conjuncts(task.goal) if not (props_of(g) & touch)
                             and is_propositional(g)]

    def h(s: Any) -> float:
        if space.is_goal(s):
            return 0.0
        for g in frozen:
            if not space.holds(s, g):
                return math.inf
        return 1.0

    return h


def make_heuristic(name: str, space: Any) -> Callable[[Any], float]:
    """Heuristic by name: ``gc``, ``01`` or ``depth``."""
    table = {"gc": h_gc, "01": h_01, "depth": h_depth}
    if name not in table:
        from delkit.errors import PlanningError

        raise PlanningError(f"unknown heuristic {name!r}; use one of {sorted(table)}")
    return table[name](space)
