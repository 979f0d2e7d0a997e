"""The door mat (SMCDEL's ``SMCDEL.Examples.DoorMat``; Gattinger, *New Directions in Model Checking
Dynamic Epistemic Logic*, PhD thesis 2018, and the cooperative epistemic planning examples there).

Bob wants the key to Anne's house. It is common knowledge that Bob has no key; Anne knows whether the key is
under the door mat (it is), Bob does not. The action *tryTake*: Bob looks under the mat, and takes the key
if it is there (he sees whether it was there; Anne does not see what he found).

Literature answer: *tryTake* reaches the goal "Bob has the key", but Bob does not know beforehand that it
will (it is not an implicitly coordinated plan for Bob alone); after Anne announces "the key is under the
mat", Bob knows that *tryTake* will get him the key, and the plan "Anne announces, then Bob tries" works.

Encoding (SMCDEL's): V = {``key`` (under the mat), ``bob_has``}, θ = ¬bob_has, Anne observes ``key``, Bob
nothing; *tryTake* is a transformer with one event variable ``t`` ↔ key, observed by Bob, changing
``key := key ∧ ¬t`` and ``bob_has := bob_has ∨ t``.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Any

from delkit.logic.formula import Iff, K, Not, Prop

__all__ = ["DoorMatResult", "door_mat_start", "try_take", "solve_door_mat"]


@dataclass(frozen=True)
class DoorMatResult:
    goal_after_try: bool
    bob_knows_beforehand: bool
    bob_knows_after_announcement: bool
    goal_after_announcement_and_try: bool
    bob_knows_goal_after_try: bool
    seconds: float

    def as_dict(self) -> dict:
        return {"puzzle": "door-mat", "engine": "symbolic", "goal_after_try": self.goal_after_try,
                "bob_knows_beforehand_that_try_works": self.bob_knows_beforehand,
                "bob_knows_after_announcement_that_try_works": self.bob_knows_after_announcement,
                "goal_after_announcement_and_try": self.goal_after_announcement_and_try,
                "bob_knows_he_has_key_after_try": self.bob_knows_goal_after_try, "seconds": self.seconds}


def door_mat_start() -> Any:
    from delkit.backends.symbolic import KnowledgeStructure

    return KnowledgeStructure.create(["key", "bob_has"], Not(Prop("bob_has")), {"anne": ["key"], "bob": []},
                                     actual=Prop("key"))


def try_take(tag: str = "") -> Any:
    from delkit.backends.symbolic import Transformer

    t = Prop(f"t{tag}")
    return Transformer((t.name,), Iff(t, Prop("key")),
                       {"key": Prop("key") & Not(t), "bob_has": Prop("bob_has") | t},
                       {"anne": (), "bob": (t.name,)})


def solve_door_mat() -> DoorMatResult:
    """Check the literature claims. "tryTake works" is, before the action, ``key`` (the action's effect on
    ``bob_has`` is exactly the value of ``key``), so "Bob knows it works" is ``K_bob key``."""
    from delkit.backends.symbolic import prepare

    prepare()
    t0 = time.process_time()
    start = door_mat_start()
    after = start.transform(try_take("1"))
    told = start.announce(Prop("key"))
    both = told.transform(try_take("2"))
    has = Prop("bob_has")
    return DoorMatResult(after.holds(has), start.holds(K("bob", Prop("key"))), told.holds(K("bob", Prop("key"))),
                         both.holds(has), after.holds(K("bob", has)), time.process_time() - t0)
