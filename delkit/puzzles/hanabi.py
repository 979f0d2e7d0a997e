"""A small Hanabi-style card game: who knows her own cards after which hints (SMCDEL's ``Toynabi``, with
Hanabi's hints).

``players`` players each hold ``hand`` distinct cards numbered ``0 … cards−1`` in positions ``0 … hand−1``;
the remaining cards are in the deck, face down. As in Hanabi (A. Bauza, 2010) every player sees the others'
cards but not her own, and the cards must be played in increasing order, card 0 first. A *hint* to player i
about value v is a truthful public announcement of which of her positions hold v — possibly none ("you have
no v"): ``⋀_p (h_i_v_p ↔ ⊤/⊥ as dealt)``. Playing card 0 is *safe* for player i when she knows where it
is: ``⋁_p K_i h_i_0_p``.

Encoding (SMCDEL's ``toynabiStartFor``): ``h{i}_{c}_{p}`` — player i holds card c at position p; the law:
each position holds exactly one card and each card is in at most one position; player i observes every
``h{j}_…`` of the other players. The deal: player i holds cards ``(i−1)·hand … i·hand − 1`` in order.
Symbolic: a :class:`~delkit.backends.symbolic.KnowledgeStructure`; explicit: one world per deal (injective map from
positions to cards), player i's relation: the same cards at the others'.

Answer for the default game (2 players, cards 0–4, hands of 2: player 1 holds 0, 1; player 2 holds 2, 3;
card 4 is in the deck), derived by hand: player 1 sees 2 and 3, so her hand is two of {0, 1, 4} in some
order (6 possibilities). One hint makes a play safe for her only if it is the hint "0" ("position 0 is a
0"); the hint "1" tells her that position 1 holds 1, but position 0 may still hold 0 or 4; "4" ("you have
no 4") leaves two orders; "2" and "3" tell her nothing. Two hints make it safe iff they include "0" or are
{"1", "4"} (5 of the 10 pairs): position 0 is then neither 1 nor 4.
"""

from __future__ import annotations

import itertools
import time
from dataclasses import dataclass
from typing import Any

from delkit.errors import ModelError
from delkit.logic.formula import Formula, K, Not, Prop, conj, disj

__all__ = ["HanabiResult", "hanabi_structure", "hanabi_model", "hint", "safe_play", "knows_card", "deal",
           "solve_hanabi"]


def _h(i: int, c: int, p: int) -> str:
    return f"h{i}_{c}_{p}"


def _check(players: int, cards: int, hand: int) -> None:
    if players < 2 or hand < 1 or players * hand > cards or cards > 8 or players * hand > 6:
        raise ModelError(f"hanabi: need 2 <= players, 1 <= hand, players*hand <= min(cards, 6), cards <= 8; got "
                         f"--players {players} --cards {cards} --hand {hand}")


def _slots(players: int, hand: int) -> list[tuple[int, int]]:
    return [(i, p) for i in range(1, players + 1) for p in range(hand)]


def deal(players: int, hand: int) -> dict[tuple[int, int], int]:
    """The actual deal: position p of player i holds card (i−1)·hand + p."""
    return {(i, p): (i - 1) * hand + p for i, p in _slots(players, hand)}


def _vocabulary(players: int, cards: int, hand: int) -> list[str]:
    return [_h(i, c, p) for i, p in _slots(players, hand) for c in range(cards)]


def _state_formula(players: int, cards: int, hand: int, assignment: dict[tuple[int, int], int]) -> Formula:
    return conj(Prop(_h(i, c, p)) if assignment[i, p] == c else Not(Prop(_h(i, c, p)))
                for i, p in _slots(players, hand) for c in range(cards))


def hanabi_structure(players: int = 2, cards: int = 5, hand: int = 2) -> Any:
    """The knowledge structure (actual state: :func:`deal`)."""
    from delkit.backends.symbolic import KnowledgeStructure

    _check(players, cards, hand)
    slots = _slots(players, hand)
    one = [disj(Prop(_h(i, c, p)) for c in range(cards)) for i, p in slots]
    one += [Not(Prop(_h(i, c, p)) & Prop(_h(i, d, p))) for i, p in slots for c, d in
            itertools.combinations(range(cards), 2)]
    once = [Not(Prop(_h(i, c, p)) & Prop(_h(j, c, q))) for c in range(cards)
            for (i, p), (j, q) in itertools.combinations(slots, 2)]
    observed = {str(i): [_h(j, c, p) for j, p in slots if j != i for c in range(cards)]
                for i in range(1, players + 1)}
    return KnowledgeStructure.create(_vocabulary(players, cards, hand), conj(one + once), observed,
                                     actual=_state_formula(players, cards, hand, deal(players, hand)))


def hanabi_model(players: int = 2, cards: int = 5, hand: int = 2) -> Any:
    """The explicit S5 model: one world per deal."""
    import numpy as np

    from delkit.models.kripke import KripkeModel
    from delkit.models.relation import Relation

    _check(players, cards, hand)
    slots = _slots(players, hand)
    deals = list(itertools.permutations(range(cards), len(slots)))
    voc = _vocabulary(players, cards, hand)
    col = {v: k for k, v in enumerate(voc)}
    val = np.zeros((len(deals), len(voc)), dtype=bool)
    for w, d in enumerate(deals):
        for (i, p), c in zip(slots, d, strict=True):
            val[w, col[_h(i, c, p)]] = True
    rels = {}
    for i in range(1, players + 1):
        others = [k for k, (j, _) in enumerate(slots) if j != i]
        seen: dict[tuple[int, ...], int] = {}
        rels[str(i)] = Relation.from_labels(np.array([seen.setdefault(tuple(d[k] for k in others), len(seen))
                                                      for d in deals]))
    actual = deals.index(tuple(deal(players, hand)[s] for s in slots))
    return KripkeModel(tuple(voc), tuple(str(i) for i in range(1, players + 1)), val, rels, (actual,))


def hint(player: int, value: int, players: int = 2, hand: int = 2) -> Formula:
    """The truthful hint to ``player`` about ``value``: which of her positions hold it (maybe none)."""
    d = deal(players, hand)
    return conj(Prop(_h(player, value, p)) if d[player, p] == value else Not(Prop(_h(player, value, p)))
                for p in range(hand))


def safe_play(player: int, hand: int = 2, card: int = 0) -> Formula:
    """⋁_p K_i h_i_card_p: the player knows where ``card`` (the next to play) is in her hand."""
    return disj(K(str(player), Prop(_h(player, card, p))) for p in range(hand))


def knows_card(player: int, position: int, cards: int) -> Formula:
    """⋁_c K_i h_i_c_p: the player knows which card is at ``position``."""
    return disj(K(str(player), Prop(_h(player, c, position))) for c in range(cards))


@dataclass(frozen=True)
class HanabiResult:
    """Which hints to ``player`` (by value) make a play safe for her / tell her a card, alone and in pairs."""

    players: int
    cards: int
    hand: int
    player: int
    engine: str
    safe_initially: bool
    safe_after_one: tuple[int, ...]
    safe_after_two: tuple[tuple[int, int], ...]
    knows_position_after_one: dict[int, tuple[int, ...]]
    seconds: float

    def as_dict(self) -> dict:
        return {"puzzle": "hanabi", "engine": self.engine, "players": self.players, "cards": self.cards,
                "hand": self.hand, "player": self.player,
                "deal": {str(i): [deal(self.players, self.hand)[i, p] for p in range(self.hand)]
                         for i in range(1, self.players + 1)},
                "safe_initially": self.safe_initially, "safe_after_one_hint": list(self.safe_after_one),
                "safe_after_two_hints": [list(p) for p in self.safe_after_two],
                "knows_position_after_one_hint": {str(p): list(v) for p, v in self.knows_position_after_one.items()},
                "seconds": self.seconds}


def solve_hanabi(players: int = 2, cards: int = 5, hand: int = 2, *, player: int = 1,
                 symbolic: bool = True) -> HanabiResult:
    """Every hint and pair of hints to ``player`` (values 0 … cards−1), on either backend (CPU seconds)."""
    if not 1 <= player <= players:
        raise ModelError(f"hanabi: --player must be 1..{players}, got {player}")
    t0 = time.process_time()
    start = hanabi_structure(players, cards, hand) if symbolic else hanabi_model(players, cards, hand)
    safe = safe_play(player, hand)
    hints = {v: hint(player, v, players, hand) for v in range(cards)}
    after = {v: start.announce(h) for v, h in hints.items()}
    one = tuple(v for v in range(cards) if after[v].holds(safe))
    two = tuple((v, w) for v, w in itertools.combinations(range(cards), 2)
                if after[v].announce(hints[w]).holds(safe))
    knows = {p: tuple(v for v in range(cards) if after[v].holds(knows_card(player, p, cards))) for p in range(hand)}
    return HanabiResult(players, cards, hand, player, "symbolic" if symbolic else "explicit",
                        start.holds(safe), one, two, knows, time.process_time() - t0)

