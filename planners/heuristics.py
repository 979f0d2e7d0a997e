"""Domain-independent heuristics for epistemic search (over any :class:`planners.epistemic.StateSpace`).

* ``h_gc`` — goal count: the number of top-level goal conjuncts false at the pointed world. One action
  can make several true (an announcement heard by three agents), so h_gc is informative but not
  admissible: used by GBFS.
* ``h_01`` — 0 on goal states, 1 elsewhere: admissible.
* ``h_cover`` — the *observer cover* bound, admissible and consistent: used by A*.

``h_cover`` rests on one fact about the mA* update. If agent c is oblivious of an action, the actual
world's c-successors after the update are the pairs (v, ε), and everything reachable from (v, ε) is
(u, ε) with u reachable from v — an isomorphic copy of the old model (ε changes nothing). So every
formula whose top-level modal operators all belong to oblivious agents (K_c ψ, Kw_c ψ, C_G ψ, E_G ψ,
D_G ψ with G oblivious), and every fluent formula over fluents the action does not set, keeps its truth
value. Hence an action A can change the truth of a goal conjunct g only if g ∈ cover(A): some top-level
agent of g may observe A (A has an ``observes``/``aware_of`` statement for it, whatever its condition), or
A is ontic and sets a fluent of g's top-level fluent part.

A plan from s must, for each false conjunct, contain an action whose cover holds it, so its length is at
least the size of a minimum set cover of U(s) = {false conjuncts} by the sets cover(A):
h_cover(s) = mincover(U(s)) (∞ if some false conjunct is in no cover: a dead end). It is consistent:
U(s) ⊆ U(s') ∪ cover(A) for a successor s' by A, so h(s) ≤ 1 + h(s'). With ≤ 16 conjuncts the minimum
cover of every subset is tabulated once per task (BFS over unions of covers, then a superset minimum);
above that the weaker ⌈|U(s)| / max_A |cover(A)|⌉ (also consistent) is used.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

from delkit.formula import C, D, E, Formula, K, Kw, Prop
from planners.task import ActionSpec, MacroSpec, Task, goal_conjuncts

__all__ = ["h_gc", "h_01", "h_cover", "cover_sets", "make_heuristic"]

_MAX_EXACT = 16


def h_gc(space: Any) -> Callable[[Any], float]:
    """Goal-count heuristic of ``space``."""
    return lambda s: float(space.goal_count(s))


def h_01(space: Any) -> Callable[[Any], float]:
    """0 on goal states, 1 elsewhere (admissible)."""
    return lambda s: 0.0 if space.is_goal(s) else 1.0


def _deps(f: Formula) -> tuple[set[str], set[str], bool]:
    """(top-level agents, top-level fluents, has an operator we cannot bound) of ``f``."""
    if isinstance(f, Prop):
        return set(), {f.name}, False
    if isinstance(f, (K, Kw)):
        return {f.agent}, set(), False
    if isinstance(f, (C, E, D)):
        return set(f.group), set(), False
    kids = [getattr(f, n) for n in ("arg", "left", "right") if isinstance(getattr(f, n, None), Formula)]
    kids += list(getattr(f, "args", ()))
    if type(f).__name__ in ("Announce", "Update"):
        return set(), set(), True
    ags: set[str] = set()
    fls: set[str] = set()
    unbounded = False
    for g in kids:
        a, p, u = _deps(g)
        ags |= a
        fls |= p
        unbounded |= u
    return ags, fls, unbounded


def cover_sets(task: Task, conjuncts: tuple[Formula, ...]) -> list[int]:
    """Per action, the bit mask of the goal conjuncts whose truth it may change (see module docstring)."""
    deps = [_deps(g) for g in conjuncts]
    out = []
    for act in task.actions:
        steps = act.steps if isinstance(act, MacroSpec) else (act,)
        if not all(isinstance(st, ActionSpec) for st in steps):  # a general event model may change anything
            out.append((1 << len(conjuncts)) - 1)
            continue
        # a macro is one action: it may change what any of its steps may change
        observers = {a for st in steps for a, _ in st.full} | {a for st in steps for a, _ in st.partial}
        sets = {p for st in steps if st.kind == "ontic" for p, _, _ in st.effects}
        m = 0
        for i, (ags, fls, unbounded) in enumerate(deps):
            if unbounded or (ags & observers) or (fls & sets):
                m |= 1 << i
        out.append(m)
    return out


def _min_cover_table(k: int, covers: list[int]) -> list[float]:
    """best[U] = least number of covers whose union contains U, for every U ⊆ {0..k-1}."""
    size = 1 << k
    dist = [math.inf] * size
    dist[0] = 0
    frontier = [0]
    uniq = sorted(set(c for c in covers if c))
    while frontier:
        nxt = []
        for m in frontier:
            d = dist[m] + 1
            for c in uniq:
                u = m | c
                if dist[u] > d:
                    dist[u] = d
                    nxt.append(u)
        frontier = nxt
    best = dist[:]
    for bit in range(k):
        b = 1 << bit
        for m in range(size):
            if not m & b and best[m | b] < best[m]:
                best[m] = best[m | b]
    return best


def h_cover(space: Any) -> Callable[[Any], float]:
    """Observer-cover heuristic (admissible, consistent; see the module docstring)."""
    conj = goal_conjuncts(space.task.goal)
    covers = cover_sets(space.task, conj)
    k = len(conj)
    if k <= _MAX_EXACT:
        table = _min_cover_table(k, covers)

        def h(s: Any) -> float:
            u = 0
            for i, g in enumerate(conj):
                if not space.holds(s, g):
                    u |= 1 << i
            return float(table[u])

        return h
    union = 0
    for c in covers:
        union |= c
    m_max = max((bin(c).count("1") for c in covers), default=0)

    def h_ratio(s: Any) -> float:
        u = 0
        for i, g in enumerate(conj):
            if not space.holds(s, g):
                u |= 1 << i
        if u & ~union:
            return math.inf
        return float(math.ceil(bin(u).count("1") / m_max)) if u else 0.0

    return h_ratio


def make_heuristic(name: str, space: Any) -> Callable[[Any], float]:
    """Heuristic by name: ``gc``, ``01`` or ``cover``."""
    table = {"gc": h_gc, "01": h_01, "cover": h_cover}
    if name not in table:
        from delkit.errors import PlanningError

        raise PlanningError(f"unknown heuristic {name!r}; use one of {sorted(table)}")
    return table[name](space)
