"""Russian cards (Moscow Math Olympiad 2000; van Ditmarsch, *The Russian Cards Problem*, Studia Logica 2003).

Seven cards 0…6 are dealt: three to Alice, three to Bob, one to Cath (140 deals, the worlds). Proposition
``a<q>`` (``b<q>``) says card q is Alice's (Bob's). Each player's partition label is her own hand.
The actual deal is 012|345|6. Alice publicly announces "my hand is one of the hands in X" (X a set of
3-card hands containing 012); as she knows her hand this is the announcement of
``K_a φ_X`` with ``φ_X = ⋁_{h∈X} ⋀_{q∈h} a_q``.

An announcement is *good* (safe) iff after it it is common knowledge among the three that Bob knows
Alice's hand and Cath knows no card of Alice or Bob:

    M, 012|345|6 ⊨ [!K_a φ_X] C_{a,b,c}(bob_knows ∧ cath_ignorant)
    bob_knows     = ⋀_q Kw_b a_q
    cath_ignorant = ⋀_q (¬K_c a_q ∧ ¬K_c b_q)

Literature answer: 102 good announcements of 5, 6 or 7 hands (60 + 36 + 6).

Candidates are enumerated with networkx: if Bob can tell two hands of X apart in every deal, they must
never be confused by Bob in the initial model (same Bob label in two worlds with those Alice hands),
so good announcements are cliques of the "Bob distinguishes" graph on Alice's hands; this graph is read
off the model's partitions. Every candidate is then decided by the model checker.
"""

from __future__ import annotations

import itertools
import time
from collections import Counter
from dataclasses import dataclass

import numpy as np

from delkit.logic.formula import C, Formula, K, Not, Prop, conj, disj
from delkit.models.kripke import KripkeModel
from delkit.models.relation import Relation
from delkit.puzzles._common import knows_which

__all__ = ["RussianCardsResult", "russian_cards_model", "announcement_formula", "good_formula",
           "is_good", "solve_russian_cards"]

CARDS = tuple(range(7))
AGENTS = ("a", "b", "c")
ACTUAL = ((0, 1, 2), (3, 4, 5), (6,))


@dataclass(frozen=True)
class RussianCardsResult:
    """Good announcements (each a tuple of Alice hands) and their count per size."""

    safe_announcements: tuple[tuple[tuple[int, ...], ...], ...]
    by_size: dict[int, int]
    candidates: int
    seconds: float

    def as_dict(self) -> dict:
        return {"puzzle": "russian-cards", "safe_announcements": len(self.safe_announcements),
                "by_size": {str(k): v for k, v in sorted(self.by_size.items())}, "candidates": self.candidates,
                "example": [list(h) for h in self.safe_announcements[0]] if self.safe_announcements else None,
                "seconds": self.seconds}


def _deals() -> list[tuple[tuple[int, ...], tuple[int, ...], tuple[int, ...]]]:
    out = []
    for alice in itertools.combinations(CARDS, 3):
        rest = [q for q in CARDS if q not in alice]
        for bob in itertools.combinations(rest, 3):
            out.append((alice, bob, tuple(q for q in rest if q not in bob)))
    return out


def russian_cards_model() -> KripkeModel:
    """The 140 deals 3|3|1; each player knows exactly her own hand. Designated: 012|345|6."""
    deals = _deals()
    props = tuple(f"a{q}" for q in CARDS) + tuple(f"b{q}" for q in CARDS)
    val = np.zeros((len(deals), len(props)), dtype=bool)
    for w, (alice, bob, _) in enumerate(deals):
        val[w, list(alice)] = True
        val[w, [7 + q for q in bob]] = True
    hand_code = val.astype(np.int64) @ (np.int64(1) << np.arange(len(props), dtype=np.int64))
    rels = {"a": Relation.from_labels(hand_code & 0x7F), "b": Relation.from_labels(hand_code >> 7),
            "c": Relation.from_labels(~(val[:, :7] | val[:, 7:]) @ np.arange(7))}
    names = tuple("".join(map(str, a)) + "|" + "".join(map(str, b)) + "|" + "".join(map(str, c))
                  for a, b, c in deals)
    return KripkeModel(props, AGENTS, val, rels, (deals.index(ACTUAL),), names)


def announcement_formula(hands: tuple[tuple[int, ...], ...]) -> Formula:
    """K_a φ_X with φ_X = ⋁_{h∈X} ⋀_{q∈h} a_q."""
    return K("a", disj(conj(Prop(f"a{q}") for q in h) for h in hands))


def good_formula() -> Formula:
    """C_{a,b,c}(bob_knows ∧ cath_ignorant)."""
    bob_knows = knows_which("b", [f"a{q}" for q in CARDS])
    cath_ignorant = conj(Not(K("c", Prop(f"{x}{q}"))) for q in CARDS for x in "ab")
    return C(AGENTS, conj([bob_knows, cath_ignorant]))


def is_good(model: KripkeModel, hands: tuple[tuple[int, ...], ...]) -> bool:
    """M, actual ⊨ K_a φ_X ∧ [!K_a φ_X] C_{abc}(bob_knows ∧ cath_ignorant), by the model checker."""
    phi = announcement_formula(hands)
    if not model.holds(phi):
        return False
    return model.announce(phi).holds(good_formula())


def _alice_hands(model: KripkeModel) -> tuple[np.ndarray, list[tuple[int, ...]]]:
    """Alice's hand index per world and the list of hands (from Alice's partition labels)."""
    lab = model.relations["a"].labels
    first = np.unique(lab, return_index=True)[1]
    hands = [tuple(int(q) for q in np.flatnonzero(model.valuation[w, :7])) for w in first]
    return lab, hands


def _bob_distinguishes(model: KripkeModel, alice: np.ndarray, n_hands: int) -> np.ndarray:
    """Boolean matrix hands × hands: Bob never confuses the two Alice hands in the model."""
    bob = model.relations["b"].labels
    incidence = np.zeros((n_hands, int(bob.max()) + 1), dtype=np.int64)
    np.add.at(incidence, (alice, bob), 1)
    confused = (incidence @ incidence.T) > 0
    return ~confused


def solve_russian_cards(sizes: tuple[int, ...] = (5, 6, 7)) -> RussianCardsResult:
    """All good announcements of the given sizes (each checked with the model checker)."""
    import networkx as nx

    t0 = time.perf_counter()
    model = russian_cards_model()
    alice, hands = _alice_hands(model)
    actual = int(alice[model.designated[0]])
    ok = _bob_distinguishes(model, alice, len(hands))
    graph = nx.Graph()
    nbrs = [h for h in range(len(hands)) if h != actual and ok[actual, h]]
    graph.add_nodes_from(nbrs)
    graph.add_edges_from((i, j) for i, j in itertools.combinations(nbrs, 2) if ok[i, j])
    good: list[tuple[tuple[int, ...], ...]] = []
    candidates = 0
    for clique in nx.enumerate_all_cliques(graph):
        if len(clique) + 1 > max(sizes):
            break
        if len(clique) + 1 not in sizes:
            continue
        candidates += 1
        announcement = tuple(sorted([hands[actual]] + [hands[h] for h in clique]))
        if is_good(model, announcement):
            good.append(announcement)
    good.sort(key=lambda x: (len(x), x))
    return RussianCardsResult(tuple(good), dict(Counter(len(x) for x in good)), candidates,
                              time.perf_counter() - t0)
