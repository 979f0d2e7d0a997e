"""Freudenthal's Sum and Product puzzle, solved with public announcements on an explicit S5 model.

Worlds are the pairs (x, y) with 1 < x < y and x + y ≤ ``limit`` (2352 worlds for 100); x and y are
encoded in binary by the propositions ``x0 x1 …`` and ``y0 y1 …``. Agent S knows the sum (its partition
label is x + y), agent P the product (label x·y). "A knows the numbers" is ``⋀_j Kw_A x_j ∧ ⋀_j Kw_A y_j``.

The dialogue (van Ditmarsch, Ruan, Verbrugge, *Sum and Product in Dynamic Epistemic Logic*, JLC 2008):

1. S: "I knew you didn't know"      — ``[!K_S ¬knows_P]``
2. P: "Now I know"                   — ``[!knows_P]``
3. S: "Now I know too"               — ``[!knows_S]``

Literature answer: exactly one world survives, (x, y) = (4, 13).
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from delkit.formula import K, Not
from delkit.kripke import KripkeModel
from delkit.puzzles._common import bit_props, encode_bits, knows_which, value_of
from delkit.relation import Relation

__all__ = ["SumProductResult", "sum_product_model", "solve_sum_product"]


@dataclass(frozen=True)
class SumProductResult:
    """Surviving pairs and the number of worlds after each announcement (initial model first)."""

    solutions: tuple[tuple[int, int], ...]
    worlds: tuple[int, ...]
    seconds: float

    def as_dict(self) -> dict:
        return {"puzzle": "sum-product", "solutions": [list(s) for s in self.solutions],
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


def solve_sum_product(limit: int = 100) -> SumProductResult:
    """Apply the three announcements; the surviving worlds are the solutions."""
    t0 = time.perf_counter()
    model = sum_product_model(limit)
    xy = model.props
    knows_p = knows_which("P", xy)
    knows_s = knows_which("S", xy)
    worlds = [model.n_worlds]
    for phi in (K("S", Not(knows_p)), knows_p, knows_s):
        model = model.announce(phi)
        worlds.append(model.n_worlds)
    return SumProductResult(tuple(_pairs(model)), tuple(worlds), time.perf_counter() - t0)
