"""Product update M ⊗ E.

Worlds of M ⊗ E are the pairs (w, e) with M, w ⊨ pre(e); (w,e) R_a (v,f) iff w R_a v and e Q_a f;
the valuation of (w,e) is given by the postconditions of e evaluated in the *old* model at w, all at
once (p ↦ post_e(p), unmentioned propositions keep their value); designated pairs are those of a
designated world and a designated event. Everything is vectorised: preconditions and postconditions are
evaluated once per event as boolean vectors, relations are products of partitions (labels) or of
sparse matrices.
"""

from __future__ import annotations

from typing import Literal, overload

import numpy as np

from delkit.errors import ModelError
from delkit.events import EventModel
from delkit.kripke import KripkeModel

__all__ = ["product_update", "applicable", "preconditions", "update_sequence"]


def preconditions(model: KripkeModel, events: EventModel) -> np.ndarray:
    """Boolean matrix worlds × events: M, w ⊨ pre(e)."""
    out = np.empty((model.n_worlds, events.n_events), dtype=bool)
    for j, pre in enumerate(events.pre):
        out[:, j] = model.check(pre)
    return out


def applicable(model: KripkeModel, events: EventModel) -> bool:
    """E is applicable in M if every designated world satisfies the precondition of some designated event."""
    pre = preconditions(model, events)
    des_e = list(events.designated)
    return all(pre[w, des_e].any() for w in model.designated)


def _check_agents(model: KripkeModel, events: EventModel) -> None:
    missing = [a for a in model.agents if a not in events.relations]
    if missing:
        raise ModelError(f"event model {events.name!r} has no relation for agent(s) {missing} of the model; "
                         f"give every agent a relation (oblivious agents map events to the skip event)")
    unknown = sorted({p for m in events.post for p in m} - set(model.props))
    if unknown:
        raise ModelError(f"event model {events.name!r} assigns unknown proposition(s) {unknown}; the model has "
                         f"{list(model.props)}")


@overload
def product_update(model: KripkeModel, events: EventModel, *, return_pairs: Literal[False] = False,
                   designated: str = "product") -> KripkeModel: ...


@overload
def product_update(model: KripkeModel, events: EventModel, *, return_pairs: Literal[True],
                   designated: str = "product") -> tuple[KripkeModel, np.ndarray]: ...


def product_update(model, events, *, return_pairs=False, designated="product"):
    """M ⊗ E. With ``return_pairs`` also the (k, 2) array of (world, event) of each new world.

    ``designated="product"`` (default) keeps the pairs of designated worlds and events;
    ``designated="all"`` keeps every designated world of M paired with any event (used for [E,e]φ).
    """
    _check_agents(model, events)
    pre = preconditions(model, events)
    w_idx, e_idx = np.nonzero(pre)  # row-major: sorted by world then event
    pairs = np.stack([w_idx, e_idx], axis=1).astype(np.int64)
    val = model.valuation[w_idx].copy()
    for j, post in enumerate(events.post):
        if not post:
            continue
        rows = np.flatnonzero(e_idx == j)
        if rows.size == 0:
            continue
        for p, f in post.items():
            val[rows, model.prop_index(p)] = model.check(f)[w_idx[rows]]
    from delkit.resources import check_time

    check_time()  # the active --timeout: a product of a large model can take seconds per relation
    rels = {}
    for a in model.agents:
        rels[a] = model.relations[a].product(events.relations[a], pairs)
        check_time()
    des_w = np.zeros(model.n_worlds, dtype=bool)
    des_w[list(model.designated)] = True
    if designated == "all":
        keep = des_w[w_idx]
    else:
        des_e = np.zeros(events.n_events, dtype=bool)
        des_e[list(events.designated)] = True
        keep = des_w[w_idx] & des_e[e_idx]
    names = None
    if model.names is not None:
        names = tuple(f"{model.names[w]}.{events.events[e]}" for w, e in pairs)
    new = KripkeModel(model.props, model.agents, val, rels, tuple(np.flatnonzero(keep)), names)
    return (new, pairs) if return_pairs else new


def update_sequence(model: KripkeModel, sequence) -> KripkeModel:
    """Apply event models one after the other: (((M ⊗ E₁) ⊗ E₂) ⊗ …)."""
    for ev in sequence:
        model = product_update(model, ev)
    return model
