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
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from delkit.formula import K, Kw, Not, Prop, conj
from delkit.kripke import KripkeModel
from delkit.relation import Relation

__all__ = ["DrinkingResult", "drinking_model", "solve_drinking"]


@dataclass(frozen=True)
class DrinkingResult:
    wants: tuple[bool, ...]
    answers: tuple[str, ...]

    def as_dict(self) -> dict:
        return {"puzzle": "drinking", "wants": list(self.wants), "answers": list(self.answers)}


def drinking_model(wants: tuple[bool, ...]) -> KripkeModel:
    """2^n worlds (bitmask of who wants a drink); logician i's label is bit i. Actual: ``wants``."""
    n = len(wants)
    w = np.arange(1 << n, dtype=np.int64)
    bits = np.int64(1) << np.arange(n, dtype=np.int64)
    val = (w[:, None] & bits[None, :]) != 0
    rels = {f"l{i}": Relation.from_labels(val[:, i].astype(np.int64)) for i in range(n)}
    actual = int(sum(1 << i for i, x in enumerate(wants) if x))
    return KripkeModel(tuple(f"w{i}" for i in range(n)), tuple(rels), val, rels, (actual,))


def solve_drinking(wants: tuple[bool, ...]) -> DrinkingResult:
    """Each logician in turn announces her truthful answer; returns the answers."""
    model = drinking_model(wants)
    everyone = conj(Prop(p) for p in model.props)
    answers = []
    for agent in model.agents:
        options = (("yes", K(agent, everyone)), ("no", K(agent, Not(everyone))),
                   ("I don't know", Not(Kw(agent, everyone))))
        word, phi = next((word, phi) for word, phi in options if model.holds(phi))
        answers.append(word)
        model = model.announce(phi)
    return DrinkingResult(tuple(wants), tuple(answers))
