"""Dining cryptographers (Chaum 1988), solved with public announcements.

n cryptographers sit round a table; either one of them paid or the NSA did. Propositions ``p<i>``
(cryptographer i paid) and ``c<i>`` (the coin shared by i and i+1 mod n shows heads). Worlds: payer ∈
{nobody, 0, …, n−1} × 2^n coins. Cryptographer i observes ``p_i``, ``c_{i-1}`` and ``c_i`` (partition
label: those three bits). Each cryptographer i says ``s_i = c_{i-1} ⊕ c_i ⊕ p_i``; the protocol is the
public announcement of the true value of every s_i.

Facts checked (Chaum; van Eijck & Orzan, *Epistemic verification of anonymity*, 2007): after the
announcements it is common knowledge whether a cryptographer paid (the parity ⊕_i s_i = ⋁_i p_i), and
if cryptographer k paid, no other cryptographer i knows who: ``¬K_i p_j`` for every j ≠ i.

``solve_dining(…, symbolic=True)`` runs the same protocol on a knowledge structure (V = {p_i, c_i},
θ = "at most one p_i", O_i = {p_i, c_{i−1}, c_i}). :func:`smcdel_dining_check` is SMCDEL's benchmark
formula on SMCDEL's encoding (complete graph: a shared bit per pair of cryptographers, P0 = the NSA paid).
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Any

import numpy as np

from delkit.logic.formula import BOT, TOP, Announce, C, Formula, Iff, Implies, K, Kw, Not, Prop, conj, disj
from delkit.models.kripke import KripkeModel
from delkit.models.relation import Relation

__all__ = ["DiningResult", "anonymity_formula", "dining_model", "dining_structure", "xor", "xor_all", "said",
           "solve_dining", "announce_whether", "smcdel_dining_structure", "smcdel_dining_formula",
           "smcdel_dining_check", "exactly_one"]


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
    engine: str = "explicit"
    seconds: float = 0.0

    def as_dict(self) -> dict:
        return {"puzzle": "dining", "engine": self.engine, "n": self.n, "payer": self.payer,
                "common_knows_whether_paid": self.common_knows_whether_paid,
                "someone_paid_known": self.someone_paid_known, "learned_payer": list(self.learned_payer),
                "anonymous": self.anonymous, "seconds": self.seconds}


def xor(a: Formula, b: Formula) -> Formula:
    """a ⊕ b = ¬(a ↔ b)."""
    return Not(Iff(a, b))


def xor_all(parts: list[Formula]) -> Formula:
    """n-ary exclusive or (odd parity), as a left-nested chain of binary ⊕ (⊥ for no parts)."""
    if not parts:
        from delkit.logic.formula import BOT

        return BOT
    out = parts[0]
    for p in parts[1:]:
        out = xor(out, p)
    return out


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


def dining_structure(n: int = 3, payer: int | None = 0, coins: int = 0) -> Any:
    """The knowledge structure of :func:`dining_model`: V = {p_i} ∪ {c_i}, θ = "no two paid",
    cryptographer ``d<i>`` observes p_i, c_{i−1}, c_i; actual state: ``payer`` and ``coins``."""
    from delkit.backends.symbolic import KnowledgeStructure

    props = [f"p{i}" for i in range(n)] + [f"c{i}" for i in range(n)]
    law = conj(Not(Prop(f"p{i}") & Prop(f"p{j}")) for i in range(n) for j in range(i + 1, n))
    observed = {f"d{i}": [f"p{i}", f"c{(i - 1) % n}", f"c{i}"] for i in range(n)}
    actual = conj([Prop(f"p{i}") if i == payer else Not(Prop(f"p{i}")) for i in range(n)]
                  + [Prop(f"c{i}") if (coins >> i) & 1 else Not(Prop(f"c{i}")) for i in range(n)])
    return KnowledgeStructure.create(props, law, observed, actual)


def solve_dining(n: int = 3, payer: int | None = 0, coins: int = 0, *, symbolic: bool = False) -> DiningResult:
    """Announce every cryptographer's truthful s_i and check what became known (``symbolic``: on
    :func:`dining_structure`; ``seconds`` is the CPU time of building it and running the protocol)."""
    if symbolic:
        from delkit.backends.symbolic import prepare

        prepare()  # imports and the interpreter's first full garbage collection before the clock starts
    t0 = time.process_time()
    model = dining_structure(n, payer, coins) if symbolic else dining_model(n, payer, coins)
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
    return DiningResult(n, payer, ck_whether, everyone_knows, learned, anonymous,
                        "symbolic" if symbolic else "explicit", time.process_time() - t0)


def announce_whether(announced: Formula, arg: Formula) -> Formula:
    """SMCDEL's ``[?!φ]ψ`` (announce whether φ): ``(φ → [!φ]ψ) ∧ (¬φ → [!¬φ]ψ)``."""
    return conj([Implies(announced, Announce(announced, arg)),
                 Implies(Not(announced), Announce(Not(announced), arg))])


def _smcdel_bits(n: int) -> dict[tuple[int, int], str]:
    return {(k, m): f"s{k}_{m}" for k in range(1, n + 1) for m in range(k + 1, n + 1)}


def smcdel_dining_manager(n: int) -> Any:
    """The BDD manager :func:`smcdel_dining_structure` creates unless given one: few nodes per variable
    (n = 80: 3,241 variables, 23.5 k nodes at the peak), a manager sized to that."""
    from delkit.backends.symbolic import new_manager, puzzle_memory

    return new_manager(memory_estimate=puzzle_memory(64 * (n + 1 + n * (n - 1) // 2)))


def smcdel_dining_structure(n: int, *, bdd: Any = None) -> Any:
    """SMCDEL's ``genDcKnsInit n``: P0 (the NSA paid), P1…Pn (cryptographer i paid) and a shared bit for
    every pair of cryptographers (complete graph, n(n−1)/2 bits); θ = exactly one of P0…Pn; agent ``i``
    observes P_i and its n−1 shared bits. Variable order as SMCDEL's: payers, then bits pair by pair."""
    from delkit.backends.symbolic import KnowledgeStructure

    bits = _smcdel_bits(n)
    props = [f"P{i}" for i in range(n + 1)] + list(bits.values())
    law = exactly_one([Prop(f"P{i}") for i in range(n + 1)])
    mgr = smcdel_dining_manager(n) if bdd is None else bdd
    return KnowledgeStructure.create(props, law, _smcdel_observed(n, bits), bdd=mgr)


def exactly_one(parts: list[Formula]) -> Formula:
    """Exactly one of ``parts`` holds — SMCDEL's ``⋁ P_i ∧ ⋀_{i<j} ¬(P_i ∧ P_j)`` as the same Boolean function
    written with O(n) shared subformulas instead of n(n+1)/2: ``one_k = (p_k ∧ none_{k+1}) ∨ (¬p_k ∧
    one_{k+1})``, ``none_k = ¬p_k ∧ none_{k+1}`` (the evaluator computes a shared subformula once; n = 80:
    244 BDD operations instead of 3,241)."""
    one: Formula = BOT
    none: Formula = TOP
    for p in reversed(parts):
        one, none = (p & none) | (Not(p) & one), Not(p) & none
    return one


def _smcdel_observed(n: int, bits: dict[tuple[int, int], str]) -> dict[str, list[str]]:
    """Agent ``i`` observes P_i and the bits it shares, in SMCDEL's order (one pass over the pairs)."""
    observed = {str(i): [f"P{i}"] for i in range(1, n + 1)}
    for (k, m), b in bits.items():
        observed[str(k)].append(b)
        observed[str(m)].append(b)
    return observed


def smcdel_dining_formula(n: int) -> Formula:
    """SMCDEL's benchmark formula (``bench/diningcrypto``): if cryptographer 1 did not pay, after the
    announcement whether the ⊕ of all revealed bits holds, 1 knows that nobody paid, or knows that one
    of 2…n paid without knowing which."""
    reveal = [xor_all([Prop(v) for v in seen]) for seen in _smcdel_observed(n, _smcdel_bits(n)).values()]
    after = disj([K("1", conj(Not(Prop(f"P{k}")) for k in range(1, n + 1))),
                  conj([K("1", disj(Prop(f"P{k}") for k in range(2, n + 1))),
                        conj(Not(K("1", Prop(f"P{k}"))) for k in range(2, n + 1))])])
    return Implies(Not(Prop("P1")), announce_whether(xor_all(reveal), after))


def smcdel_dining_check(n: int, *, bdd: Any = None) -> tuple[bool, float]:
    """Validity of :func:`smcdel_dining_formula` on :func:`smcdel_dining_structure` (SMCDEL's
    ``genDcValid``, literature answer: valid) and the CPU seconds of building both and checking (manager
    creation included unless a fresh manager ``bdd`` is given, :func:`smcdel_dining_manager`)."""
    from delkit.backends.symbolic import prepare

    prepare()  # imports and the interpreter's first full garbage collection before the clock starts

    t0 = time.process_time()
    ok = smcdel_dining_structure(n, bdd=bdd).valid(smcdel_dining_formula(n))
    return bool(ok), time.process_time() - t0


def anonymity_formula(n: int, observer: int) -> Formula:
    """If someone else paid, ``observer`` does not know which one: ⋀_{j≠i} (p_j → ⋀_{k≠i} ¬K_i p_k)."""
    i = observer
    others = [j for j in range(n) if j != i]
    return conj(Prop(f"p{j}") >> conj(Not(K(f"d{i}", Prop(f"p{k}"))) for k in others) for j in others)
