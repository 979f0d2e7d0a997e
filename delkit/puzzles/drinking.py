"""Three (or n) logicians walk into a bar, solved with public announcements.

The bartender asks "Does everyone want a drink?". Proposition ``w<i>``: logician i wants one; logician i
knows only her own wish (partition label: the bit ``w_i``). Logicians answer in turn; an answer is the
public announcement of the true one of

* "yes"          ``K_i ⋀_j w_j``,
* "no"           ``K_i ¬⋀_j w_j``,
* "I don't know" ``¬Kw_i ⋀_j w_j``.

Literature answer: if everybody wants a drink, logicians 1…n−1 say "I don't know" and the last says
"yes"; otherwise the first logician who does not want one says "no" (those before her "I don't know")
and everyone after her knows the answer is "no".

Symbolically (:func:`drinking_structure`, SMCDEL's ``thirstyScene``): V = {w_i}, θ = ⊤, O_i = {w_i}; the
same protocol runs on it (``solve_drinking(…, symbolic=True)``), and :func:`thirsty_formula` is SMCDEL's
single nested formula ``⋀_k ¬Kw_k all ∧ [!¬Kw_1 all]…[!¬Kw_{n−1} all] K_n all`` (true iff all want).
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Any

import numpy as np

from delkit.logic.formula import Announce, Formula, K, Kw, Not, Prop, conj
from delkit.models.kripke import KripkeModel
from delkit.models.relation import Relation

__all__ = ["DrinkingResult", "drinking_model", "drinking_structure", "solve_drinking", "thirsty_formula",
           "check_thirsty"]


@dataclass(frozen=True)
class DrinkingResult:
    """The answers in turn; ``seconds``: CPU time of building the model/structure and running the protocol."""

    wants: tuple[bool, ...]
    answers: tuple[str, ...]
    engine: str = "explicit"
    seconds: float = 0.0

    def as_dict(self) -> dict:
        return {"puzzle": "drinking", "engine": self.engine, "wants": list(self.wants),
                "answers": list(self.answers), "seconds": self.seconds}


def drinking_model(wants: tuple[bool, ...]) -> KripkeModel:
    """2^n worlds (bitmask of who wants a drink); logician i's label is bit i. Actual: ``wants``."""
    n = len(wants)
    w = np.arange(1 << n, dtype=np.int64)
    bits = np.int64(1) << np.arange(n, dtype=np.int64)
    val = (w[:, None] & bits[None, :]) != 0
    rels = {f"l{i}": Relation.from_labels(val[:, i].astype(np.int64)) for i in range(n)}
    actual = int(sum(1 << i for i, x in enumerate(wants) if x))
    return KripkeModel(tuple(f"w{i}" for i in range(n)), tuple(rels), val, rels, (actual,))


def drinking_manager(n: int) -> Any:
    """The BDD manager :func:`drinking_structure` creates unless given one: sized to the puzzle (peak nodes
    ~1.2 n^2: n = 400, 187 k)."""
    from delkit.backends.symbolic import new_manager, puzzle_memory

    return new_manager(memory_estimate=puzzle_memory(2 * n ** 2))


def drinking_structure(wants: tuple[bool, ...], *, bdd: Any = None) -> Any:
    """The knowledge structure: V = {w_i}, θ = ⊤, logician ``l<i>`` observes w_i; actual state ``wants``
    (on ``bdd``, by default a fresh :func:`drinking_manager`)."""
    from delkit.backends.symbolic import KnowledgeStructure

    props = [f"w{i}" for i in range(len(wants))]
    mgr = drinking_manager(len(props)) if bdd is None else bdd
    return KnowledgeStructure.create(props, observed={f"l{i}": [p] for i, p in enumerate(props)},
                                     actual=conj(Prop(p) if w else Not(Prop(p)) for p, w in zip(props, wants,
                                                                                                 strict=True)),
                                     bdd=mgr)


def solve_drinking(wants: tuple[bool, ...], *, symbolic: bool = False) -> DrinkingResult:
    """Each logician in turn announces her truthful answer; returns the answers.

    ``symbolic`` runs the same protocol on :func:`drinking_structure` (BDDs; hundreds of logicians).
    """
    if symbolic:
        from delkit.backends.symbolic import prepare

        prepare()  # imports and the interpreter's first full garbage collection before the clock starts
    t0 = time.process_time()
    model = drinking_structure(wants) if symbolic else drinking_model(wants)
    agents = [f"l{i}" for i in range(len(wants))]
    everyone = conj(Prop(f"w{i}") for i in range(len(wants)))
    answers = []
    for agent in agents:
        options = (("yes", K(agent, everyone)), ("no", K(agent, Not(everyone))),
                   ("I don't know", Not(Kw(agent, everyone))))
        word, phi = next((word, phi) for word, phi in options if model.holds(phi))
        answers.append(word)
        model = model.announce(phi)
    return DrinkingResult(tuple(wants), tuple(answers), "symbolic" if symbolic else "explicit",
                          time.process_time() - t0)


def thirsty_formula(n: int) -> Formula:
    """SMCDEL's ``thirstyF n``: nobody knows whether all want, and after the first n−1 logicians announce
    that they don't know, the last one knows that all want: true at the state where everybody wants."""
    everyone = conj(Prop(f"w{i}") for i in range(n))

    def does_not_know(i: int) -> Formula:
        return Not(Kw(f"l{i}", everyone))

    stack: Formula = K(f"l{n - 1}", everyone)
    for i in reversed(range(n - 1)):
        stack = Announce(does_not_know(i), stack)
    return conj([conj(does_not_know(i) for i in range(n)), stack])


def check_thirsty(n: int, *, symbolic: bool = True, bdd: Any = None) -> tuple[bool, float]:
    """Truth of :func:`thirsty_formula` at the state where all n want (SMCDEL's ``thirstyCheck``), and the
    CPU seconds of building the structure and evaluating the formula (formula construction included;
    manager creation too unless a fresh manager ``bdd`` is given, :func:`drinking_manager`)."""
    if symbolic:
        from delkit.backends.symbolic import prepare

        prepare()  # imports and the interpreter's first full garbage collection before the clock starts
    t0 = time.process_time()
    wants = (True,) * n
    model = drinking_structure(wants, bdd=bdd) if symbolic else drinking_model(wants)
    ok = model.holds(thirsty_formula(n))
    return bool(ok), time.process_time() - t0
