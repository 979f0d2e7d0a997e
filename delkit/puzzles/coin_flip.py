"""The coin flip (SMCDEL's ``SMCDEL.Examples.CoinFlip``; Gattinger, *New Directions in Model Checking Dynamic
Epistemic Logic*, PhD thesis 2018, ch. 3, belief structures and transformers with factual change; the
observation types are those of Baltag, Moss & Solecki 1998 and of mA*, Baral et al. 2015).

A coin lies heads up; that is common knowledge between Anne (``a``) and Bob (``b``). The coin is flipped at
random and the outcome is shown to Bob only. Anne either watches the flip without seeing the outcome
(*partial*: SMCDEL's total relation for ``a`` on the two outcomes) or does not notice it at all
(*oblivious*: she relates every outcome to "nothing happened").

Literature answer (what the update must give):

* partial — Bob knows the outcome; Anne does not know whether the coin is heads; she knows that Bob knows
  whether it is, and that is common knowledge (``C_{a,b} Kw_b heads``); the result is again S5;
* oblivious — Bob knows the outcome and knows that Anne still believes heads; Anne believes heads and
  believes that Bob believes heads too — a false belief when the coin landed tails; the model is KD45, not
  S5 (an agent who is not aware of an event keeps her old beliefs).

Encodings: explicit (a one-world S5 model and the mA* event model of the flip, product update), symbolic S5
(a knowledge structure V = {heads}, θ = heads, both observe heads; the flip is a transformer with one event
variable ``q``, heads := q, observed by Bob only — partial case only, since a knowledge structure is S5)
and belief structures (:mod:`delkit.backends.symbolic_belief`, both cases, the event model as a transformer).
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Any

from delkit.errors import ModelError
from delkit.logic.formula import BOT, TOP, C, Formula, K, Kw, Not, Prop

__all__ = ["CLAIMS", "CoinFlipResult", "coin_start", "flip_event", "flip_transformer", "after_flips",
           "solve_coin_flip"]

AGENTS = ("a", "b")
HEADS = Prop("heads")
MODES = ("partial", "oblivious")
ENGINES = ("explicit", "symbolic", "belief")


def _claims(outcome: bool, mode: str) -> dict[str, Formula]:
    """The literature's statements after one flip shown to Bob, each expected to hold at the actual state."""
    side = HEADS if outcome else Not(HEADS)
    out = {"bob knows the outcome": K("b", side)}
    if mode == "partial":
        out |= {"anne does not know whether heads": Not(Kw("a", HEADS)),
                "anne knows bob knows whether heads": K("a", Kw("b", HEADS)),
                "common knowledge that bob knows whether heads": C(AGENTS, Kw("b", HEADS))}
    else:
        out |= {"anne believes heads": K("a", HEADS), "anne believes bob believes heads": K("a", K("b", HEADS)),
                "bob knows anne believes heads": K("b", K("a", HEADS))}
    return out


#: the claims by case, ``CLAIMS[(outcome_is_heads, mode)]``
CLAIMS = {(o, m): _claims(o, m) for o in (True, False) for m in MODES}


@dataclass(frozen=True)
class CoinFlipResult:
    """``claims``: each statement of the literature answer and whether it holds; ``s5``: whether the model
    after the flip is S5 (the explicit engine says; the symbolic engines give the same by construction)."""

    outcome: str
    anne: str
    engine: str
    claims: dict[str, bool]
    states: int
    seconds: float

    @property
    def ok(self) -> bool:
        return all(self.claims.values())

    def as_dict(self) -> dict:
        return {"puzzle": "coin-flip", "engine": self.engine, "outcome": self.outcome, "anne": self.anne,
                "claims": self.claims, "all_claims_hold": self.ok, "states_after_flip": self.states,
                "seconds": self.seconds}


def coin_start(engine: str = "explicit", *, bdd: Any = None) -> Any:
    """Heads up, common knowledge (both agents observe the coin)."""
    if engine == "explicit":
        from delkit.models.kripke import KripkeModel

        return KripkeModel.build([{"heads"}], {a: [[0]] for a in AGENTS}, props=["heads"], agents=AGENTS)
    if engine == "symbolic":
        from delkit.backends.symbolic import KnowledgeStructure

        return KnowledgeStructure.create(["heads"], HEADS, {a: ["heads"] for a in AGENTS}, bdd=bdd)
    if engine == "belief":
        from delkit.backends.symbolic_belief import BeliefStructure

        return BeliefStructure.create(["heads"], HEADS, {a: "heads' <-> heads" for a in AGENTS}, bdd=bdd)
    raise ModelError(f"coin flip: unknown engine {engine!r}; use {', '.join(ENGINES)}")


def flip_event(seer: str = "b", mode: str = "partial", outcome: bool = False) -> Any:
    """The mA* event model of "flip the coin, show the outcome to ``seer``": events heads / tails (heads :=
    ⊤ / ⊥), the seer tells them apart, the other agent confuses them (partial) or maps both to the skip event
    (oblivious); designated: the actual outcome."""
    from delkit.models.events import action

    _check(seer, mode)
    others = [a for a in AGENTS if a != seer]
    return action(AGENTS, [("heads", TOP, {"heads": TOP}), ("tails", TOP, {"heads": BOT})], full=[seer],
                  partial=others if mode == "partial" else [], designated=["heads" if outcome else "tails"],
                  name=f"flip_shown_to_{seer}")


def flip_transformer(seer: str, outcome: bool, tag: str) -> Any:
    """The flip as a knowledge transformer (S5, partial observers only): event variable ``q<tag>`` is the
    new side (heads := q), observed by the seer; designated: q = outcome."""
    from delkit.backends.symbolic import Transformer

    _check(seer, "partial")
    q = Prop(f"q{tag}")
    return Transformer((q.name,), TOP, {"heads": q}, {a: ((q.name,) if a == seer else ()) for a in AGENTS},
                       designated=q if outcome else Not(q))


def _check(seer: str, mode: str) -> None:
    if seer not in AGENTS:
        raise ModelError(f"coin flip: the coin is shown to 'a' or 'b', got {seer!r}")
    if mode not in MODES:
        raise ModelError(f"coin flip: the other agent is 'partial' (sees the flip, not the outcome) or 'oblivious' "
                         f"(does not notice it), got {mode!r}")


def after_flips(flips: list[tuple[str, str, bool]], engine: str = "explicit") -> Any:
    """The start updated with each flip ``(seer, mode, outcome is heads)`` in turn."""
    if engine == "symbolic" and any(m != "partial" for _, m, _ in flips):
        raise ModelError("coin flip: an oblivious agent makes the model KD45, which a knowledge structure (S5) "
                         "cannot hold; use the belief structures (engine 'belief', CLI --symbolic --oblivious) "
                         "or the explicit engine")
    state = coin_start(engine)
    for step, (seer, mode, outcome) in enumerate(flips):
        if engine == "symbolic":
            state = state.transform(flip_transformer(seer, outcome, f"{step}"))
        elif engine == "belief":
            state = state.transform(flip_event(seer, mode, outcome))
        else:
            from delkit.models.update import product_update

            state = product_update(state, flip_event(seer, mode, outcome))
    return state


def solve_coin_flip(outcome: bool = False, mode: str = "partial", *, engine: str = "explicit") -> CoinFlipResult:
    """One flip shown to Bob; evaluate the literature's claims at the actual state."""
    if engine != "explicit":
        from delkit.backends.symbolic import prepare

        prepare()
    t0 = time.process_time()
    state = after_flips([("b", mode, outcome)], engine)
    claims = {name: bool(state.holds(f)) for name, f in CLAIMS[(outcome, mode)].items()}
    states = state.n_worlds if engine == "explicit" else state.count_states()
    return CoinFlipResult("heads" if outcome else "tails", mode, engine, claims, states, time.process_time() - t0)
