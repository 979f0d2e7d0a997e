"""What Sum (van Ditmarsch & Kooi, *One Hundred Prisoners and a Light Bulb*, Springer 2015, ch. 4 "What
is my number?"; SMCDEL's ``SMCDEL.Examples.WhatSum``).

Anne, Bill and Cath each have a positive integer on their forehead; they see the others' numbers, not
their own, and it is common knowledge that one number is the sum of the other two. Anne says "I don't know
my number", then Bill, then Cath say the same; then Anne says "I know my number: it is 50". What are the
other two numbers?

Literature answer: Bill has 20 and Cath has 30.

Encoding (SMCDEL's): numbers 1…``bound`` in binary, bits ``a*``, ``b*``, ``c*``; θ = the disjunction of the
triples where one is the sum of the other two; Anne observes ``b* c*``, Bill ``a* c*``, Cath ``a* b*``;
"Anne knows her number" is ``⋁_x K_anne (a = x)``. :func:`solve_what_sum` announces the three "I don't
know"s and reads off the states where Anne then knows her number and it is ``anne_says``.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Any

import numpy as np

from delkit.formula import Formula, K, Not, Prop, conj, disj
from delkit.puzzles._common import encode_bits

__all__ = ["WhatSumResult", "what_sum_structure", "solve_what_sum", "number_is"]

AGENTS = ("anne", "bill", "cath")


@dataclass(frozen=True)
class WhatSumResult:
    """``states`` after the three "I don't know"s; ``solutions``: the (a, b, c) where Anne then knows her
    number and it is ``anne_says``; ``seconds``: CPU time of building the structure and the announcements."""

    bound: int
    anne_says: int
    states: int
    solutions: tuple[tuple[int, int, int], ...]
    engine: str
    seconds: float

    def as_dict(self) -> dict:
        return {"puzzle": "what-sum", "engine": self.engine, "bound": self.bound, "anne_says": self.anne_says,
                "states_after_three_dont_knows": self.states, "solutions": [list(s) for s in self.solutions],
                "seconds": self.seconds}


def _width(bound: int) -> int:
    return max(1, int(bound).bit_length())


def _triples(bound: int) -> np.ndarray:
    r = np.arange(1, bound + 1)
    x, y, z = np.meshgrid(r, r, r, indexing="ij")
    keep = (x + y == z) | (x + z == y) | (y + z == x)
    return np.stack([x[keep], y[keep], z[keep]], axis=1)


def number_is(who: str, value: int, width: int) -> Formula:
    """The bits of ``who``'s number (``a*``, ``b*`` or ``c*``) spell ``value``."""
    p = who[0]
    return conj(Prop(f"{p}{j}") if (value >> j) & 1 else Not(Prop(f"{p}{j}")) for j in range(width))


def knows_own(who: str, bound: int) -> Formula:
    """``⋁_x K_who (who's number = x)``."""
    w = _width(bound)
    return disj(K(who, number_is(who, x, w)) for x in range(1, bound + 1))


def what_sum_structure(bound: int = 50) -> Any:
    """SMCDEL's knowledge structure for numbers up to ``bound``."""
    from delkit.symbolic import KnowledgeStructure, declare, new_manager

    w = _width(bound)
    bits = {p: [f"{p}{j}" for j in range(w)] for p in "abc"}
    voc = bits["a"] + bits["b"] + bits["c"]
    mgr = new_manager()
    declare(mgr, voc)
    t = _triples(bound)
    rows = np.concatenate([encode_bits(t[:, 0], w), encode_bits(t[:, 1], w), encode_bits(t[:, 2], w)], axis=1)
    law = mgr.false
    for row in rows:
        law = law | mgr.cube(dict(zip(voc, (bool(b) for b in row), strict=True)))
    observed = {"anne": bits["b"] + bits["c"], "bill": bits["a"] + bits["c"], "cath": bits["a"] + bits["b"]}
    ks = KnowledgeStructure.create(voc, observed=observed, bdd=mgr)
    return KnowledgeStructure(mgr, ks.vocabulary, law, ks.observed, law, _props=ks._props)


def _what_sum_model(bound: int) -> Any:
    """The explicit S5 model of the same puzzle: one world per triple; Anne's partition is (b, c), etc."""
    from delkit.kripke import KripkeModel
    from delkit.relation import Relation

    w = _width(bound)
    t = _triples(bound)
    val = np.concatenate([encode_bits(t[:, i], w) for i in range(3)], axis=1)
    props = tuple(f"{p}{j}" for p in "abc" for j in range(w))
    span = bound + 1
    rels = {"anne": Relation.from_labels(t[:, 1] * span + t[:, 2]),
            "bill": Relation.from_labels(t[:, 0] * span + t[:, 2]),
            "cath": Relation.from_labels(t[:, 0] * span + t[:, 1])}
    return KripkeModel(props, AGENTS, val, rels, designated=tuple(range(len(t))))


def _decode(state: dict[str, bool], w: int) -> tuple[int, int, int]:
    return tuple(sum(1 << j for j in range(w) if state[f"{p}{j}"]) for p in "abc")  # type: ignore[return-value]


def solve_what_sum(bound: int = 50, anne_says: int = 50, *, symbolic: bool = True) -> WhatSumResult:
    """Announce "Anne, Bill, Cath: I don't know my number" in turn; return the triples where Anne then
    knows her number and it is ``anne_says``."""
    if symbolic:
        from delkit.symbolic import prepare

        prepare()
    w = _width(bound)
    t0 = time.process_time()
    model = what_sum_structure(bound) if symbolic else _what_sum_model(bound)
    for who in AGENTS:
        model = model.announce(Not(knows_own(who, bound)))
    final = conj([knows_own("anne", bound), number_is("anne", anne_says, w)])
    if symbolic:
        states = model.count_states()
        sols = sorted(_decode(s, w) for s in model.states(model.evaluate(final)))
    else:
        states = model.n_worlds
        truth = model.check(final)
        sols = sorted(tuple(int(sum(int(b) << j for j, b in enumerate(model.valuation[i, k * w:(k + 1) * w])))
                            for k in range(3)) for i in np.flatnonzero(truth))
    return WhatSumResult(bound, anne_says, states, tuple(sols), "symbolic" if symbolic else "explicit",
                         time.process_time() - t0)
