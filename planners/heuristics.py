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

* ``h_chain`` — ``max(h_epi, h_exe)``: the executability chains of the pointed world's fluents
  (see :func:`h_chain`).
* ``h_elim`` — ``h_chain`` and the *elimination bound*: a false K_x φ needs every valuation of x's view that
  falsifies φ removed, each by a step x observes whose content tells it from the actual one, executable first
  (with h_max chains that read effect conditions and the beliefs x always has right: :func:`transparent_props`).
* ``h_pdb`` — A*'s default: ``h_chain`` and, per such goal conjunct, the exact distance in an abstraction
  (the pointed valuation on the propositions its actions need, x's and the tellers' views), tabulated once
  per task (see :func:`h_pdb`).
* ``h_epi`` — the same set-cover bound with smaller covers for *first-order belief* conjuncts (A*'s
  default). Write V_x(s) for the set of valuations of agent x's accessible worlds at the pointed world.
  Under the mA* update V_x only shrinks when the action is epistemic (full observer of an announcement of
  ψ: V ∩ [ψ]; of a sensing: V ∩ [actual outcome]; partial observer or oblivious: V unchanged), is the image
  of V under the postconditions when x fully observes an ontic action, and is unchanged when x is
  oblivious of it. Hence:

  - ``¬K_x φ`` (φ propositional) false means V ⊆ [φ]; shrinking and ontic updates that do not set a
    proposition of φ keep V ⊆ [φ]: only an ontic action that x may observe and that sets a proposition of
    φ can make it true;
  - ``K_x φ`` / ``Kw_x φ`` (φ propositional over props P) false: split the propositions into the finest
    blocks that every action keeps apart (:func:`prop_blocks`: an announced conjunct, a sensed formula, an
    ontic effect with its condition each lie in one block) and let Q be the least union of blocks ⊇ P on
    which x's view factors, V = V_-Q × V_Q (blocks correlated with Q in V are merged in; checked in the
    initial state). Every action keeps that product form (V ∩ [ψ] with each conjunct of ψ on one side; the
    postconditions stay on one side), and an action whose content does not mention Q keeps V_Q — so V
    keeps, beside any remaining world, a Q-part falsifying φ (for Kw: one falsifying and one satisfying
    φ), unless V becomes empty, a state where x believes ⊥ that the search never expands. Only an action
    that x may *fully* observe and whose content (announced / sensed formula, or ontic effect) mentions
    a proposition of Q can make it true. The argument is not used with ``allow_inconsistent`` or when a
    content or condition is not propositional; an action given as a general event model (``EventAction``)
    may change every conjunct (and turns the argument off); a macro's cover is the union of its steps'.

  Covers stay state-independent, so ``h_epi`` is admissible and consistent like ``h_cover``, and a false
  conjunct that no action can change (Grapevine's ``¬B(a, sc)`` once a has heard sc) is a dead end (∞).
"""

from __future__ import annotations

import math
from collections.abc import Callable

from delkit.logic.formula import And, C, D, E, Formula, K, Kw, Not, Prop, is_propositional, props_of
from planners.task import Task, goal_conjuncts

TYPE_CHECKING = False  # typing.TYPE_CHECKING without importing typing (start-up: delkit._records)
if TYPE_CHECKING:
    from typing import Any

__all__ = ["h_gc", "h_01", "h_cover", "h_epi", "h_chain", "h_elim", "h_pdb", "transparent_props", "dead_end_test",
           "cover_sets", "prop_blocks", "content_conjuncts", "make_heuristic"]

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
    """("pos", x, P) for K_x φ / Kw_x φ, ("neg", x, P) for ¬K_x φ / ¬Kw_x φ, φ propositional and P = props(φ);
    None for any other conjunct."""
    if isinstance(g, (K, Kw)) and is_propositional(g.arg):
        return "pos", g.agent, frozenset(props_of(g.arg))
    if isinstance(g, Not) and isinstance(g.arg, (K, Kw)) and is_propositional(g.arg.arg):
        return "neg", g.arg.agent, frozenset(props_of(g.arg.arg))
    return None


def _conjuncts(f: Formula) -> list[Formula]:
    if isinstance(f, And):
        return [h for g in f.args for h in _conjuncts(g)]
    return [f]


def prop_blocks(task: Task) -> dict[str, frozenset[str]] | None:
    """The finest partition of the propositions whose blocks every action keeps *separate*: each announced
    conjunct, each sensed formula and each ontic effect together with its condition lies within one block.
    None if some content or condition is not propositional, or an action is a general event model.

    Why: if an agent's view V (the valuations of its accessible worlds at the pointed world) is a product
    V = V_-Q × V_Q for a union Q of blocks, every action keeps it one — V ∩ [ψ] with each conjunct of ψ on
    one side, the image under postconditions that stay on one side — see the module docstring."""
    parent = {p: p for p in task.props}

    def find(p: str) -> str:
        while parent[p] != p:
            parent[p] = parent[parent[p]]
            p = parent[p]
        return p

    def join(ps: set[str]) -> None:
        ps = [p for p in ps if p in parent]
        for q in ps[1:]:
            parent[find(q)] = find(ps[0])

    for act in task.actions:
        steps = _steps(act)
        if steps is None:
            return None
        for st in steps:
            if st.kind == "ontic":
                for p, _, cond in st.effects:
                    if not is_propositional(cond):
                        return None
                    join({p} | props_of(cond))
                continue
            for f, _ in st.sensed:
                if not is_propositional(f):
                    return None
                for part in (_conjuncts(f) if st.kind == "announcement" else [f]):
                    join(set(props_of(part)))
    blocks: dict[str, set[str]] = {}
    for p in task.props:
        blocks.setdefault(find(p), set()).add(p)
    return {p: frozenset(blocks[find(p)]) for p in task.props}


def _factor_block(space: Any, state: Any, agent: str, props: frozenset[str],
                  blocks: dict[str, frozenset[str]]) -> frozenset[str] | None:
    """The least union Q of blocks containing ``props`` with ``agent``'s view at the pointed world of ``state``
    a product V = V_-Q × V_Q (blocks correlated with Q in V are merged in), or None if there is none but all."""
    task = space.task
    ai = task.agents.index(agent)
    m = state.masks[ai][state.point]
    view = {v for w, v in enumerate(state.val) if (m >> w) & 1}
    bit = {p: 1 << i for i, p in enumerate(task.props)}

    def mask_of(ps: frozenset[str]) -> int:
        out = 0
        for p in ps:
            out |= bit[p]
        return out

    def product(qm: int) -> bool:
        return len(view) == len({v & qm for v in view}) * len({v & ~qm for v in view})

    q = frozenset().union(*(blocks[p] for p in props))
    others = {blocks[p] for p in task.props} - {blocks[p] for p in q}
    changed = True
    while changed and not product(mask_of(q)):
        changed = False
        qm = mask_of(q)
        for b in list(others):
            bm = mask_of(b)
            pair = {v & (qm | bm) for v in view}
            if len(pair) != len({v & qm for v in view}) * len({v & bm for v in view}):
                q |= b
                others.discard(b)
                changed = True
                break
    return q if product(mask_of(q)) else None


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
    blocks = prop_blocks(task)
    out = {}
    for i, g in enumerate(conj):
        c = _belief_goal(g)
        if c is None:
            continue
        kind, x, ps = c
        if kind == "neg":
            out[i] = c
        elif blocks is not None and not getattr(space, "allow_inconsistent", False):
            q = _factor_block(space, s0, x, ps, blocks)
            if q is not None:
                out[i] = ("pos", x, q)
    return out


def h_epi(space: Any) -> Callable[[Any], float]:
    """Belief-content cover heuristic (admissible and consistent; see the module docstring): the
    observer cover with the belief-content argument for first-order belief goals."""
    conj = goal_conjuncts(space.task.goal)
    return _set_cover_bound(space, conj, cover_sets(space.task, conj, content=content_conjuncts(space)))


def dead_end_test(space: Any) -> Callable[[Any], bool] | None:
    """A test for the states h_epi proves dead ends, or None when it never can: a goal conjunct in no action's
    cover (h_epi's, :func:`cover_sets`) can never be made true again once false (Grapevine's ``¬B(a, sc)``
    once a has heard sc), so a state where one of them is false cannot reach the goal. Only those conjuncts
    are evaluated. Pruning such states keeps BFS's plan: none of them lies on a path to a goal, and the
    others are generated and expanded in the same order."""
    conj = goal_conjuncts(space.task.goal)
    covers = cover_sets(space.task, conj, content=content_conjuncts(space))
    union = 0
    for c in covers:
        union |= c
    fixed = [g for i, g in enumerate(conj) if not union >> i & 1]
    if not fixed:
        return None
    holds = space.holds
    return lambda s: not all(holds(s, g) for g in fixed)


def _lits(f: Formula) -> list[tuple[str, bool]]:
    """The literal conjuncts of ``f`` (each necessary for f to hold at a world)."""
    out = []
    for g in _conjuncts(f):
        if isinstance(g, Prop):
            out.append((g.name, True))
        elif isinstance(g, Not) and isinstance(g.arg, Prop):
            out.append((g.arg.name, False))
    return out


def _point_valuation(s: Any, pidx: dict[str, int]) -> int | None:
    """The pointed world's valuation as a bit mask over the task's propositions (None: several points)."""
    points = getattr(s, "points", None)
    if points is not None:  # CompactState
        return s.val[points[0]] if len(points) == 1 else None
    des = list(s.designated)
    if len(des) != 1:
        return None
    v = 0
    for p, i in pidx.items():
        if p in s.props and s.valuation[des[0], s.prop_index(p)]:
            v |= 1 << i
    return v


def _chain_costs(v: int, ontic, kinds) -> tuple[Any, tuple[float, ...]]:
    """h_max of the delete relaxation from the pointed valuation ``v``: ``ontic`` holds (executability
    literals, condition literals, effect literals) per action; returns (the cost of a literal set, each goal
    conjunct's cost by its kind: "lits" its literals, "cover" 1 + the cheapest executability, else 0)."""
    inf = math.inf
    cost: dict[tuple[int, bool], float] = {}

    def c(lit: tuple[int, bool]) -> float:
        return 0.0 if bool(v >> lit[0] & 1) == lit[1] else cost.get(lit, inf)

    def c_set(lits: tuple[tuple[int, bool], ...]) -> float:
        return max(map(c, lits), default=0.0)

    changed = True
    while changed:
        changed = False
        for p, cond, effs in ontic:
            cb = max(c_set(p), c_set(cond)) + 1.0
            if cb == inf:
                continue
            for lit in effs:
                if c(lit) > cb:
                    cost[lit] = cb
                    changed = True
    per = []
    for kind, data in kinds:
        if kind == "lits":
            per.append(c_set(data))
        elif kind == "cover":
            per.append(1.0 + min((c_set(p) for p in data), default=inf))
        else:
            per.append(0.0)
    return c_set, tuple(per)


def h_chain(space: Any) -> Callable[[Any], float]:
    """``max(h_epi, h_exe)``: h_epi strengthened by executability chains (admissible and consistent).

    ``h_exe(s)`` is the largest, over the goal conjuncts g false in s, of a lower bound on the steps to make g
    true, read from the pointed world's valuation only:

    * a fluent literal l (or a conjunction of them) false at the pointed world becomes true only through an
      ontic action that sets it (the pointed world's valuation changes by ontic postconditions only), which
      must be executable there: c(l) = 1 + min over the actions A setting l of c(exe(A)), where c(L) of a set
      of literals is the max of their costs (0 when true) and exe(A)'s literal conjuncts are the ones
      counted — h_max of the delete relaxation on the pointed valuation (conditions of effects ignored);
    * any other conjunct g changes its truth only by an action whose cover (:func:`cover_sets`, h_epi's own)
      holds g, executable at that moment: cost(g) = 1 + min over those actions A of c(exe(A)).

    Both are consistent (a successor by A: every literal true after A was true before or set by A, whose
    executability held before, so c_s ≤ 1 + c_s'; a conjunct made true by A costs 1 in s), and so is the max
    with h_epi. The chain part is used for single-pointed states of tasks of mA* actions (a macro counts as
    its first step's executability and all its steps' effects); otherwise ``h_chain`` is ``h_epi``.
    """
    base = h_epi(space)
    task = space.task
    conj = goal_conjuncts(task.goal)
    steps = [_steps(a) for a in task.actions]
    if not conj or any(st is None for st in steps):
        return base
    pidx = {p: i for i, p in enumerate(task.props)}
    covers = cover_sets(task, conj, content=content_conjuncts(space))

    def code(lits: list[tuple[str, bool]]) -> tuple[tuple[int, bool], ...]:
        return tuple(sorted({(pidx[p], b) for p, b in lits if p in pidx}))

    pre = [code(_lits(st[0].executable)) for st in steps]  # type: ignore[index]
    ontic = []
    for i, st in enumerate(steps):
        effs = set()
        for step in st:  # type: ignore[union-attr]
            if step.kind == "ontic":
                for p, v, _c in step.effects:
                    if p in pidx:
                        effs |= {(pidx[p], v)} if isinstance(v, bool) else {(pidx[p], True), (pidx[p], False)}
        if effs:
            ontic.append((pre[i], (), tuple(sorted(effs))))
    kinds: list[tuple[str, Any]] = []  # per conjunct: ("lits", literals) or ("cover", distinct exe literal sets)
    for i, g in enumerate(conj):
        lp = _literal_props(g)
        if lp is not None:
            kinds.append(("lits", code(_lits(g))))
        elif is_propositional(g):
            kinds.append(("none", None))
        else:
            kinds.append(("cover", sorted({pre[a] for a, c in enumerate(covers) if c >> i & 1})))
    inf = math.inf
    memo: dict[int, tuple[float, tuple[float, ...]]] = {}

    def per_conjunct(v: int) -> tuple[float, tuple[float, ...]]:
        _, per = _chain_costs(v, ontic, kinds)
        return max(per, default=0.0), per

    holds = space.holds

    def h(s: Any) -> float:
        b = base(s)
        if b == inf:
            return b
        v = _point_valuation(s, pidx)
        if v is None:
            return b
        got = memo.get(v)
        if got is None:
            if len(memo) > 100_000:
                memo.clear()
            got = memo[v] = per_conjunct(v)
        top, costs = got
        if top <= b:
            return b
        best = b
        for i, g in enumerate(conj):
            if costs[i] > best and not holds(s, g):
                best = costs[i]
        return best

    return h


def make_heuristic(name: str, space: Any) -> Callable[[Any], float]:
    """Heuristic by name: ``gc``, ``01``, ``cover``, ``epi``, ``chain``, ``elim`` or ``pdb``."""
    table = {"gc": h_gc, "01": h_01, "cover": h_cover, "epi": h_epi, "chain": h_chain, "elim": h_elim,
             "pdb": h_pdb}
    if name not in table:
        from delkit.errors import PlanningError

        raise PlanningError(f"unknown heuristic {name!r}; use one of {sorted(table)}")
    return table[name](space)


def _peval(f: Formula, v: int, pidx: dict[str, int]) -> bool:
    """Truth of a propositional formula at a valuation given as a bit mask over ``pidx``."""
    from delkit.logic.formula import Bot, Iff, Implies, Or, Top

    if isinstance(f, Prop):
        return bool(v >> pidx[f.name] & 1)
    if isinstance(f, Not):
        return not _peval(f.arg, v, pidx)
    if isinstance(f, And):
        return all(_peval(g, v, pidx) for g in f.args)
    if isinstance(f, Or):
        return any(_peval(g, v, pidx) for g in f.args)
    if isinstance(f, Implies):
        return not _peval(f.left, v, pidx) or _peval(f.right, v, pidx)
    if isinstance(f, Iff):
        return _peval(f.left, v, pidx) == _peval(f.right, v, pidx)
    if isinstance(f, Top):
        return True
    if isinstance(f, Bot):
        return False
    raise TypeError(f"not propositional: {f!r}")


def transparent_props(space: Any) -> dict[str, frozenset[str]]:
    """Per agent x, the propositions whose value x always believes truly: B_x l ⟺ l at the pointed world.

    A proposition p is *x-transparent* when x's accessible worlds at the initial pointed world all agree with it
    on p, x observes every action step that sets p unconditionally (``x observes A``), and the conditions of
    those effects mention x-transparent propositions only (the greatest such set). Invariant along any plan:
    an action x is oblivious of sets no transparent p, and x's new accessible worlds are copies of old ones
    (same values); a sensing or announcement changes no value and only selects among x's old worlds; an ontic
    step x fully observes gives every x-accessible world (v, e) the values of the effects evaluated at v, which
    agrees with the pointed world on the conditions — so x's view keeps agreeing with the pointed world on p.
    Empty when an action is a general event model, the initial state is multi-pointed, or states where an
    agent believes ⊥ are kept (``allow_inconsistent``: B_x l would hold vacuously there)."""
    task = space.task
    steps = [_steps(a) for a in task.actions]
    if any(st is None for st in steps) or getattr(space, "allow_inconsistent", False):
        return {x: frozenset() for x in task.agents}
    s0, _ = space.initial()
    if not hasattr(s0, "masks") or len(s0.points) != 1:
        return {x: frozenset() for x in task.agents}
    from delkit.logic.formula import Top

    pidx = {p: i for i, p in enumerate(task.props)}
    flat = [step for st in steps for step in st]  # type: ignore[union-attr]
    out = {}
    for ai, x in enumerate(task.agents):
        pv = s0.val[s0.point]
        view = [s0.val[w] for w in range(len(s0.val)) if s0.masks[ai][s0.point] >> w & 1]
        cand = {p for p in task.props if all((v ^ pv) >> pidx[p] & 1 == 0 for v in view)}
        for step in flat:
            if step.kind != "ontic" or not step.effects:
                continue
            sure = any(a == x and isinstance(c, Top) for a, c in step.full)
            for p, _v, _c in step.effects:
                if not sure:
                    cand.discard(p)
        changed = True
        while changed:
            changed = False
            for step in flat:
                if step.kind != "ontic":
                    continue
                for p, v, c in step.effects:
                    if p in cand and (not is_propositional(c) or not props_of(c) <= cand
                                      or not (isinstance(v, bool) or (is_propositional(v) and props_of(v) <= cand))):
                        cand.discard(p)
                        changed = True
        out[x] = frozenset(cand)
    return out


def _elim_setup(space: Any) -> Any:
    """What :func:`h_elim` and :func:`h_pdb` share: the elimination atoms (agent index, Q mask, φ, removers),
    the goal's, each action's executability as (literals, atoms), the ontic effects for the h_max chains;
    None when the analysis does not apply (general event models, several pointed worlds, no goal)."""
    from types import SimpleNamespace

    task = space.task
    conj = goal_conjuncts(task.goal)
    steps = [_steps(a) for a in task.actions]
    s0, _ = space.initial()
    if not conj or any(st is None for st in steps) or not hasattr(s0, "masks") or len(s0.points) != 1:
        return None
    pidx = {p: i for i, p in enumerate(task.props)}
    trans = transparent_props(space)
    content = content_conjuncts(space)
    covers = cover_sets(task, conj, content=content)
    blocks = prop_blocks(task)
    set_props = {p for st in steps for step in st for p, _, _ in (step.effects if step.kind == "ontic" else ())}  # type: ignore[union-attr]
    atoms: list[tuple[int, int, Formula, list]] = []   # (agent index, Q mask, φ, removers)
    atom_of: dict[tuple[str, Formula], int | None] = {}

    def atom(x: str, phi: Formula, q: frozenset[str] | None) -> int | None:
        """The elimination atom of K_x φ (None when the argument does not apply)."""
        if (x, phi) in atom_of:
            return atom_of[(x, phi)]
        atom_of[(x, phi)] = None
        if q is None and blocks is not None and not getattr(space, "allow_inconsistent", False) \
                and is_propositional(phi) and props_of(phi):
            q = _factor_block(space, s0, x, frozenset(props_of(phi)), blocks)
        if q is None or q & set_props:
            return None
        qmask = 0
        for p in q:
            qmask |= 1 << pidx[p]
        removers = []
        for a, st in enumerate(steps):
            for step in st:  # type: ignore[union-attr]
                if step.kind == "ontic" or x not in {ag for ag, _ in step.full}:
                    continue
                parts = [f for f, _ in step.sensed] if step.kind == "sensing" else \
                    [h for f, _ in step.sensed for h in _conjuncts(f)]
                fs = tuple(f for f in parts if props_of(f) and props_of(f) <= q)
                if fs:
                    removers.append((a, "sense" if step.kind == "sensing" else "announce", fs))
        atoms.append((task.agents.index(x), qmask, phi, removers))
        atom_of[(x, phi)] = len(atoms) - 1
        return atom_of[(x, phi)]

    goal_atoms = []
    for i, c in content.items():
        kind, x, q = c
        if kind == "pos" and isinstance(conj[i], K):
            t = atom(x, conj[i].arg, q)
            if t is not None:
                goal_atoms.append((i, t))

    def exe_parts(f: Formula) -> tuple[tuple[tuple[int, bool], ...], tuple[int, ...]]:
        """(literals, elimination atoms) among the conjuncts of an executability condition."""
        lits, ats = set(), set()
        for g in _conjuncts(f):
            if isinstance(g, Prop):
                lits.add((pidx[g.name], True))
            elif isinstance(g, Not) and isinstance(g.arg, Prop):
                lits.add((pidx[g.arg.name], False))
            elif isinstance(g, K):
                if _literal_props(g.arg) is not None and _literal_props(g.arg) <= trans.get(g.agent, frozenset()):
                    lits |= {(pidx[p], b) for p, b in _lits(g.arg)}
                elif is_propositional(g.arg) and g.agent in task.agents:
                    t = atom(g.agent, g.arg, None)
                    if t is not None:
                        ats.add(t)
        return tuple(sorted(lits)), tuple(sorted(ats))

    exe = [exe_parts(st[0].executable) for st in steps]  # type: ignore[index]
    pre = [e[0] for e in exe]
    # ontic effects: (executability literals, condition literals, effect literals); a macro's conditions are
    # read at intermediate states, so they are dropped (weaker, still sound)
    ontic = []
    for i, st in enumerate(steps):
        for step in st:  # type: ignore[union-attr]
            if step.kind != "ontic":
                continue
            for p, v, c in step.effects:
                if p not in pidx:
                    continue
                cond = tuple(sorted({(pidx[q], b) for q, b in _lits(c) if q in pidx})) if len(st) == 1 else ()  # type: ignore[arg-type]
                effs = ((pidx[p], v),) if isinstance(v, bool) else ((pidx[p], True), (pidx[p], False))
                ontic.append((pre[i], cond, effs))
    return SimpleNamespace(task=task, conj=conj, steps=steps, s0=s0, pidx=pidx, trans=trans, covers=covers,
                           atoms=atoms, goal_atoms=goal_atoms, exe=exe, pre=pre, ontic=ontic, atom=atom)


def h_elim(space: Any) -> Callable[[Any], float]:
    """``max(h_chain, h_el)``: the elimination bound (admissible and consistent).

    *Elimination atoms.* Take K_x φ (a goal conjunct, or a conjunct of an action's executability), φ
    propositional, to which h_epi's belief-content argument applies (x's view V = V_-Q × V_Q at the initial
    state, φ over the block union Q; :func:`content_conjuncts`), with no action setting a proposition of Q (so
    the actual Q-part a is fixed and V_Q only shrinks). K_x φ holds exactly when every u ∈ V_Q with u ⊭ φ
    has left V_Q. Such a u leaves only by a step x may fully observe whose Q-content tells u from a — a sensing
    of a formula over Q with another value at u than at a, or an announcement whose Q-conjuncts hold at a (it
    is applicable only where its content holds at the pointed world) but not at u — and that step must be
    executable. So from s at least ``e(K_x φ) = max over the bad u of 1 + min over u's removers A of
    c(exe A)`` steps are needed (0 if no bad u, ∞ if a bad u has no remover: a dead end).

    *Costs of executability,* from the pointed valuation v of s: ``c0`` is h_max of the delete relaxation
    *with* effect conditions (an effect l of A with literal-conjunct condition c costs 1 + max(c0(exe A),
    c0(c))), where exe's literal conjuncts count and so do its belief literals B_x l over x-transparent
    propositions (:func:`transparent_props`: B_x l ⟺ l at the pointed world); other conjuncts cost 0. Level 1
    ``c1(exe A)`` is the max of c0 and of e¹ of the elimination atoms among exe(A)'s conjuncts, where e¹ uses
    c0 for the removers; the goal's elimination conjuncts use c1 (e²): a ``tell`` by y of where a box is costs
    what y needs to learn it first.

    h_el(s) = the largest e² over the false goal elimination conjuncts, of c0(l) over false literal conjuncts,
    of 1 + min c0(exe A) over the actions A whose cover holds any other false conjunct. Admissible: each level
    bounds the steps before its formula first holds (the first remover of a bad u is executable then), by
    induction on the plan's length. Consistent level by level: for a successor s' by B, c0_s ≤ 1 + c0_s'
    (h_max over the pointed valuation), a u left over at s' is a u of s with the same removers, and a u that
    B removed costs 1 at s (B was executable at s, so its level costs are 0 there).
    """
    base = h_chain(space)
    z = _elim_setup(space)
    if z is None:
        return base
    conj, pidx, atoms, goal_atoms, exe, pre, ontic, covers = (z.conj, z.pidx, z.atoms, z.goal_atoms, z.exe, z.pre,
                                                              z.ontic, z.covers)
    if not goal_atoms and not ontic:
        return base
    kinds: list[tuple[str, Any]] = []
    for i, g in enumerate(conj):
        if _literal_props(g) is not None:
            kinds.append(("lits", tuple(sorted({(pidx[p], b) for p, b in _lits(g)}))))
        elif is_propositional(g):
            kinds.append(("none", None))
        else:
            kinds.append(("cover", sorted({pre[a] for a, cv in enumerate(covers) if cv >> i & 1})))
    inf = math.inf
    memo: dict[int, tuple[tuple[float, ...], tuple[float, ...]]] = {}

    def lit_costs(v: int) -> tuple[tuple[float, ...], tuple[float, ...]]:
        """(c0 of each action's executability, each goal conjunct's chain cost) at pointed valuation v."""
        c_set, per = _chain_costs(v, ontic, kinds)
        return tuple(c_set(p) for p in pre), per

    holds = space.holds
    rem_memo: dict[tuple[int, int, int], tuple[int, ...]] = {}

    def h(s: Any) -> float:
        b = base(s)
        if b == inf or len(s.points) != 1:
            return b
        v = s.val[s.point]
        got = memo.get(v)
        if got is None:
            if len(memo) > 100_000:
                memo.clear()
            got = memo[v] = lit_costs(v)
        c0, per = got
        best = b
        for i, g in enumerate(conj):
            if per[i] > best and not holds(s, g):
                best = per[i]
        views: dict[int, set[int]] = {}
        lvl1: dict[int, float] = {}

        def bad_of(t: int) -> tuple[list[int], int]:
            ai, qmask, phi, _ = atoms[t]
            view = views.get(ai)
            if view is None:
                m, w, view = s.masks[ai][s.point], 0, set()
                while m:
                    if m & 1:
                        view.add(s.val[w])
                    m >>= 1
                    w += 1
                views[ai] = view
            return [u for u in {x & qmask for x in view} if not _peval(phi, u, pidx)], v & qmask

        def elim(t: int, cost_of: Callable[[int], float]) -> float:
            bad, a_q = bad_of(t)
            out = 0.0
            for u in bad:
                key = (t, u, a_q)
                rem = rem_memo.get(key)
                if rem is None:
                    rem = rem_memo[key] = _removers_of(u, a_q, atoms[t][3], pidx)
                out = max(out, 1.0 + min((cost_of(a) for a in rem), default=inf))
                if out == inf:
                    break
            return out

        def e1(t: int) -> float:
            got = lvl1.get(t)
            if got is None:
                got = lvl1[t] = elim(t, c0.__getitem__)
            return got

        def c1(a: int) -> float:
            return max([c0[a], *(e1(t) for t in exe[a][1])])

        for _i, t in goal_atoms:
            e2 = elim(t, c1)
            if e2 > best:
                best = e2
                if best == inf:
                    return best
        return best

    return h


def _removers_of(u: int, a: int, removers: list[tuple[int, str, tuple[Formula, ...]]],
                 pidx: dict[str, int]) -> tuple[int, ...]:
    """The actions whose Q-content tells the Q-part u from the actual Q-part a (see :func:`h_elim`)."""
    out = []
    for act, kind, fs in removers:
        if kind == "sense":
            hit = any(_peval(f, u, pidx) != _peval(f, a, pidx) for f in fs)
        else:
            hit = all(_peval(f, a, pidx) for f in fs) and not all(_peval(f, u, pidx) for f in fs)
        if hit:
            out.append(act)
    return tuple(sorted(set(out)))


_PDB_LIMIT = 40_000


def h_pdb(space: Any) -> Callable[[Any], float]:
    """``max(h_chain, max_i d_i)``: a pattern database per goal elimination conjunct (admissible, consistent).

    For a goal conjunct K_x φ with an elimination atom (see :func:`h_elim`) the *pattern* tracks: the pointed
    valuation on a set P of propositions, and the views V_Q of the tracked (agent, Q) pairs — x's for the
    conjunct, and those of the elimination atoms in the executability of its removers (a ``tell`` needs the
    teller to believe what it tells). P holds the literals (and transparent belief literals) of the
    executability of every action in the pattern, closed under the effect conditions and executability of
    the ontic actions that set P. An abstract state is (v_P, V_1, ..., V_m) with V_j ⊆ V_j(s0); an action is
    applicable when its executability literals over P hold at v_P and its tracked atoms hold (V has no bad
    value), ontic effects on P move v_P (conditions over P), and V_j loses every value the action may remove
    (:func:`h_elim`'s removers). The goal: x's V has no value falsifying φ. d_i is the exact abstract goal
    distance, tabulated once per task by backward BFS over every abstract state (patterns over
    ``_PDB_LIMIT`` states are dropped).

    Admissible: a real plan from s is an abstract plan from α(s) (real steps are applicable abstractly — the
    abstract views are subsets of the real ones, since they lose everything that may be removed — and a
    real goal state's views have no bad value). Consistent: for a real step s → s' by B, B's abstract
    successor of α(s) has the same v_P and views ⊆ those of α(s'), and the abstract distance only grows with
    the views (removal is per value), so d(α(s)) ≤ 1 + d(α(s'))."""
    base = h_chain(space)
    z = _elim_setup(space)
    if z is None or not z.goal_atoms:
        return base
    tables = [t for t in (_pattern_table(z, i, a) for i, a in z.goal_atoms) if t is not None]
    if not tables:
        return base
    inf = math.inf

    def h(s: Any) -> float:
        b = base(s)
        if b == inf or len(s.points) != 1:
            return b
        v = s.val[s.point]
        views: dict[int, set[int]] = {}
        best = b
        for pmask, tracked, dist in tables:
            key = [v & pmask]
            for ai, qmask, vals in tracked:
                view = views.get(ai)
                if view is None:
                    m, w, view = s.masks[ai][s.point], 0, set()
                    while m:
                        if m & 1:
                            view.add(s.val[w])
                        m >>= 1
                        w += 1
                    views[ai] = view
                bits = 0
                for u in {x & qmask for x in view}:
                    j = vals.get(u)
                    if j is None:
                        bits = -1
                        break
                    bits |= 1 << j
                if bits < 0:
                    break
                key.append(bits)
            else:
                d = float(dist.get(tuple(key), inf))
                if d > best:
                    best = d
                    if best == inf:
                        return best
        return best

    return h


def _pattern_table(z: Any, conj_index: int, goal_atom: int) -> tuple[int, list, dict] | None:
    """(P mask, tracked [(agent index, Q mask, {Q-value: bit})], {abstract state: distance}) of one goal
    elimination atom's pattern (see :func:`h_pdb`), or None when it is too large or does not apply."""
    import itertools
    from collections import deque

    atoms, steps, exe, pidx, s0 = z.atoms, z.steps, z.exe, z.pidx, z.s0
    v0 = s0.val[s0.point]
    tracked_atoms = {goal_atom}
    for a, _kind, _fs in atoms[goal_atom][3]:
        tracked_atoms |= set(exe[a][1])
    pairs = sorted({(atoms[t][0], atoms[t][1]) for t in tracked_atoms})
    idx = {pq: j for j, pq in enumerate(pairs)}
    vals = []
    for ai, qmask in pairs:
        view = {s0.val[w] & qmask for w in range(len(s0.val)) if s0.masks[ai][s0.point] >> w & 1}
        vals.append({u: j for j, u in enumerate(sorted(view))})
    acts = {a for t in tracked_atoms for a, _k, _f in atoms[t][3]}
    # P: executability literals of the pattern's actions, closed under the ontic actions setting P
    pset = {p for a in acts for p, _ in exe[a][0]}
    ontic_of: dict[int, list] = {}
    for a, st in enumerate(steps):
        if len(st) != 1 or st[0].kind != "ontic":
            if any(step.kind == "ontic" for step in st):
                for step in st:
                    for p, _v, _c in step.effects:
                        if p in pidx and pidx[p] in pset:
                            return None   # a macro moves P: its intermediate conditions are not tracked
            continue
        ontic_of[a] = [(pidx[p], v, tuple(sorted({(pidx[q], b) for q, b in _lits(c) if q in pidx})))
                       for p, v, c in st[0].effects if p in pidx]
    changed = True
    while changed:
        changed = False
        for a, effs in ontic_of.items():
            if any(p in pset for p, _, _ in effs):
                if any(not isinstance(v, bool) for p, v, _ in effs if p in pset):
                    return None
                need = {p for p, _ in exe[a][0]} | {q for p, _v, c in effs if p in pset for q, _ in c}
                if not need <= pset:
                    pset |= need
                    changed = True
                acts.add(a)
    for effs in ontic_of.values():   # a condition on an untracked proposition: the effect is not determined
        for p, _v, c in effs:
            if p in pset and any(q not in pset for q, _ in c):
                return None
    pmask = 0
    for p in pset:
        pmask |= 1 << p
    # reachable v_P from s0 through the ontic actions (exe literals over P only)
    def moved(vp: int, a: int) -> int | None:
        if any(bool(vp >> p & 1) != b for p, b in exe[a][0] if p in pset):
            return None
        out = vp
        for p, v, c in ontic_of.get(a, ()):
            if p in pset and all(bool(vp >> q & 1) == b for q, b in c):
                out = out | (1 << p) if v else out & ~(1 << p)
        return out

    reach = {v0 & pmask}
    todo = [v0 & pmask]
    while todo:
        vp = todo.pop()
        for a in ontic_of:
            if a in acts:
                n = moved(vp, a)
                if n is not None and n not in reach:
                    reach.add(n)
                    todo.append(n)
    size = len(reach)
    for vs in vals:
        size *= 1 << len(vs)
    if size > _PDB_LIMIT:
        return None
    # per (action, tracked pair): the bits of the values it may remove; per tracked atom: its bad bits
    a_q = [v0 & qmask for _ai, qmask in pairs]
    remove: dict[int, list[int]] = {a: [0] * len(pairs) for a in acts}
    for t in tracked_atoms:
        j = idx[(atoms[t][0], atoms[t][1])]
        for u, bit in vals[j].items():
            for a in _removers_of(u, a_q[j], atoms[t][3], pidx):
                if a in remove:
                    remove[a][j] |= 1 << bit
    # removal does not depend on φ: every tracked atom of the same pair has the same removers' contents
    # (the removers of (x, Q) are the steps x may fully observe with Q-content), so one pass per pair suffices

    def bad_bits(t: int) -> tuple[int, int]:
        j = idx[(atoms[t][0], atoms[t][1])]
        bits = 0
        for u, bit in vals[j].items():
            if not _peval(atoms[t][2], u, pidx):
                bits |= 1 << bit
        return j, bits

    goal_j, goal_bad = bad_bits(goal_atom)
    need_of = {a: [bad_bits(t) for t in exe[a][1] if t in tracked_atoms] for a in acts}
    if any(not need_of[a] and not exe[a][0] and remove[a][goal_j] & goal_bad == goal_bad for a in acts):
        return None   # one always-applicable step removes every bad value: every distance is ≤ 1 (h_epi's own)
    states = [tuple(k) for k in itertools.product(sorted(reach), *[range(1 << len(vs)) for vs in vals])]
    pred: dict[tuple, list[tuple]] = {k: [] for k in states}
    for k in states:
        for a in acts:
            if any(k[1 + j] & bad for j, bad in need_of[a]):
                continue
            vp = moved(k[0], a) if a in ontic_of else (
                k[0] if all(bool(k[0] >> p & 1) == b for p, b in exe[a][0] if p in pset) else None)
            if vp is None:
                continue
            nk = (vp, *(k[1 + j] & ~remove[a][j] for j in range(len(pairs))))
            if nk != k and nk in pred:
                pred[nk].append(k)
    dist = {k: 0 for k in states if not k[1 + goal_j] & goal_bad}
    todo2 = deque(dist)
    while todo2:
        k = todo2.popleft()
        for pk in pred[k]:
            if pk not in dist:
                dist[pk] = dist[k] + 1
                todo2.append(pk)
    tracked = [(ai, qmask, vals[j]) for j, (ai, qmask) in enumerate(pairs)]
    return pmask, tracked, dist
