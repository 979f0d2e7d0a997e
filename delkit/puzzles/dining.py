"""Dining cryptographers (Chaum 1988), solved with public announcements.

n cryptographers sit round a table; either one of them paid or the NSA did. Propositions ``p<i>``
(cryptographer i paid) and ``c<i>`` (the coin shared by i and i+1 mod n shows heads). Worlds: payer ∈
{nobody, 0, …, n−1} × 2^n coins. Cryptographer i observes ``p_i``, ``c_{i-1}`` and ``c_i`` (partition
label: those three bits). Each cryptographer i says ``s_i = c_{i-1} ⊕ c_i ⊕ p_i``; the protocol is the
public announcement of the true value of every s_i.

Facts checked (Chaum; van Eijck & Orzan, *Epistemic verification of anonymity*, 2007): after the
announcements it is common knowledge whether a cryptographer paid (the parity ⊕_i s_i = ⋁_i p_i), and
if cryptographer k paid, no other cryptographer i knows who: ``¬K_i p_j`` for every j ≠ i.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from delkit.formula import C, Formula, Iff, K, Kw, Not, Prop, conj, disj
from delkit.kripke import KripkeModel
from delkit.relation import Relation

__all__ = ["DiningResult", "anonymity_formula", "dining_model", "xor", "said", "solve_dining"]


@dataclass(frozen=True)
class DiningResult:
    """``common_knows_whether_paid``: C_G ⋁p ∨ C_G ¬⋁p at the actual world after the protocol;
    ``someone_paid_known``: everybody knows whether a cryptographer paid; ``learned_payer[i]``: whether
    cryptographer i knows who paid (or that nobody did); ``anonymous``: :func:`anonymity_formula` holds
    for every cryptographer."""

    n: int
    payer: int | None
    common_knows_whether_paid: bool
    someone_paid_known: bool
    learned_payer: tuple[bool, ...]
    anonymous: bool

    def as_dict(self) -> dict:
        return {"puzzle": "dining", "n": self.n, "payer": self.payer,
                "common_knows_whether_paid": self.common_knows_whether_paid,
                "someone_paid_known": self.someone_paid_known, "learned_payer": list(self.learned_payer),
                "anonymous": self.anonymous}


def xor(a: Formula, b: Formula) -> Formula:
    """a ⊕ b = ¬(a ↔ b)."""
    return Not(Iff(a, b))


def said(i: int, n: int) -> Formula:
    """s_i = c_{i-1} ⊕ c_i ⊕ p_i."""
    return xor(xor(Prop(f"c{(i - 1) % n}"), Prop(f"c{i}")), Prop(f"p{i}"))


def dining_model(n: int = 3, payer: int | None = 0, coins: int = 0) -> KripkeModel:
    """(n+1)·2^n worlds; actual world: ``payer`` (None = NSA) and coins given as a bitmask."""
    payers = np.repeat(np.arange(-1, n), 1 << n)
    coin = np.tile(np.arange(1 << n), n + 1)
    p = payers[:, None] == np.arange(n)[None, :]
    c = ((coin[:, None] >> np.arange(n)[None, :]) & 1).astype(bool)
    val = np.concatenate([p, c], axis=1)
    rels = {}
    for i in range(n):
        obs = p[:, i].astype(np.int64) * 4 + c[:, (i - 1) % n] * 2 + c[:, i]
        rels[f"d{i}"] = Relation.from_labels(obs)
    props = tuple(f"p{i}" for i in range(n)) + tuple(f"c{i}" for i in range(n))
    actual = int(((-1 if payer is None else payer) + 1) * (1 << n) + coins)
    return KripkeModel(props, tuple(rels), val, rels, (actual,))


def solve_dining(n: int = 3, payer: int | None = 0, coins: int = 0) -> DiningResult:
    """Announce every cryptographer's truthful s_i and check what became known."""
    model = dining_model(n, payer, coins)
    for i in range(n):
        s = said(i, n)
        model = model.announce(s if model.holds(s) else Not(s))
    paid = disj(Prop(f"p{i}") for i in range(n))
    group = model.agents
    ck_whether = model.holds(C(group, paid) | C(group, Not(paid)))
    everyone_knows = model.holds(conj(Kw(a, paid) for a in group))
    learned = tuple(
        model.holds(conj(Kw(a, Prop(f"p{j}")) for j in range(n))) for a in group)
    anonymous = all(model.holds(anonymity_formula(n, i)) for i in range(n))
    return DiningResult(n, payer, ck_whether, everyone_knows, learned, anonymous)


def anonymity_formula(n: int, observer: int) -> Formula:
    """If someone else paid, ``observer`` does not know which one: ⋀_{j≠i} (p_j → ⋀_{k≠i} ¬K_i p_k)."""
    i = observer
    others = [j for j in range(n) if j != i]
    return conj(Prop(f"p{j}") >> conj(Not(K(f"d{i}", Prop(f"p{k}"))) for k in others) for j in others)
