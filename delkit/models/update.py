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

from delkit.models.events import EventModel
from delkit.models.kripke import KripkeModel

__all__ = ["product_update", "applicable", "preconditions", "update_sequence"]


def preconditions(model: KripkeModel, events: EventModel) -> np.ndarray:
    """Boolean matrix worlds × events: M, w ⊨ pre(e)."""
    return model.preconditions(events)


def applicable(model: KripkeModel, events: EventModel) -> bool:
    """E is applicable in M if every designated world satisfies the precondition of some designated event."""
    pre = preconditions(model, events)
    des_e = list(events.designated)
    return all(pre[w, des_e].any() for w in model.designated)


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
    The construction is :meth:`KripkeModel.product <delkit.models.kripke.KripkeModel.product>`.
    """
    new, pairs = model.product(events, designated=designated)
    return (new, pairs) if return_pairs else new


def update_sequence(model: KripkeModel, sequence) -> KripkeModel:
    """Apply event models one after the other: (((M ⊗ E₁) ⊗ E₂) ⊗ …)."""
    for ev in sequence:
        model = product_update(model, ev)
    return model
