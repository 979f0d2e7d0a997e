"""Composition of event models (macros).

E₁;E₂ has the events (e₁, e₂) with

* pre(e₁,e₂)  = pre₁(e₁) ∧ [E₁,e₁] pre₂(e₂)
* post(e₁,e₂)(p) = post₂(e₂)(p)[q := post₁(e₁)(q)]   (substitution; postconditions are propositional)
* (e₁,e₂) Q_a (f₁,f₂) iff e₁ Q¹_a f₁ and e₂ Q²_a f₂
* designated: pairs of designated events.

Theorem (tested): (M ⊗ E₁) ⊗ E₂ is bisimilar (indeed isomorphic) to M ⊗ (E₁;E₂).
Pairs whose composed precondition is unsatisfiable can be pruned with ``prune=True`` (z3, propositional
preconditions only), which keeps macros small.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from delkit.errors import ModelError
from delkit.logic.formula import Formula, Prop, Update, conj, is_propositional, substitute
from delkit.models.events import EventModel

__all__ = ["compose", "compose_all"]


def compose(e1: EventModel, e2: EventModel, *, name: str | None = None, prune: bool = False) -> EventModel:
    """The composition E₁;E₂ (first E₁, then E₂)."""
    if set(e1.agents) != set(e2.agents):
        raise ModelError(f"cannot compose {e1.name!r} and {e2.name!r}: agents differ "
                         f"({sorted(e1.agents)} vs {sorted(e2.agents)})")
    n1, n2 = e1.n_events, e2.n_events
    pairs = np.array([(i, j) for i in range(n1) for j in range(n2)], dtype=np.int64).reshape(-1, 2)
    pres: list[Formula] = []
    posts: list[dict[str, Formula]] = []
    for i, j in pairs:
        pre2 = e2.pre[j]
        if is_propositional(pre2):
            # [E₁,e₁]ψ for propositional ψ reduces to ψ with post₁ substituted (pre₁ is conjoined anyway)
            after = substitute(pre2, e1.post[i])
        else:
            after = Update(e1, int(i), pre2, e1.name)
        pres.append(conj([e1.pre[i], after]))
        post: dict[str, Formula] = {}
        for p in set(e1.post[i]) | set(e2.post[j]):
            post[p] = substitute(e2.post[j].get(p, Prop(p)), e1.post[i])
        posts.append(post)
    keep = np.ones(len(pairs), dtype=bool)
    if prune:
        from delkit.logic.propositional import satisfiable

        for k, f in enumerate(pres):
            if is_propositional(f) and not satisfiable(f):
                keep[k] = False
        des_ok = [k for k in range(len(pairs)) if keep[k] and pairs[k, 0] in e1.designated
                  and pairs[k, 1] in e2.designated]
        if not des_ok:  # keep at least the designated structure so the macro stays well-formed
            keep[[k for k in range(len(pairs)) if pairs[k, 0] in e1.designated and pairs[k, 1] in e2.designated]] = True
    idx = np.flatnonzero(keep)
    pairs = pairs[idx]
    rels = {a: e1.relations[a].product(e2.relations[a], pairs) for a in e1.agents}
    names = tuple(f"{e1.events[i]};{e2.events[j]}" for i, j in pairs)
    des = tuple(k for k, (i, j) in enumerate(pairs) if i in e1.designated and j in e2.designated)
    return EventModel(names, tuple(e1.agents), tuple(pres[k] for k in idx), tuple(posts[k] for k in idx),
                      rels, des, name or f"{e1.name};{e2.name}")


def compose_all(models: Sequence[EventModel], *, name: str | None = None, prune: bool = False) -> EventModel:
    """E₁;E₂;…;Eₙ (left to right)."""
    if not models:
        raise ModelError("compose_all needs at least one event model")
    out = models[0]
    for m in models[1:]:
        out = compose(out, m, prune=prune)
    return out if name is None else out.renamed(name)


