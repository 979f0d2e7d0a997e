"""Vectorised model checking.

Bottom-up over subformulas: each subformula becomes one boolean vector over the worlds (numpy),
memoised per model. The clauses:

* ``K_a φ`` at w  iff φ holds at every v with w R_a v (a box; on KD45 models this is belief);
* ``Kw_a φ``      iff ``K_a φ ∨ K_a ¬φ``;
* ``E_G φ``       iff ``⋀_{a∈G} K_a φ``;
* ``C_G φ`` at w  iff φ holds at every v reachable from w in **one or more** steps of ``⋃_{a∈G} R_a``
  (the transitive, not reflexive-transitive, closure: on KD45 models C_G φ does not imply φ);
* ``D_G φ`` at w  iff φ holds at every v with w (⋂_{a∈G} R_a) v;
* ``[!φ]ψ`` at w  iff M,w ⊭ φ or M|φ, w ⊨ ψ;
* ``[E,e]ψ`` at w iff M,w ⊭ pre(e) or M⊗E, (w,e) ⊨ ψ.

The common-knowledge clause is a fixpoint computed to the end (backward reachability of the worlds
where φ fails), never cut at a fixed depth.
"""

from __future__ import annotations

import numpy as np

from delkit.errors import UnknownSymbolError
from delkit.logic.formula import (
    And,
    Announce,
    Bot,
    C,
    D,
    E,
    Formula,
    Iff,
    Implies,
    K,
    Kw,
    Not,
    Or,
    Prop,
    Top,
    Update,
    parse,
)

__all__ = ["evaluate", "holds", "common_reach"]


def evaluate(model, formula: Formula | str) -> np.ndarray:
    """Truth vector of ``formula`` over the worlds of ``model`` (read-only, memoised)."""
    if isinstance(formula, str):
        formula = parse(formula)
    cache = model._cache
    hit = cache.get(formula)
    if hit is not None:
        return hit
    vec = _eval(model, formula)
    vec.setflags(write=False)
    cache[formula] = vec
    return vec


def holds(model, formula: Formula | str) -> bool:
    """True iff ``formula`` holds at every designated world."""
    return model.holds(formula)


def _eval(m, f: Formula) -> np.ndarray:  # noqa: C901 - one clause per operator
    n = m.n_worlds
    if isinstance(f, Prop):
        return m.valuation[:, m.prop_index(f.name)].copy()
    if isinstance(f, Top):
        return np.ones(n, dtype=bool)
    if isinstance(f, Bot):
        return np.zeros(n, dtype=bool)
    if isinstance(f, Not):
        return ~evaluate(m, f.arg)
    if isinstance(f, And):
        out = np.ones(n, dtype=bool)
        for a in f.args:
            out &= evaluate(m, a)
        return out
    if isinstance(f, Or):
        out = np.zeros(n, dtype=bool)
        for a in f.args:
            out |= evaluate(m, a)
        return out
    if isinstance(f, Implies):
        return ~evaluate(m, f.left) | evaluate(m, f.right)
    if isinstance(f, Iff):
        return evaluate(m, f.left) == evaluate(m, f.right)
    if isinstance(f, K):
        return m.relation(f.agent).box(evaluate(m, f.arg))
    if isinstance(f, Kw):
        r = m.relation(f.agent)
        t = evaluate(m, f.arg)
        return r.box(t) | r.box(~t)
    if isinstance(f, E):
        t = evaluate(m, f.arg)
        out = np.ones(n, dtype=bool)
        for a in f.group:
            out &= m.relation(a).box(t)
        return out
    if isinstance(f, D):
        rels = [m.relation(a) for a in f.group]
        inter = rels[0]
        for r in rels[1:]:
            inter = inter.intersect(r)
        return inter.box(evaluate(m, f.arg))
    if isinstance(f, C):
        return _common(m, f.group, evaluate(m, f.arg))
    if isinstance(f, Announce):
        pre = evaluate(m, f.announced)
        out = np.ones(n, dtype=bool)
        if pre.any():
            sub = m.restrict(pre)
            out[np.flatnonzero(pre)] = evaluate(sub, f.arg)
        return out
    if isinstance(f, Update):
        model_e = f.model
        pre = evaluate(m, model_e.pre[f.event])
        out = np.ones(n, dtype=bool)
        if pre.any():
            new, pairs = m.product(model_e, designated="all")  # M ⊗ E (delkit.models.update), via the model
            sel = np.flatnonzero(pairs[:, 1] == f.event)
            out[pairs[sel, 0]] = evaluate(new, f.arg)[sel]
        return out
    raise TypeError(f"cannot evaluate {f!r}")


def common_reach(m, group) -> tuple[str, object]:
    """How C_G is computed on ``m``: ("components", labels) if all relations are partitions."""
    rels = [m.relation(a) for a in group]
    if all(r.is_partition for r in rels):
        key = ("__ccomp", tuple(group))
        lab = m._cache.get(key)
        if lab is None:
            lab = _components(m.n_worlds, [r.labels for r in rels])
            m._cache[key] = lab
        return "components", lab
    key = ("__union", tuple(group))
    u = m._cache.get(key)
    if u is None:  # the union as a Relation (numpy-only rows: no scipy import for small replays)
        u = rels[0].union(rels[1:]) if len(rels) > 1 else rels[0]
        m._cache[key] = u
    return "relation", u


def _components(n: int, labelings: list[np.ndarray]) -> np.ndarray:
    """Connected components of the union of equivalence relations (worlds linked via shared classes).

    Labels are numbered 0..k-1 in the order of each component's first world. Minimum-label propagation in
    numpy settles in a few rounds on the usual models (and does not need scipy, whose import would cost a
    small command ~0.1 s); a component of large diameter falls back to scipy's connected_components."""
    if n == 0:
        return np.zeros(0, dtype=np.int64)
    comp = np.arange(n, dtype=np.int64)
    for _ in range(32):
        old = comp
        for lab in labelings:
            low = np.full(int(lab.max()) + 1, n, dtype=np.int64)
            np.minimum.at(low, lab, comp)
            comp = low[lab]
        if np.array_equal(comp, old):
            return np.unique(comp, return_inverse=True)[1].astype(np.int64).ravel()
    import scipy.sparse as sp
    from scipy.sparse.csgraph import connected_components

    rows, cols, offset = [], [], n
    for lab in labelings:
        rows.append(np.arange(n))
        cols.append(offset + lab)
        offset += int(lab.max()) + 1
    r = np.concatenate(rows)
    c = np.concatenate(cols)
    g = sp.csr_matrix((np.ones(r.size, dtype=bool), (r, c)), shape=(offset, offset))
    _, lab = connected_components(g, directed=False)
    return lab[:n]


def _common(m, group, truth: np.ndarray) -> np.ndarray:
    for a in group:
        if a not in m.relations:
            raise UnknownSymbolError(f"unknown agent {a!r}; the model has {list(m.agents)}")
    kind, data = common_reach(m, group)
    if kind == "components":
        lab = data
        bad = np.bincount(lab, weights=~truth, minlength=int(lab.max(initial=-1)) + 1)
        return bad[lab] == 0
    union = data
    # X = worlds with a path of >= 1 steps to a world where φ fails: least fixpoint of X = pre(bad ∪ X).
    x = union.diamond(~truth)
    while True:
        nxt = x | union.diamond(x)
        if (nxt == x).all():
            break
        x = nxt
    return ~x
