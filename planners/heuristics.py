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

* ``h_epi`` — the same set-cover bound with smaller covers for *first-order belief* conjuncts (A*'s
  default). Write V_x(s) for the set of valuations of agent x's accessible worlds at the pointed world.
  Under the mA* update V_x only shrinks when the action is epistemic (full observer of an announcement of
  ψ: V ∩ [ψ]; of a sensing: V ∩ [actual outcome]; partial observer or oblivious: V unchanged), is the image
  of V under the postconditions when x fully observes an ontic action, and is unchanged when x is
  oblivious of it. Hence:

  - ``¬K_x φ`` (φ propositional) false means V ⊆ [φ]; shrinking and ontic updates that do not set a
    proposition of φ keep V ⊆ [φ]: only an ontic action that x may observe and that sets a proposition of
    φ can make it true;
  - ``K_x φ`` (φ a literal or a conjunction of literals; also ``Kw_x l``) false means some v ∈ V falsifies
    a literal on q. If q is *independent* in V (V = V' × S_q) and stays so (every action keeps the product
    form: :func:`safe_props`), then V ∩ [ψ] ⊆ [φ] with ψ not mentioning q would contain, with each v, its
    q-flipped twin — so V ∩ [ψ] = ∅, a state where x believes ⊥, which the search never expands. Only an
    action that x may *fully* observe and whose content (announced / sensed formula, or ontic effect)
    mentions a proposition of φ can make it true. Independence is checked in the initial state (it is then
    preserved along every path), the argument is not used with ``allow_inconsistent``, and an action given
    as a general event model (``EventAction``) may change every conjunct; a macro's cover is the union of
    its steps' covers.

  Covers stay state-independent, so ``h_epi`` is admissible and consistent like ``h_cover``, and a false
  conjunct that no action can change (Grapevine's ``¬B(a, sc)`` once a has heard sc) is a dead end (∞).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

from delkit.formula import TOP, And, C, D, E, Formula, K, Kw, Not, Prop, is_propositional, props_of
from planners.task import Task, goal_conjuncts

__all__ = ["h_gc", "h_01", "h_cover", "h_epi", "cover_sets", "safe_props", "content_conjuncts", "make_heuristic"]

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


def _steps(act: Any) -> tuple[Any, ...] | None:
    """The mA* steps of an action (a macro's steps), or None for an action given as a general event model
    (``EventAction``) or of unknown shape: the heuristics treat those as able to change anything."""
    if hasattr(act, "steps"):
        steps = tuple(act.steps)
        return steps if all(_steps(st) is not None for st in steps) else None
    if all(hasattr(act, n) for n in ("kind", "effects", "sensed", "full", "partial")) and act.kind in (
            "ontic", "sensing", "announcement"):
        return (act,)
    return None


def _literal_props(f: Formula) -> frozenset[str] | None:
    """The propositions of ``f`` if it is a literal or a conjunction of literals, else None."""
    if isinstance(f, Prop):
        return frozenset((f.name,))
    if isinstance(f, Not) and isinstance(f.arg, Prop):
        return frozenset((f.arg.name,))
    if isinstance(f, And):
        out: frozenset[str] = frozenset()
        for g in f.args:
            p = _literal_props(g)
            if p is None:
                return None
            out |= p
        return out
    return None


def _belief_goal(g: Formula) -> tuple[str, str, frozenset[str]] | None:
    """("pos", x, P) for K_x φ / Kw_x l (φ a literal or conjunction of literals, l a literal; P = props(φ)),
    ("neg", x, P) for ¬K_x φ / ¬Kw_x φ with φ propositional; None for any other conjunct."""
    if isinstance(g, K) and _literal_props(g.arg) is not None:
        return "pos", g.agent, _literal_props(g.arg)  # type: ignore[return-value]
    if isinstance(g, Kw):
        lit = _literal_props(g.arg)
        if lit is not None and len(lit) == 1 and not isinstance(g.arg, And):
            return "pos", g.agent, lit
    if isinstance(g, Not) and isinstance(g.arg, (K, Kw)) and is_propositional(g.arg.arg):
        return "neg", g.arg.agent, frozenset(props_of(g.arg.arg))
    return None


def safe_props(task: Task) -> frozenset[str]:
    """Propositions q whose *independence* in an agent's view is preserved by every action of the task.

    An agent x's view at the pointed world is the set V of valuations of its accessible worlds; q is
    independent in V if V = V' × S_q (flipping q inside S_q stays in V). Announcing / sensing a formula that
    does not mention q, or a conjunction of literals, keeps that product form (V ∩ [ψ]); so does an ontic
    update whose conditions do not mention q and whose effects on q are unconditional. A conditional effect
    on q, a condition or a non-literal content that mentions q, or any non-propositional content or
    condition (its truth at a world is not a function of the world's valuation) breaks it."""
    props = set(task.props)
    for act in task.actions:
        steps = _steps(act)
        if steps is None:
            return frozenset()
        for st in steps:
            if st.kind == "ontic":
                for p, _, cond in st.effects:
                    if not is_propositional(cond):
                        return frozenset()
                    props -= props_of(cond)
                    if cond != TOP:
                        props.discard(p)
                continue
            for f, _ in st.sensed:
                if not is_propositional(f):
                    return frozenset()
                lits = _literal_props(f)
                if lits is None or (st.kind == "sensing" and isinstance(f, And)):
                    props -= props_of(f)
    return frozenset(props)


def _independent(space: Any, state: Any, agent: str, props: frozenset[str]) -> bool:
    """Every q in ``props`` is independent in ``agent``'s view at the pointed world of ``state``."""
    task = space.task
    ai = task.agents.index(agent)
    m = state.masks[ai][state.point]
    view = {v for w, v in enumerate(state.val) if (m >> w) & 1}
    for q in props:
        bit = 1 << task.props.index(q)
        if len({v & bit for v in view}) > 1 and any((v ^ bit) not in view for v in view):
            return False
    return True


def cover_sets(task: Task, conjuncts: tuple[Formula, ...], *, content: dict[int, tuple[str, str, frozenset[str]]]
               | None = None) -> list[int]:
    """Per action, the bit mask of the goal conjuncts whose truth it may change (see the module docstring).

    ``content`` maps the index of a conjunct to its :func:`_belief_goal` analysis when the belief-content
    argument applies to it (see :func:`h_epi`); the other conjuncts use the observer rule."""
    content = content or {}
    deps = [_deps(g) for g in conjuncts]
    out = []
    for act in task.actions:
        steps = _steps(act)
        if steps is None:  # a general event model: may change every conjunct
            out.append((1 << len(conjuncts)) - 1)
            continue
        m = 0
        for st in steps:
            full = {a for a, _ in st.full}
            observers = full | {a for a, _ in st.partial}
            sets = {p for p, _, _ in st.effects} if st.kind == "ontic" else set()
            mentions: set[str] = set()
            if st.kind != "ontic":
                for f, _ in st.sensed:
                    mentions |= props_of(f)
            for i, (ags, fls, unbounded) in enumerate(deps):
                c = content.get(i)
                if c is not None:
                    kind, x, ps = c
                    if kind == "pos":
                        hit = x in full and bool(ps & (sets | mentions))
                    else:
                        hit = x in observers and bool(ps & sets)
                else:
                    hit = unbounded or bool(ags & observers) or bool(fls & sets)
                if hit:
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


def _set_cover_bound(space: Any, conj: tuple[Formula, ...], covers: list[int]) -> Callable[[Any], float]:
    """h(s) = least number of covers whose union holds every conjunct false in s (∞ if impossible)."""
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


def h_cover(space: Any) -> Callable[[Any], float]:
    """Observer-cover heuristic (admissible, consistent; see the module docstring)."""
    conj = goal_conjuncts(space.task.goal)
    return _set_cover_bound(space, conj, cover_sets(space.task, conj))


def content_conjuncts(space: Any) -> dict[int, tuple[str, str, frozenset[str]]]:
    """The goal conjuncts (by index) to which the belief-content argument of :func:`h_epi` applies."""
    task = space.task
    conj = goal_conjuncts(task.goal)
    if any(_steps(a) is None for a in task.actions):
        return {}
    s0, _ = space.initial()
    if not hasattr(s0, "point") or len(getattr(s0, "points", (s0.point,))) != 1:
        return {}  # the argument is about one pointed world (general event models are excluded above)
    safe = safe_props(task)
    out = {}
    for i, g in enumerate(conj):
        c = _belief_goal(g)
        if c is None:
            continue
        kind, x, ps = c
        if kind == "neg" or (not getattr(space, "allow_inconsistent", False) and ps <= safe
                             and _independent(space, s0, x, ps)):
            out[i] = c
    return out


def h_epi(space: Any) -> Callable[[Any], float]:
    """Belief-content cover heuristic (admissible and consistent; see the module docstring): the
    observer cover with the belief-content argument for first-order belief goals."""
    conj = goal_conjuncts(space.task.goal)
    return _set_cover_bound(space, conj, cover_sets(space.task, conj, content=content_conjuncts(space)))


def make_heuristic(name: str, space: Any) -> Callable[[Any], float]:
    """Heuristic by name: ``gc``, ``01``, ``cover`` or ``epi``."""
    table = {"gc": h_gc, "01": h_01, "cover": h_cover, "epi": h_epi}
    if name not in table:
        from delkit.errors import PlanningError

        raise PlanningError(f"unknown heuristic {name!r}; use one of {sorted(table)}")
    return table[name](space)
