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
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from delkit.errors import ParseError
from delkit.formula import And, C, Formula, K, Not, Or, Prop, is_propositional, show
from delkit.kripke import KripkeModel
from delkit.relation import Relation

__all__ = ["finitary_s5", "knows_whether"]

_MAX_FREE = 24


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
                *, source: str = "<spec>") -> KripkeModel:
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
    free = [p for p in props if p not in fixed]
    if len(free) > _MAX_FREE:
        raise ParseError(f"{len(free)} fluents are not fixed by the initial common knowledge; the explicit "
                         f"initial model would have 2^{len(free)} worlds (limit 2^{_MAX_FREE})", source=source)
    n = 1 << len(free)
    val = np.zeros((n, len(props)), dtype=bool)
    pidx = {p: i for i, p in enumerate(props)}
    codes = np.arange(n, dtype=np.int64)
    for j, p in enumerate(free):
        val[:, pidx[p]] = ((codes >> (len(free) - 1 - j)) & 1).astype(bool)
    for p, v in fixed.items():
        val[:, pidx[p]] = v
    flat = KripkeModel(props, (), val, {}, ())
    keep = np.ones(n, dtype=bool)
    for f in prop_filters:
        keep &= flat.check(f)
    val = val[keep]
    if val.shape[0] == 0:
        raise ParseError("no valuation satisfies the initial common knowledge", source=source)
    flat = KripkeModel(props, (), val, {}, ())
    m = val.shape[0]
    rels: dict[str, Relation] = {}
    for a in agents:
        lab = np.zeros(m, dtype=np.int64)
        for psi in kw[a]:
            lab = lab * 2 + flat.check(psi).astype(np.int64)
        rels[a] = Relation.from_labels(lab)
    match = np.ones(m, dtype=bool)
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
    model = KripkeModel(props, agents, val, rels, (int(hits[0]),))
    everyone = tuple(sorted(agents))
    for phi, where in common:
        if not model.holds(C(everyone, phi)) or not model.holds(phi):
            raise ParseError(f"initial statement C({show(phi)}) is not made true by the finitary-S5 "
                             f"construction (supported: fluent formulas and B(i,ψ) | B(i,-ψ) under C)",
                             source=where)
    for phi, where in others:
        if not model.holds(phi):
            raise ParseError(f"initial statement {show(phi)} does not hold in the initial state",
                             source=where)
    return model
