"""The finitary-S5 initial state that EFP builds from ``initially`` statements.

Given the fluents F, the agents AG, the common-knowledge statements ``initially C(AG, φ)`` and the
pointed-world literals, the initial pointed Kripke model is (Son et al.'s finitary S5 theories, as
EFP's ``kstate::build_initial_prune``):

* worlds: every valuation of F that satisfies every *propositional* part φ of the C statements;
* relations: start from the total relation for every agent; for every statement
  ``C(B(i, ψ) ∨ B(i, ¬ψ))`` (i knows whether ψ, ψ propositional) remove the i-edges between worlds that
  disagree on ψ. Each relation stays an equivalence (a partition: S5);
* pointed world: the unique world satisfying the initial literals.

Other modal statements (e.g. ``C(¬B(i,ψ) ∧ ¬B(i,¬ψ))``, which says i is ignorant — the default) add no
structure; after construction *every* initial statement is checked on the model, and a statement the
construction does not make true is reported as an error instead of being silently ignored.

The worlds are found without enumerating all valuations (:func:`models`): unit propagation, then the
constraints are split into independent components (conjuncts sharing no fluent); a component over few
fluents is enumerated with numpy, a larger one is split on a top-level disjunction (DPLL-style, each branch
propagated) and what is left goes to a BDD (``dd.cudd``, imported only then: it costs 0.3 s of start-up);
the worlds are the product of the components' models with the unconstrained fluents. A ``deadline`` is
honoured throughout (:class:`planners.lang.epddl2026.LoadTimeout`).

Small tasks (every component over at most ``_SPLIT_VARS`` fluents, at most :data:`PLAIN_WORLDS` worlds) are
built with integers only (:func:`plain_models`, :func:`plain_labels`: the same worlds in the same order and
the same partitions) as a :class:`delkit.backends.compact.PlainModel`, their initial statements checked on the
compact backend: planning them never imports numpy, whose import is most of a small ``delkit plan``'s
start-up. ``Task.initial`` converts such a model to a KripkeModel when it is read.
"""

from __future__ import annotations

import time
from collections.abc import Sequence

from delkit._lazy import lazy_module
from delkit.backends.compact import CompactEngine, PlainModel
from delkit.errors import ModelError, ParseError, PlanningError
from delkit.logic.formula import (
    BOT,
    TOP,
    And,
    Bot,
    C,
    Formula,
    Iff,
    Implies,
    K,
    Not,
    Or,
    Prop,
    Top,
    is_propositional,
    props_of,
    show,
    substitute,
)

TYPE_CHECKING = False  # typing.TYPE_CHECKING without importing typing (start-up: delkit._records)
if TYPE_CHECKING:
    import numpy as np

    from delkit.models.kripke import KripkeModel
    from delkit.models.relation import Relation
else:  # imported when a task too large for the integer path (PlainModel) is read
    np = lazy_module("numpy")

__all__ = ["finitary_s5", "finitary_s5_epddl", "knows_whether", "models", "LoadTimeout"]

_MAX_WORLDS = 1 << 22   # refuse initial models larger than this (4 M worlds)
_NUMPY_VARS = 16        # components over at most this many fluents are enumerated with numpy, ...
_SPLIT_VARS = 12        # ... those over more are first split on a disjunction whose branches fix fluents


class LoadTimeout(PlanningError):
    """The time limit ran out while reading, grounding or building the initial state of a task."""


InitTimeout = LoadTimeout


def _check_deadline(deadline: float | None) -> None:
    if deadline is not None and time.monotonic() > deadline:
        raise LoadTimeout("time limit reached while building the initial state")


def _components(parts: list[Formula], support: dict | None = None) -> list[tuple[list[str], list[Formula]]]:
    """Group conjuncts into components connected by shared fluents (union-find)."""
    support = {} if support is None else support
    parent: dict[str, str] = {}

    def find(x: str) -> str:
        while parent[x] != x:
            parent[x] = parent[parent[x]]
            x = parent[x]
        return x

    supports = []
    for f in parts:
        ps = sorted(_support(f, support))
        supports.append(ps)
        for p in ps:
            parent.setdefault(p, p)
        for p in ps[1:]:
            ra, rb = find(ps[0]), find(p)
            if ra != rb:
                parent[rb] = ra
    groups: dict[str, tuple[list[str], list[Formula]]] = {}
    for f, ps in zip(parts, supports, strict=True):
        if not ps:
            continue
        r = find(ps[0])
        groups.setdefault(r, ([], []))[1].append(f)
    for p in parent:
        groups[find(p)][0].append(p)
    return list(groups.values())


def prop_eval(val: np.ndarray, pidx: dict[str, int], f: Formula) -> np.ndarray:  # noqa: C901 - one per connective
    """Truth of a propositional formula in each row of a valuation matrix (numpy; no delkit.logic.semantics, whose
    scipy.sparse.csgraph import costs 0.3 s of start-up)."""
    if isinstance(f, Prop):
        return val[:, pidx[f.name]]
    if isinstance(f, Top):
        return np.ones(val.shape[0], dtype=bool)
    if isinstance(f, Bot):
        return np.zeros(val.shape[0], dtype=bool)
    if isinstance(f, Not):
        return ~prop_eval(val, pidx, f.arg)
    if isinstance(f, And):
        out = np.ones(val.shape[0], dtype=bool)
        for g in f.args:
            out &= prop_eval(val, pidx, g)
        return out
    if isinstance(f, Or):
        out = np.zeros(val.shape[0], dtype=bool)
        for g in f.args:
            out |= prop_eval(val, pidx, g)
        return out
    if isinstance(f, Implies):
        return ~prop_eval(val, pidx, f.left) | prop_eval(val, pidx, f.right)
    if isinstance(f, Iff):
        return prop_eval(val, pidx, f.left) == prop_eval(val, pidx, f.right)
    raise ParseError(f"not a propositional formula: {show(f)}")


def _numpy_models(vars_: list[str], fs: list[Formula], deadline: float | None) -> np.ndarray:
    n = len(vars_)
    codes = np.arange(1 << n, dtype=np.int64)
    val = ((codes[:, None] >> np.arange(n - 1, -1, -1)) & 1).astype(bool)
    pidx = {p: i for i, p in enumerate(vars_)}
    keep = np.ones(1 << n, dtype=bool)
    for f in fs:
        _check_deadline(deadline)
        keep &= prop_eval(val, pidx, f)
    return val[keep]


def _bdd_models(vars_: list[str], fs: list[Formula], deadline: float | None) -> np.ndarray:
    try:
        from dd.cudd import BDD
    except ImportError:  # pragma: no cover - dd without its CUDD extension
        from dd.autoref import BDD
    bdd = BDD()
    names = {p: f"v{i}" for i, p in enumerate(vars_)}
    bdd.declare(*names.values())
    memo: dict[Formula, object] = {}

    def conv(f: Formula):
        got = memo.get(f)
        if got is not None:
            return got
        if isinstance(f, Prop):
            r = bdd.var(names[f.name])
        elif isinstance(f, Top):
            r = bdd.true
        elif isinstance(f, Bot):
            r = bdd.false
        elif isinstance(f, Not):
            r = ~conv(f.arg)
        elif isinstance(f, And):
            r = bdd.true
            for g in f.args:
                r = r & conv(g)
        elif isinstance(f, Or):
            r = bdd.false
            for g in f.args:
                r = r | conv(g)
        elif isinstance(f, Implies):
            r = ~conv(f.left) | conv(f.right)
        elif isinstance(f, Iff):
            r = conv(f.left).equiv(conv(f.right))
        else:
            raise ParseError(f"not a propositional formula: {show(f)}")
        memo[f] = r
        return r

    u = bdd.true
    for f in fs:
        _check_deadline(deadline)
        u = u & conv(f)
    count = int(bdd.count(u, nvars=len(vars_)))
    if count > _MAX_WORLDS:
        raise ParseError(f"the initial common knowledge has {count} models over {len(vars_)} fluents (limit "
                         f"{_MAX_WORLDS})")
    rows = np.zeros((count, len(vars_)), dtype=bool)
    order = list(names.values())
    for i, m in enumerate(bdd.pick_iter(u, care_vars=order)):
        if (i & 4095) == 0:
            _check_deadline(deadline)
        rows[i] = [m[v] for v in order]
    return rows


def _simplify(f: Formula) -> Formula:  # noqa: C901 - one clause per connective
    """Constant folding (after substituting fixed fluents by ⊤/⊥)."""
    if isinstance(f, (Prop, Top, Bot)):
        return f
    if isinstance(f, Not):
        a = _simplify(f.arg)
        return BOT if a == TOP else TOP if a == BOT else a.arg if isinstance(a, Not) else Not(a)
    if isinstance(f, And):
        out = []
        for g in f.args:
            g = _simplify(g)
            if g == BOT:
                return BOT
            if g != TOP:
                out.extend(g.args if isinstance(g, And) else (g,))
        return TOP if not out else out[0] if len(out) == 1 else And(tuple(out))
    if isinstance(f, Or):
        out = []
        for g in f.args:
            g = _simplify(g)
            if g == TOP:
                return TOP
            if g != BOT:
                out.extend(g.args if isinstance(g, Or) else (g,))
        return BOT if not out else out[0] if len(out) == 1 else Or(tuple(out))
    if isinstance(f, Implies):
        return _simplify(Or((Not(f.left), f.right)))
    if isinstance(f, Iff):
        a, b = _simplify(f.left), _simplify(f.right)
        if a in (TOP, BOT):
            return b if a == TOP else _simplify(Not(b))
        if b in (TOP, BOT):
            return a if b == TOP else _simplify(Not(a))
        return Iff(a, b)
    raise ParseError(f"not a propositional formula: {show(f)}")


def _assign(f: Formula, vals: dict[str, bool]) -> Formula:  # noqa: C901 - one clause per connective
    """``_simplify(substitute(f, vals as ⊤/⊥))`` in one pass, for an ``f`` that :func:`_simplify` already
    folded (it is its own fixpoint): a subformula that mentions no fluent of ``vals`` comes back as itself."""
    t = type(f)
    if t is Prop:
        v = vals.get(f.name)
        return f if v is None else (TOP if v else BOT)
    if t is Top or t is Bot:
        return f
    if t is Not:
        a = _assign(f.arg, vals)
        if a is f.arg:
            return f
        ta = type(a)
        return BOT if ta is Top else TOP if ta is Bot else a.arg if ta is Not else Not(a)
    if t is And or t is Or:
        stop, skip = (Bot, Top) if t is And else (Top, Bot)
        out: list[Formula] = []
        changed = False
        for g in f.args:
            h = _assign(g, vals)
            if h is g:
                out.append(g)
                continue
            changed = True
            th = type(h)
            if th is stop:
                return h
            if th is not skip:
                out.extend(h.args if th is t else (h,))
        if not changed:
            return f
        if not out:
            return TOP if t is And else BOT
        return out[0] if len(out) == 1 else t(tuple(out))
    return _simplify(substitute(f, {p: (TOP if v else BOT) for p, v in vals.items()}))


def _support(f: Formula, cache: dict[int, tuple[Formula, frozenset[str]]]) -> frozenset[str]:
    """The fluents of a propositional ``f`` (cached by identity; the entry keeps ``f`` alive)."""
    got = cache.get(id(f))
    if got is None:
        out: set[str] = set()
        stack = [f]
        while stack:
            g = stack.pop()
            t = type(g)
            if t is Prop:
                out.add(g.name)
            elif t is Not:
                stack.append(g.arg)
            elif t is And or t is Or:
                stack.extend(g.args)
            elif t is Implies or t is Iff:
                stack += (g.left, g.right)
            elif t is not Top and t is not Bot:
                out |= props_of(g)
        got = cache[id(f)] = (f, frozenset(out))
    return got[1]


def _propagate(parts: list[Formula], fixed: dict[str, bool],
               support: dict[int, tuple[Formula, frozenset[str]]] | None = None) -> list[Formula] | None:
    """Unit propagation: fix the literal conjuncts, substitute and fold until nothing changes (None if ⊥).

    A worklist: each round rewrites only the formulas that mention a fluent fixed in the previous round
    (found through an index fluent -> cells); a rewritten formula's conjuncts take its place, so the result
    keeps the order of a full re-simplification of every formula in every round."""
    support = {} if support is None else support
    new: dict[str, bool] = {}

    def absorb(f: Formula, cell: list) -> bool:
        """Split ``f`` into conjuncts: units into ``new``, the others into child cells of ``cell``."""
        for part in _conjuncts(f):
            u = _unit(part)
            if u is not None:
                if fixed.get(u[0], u[1]) != u[1] or new.get(u[0], u[1]) != u[1]:
                    return False
                if u[0] not in fixed:
                    new[u[0]] = u[1]
            elif type(part) is Bot:
                return False
            elif type(part) is not Top:
                child = [part]
                cell.append(child)
                for p in _support(part, support):
                    index.setdefault(p, []).append(child)
        return True

    index: dict[str, list[list]] = {}
    root: list = [None]
    for f in parts:
        if not absorb(f, root):
            return None
    while new:
        fixed.update(new)
        done, new = new, {}
        seen: set[int] = set()
        for p in done:
            for cell in index.pop(p, ()):
                if cell[0] is None or id(cell) in seen:
                    continue
                seen.add(id(cell))
                g = _assign(cell[0], done)
                if g is cell[0]:
                    continue
                cell[0] = None   # replaced by the conjuncts of g, in its place
                if not absorb(g, cell):
                    return None
    out: list[Formula] = []
    stack = [root]
    while stack:   # depth-first, children in order
        cell = stack.pop()
        if cell[0] is not None:
            out.append(cell[0])
        stack.extend(reversed(cell[1:]))
    return out


def _prepare(pidx: dict[str, int], constraints: Sequence[Formula], fixed: dict[str, bool], folded: bool,
             support: dict) -> list[tuple[list[str], list[Formula]]] | None:
    """The constraints simplified under ``fixed`` and unit-propagated (``fixed`` is extended in place), split
    into independent components (fluents, formulas); None if they are unsatisfiable."""
    if fixed:
        sub = {p: (TOP if v else BOT) for p, v in fixed.items()}
        constraints = [_simplify(substitute(f, sub)) for f in constraints]
    parts = _propagate(list(constraints) if folded else [_simplify(f) for f in constraints], fixed, support)
    if parts is None:
        return None
    comps = _components(parts, support)
    for unknown in [[p for p in fixed if p not in pidx]] + [[p for p in v if p not in pidx] for v, _ in comps]:
        if unknown:
            raise ParseError(f"the initial state mentions unknown fluent(s) {unknown}")
    return comps


PLAIN_WORLDS = 4096   # initial models up to this many worlds are built without numpy (PlainModel)


def plain_models(props: Sequence[str], constraints: Sequence[Formula], *, fixed: dict[str, bool] | None = None,
                 deadline: float | None = None) -> list[int] | None:
    """:func:`models` as bit masks over ``props`` (bit i: ``props[i]``), in the same order, computed with
    integers only — or None when the task is not small (a component over more than ``_SPLIT_VARS`` fluents,
    or more than :data:`PLAIN_WORLDS` worlds): the caller then uses :func:`models`."""
    props = tuple(props)
    pidx = {p: i for i, p in enumerate(props)}
    fixed = dict(fixed or {})
    comps = _prepare(pidx, constraints, fixed, False, {})
    if comps is None:
        return []
    blocks: list[list[int]] = []  # per component: its models as masks over props
    total = 1
    for vars_, fs in comps:
        _check_deadline(deadline)
        n = len(vars_)
        if n > _SPLIT_VARS:
            return None
        fns = [_pfun(f, {p: 1 << (n - 1 - i) for i, p in enumerate(vars_)}) for f in fs]  # vars_[0]: top bit
        bits = [1 << pidx[p] for p in vars_]
        rows = []
        for code in range(1 << n):
            if all(fn(code) for fn in fns):
                m = 0
                for i, b in enumerate(bits):
                    if (code >> (n - 1 - i)) & 1:
                        m |= b
                rows.append(m)
        if not rows:
            return []
        blocks.append(rows)
        total *= len(rows)
        if total > PLAIN_WORLDS:
            return None
    covered = {pidx[p] for vars_, _ in comps for p in vars_} | {pidx[p] for p in fixed}
    for i in range(len(props)):
        if i not in covered:
            blocks.append([0, 1 << i])
            total *= 2
            if total > PLAIN_WORLDS:
                return None
    base = 0
    for p, v in fixed.items():
        if v:
            base |= 1 << pidx[p]
    out = [base]
    for rows in blocks:  # mixed-radix product, first block varies slowest
        out = [m | r for m in out for r in rows]
    return out


def _pfun(f: Formula, bit: dict[str, int]):  # noqa: C901 - one clause per connective
    """A propositional formula as a function of a valuation given as an int (``bit[p]``: the bit of p)."""
    if isinstance(f, Prop):
        b = bit[f.name]
        return lambda v: bool(v & b)
    if isinstance(f, Top):
        return lambda v: True
    if isinstance(f, Bot):
        return lambda v: False
    if isinstance(f, Not):
        g = _pfun(f.arg, bit)
        return lambda v: not g(v)
    if isinstance(f, And):
        gs = [_pfun(g, bit) for g in f.args]
        return lambda v: all(g(v) for g in gs)
    if isinstance(f, Or):
        gs = [_pfun(g, bit) for g in f.args]
        return lambda v: any(g(v) for g in gs)
    if isinstance(f, Implies):
        a, b = _pfun(f.left, bit), _pfun(f.right, bit)
        return lambda v: not a(v) or b(v)
    if isinstance(f, Iff):
        a, b = _pfun(f.left, bit), _pfun(f.right, bit)
        return lambda v: a(v) == b(v)
    raise ParseError(f"not a propositional formula: {show(f)}")


def plain_labels(vals: Sequence[int], pidx: dict[str, int], formulas: Sequence[Formula]) -> list[int]:
    """A partition's class labels as :func:`_kw_relations` numbers them: worlds agreeing on every formula, the
    classes ranked by their tuple of truth values (False before True)."""
    if not formulas:
        return [0] * len(vals)
    fns = [_pfun(f, {p: 1 << i for p, i in pidx.items()}) for f in formulas]
    keys = [tuple(fn(v) for fn in fns) for v in vals]
    rank = {k: i for i, k in enumerate(sorted(set(keys)))}
    return [rank[k] for k in keys]


def models(props: Sequence[str], constraints: Sequence[Formula], *, deadline: float | None = None,
           fixed: dict[str, bool] | None = None, _depth: int = 0, _folded: bool = False,
           _support_cache: dict | None = None) -> np.ndarray:
    """Every valuation of ``props`` (a worlds × props boolean array) satisfying all ``constraints``
    (propositional) and the ``fixed`` fluent values, without enumerating the unconstrained product.

    Unit propagation first; then a component over more than ``_SPLIT_VARS`` fluents is split on a top-level
    disjunction whose branches fix fluents (each disjunct propagated in turn, at most 3 levels deep), one
    over at most ``_NUMPY_VARS`` fluents is otherwise enumerated with numpy, and only what remains goes to a
    BDD."""
    props = tuple(props)
    pidx = {p: i for i, p in enumerate(props)}
    empty = np.zeros((0, len(props)), dtype=bool)
    fixed = dict(fixed or {})
    support: dict[int, tuple[Formula, frozenset[str]]] = {} if _support_cache is None else _support_cache
    comps = _prepare(pidx, constraints, fixed, _folded, support)
    if comps is None:
        return empty
    blocks: list[tuple[list[int], np.ndarray]] = []
    for vars_, fs in comps:
        _check_deadline(deadline)
        split = None
        if len(vars_) > _SPLIT_VARS and _depth < 3:
            # the disjunction whose every branch fixes the most fluents (then the fewest branches)
            ors = [(-min(sum(1 for c in _conjuncts(d) if _unit(c)) for d in f.args), len(f.args), i, f)
                   for i, f in enumerate(fs) if isinstance(f, Or)]
            best = min(ors, default=None)
            if best is not None and (best[0] < 0 or len(vars_) > _NUMPY_VARS):
                split = best[3]
        if split is None and len(vars_) <= _NUMPY_VARS:
            rows = _numpy_models(vars_, fs, deadline)
        else:
            if split is not None:
                others = [f for f in fs if f is not split]
                got = [models(vars_, [d, *others], deadline=deadline, _depth=_depth + 1, _folded=True,
                              _support_cache=support) for d in split.args]  # (the parts are folded already)
                # (return_index: without it np.unique imports numpy.ma to test for a masked array)
                rows = (np.unique(np.concatenate(got, axis=0), axis=0, return_index=True)[0] if got
                        else np.zeros((0, len(vars_)), bool))
            else:
                rows = _bdd_models(vars_, fs, deadline)
        if rows.shape[0] == 0:
            return empty
        blocks.append(([pidx[p] for p in vars_], rows))
    covered = {i for cols, _ in blocks for i in cols} | {pidx[p] for p in fixed}
    for i in range(len(props)):
        if i not in covered:
            blocks.append(([i], np.array([[False], [True]])))
    total = 1
    for _, rows in blocks:
        total *= rows.shape[0]
    if total > _MAX_WORLDS:
        raise ParseError(f"the initial state would have {total} worlds (limit {_MAX_WORLDS}); "
                         f"{sum(1 for c, r in blocks if len(c) == 1 and r.shape[0] == 2)} fluent(s) are left "
                         f"unconstrained by the common knowledge")
    val = np.zeros((total, len(props)), dtype=bool)
    for p, v in fixed.items():
        val[:, pidx[p]] = v
    rep = total
    for cols, rows in blocks:  # mixed-radix product, first block varies slowest
        _check_deadline(deadline)
        rep //= rows.shape[0]
        idx = (np.arange(total) // rep) % rows.shape[0]
        val[:, cols] = rows[idx]
    return val


def _kw_relations(val: np.ndarray, pidx: dict[str, int], agents: Sequence[str], kw: dict[str, list[Formula]],
                  deadline: float | None) -> dict[str, Relation]:
    """Agent i's partition: the worlds agreeing on every formula i knows whether."""
    from delkit.models.relation import Relation

    rels: dict[str, Relation] = {}
    n = val.shape[0]
    for a in agents:
        _check_deadline(deadline)
        key = [prop_eval(val, pidx, f) for f in kw.get(a, [])]
        lab = np.zeros(n, dtype=np.int64)
        if key:
            _, inv = np.unique(np.stack(key, axis=1), axis=0, return_inverse=True)
            lab = np.asarray(inv).reshape(-1)
        rels[a] = Relation.from_labels(lab)
    return rels


def finitary_s5_epddl(props: Sequence[str], agents: Sequence[str], type1: Sequence[Formula],
                      type2: Sequence[Formula], type3: dict[str, list[Formula]], *, source: str = "<init>",
                      deadline: float | None = None) -> KripkeModel:
    """The EPDDL finitary-S5 initial state (plank's construction, see :mod:`planners.lang.epddl2026`):
    worlds satisfy every ``type2`` formula, designated ones also every ``type1`` formula, and agent i's
    relation links the worlds agreeing on every formula of ``type3[i]``."""
    props, agents = tuple(props), tuple(agents)
    plain = _plain_s5_epddl(props, agents, type1, type2, type3, source, deadline)
    if plain is not None:
        return plain
    val = models(props, list(type2), deadline=deadline)
    if val.shape[0] == 0:
        raise ParseError("no world satisfies the initial common knowledge ([C. All] formulas)", source=source)
    pidx = {p: i for i, p in enumerate(props)}
    des = np.ones(val.shape[0], dtype=bool)
    for f in type1:
        des &= prop_eval(val, pidx, f)
    if not des.any():
        raise ParseError("no world satisfies the initial facts together with the common knowledge "
                         "(no designated world)", source=source)
    rels = _kw_relations(val, pidx, agents, type3, deadline)
    from delkit.models.kripke import KripkeModel

    return KripkeModel(props, agents, val, rels, tuple(np.flatnonzero(des).tolist()))


def knows_whether(f: Formula) -> tuple[str, Formula] | None:
    """(i, ψ) if ``f`` is B(i,ψ) ∨ B(i,¬ψ) (either order) with ψ propositional, else None."""
    if not isinstance(f, Or) or len(f.args) != 2:
        return None
    a, b = f.args
    if not (isinstance(a, K) and isinstance(b, K) and a.agent == b.agent):
        return None
    if b.arg == Not(a.arg) and is_propositional(a.arg):
        return a.agent, a.arg
    if a.arg == Not(b.arg) and is_propositional(b.arg):
        return a.agent, b.arg
    return None


def _conjuncts(f: Formula) -> list[Formula]:
    if isinstance(f, And):
        out: list[Formula] = []
        for g in f.args:
            out.extend(_conjuncts(g))
        return out
    return [f]


def _unit(f: Formula) -> tuple[str, bool] | None:
    if isinstance(f, Prop):
        return f.name, True
    if isinstance(f, Not) and isinstance(f.arg, Prop):
        return f.arg.name, False
    return None


def finitary_s5(props: Sequence[str], agents: Sequence[str], pointed: dict[str, bool],
                common: Sequence[tuple[Formula, str]], others: Sequence[tuple[Formula, str]] = (),
                *, source: str = "<spec>", deadline: float | None = None) -> KripkeModel:
    """Build the initial model. ``common`` are the φ of ``C(...,φ)`` statements with their location
    (``"file:line:col"``), ``others`` further formulas that must hold at the pointed world."""
    props, agents = tuple(props), tuple(agents)
    fixed: dict[str, bool] = {}
    prop_filters: list[Formula] = []
    kw: dict[str, list[Formula]] = {a: [] for a in agents}
    for phi, _where in common:
        for part in _conjuncts(phi):
            u = _unit(part)
            if u is not None:
                if fixed.get(u[0], u[1]) != u[1]:
                    raise ParseError(f"the initial common knowledge is contradictory on fluent {u[0]!r}",
                                     source=source)
                fixed[u[0]] = u[1]
            elif is_propositional(part):
                prop_filters.append(part)
            else:
                k = knows_whether(part)
                if k is not None:
                    kw[k[0]].append(k[1])
    vals = plain_models(props, prop_filters, fixed=fixed, deadline=deadline)
    if vals is not None:
        return _plain_s5(props, agents, vals, kw, pointed, common, others, source, deadline)
    val = models(props, prop_filters, fixed=fixed, deadline=deadline)
    if val.shape[0] == 0:
        raise ParseError("no valuation satisfies the initial common knowledge", source=source)
    pidx = {p: i for i, p in enumerate(props)}
    rels = _kw_relations(val, pidx, agents, kw, deadline)
    _check_deadline(deadline)
    match = np.ones(val.shape[0], dtype=bool)
    for p, v in pointed.items():
        match &= val[:, pidx[p]] == v
    hits = np.flatnonzero(match)
    if hits.size == 0:
        raise ParseError("the initial literals contradict the initial common knowledge (no world satisfies "
                         "both)", source=source)
    if hits.size > 1:
        undecided = [p for p in props if p not in pointed and len(set(val[hits, pidx[p]].tolist())) > 1]
        raise ParseError(f"the initial literals do not determine the actual world: fluent(s) {undecided} are "
                         f"neither given nor fixed by common knowledge; add them (negated if false) to the "
                         f"'initially' literals", source=source)
    from delkit.models.kripke import KripkeModel

    model = KripkeModel(props, agents, val, rels, (int(hits[0]),))
    everyone = tuple(sorted(agents))
    for phi, where in common:
        _check_deadline(deadline)
        if not model.holds(C(everyone, phi)) or not model.holds(phi):
            raise ParseError(f"initial statement C({show(phi)}) is not made true by the finitary-S5 "
                             f"construction (supported: fluent formulas and B(i,ψ) | B(i,-ψ) under C)",
                             source=where)
    for phi, where in others:
        _check_deadline(deadline)
        if not model.holds(phi):
            raise ParseError(f"initial statement {show(phi)} does not hold in the initial state",
                             source=where)
    return model


# ------------------------------------------------------------------------------------- small tasks, no numpy
def _plain_s5(props: tuple[str, ...], agents: tuple[str, ...], vals: list[int], kw: dict[str, list[Formula]],
              pointed: dict[str, bool], common: Sequence[tuple[Formula, str]], others: Sequence[tuple[Formula, str]],
              source: str, deadline: float | None) -> PlainModel:
    """:func:`finitary_s5` for a small task: the same model as a PlainModel (integers only), its initial
    statements checked on the compact backend."""
    if not vals:
        raise ParseError("no valuation satisfies the initial common knowledge", source=source)
    pidx = {p: i for i, p in enumerate(props)}
    labels = {a: plain_labels(vals, pidx, kw.get(a, [])) for a in agents}
    _check_deadline(deadline)
    want = on = 0
    for p, v in pointed.items():
        want |= 1 << pidx[p]
        on |= (1 << pidx[p]) if v else 0
    hits = [w for w, v in enumerate(vals) if v & want == on]
    if not hits:
        raise ParseError("the initial literals contradict the initial common knowledge (no world satisfies "
                         "both)", source=source)
    if len(hits) > 1:
        undecided = [p for p in props if p not in pointed and len({(vals[w] >> pidx[p]) & 1 for w in hits}) > 1]
        raise ParseError(f"the initial literals do not determine the actual world: fluent(s) {undecided} are "
                         f"neither given nor fixed by common knowledge; add them (negated if false) to the "
                         f"'initially' literals", source=source)
    model = PlainModel(props, agents, vals, labels, (hits[0],))
    holds = _plain_holds(model)
    everyone = tuple(sorted(agents))
    for phi, where in common:
        _check_deadline(deadline)
        if not holds(C(everyone, phi)) or not holds(phi):
            raise ParseError(f"initial statement C({show(phi)}) is not made true by the finitary-S5 "
                             f"construction (supported: fluent formulas and B(i,ψ) | B(i,-ψ) under C)",
                             source=where)
    for phi, where in others:
        _check_deadline(deadline)
        if not holds(phi):
            raise ParseError(f"initial statement {show(phi)} does not hold in the initial state",
                             source=where)
    return model


def _plain_s5_epddl(props: tuple[str, ...], agents: tuple[str, ...], type1: Sequence[Formula],
                    type2: Sequence[Formula], type3: dict[str, list[Formula]], source: str,
                    deadline: float | None) -> PlainModel | None:
    """:func:`finitary_s5_epddl` for a small task as a PlainModel, or None (not small)."""
    vals = plain_models(props, list(type2), deadline=deadline)
    if vals is None:
        return None
    if not vals:
        raise ParseError("no world satisfies the initial common knowledge ([C. All] formulas)", source=source)
    pidx = {p: i for i, p in enumerate(props)}
    bit = {p: 1 << i for p, i in pidx.items()}
    fns = [_pfun(f, bit) for f in type1]
    des = [w for w, v in enumerate(vals) if all(fn(v) for fn in fns)]
    if not des:
        raise ParseError("no world satisfies the initial facts together with the common knowledge "
                         "(no designated world)", source=source)
    labels = {a: plain_labels(vals, pidx, type3.get(a, [])) for a in agents}
    return PlainModel(props, agents, vals, labels, des)


def _plain_holds(model: PlainModel):
    """``model.holds`` on the compact backend (the KripkeModel's for what the compact backend refuses)."""
    eng = CompactEngine(model.props, model.agents)
    state = eng.from_plain(model)

    def holds(f: Formula) -> bool:
        try:
            return eng.holds(state, f)
        except ModelError:
            return model.kripke().holds(f)
    return holds
