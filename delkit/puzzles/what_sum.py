"""What Sum (van Ditmarsch & Kooi, *One Hundred Prisoners and a Light Bulb*, Springer 2015, ch. 4 "What
is my number?"; SMCDEL's ``SMCDEL.Examples.WhatSum``).

Anne, Bill and Cath each have a positive integer on their forehead; they see the others' numbers, not
their own, and it is common knowledge that one number is the sum of the other two. Anne says "I don't know
my number", then Bill, then Cath say the same; then Anne says "I know my number: it is 50". What are the
other two numbers?

Literature answer: Bill has 20 and Cath has 30.

Two ways to the answer:

* **Unbounded** (:func:`exact_solutions`, the default of :func:`solve_what_sum`): the puzzle's own model,
  all positive triples, decided exactly by a finite argument. An agent who sees y and z considers possible
  her number y + z and |y − z| (when positive), nothing else; so whether a triple survives the three
  announcements, and whether Anne then knows, depends only on the few triples reachable from it in at most
  four such steps (:func:`decide`, which inspects exactly those). Anne says A: her candidates are
  (A, b, A − b), finitely many, and the two families (A, b, b + A), (A, b + A, b) for every b ≥ 1. On a
  family every triple inspected is a pair of linear forms in b, so all the comparisons the decision makes
  (sign of a difference, equality) come out the same for every b above a threshold T that the decision
  itself computes (:class:`_Large`: b as a formal large number, each comparison records the b past which
  it is settled); the family is decided once for all b > T, and b ≤ T one by one.
* **Bounded** (``bound=B``, SMCDEL's encoding): numbers 1…B in binary, bits ``a*``, ``b*``, ``c*``; θ = the
  disjunction of the triples where one is the sum of the other two; Anne observes ``b* c*``, Bill ``a* c*``,
  Cath ``a* b*``; "Anne knows her number" is ``⋁_x K_anne (a = x)``. Near the bound an agent rules out
  x + y > B, which the puzzle does not: the bounded model is exact on a triple exactly when every triple
  :func:`decide` inspects for it is within the bound (:func:`support`), and ``certified`` lists the
  solutions for which that holds. A finite bound never singles (50, 20, 30) out by itself (the triples
  near the bound give spurious solutions), so the bounded model answers the question only together with
  the support check.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Any

import numpy as np

from delkit.logic.formula import Formula, K, Not, Prop, conj, disj
from delkit.puzzles._common import encode_bits

__all__ = ["WhatSumResult", "what_sum_structure", "solve_what_sum", "number_is", "decide", "support",
           "exact_solutions", "ExactWhatSum"]

AGENTS = ("anne", "bill", "cath")


@dataclass(frozen=True)
class WhatSumResult:
    """``solutions``: the (a, b, c) where Anne, after the three "I don't know"s, knows her number and it is
    ``anne_says``. Unbounded (``bound`` None, engine "unbounded"): exact; ``threshold`` is the T past which
    the families (A, b, b + A), (A, b + A, b) were decided at once, ``states`` None. Bounded: ``states`` after
    the three "I don't know"s, ``solutions`` those of the bounded model and ``certified`` the ones on which the
    bound provably does not matter (:func:`support` <= bound); :meth:`as_dict` adds the unbounded answer and
    whether the bounded one equals it. ``seconds``: CPU time."""

    bound: int | None
    anne_says: int
    states: int | None
    solutions: tuple[tuple[int, int, int], ...]
    engine: str
    seconds: float
    certified: tuple[tuple[int, int, int], ...] = ()
    threshold: int | None = None

    def as_dict(self) -> dict:
        out = {"puzzle": "what-sum", "engine": self.engine, "bound": self.bound, "anne_says": self.anne_says,
               "states_after_three_dont_knows": self.states, "solutions": [list(s) for s in self.solutions],
               "seconds": self.seconds}
        if self.bound is None:
            out["exact"] = True
            out["family_threshold"] = self.threshold
        else:
            truth = exact_solutions(self.anne_says).solutions
            out["exact"] = tuple(self.solutions) == truth  # the bounded answer is the puzzle's
            out["certified_solutions"] = [list(s) for s in self.certified]
            out["unbounded_solutions"] = [list(s) for s in truth]
        return out


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
    from delkit.backends.symbolic import KnowledgeStructure, declare, new_manager

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
    from delkit.models.kripke import KripkeModel
    from delkit.models.relation import Relation

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


def solve_what_sum(bound: int | None = None, anne_says: int = 50, *, symbolic: bool = True) -> WhatSumResult:
    """Announce "Anne, Bill, Cath: I don't know my number" in turn; return the triples where Anne then
    knows her number and it is ``anne_says``: exactly (unbounded, :func:`exact_solutions`) when ``bound``
    is None, else on the bounded model (``symbolic``: knowledge structure, or explicit), with the certified
    solutions."""
    if bound is None:
        t0 = time.process_time()
        exact = exact_solutions(anne_says)
        return WhatSumResult(None, anne_says, None, exact.solutions, "unbounded", time.process_time() - t0,
                             exact.solutions, exact.threshold)
    if symbolic:
        from delkit.backends.symbolic import prepare

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
    seconds = time.process_time() - t0
    certified = tuple(t for t in sols if support(t) <= bound)
    return WhatSumResult(bound, anne_says, states, tuple(sols), "symbolic" if symbolic else "explicit", seconds,
                         certified)


# ----------------------------------------------------------------------------- the unbounded puzzle


def _alternatives(t: tuple, i: int) -> list[tuple]:
    """The other triples agent i (0 Anne, 1 Bill, 2 Cath) considers possible at ``t``: the same two numbers
    she sees, her own the sum or the (positive) difference of them."""
    y, z = (t[j] for j in range(3) if j != i)
    out = []
    for v in (y + z, abs(y - z)):
        if v > 0 and v != t[i]:
            out.append(t[:i] + (v,) + t[i + 1:])
    return out


def _survives(t: tuple, stage: int, seen: set | None, memo: dict) -> bool:
    """Whether ``t`` is left after the first ``stage`` announcements (Anne, Bill, Cath: "I don't know"): it
    was left after stage − 1 and the speaker had another triple left then. ``seen`` collects every triple
    inspected."""
    if seen is not None:
        seen.add(t)
    if stage == 0:
        return True
    key = (t, stage)
    hit = memo.get(key)
    if hit is None:
        hit = memo[key] = _survives(t, stage - 1, seen, memo) and any(
            _survives(u, stage - 1, seen, memo) for u in _alternatives(t, stage - 1))
    return hit


def decide(t: tuple, *, seen: set | None = None) -> tuple[bool, bool]:
    """In the unbounded puzzle: whether triple ``t`` is left after the three "I don't know"s, and whether
    Anne then knows her number there. Exact: it inspects the triples at most four steps from ``t`` (each
    step replaces one number by the sum or the difference of the other two), which ``seen`` collects."""
    memo: dict = {}
    left = _survives(t, 3, seen, memo)
    knows = left and not any(_survives(u, 3, seen, memo) for u in _alternatives(t, 0))
    return left, knows


def support(t: tuple[int, int, int]) -> int:
    """The largest number in a triple :func:`decide` inspects for ``t`` (``t`` included): a bounded model
    with bound >= this holds every triple the decision depends on and so decides ``t`` as the unbounded
    puzzle does. At most 16 · max(t): each of the four steps at most doubles the largest number."""
    seen: set = set()
    decide(tuple(int(x) for x in t), seen=seen)
    return max(max(u) for u in seen)


class _Large:
    """``alpha · b + beta`` for a formal large b (the parameter of a family of triples): comparisons are
    settled as for every b above a threshold, which each comparison raises to what it needs (``Threshold``)."""

    __slots__ = ("alpha", "beta", "limit")

    def __init__(self, alpha: int, beta: int, limit: list[int]) -> None:
        self.alpha, self.beta, self.limit = alpha, beta, limit

    def _sign(self) -> int:
        """The sign for every b > limit[0] (raised to |beta| / |alpha| when alpha ≠ 0)."""
        if self.alpha:
            self.limit[0] = max(self.limit[0], -(-abs(self.beta) // abs(self.alpha)))
            return 1 if self.alpha > 0 else -1
        return (self.beta > 0) - (self.beta < 0)

    def __add__(self, other: _Large) -> _Large:
        return _Large(self.alpha + other.alpha, self.beta + other.beta, self.limit)

    def __sub__(self, other: _Large) -> _Large:
        return _Large(self.alpha - other.alpha, self.beta - other.beta, self.limit)

    def __abs__(self) -> _Large:
        return self if self._sign() >= 0 else _Large(-self.alpha, -self.beta, self.limit)

    def __gt__(self, zero: int) -> bool:
        if zero != 0:
            raise ValueError("_Large compares with 0 only")
        return self._sign() > 0

    def __eq__(self, other: object) -> bool:
        return isinstance(other, _Large) and (self - other)._sign() == 0

    def __ne__(self, other: object) -> bool:
        return not self == other

    def __hash__(self) -> int:  # equal forms hash alike; distinct forms compare unequal past the threshold
        return hash((self.alpha, self.beta))


@dataclass(frozen=True)
class ExactWhatSum:
    """:func:`exact_solutions`: the solutions, the threshold T past which both families were decided at once
    (every b > T: Anne does not know), and how many triples were decided one by one."""

    anne_says: int
    solutions: tuple[tuple[int, int, int], ...]
    threshold: int
    decided_one_by_one: int


def exact_solutions(anne_says: int = 50) -> ExactWhatSum:
    """The triples (A, b, c), A = ``anne_says``, where Anne knows her number after the three "I don't know"s,
    in the unbounded puzzle (module docstring): the families (A, b, b + A) and (A, b + A, b) decided for
    every b past a threshold T at once, the remaining finitely many triples one by one with :func:`decide`.
    Raises :class:`~delkit.errors.ModelError` if a whole family were solutions (infinitely many)."""
    from delkit.errors import ModelError

    a = int(anne_says)
    if a < 1:
        raise ModelError(f"what-sum: Anne's number must be a positive integer, got {anne_says}")
    limit = [0]
    big_a, b = _Large(0, a, limit), _Large(1, 0, limit)
    for family in ((big_a, b, b + big_a), (big_a, b + big_a, b)):
        if decide(family)[1]:
            raise ModelError(f"what-sum: Anne knows {a} on a whole family of triples: infinitely many solutions")
    threshold = limit[0]
    candidates = {(a, x, a - x) for x in range(1, a)}
    candidates |= {(a, x, x + a) for x in range(1, threshold + 1)} | {(a, x + a, x) for x in range(1, threshold + 1)}
    sols = tuple(sorted(t for t in candidates if decide(t)[1]))
    return ExactWhatSum(a, sols, threshold, len(candidates))
