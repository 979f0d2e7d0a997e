"""Epistemic puzzles with literature answers, each solved with delkit's DEL machinery.

* :mod:`~delkit.puzzles.muddy` — muddy children (M−1 "nobody knows" rounds);
* :mod:`~delkit.puzzles.sum_product` — Freudenthal's Sum and Product (unique (4, 13));
* :mod:`~delkit.puzzles.cheryl` — Cheryl's birthday (July 16);
* :mod:`~delkit.puzzles.russian_cards` — Russian cards (102 safe announcements of 5–7 hands);
* :mod:`~delkit.puzzles.drinking` — three logicians in a bar;
* :mod:`~delkit.puzzles.dining` — dining cryptographers.

:func:`summary_table` runs them all (a few seconds) for ``delkit demo``.
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
    "summary_table", "sum_product_model",
]


#: how many rows :func:`summary_table` has (for a progress display)
N_PUZZLES = 6


def summary_table(on_row=None) -> list[dict]:
    """Run every puzzle once; one row per puzzle: ``puzzle``, ``answer``, ``expected``, ``ok``, ``seconds``.
    ``on_row(row)`` is called after each puzzle (e.g. to advance a progress display)."""
    rows: list[dict] = []

    def row(name: str, run, answer, expected) -> None:
        t0 = time.perf_counter()
        result = run()
        got = answer(result)
        rows.append({"puzzle": name, "answer": got, "expected": expected, "ok": got == expected,
                     "seconds": round(time.perf_counter() - t0, 4)})
        if on_row is not None:
            on_row(rows[-1])

    row("muddy children (N=10, M=4): nobody-knows rounds", lambda: solve_muddy(10, 4),
        lambda r: r.nobody_knows_rounds, 3)
    row("sum and product", solve_sum_product, lambda r: [list(s) for s in r.solutions], [[4, 13]])
    row("Cheryl's birthday", solve_cheryl, lambda r: list(r.solutions), ["July 16"])
    row("Russian cards: safe 5-7 hand announcements", solve_russian_cards,
        lambda r: len(r.safe_announcements), 102)
    row("drinking logicians (all want)", lambda: solve_drinking((True, True, True)), lambda r: list(r.answers),
        ["I don't know", "I don't know", "yes"])
    row("dining cryptographers (0 paid): anonymous, paid known", lambda: solve_dining(3, 0, 5),
        lambda r: [r.anonymous, r.common_knows_whether_paid], [True, True])
    return rows
