"""Freudenthal's Sum and Product puzzle, solved with public announcements on an explicit S5 model.

Worlds are the pairs (x, y) with 1 < x < y and x + y ≤ ``limit`` (2352 worlds for 100); x and y are
encoded in binary by the propositions ``x0 x1 …`` and ``y0 y1 …``. Agent S knows the sum (its partition
label is x + y), agent P the product (label x·y). "A knows the numbers" is ``⋀_j Kw_A x_j ∧ ⋀_j Kw_A y_j``.

The dialogue (van Ditmarsch, Ruan, Verbrugge, *Sum and Product in Dynamic Epistemic Logic*, JLC 2008):

1. S: "I knew you didn't know"      — ``[!K_S ¬knows_P]``
2. P: "Now I know"                   — ``[!knows_P]``
3. S: "Now I know too"               — ``[!knows_S]``

Literature answer: exactly one world survives, (x, y) = (4, 13).

``solve_sum_product(…, symbolic=True)`` runs the same dialogue on SMCDEL's encoding as a knowledge
structure (:func:`sum_product_structure`: bits of x, y, x + y and x·y; S observes the sum bits, P the
product bits); :func:`smcdel_sum_product` evaluates SMCDEL's own protocol formula, whose "A knows the
numbers" is the disjunction over all pairs of ``K_A(x = a ∧ y = b)``.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Any

import numpy as np

from delkit.logic.formula import Formula, K, Not, Prop, conj, disj
from delkit.models.kripke import KripkeModel
from delkit.models.relation import Relation
from delkit.puzzles._common import bit_props, encode_bits, knows_which, value_of

__all__ = ["SumProductResult", "sum_product_model", "sum_product_structure", "solve_sum_product",
           "smcdel_sum_product"]


@dataclass(frozen=True)
class SumProductResult:
    """Surviving pairs and the number of worlds after each announcement (initial model first)."""

    solutions: tuple[tuple[int, int], ...]
    worlds: tuple[int, ...]
    seconds: float
    engine: str = "explicit"

    def as_dict(self) -> dict:
        return {"puzzle": "sum-product", "engine": self.engine, "solutions": [list(s) for s in self.solutions],
                "worlds": list(self.worlds), "seconds": self.seconds}


def sum_product_model(limit: int = 100) -> KripkeModel:
    """All pairs 1 < x < y with x + y ≤ limit; S observes x + y, P observes x·y (vectorised)."""
    x, y = np.triu_indices(limit, k=1)
    keep = (x > 1) & (x + y <= limit)
    x, y = x[keep].astype(np.int64), y[keep].astype(np.int64)
    xp, yp = bit_props("x", x), bit_props("y", y)
    val = np.concatenate([encode_bits(x, len(xp)), encode_bits(y, len(yp))], axis=1)
    rels = {"S": Relation.from_labels(x + y), "P": Relation.from_labels(x * y)}
    return KripkeModel(xp + yp, ("S", "P"), val, rels, designated=())


def _pairs(model: KripkeModel) -> list[tuple[int, int]]:
    nx = sum(p.startswith("x") for p in model.props)
    xs = value_of(model.valuation[:, :nx])
    ys = value_of(model.valuation[:, nx:])
    return [(int(a), int(b)) for a, b in zip(xs, ys, strict=True)]


def _pairs_of(limit: int) -> tuple[np.ndarray, np.ndarray]:
    x, y = np.triu_indices(limit, k=1)
    keep = (x > 1) & (x + y <= limit)
    return x[keep].astype(np.int64), y[keep].astype(np.int64)


def sum_product_structure(limit: int = 100, *, bdd: Any = None) -> Any:
    """SMCDEL's encoding as a knowledge structure: binary digits ``x* y* s* p*`` of x, y, x + y and x·y;
    θ = the disjunction of the 2352 (for 100) full assignments; S observes ``s*``, P observes ``p*``."""
    from delkit.backends.symbolic import KnowledgeStructure, declare, new_manager

    x, y = _pairs_of(limit)
    xp, yp, sp, pp = bit_props("x", x), bit_props("y", y), bit_props("s", x + y), bit_props("p", x * y)
    voc = xp + yp + sp + pp
    mgr = new_manager() if bdd is None else bdd
    declare(mgr, voc)
    bits = np.concatenate([encode_bits(x, len(xp)), encode_bits(y, len(yp)), encode_bits(x + y, len(sp)),
                           encode_bits(x * y, len(pp))], axis=1)
    law = mgr.false
    for row in bits[::-1]:  # any order gives the same BDD
        law = law | mgr.cube(dict(zip(voc, (bool(b) for b in row), strict=True)))
    ks = KnowledgeStructure.create(voc, observed={"S": sp, "P": pp}, bdd=mgr)
    return KnowledgeStructure(mgr, ks.vocabulary, law, ks.observed, law, _props=ks._props)


def _solutions(ks: Any, node: Any = None) -> list[tuple[int, int]]:
    out = []
    for st in ks.states(node):
        xv = sum(1 << int(v[1:]) for v, b in st.items() if b and v.startswith("x"))
        yv = sum(1 << int(v[1:]) for v, b in st.items() if b and v.startswith("y"))
        out.append((xv, yv))
    return sorted(out)


def solve_sum_product(limit: int = 100, *, symbolic: bool = False) -> SumProductResult:
    """Apply the three announcements; the surviving worlds (states) are the solutions.

    ``seconds`` is the CPU time of building the model/structure and the three announcements."""
    if symbolic:
        from delkit.backends.symbolic import prepare

        prepare()  # imports and the interpreter's first full garbage collection before the clock starts
    t0 = time.process_time()
    if symbolic:
        model = sum_product_structure(limit)
        xy = tuple(v for v in model.vocabulary if v[0] in "xy")
        count = model.count_states
    else:
        model = sum_product_model(limit)
        xy = model.props

        def count() -> int:
            return model.n_worlds
    knows_p = knows_which("P", xy)
    knows_s = knows_which("S", xy)
    worlds = [count()]
    for phi in (K("S", Not(knows_p)), knows_p, knows_s):
        model = model.announce(phi)
        worlds.append(model.count_states() if symbolic else model.n_worlds)
    pairs = _solutions(model) if symbolic else _pairs(model)
    return SumProductResult(tuple(pairs), tuple(worlds), time.process_time() - t0,
                            "symbolic" if symbolic else "explicit")


def _value_is(name: str, props: tuple[str, ...], value: int) -> Formula:
    return conj(Prop(p) if (value >> int(p[len(name):])) & 1 else Not(Prop(p)) for p in props)


def smcdel_sum_product(limit: int = 100, *, bdd: Any = None) -> tuple[list[tuple[int, int]], float]:
    """SMCDEL's ``sapSolutions``: the states where ``f1 ∧ [!f1]f2 ∧ [!f1][!f2]f3`` holds, with
    f1 = K_S ¬knows_P, f2 = knows_P, f3 = knows_S and knows_A = ⋁_{(x,y)} K_A(x = a ∧ y = b); returns the
    (x, y) of those states and the CPU seconds of building the structure and evaluating (formula included;
    manager creation too unless a fresh manager ``bdd``, ``delkit.backends.symbolic.new_manager()``, is given)."""
    from delkit.backends.symbolic import prepare

    prepare()  # imports and the interpreter's first full garbage collection before the clock starts

    t0 = time.process_time()
    ks = sum_product_structure(limit, bdd=bdd)
    xp = tuple(v for v in ks.vocabulary if v[0] == "x")
    yp = tuple(v for v in ks.vocabulary if v[0] == "y")
    xs, ys = _pairs_of(limit)
    are = [conj([_value_is("x", xp, int(a)), _value_is("y", yp, int(b))]) for a, b in zip(xs, ys, strict=True)]

    def knows(agent: str) -> Formula:
        return disj(K(agent, f) for f in are)

    from delkit.logic.formula import Announce

    f1, f2, f3 = K("S", Not(knows("P"))), knows("P"), knows("S")
    protocol = conj([f1, Announce(f1, f2), Announce(f1, Announce(f2, f3))])
    return _solutions(ks, ks.evaluate(protocol)), time.process_time() - t0
