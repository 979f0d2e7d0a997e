"""Cheryl's birthday (Singapore and Asian Schools Math Olympiad 2015), solved with public announcements.

Ten candidate dates are the worlds; propositions ``month_<M>`` and ``day_<d>`` give the date. Albert is
told the month (his partition label is the month), Bernard the day. "A knows the birthday" is
``⋀_p Kw_A p`` over all date propositions. The dialogue as announcements:

1. Albert: "I don't know when Cheryl's birthday is, but I know that Bernard does not know too."
   — ``[!(¬knows_A ∧ K_A ¬knows_B)]``
2. Bernard: "At first I didn't know, but now I do."   — ``[!knows_B]``
3. Albert: "Then I also know."                         — ``[!knows_A]``

Literature answer: July 16.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

from delkit.logic.formula import K, Not
from delkit.models.kripke import KripkeModel
from delkit.models.relation import Relation
from delkit.puzzles._common import knows_which

__all__ = ["CHERYL_DATES", "CherylResult", "cheryl_model", "solve_cheryl"]

CHERYL_DATES: tuple[tuple[str, int], ...] = (
    ("May", 15), ("May", 16), ("May", 19), ("June", 17), ("June", 18),
    ("July", 14), ("July", 16), ("August", 14), ("August", 15), ("August", 17),
)


@dataclass(frozen=True)
class CherylResult:
    solutions: tuple[str, ...]
    worlds: tuple[int, ...]
    seconds: float

    def as_dict(self) -> dict:
        return {"puzzle": "cheryl", "solutions": list(self.solutions), "worlds": list(self.worlds),
                "seconds": self.seconds}


def cheryl_model(dates: tuple[tuple[str, int], ...] = CHERYL_DATES) -> KripkeModel:
    """One world per date; Albert's partition by month, Bernard's by day."""
    months = sorted({m for m, _ in dates})
    days = sorted({d for _, d in dates})
    worlds = {f"{m} {d}": {f"month_{m}", f"day_{d}"} for m, d in dates}
    model = KripkeModel.build(worlds, {}, designated=(), props=[f"month_{m}" for m in months] +
                              [f"day_{d}" for d in days], agents=())
    rels = {"Albert": Relation.from_labels([months.index(m) for m, _ in dates]),
            "Bernard": Relation.from_labels([days.index(d) for _, d in dates])}
    return KripkeModel(model.props, ("Albert", "Bernard"), model.valuation, rels, (), model.names)


def solve_cheryl(dates: tuple[tuple[str, int], ...] = CHERYL_DATES) -> CherylResult:
    """Apply the three announcements; the surviving world names are the solutions."""
    t0 = time.perf_counter()
    model = cheryl_model(dates)
    knows_a = knows_which("Albert", model.props)
    knows_b = knows_which("Bernard", model.props)
    worlds = [model.n_worlds]
    for phi in (Not(knows_a) & K("Albert", Not(knows_b)), knows_b, knows_a):
        model = model.announce(phi)
        worlds.append(model.n_worlds)
    return CherylResult(tuple(model.names or ()), tuple(worlds), time.perf_counter() - t0)
