"""Epistemic puzzles with literature answers, each solved with delkit's DEL machinery.

* :mod:`~delkit.puzzles.muddy` — muddy children (M−1 "nobody knows" rounds);
* :mod:`~delkit.puzzles.sum_product` — Freudenthal's Sum and Product (unique (4, 13));
* :mod:`~delkit.puzzles.cheryl` — Cheryl's birthday (July 16);
* :mod:`~delkit.puzzles.russian_cards` — Russian cards (102 safe announcements of 5–7 hands);
* :mod:`~delkit.puzzles.drinking` — three logicians in a bar;
* :mod:`~delkit.puzzles.dining` — dining cryptographers;
* :mod:`~delkit.puzzles.gossip` — the gossip problem (2n − 4 calls), with knowledge transformers;
* :mod:`~delkit.puzzles.door_mat` — the door mat (factual change, knowledge transformers);
* :mod:`~delkit.puzzles.what_sum` — What Sum (SMCDEL's encoding; see docs/puzzles.md for what is checked);
* :mod:`~delkit.puzzles.hanabi` — Hanabi-style hints (which hints make a play safe).

:data:`CATALOGUE` lists them for ``delkit puzzle --list`` (command, literature answer, backends, source).

:func:`summary_table` runs every one of them on a small instance (a few seconds) for ``delkit demo`` and
``delkit puzzle all``.
"""

from __future__ import annotations

import time

from delkit.puzzles.cheryl import CherylResult, cheryl_model, solve_cheryl
from delkit.puzzles.dining import DiningResult, dining_model, solve_dining
from delkit.puzzles.drinking import DrinkingResult, drinking_model, solve_drinking
from delkit.puzzles.muddy import MuddyResult, muddy_model, solve_muddy
from delkit.puzzles.russian_cards import RussianCardsResult, russian_cards_model, solve_russian_cards
from delkit.puzzles.sum_product import SumProductResult, solve_sum_product, sum_product_model

__all__ = [
    "CherylResult", "DiningResult", "DrinkingResult", "MuddyResult", "RussianCardsResult", "SumProductResult",
    "cheryl_model", "dining_model", "drinking_model", "muddy_model", "russian_cards_model", "solve_cheryl",
    "solve_dining", "solve_drinking", "solve_muddy", "solve_russian_cards", "solve_sum_product",
    "summary_table", "sum_product_model", "CATALOGUE",
]

_DOC = "docs/puzzles.md"
CATALOGUE: list[dict] = [
    {"command": "muddy", "answer": "M-1 rounds of 'nobody knows', then the muddy children know",
     "backends": ["explicit", "symbolic"], "source": "Fagin, Halpern, Moses, Vardi 1995, sec. 1.1",
     "docs": _DOC + "#muddy-children"},
    {"command": "sum-product", "answer": "(x, y) = (4, 13)", "backends": ["explicit", "symbolic"],
     "source": "Freudenthal 1969; van Ditmarsch, Ruan, Verbrugge 2008", "docs": _DOC + "#sum-and-product"},
    {"command": "cheryl", "answer": "July 16", "backends": ["explicit"], "source": "Singapore and Asian Schools "
     "Math Olympiad 2015", "docs": _DOC + "#cheryls-birthday"},
    {"command": "russian-cards", "answer": "102 safe announcements of 5-7 hands", "backends": ["explicit"],
     "source": "van Ditmarsch 2003", "docs": _DOC + "#russian-cards"},
    {"command": "drinking", "answer": "'I don't know' n-1 times, then 'yes' (all want)",
     "backends": ["explicit", "symbolic"], "source": "the three-logicians cartoon; SMCDEL's DrinkLogic",
     "docs": _DOC + "#drinking-logicians"},
    {"command": "dining", "answer": "whether someone paid becomes common knowledge, not who",
     "backends": ["explicit", "symbolic"], "source": "Chaum 1988; van Eijck & Orzan 2007",
     "docs": _DOC + "#dining-cryptographers"},
    {"command": "gossip", "answer": "least calls making all experts: 1, 3, 4 for n = 2, 3, 4 (2n-4, n >= 4)",
     "backends": ["symbolic"], "source": "Tijdeman 1971; Baker & Shostak 1972; SMCDEL's GossipS5",
     "docs": _DOC + "#gossip"},
    {"command": "what-sum", "answer": "(50, 20, 30) is the only triple where Anne then knows 50 (unbounded, "
     "exact; a bounded model certifies it from bound 190)", "backends": ["unbounded", "explicit", "symbolic"],
     "source": "van Ditmarsch & Kooi 2015, ch. 4; "
     "SMCDEL's WhatSum", "docs": _DOC + "#what-sum"},
    {"command": "door-mat", "answer": "tryTake gets Bob the key; he knows it will only after Anne announces "
     "where it is", "backends": ["symbolic", "explicit (via the event model)"], "source": "Gattinger 2018; "
     "SMCDEL's DoorMat", "docs": _DOC + "#door-mat"},
    # ---- protocols: prisoners, letter passing, coin flip, number triangle
    {"command": "prisoners", "answer": "the counter knows everyone has been interviewed exactly when his count "
     "reaches n-1 (n >= 3); expected n(n-1) + n H_{n-1} days (10,417.7 for 100)",
     "backends": ["explicit", "symbolic (transformers; image beyond 7)"],
     "source": "Dehaye, Ford & Segerman 2003; van Ditmarsch, van Eijck & Wu 2010; SMCDEL's Prisoners",
     "docs": _DOC + "#100-prisoners-and-a-light-bulb-bounded"},
    {"command": "letter-passing", "answer": "1->2->...->n delivers the letter in n-1 passes; each agent learns "
     "the address when the letter reaches it; then the goal is common knowledge",
     "backends": ["explicit", "symbolic"], "source": "Engesser, Bolander, Mattmüller & Nebel 2017; SMCDEL's "
     "LetterPassing", "docs": _DOC + "#letter-passing"},
    {"command": "coin-flip", "answer": "Bob knows the outcome; Anne knows that he does (partial) or still "
     "believes heads (oblivious: KD45)", "backends": ["explicit", "symbolic (S5)", "belief structures"],
     "source": "Gattinger 2018, ch. 3; SMCDEL's CoinFlip", "docs": _DOC + "#coin-flip"},
    {"command": "number-triangle", "answer": "'some': M-1 rounds of 'nobody knows', then the muddy children "
     "know, on 2n+1 points instead of 2^n worlds", "backends": ["triangle", "explicit", "symbolic"],
     "source": "Gierasimczuk & Szymanik 2011; SMCDEL's MCTRIANGLE", "docs": _DOC + "#number-triangle"},
]

# SMCDEL's second gossip variant and the Hanabi-style card game
CATALOGUE += [
    {"command": "gossip --variant kw", "answer": "knowing-whether experts: least calls 1, 3, 4 for n = 2, 3, 4; "
     "after 01 23 02 13 all are experts but not all know it", "backends": ["symbolic", "explicit (n <= 3)"],
     "source": "Tijdeman 1971; SMCDEL's GossipKw", "docs": _DOC + "#gossip-knowing-whether"},
    {"command": "hanabi", "answer": "2 players, cards 0-4, hands 0 1 | 2 3: playing 0 is safe for player 1 after "
     "the hint '0', or after '1' and 'no 4' together (derived by hand)", "backends": ["symbolic", "explicit"],
     "source": "Bauza's Hanabi (2010); SMCDEL's Toynabi", "docs": _DOC + "#hanabi-style-hints"},
]


#: how many rows :func:`summary_table` has (for a progress display)
N_PUZZLES = 16


def summary_table(on_row=None) -> list[dict]:
    """Run every puzzle of :data:`CATALOGUE` once, on a small instance (a few seconds in all); one row per
    run: ``puzzle``, ``command`` (its :data:`CATALOGUE` command), ``answer``, ``expected`` (the literature
    answer, or for What Sum SMCDEL's own test count), ``ok``, ``seconds`` (wall). ``on_row(row)`` is called
    after each puzzle (e.g. to advance a progress display)."""
    from delkit.puzzles.coin_flip import solve_coin_flip
    from delkit.puzzles.door_mat import solve_door_mat
    from delkit.puzzles.gossip import solve_gossip, solve_gossip_kw
    from delkit.puzzles.hanabi import solve_hanabi
    from delkit.puzzles.letter_passing import solve_letter_passing
    from delkit.puzzles.number_triangle import solve_number_triangle
    from delkit.puzzles.prisoners import solve_prisoners
    from delkit.puzzles.what_sum import solve_what_sum

    rows: list[dict] = []

    def row(command: str, name: str, run, answer, expected) -> None:
        t0 = time.perf_counter()
        result = run()
        got = answer(result)
        rows.append({"puzzle": name, "command": command, "answer": got, "expected": expected, "ok": got == expected,
                     "seconds": round(time.perf_counter() - t0, 4)})
        if on_row is not None:
            on_row(rows[-1])

    row("muddy", "muddy children (N=10, M=4): nobody-knows rounds", lambda: solve_muddy(10, 4),
        lambda r: r.nobody_knows_rounds, 3)
    row("sum-product", "sum and product", solve_sum_product, lambda r: [list(s) for s in r.solutions], [[4, 13]])
    row("cheryl", "Cheryl's birthday", solve_cheryl, lambda r: list(r.solutions), ["July 16"])
    row("russian-cards", "Russian cards: safe 5-7 hand announcements", solve_russian_cards,
        lambda r: len(r.safe_announcements), 102)
    row("drinking", "drinking logicians (all want)", lambda: solve_drinking((True, True, True)),
        lambda r: list(r.answers), ["I don't know", "I don't know", "yes"])
    row("dining", "dining cryptographers (0 paid): anonymous, paid known", lambda: solve_dining(3, 0, 5),
        lambda r: [r.anonymous, r.common_knows_whether_paid], [True, True])
    row("gossip", "gossip (n=3): least calls making all experts, fewer fail", lambda: solve_gossip(3),
        lambda r: [len(r.calls), r.shorter_fail], [3, True])
    row("what-sum", "What Sum: the triples where Anne then knows 50 (unbounded, exact)",
        lambda: solve_what_sum(None, 50), lambda r: [list(s) for s in r.solutions], [[50, 20, 30]])
    row("door-mat", "door mat: key after tryTake; Bob knows it before / after the announcement", solve_door_mat,
        lambda r: [r.goal_after_try, r.bob_knows_beforehand, r.bob_knows_after_announcement], [True, False, True])
    row("prisoners", "prisoners (n=4): the counter knows exactly when his count reaches n-1",
        lambda: solve_prisoners(4, 200, 0), lambda r: [r.sound, r.knows_day == r.announce_day], [True, True])
    row("letter-passing", "letter passing (n=3): passes; goal common knowledge at the end",
        lambda: solve_letter_passing(3), lambda r: [len(r.plan), r.steps[-1]["common_knowledge_of_goal"]],
        [2, True])
    row("coin-flip", "coin flip (partial): every claim holds", lambda: solve_coin_flip(False, "partial"),
        lambda r: all(r.claims.values()), True)
    row("coin-flip", "coin flip (oblivious, KD45): every claim holds", lambda: solve_coin_flip(False, "oblivious"),
        lambda r: all(r.claims.values()), True)
    row("number-triangle", "number triangle (N=10, M=4, 'some'): rounds, then the muddy know",
        lambda: solve_number_triangle(10, 4), lambda r: [r.nobody_knows_rounds, r.muddy_know], [3, True])
    row("gossip --variant kw", "gossip, knowing whether (n=3): least calls", lambda: solve_gossip_kw(3),
        lambda r: [len(r.calls), r.shorter_fail], [3, True])
    row("hanabi", "Hanabi hints: safe after one hint; after two", solve_hanabi,
        lambda r: [list(r.safe_after_one), [1, 4] in [list(p) for p in r.safe_after_two]], [[0], True])
    return rows
