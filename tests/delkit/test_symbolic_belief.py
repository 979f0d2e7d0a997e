"""Belief structures (K, KD45, S5) agree with the explicit engine: random models, formulas with
announcements and event models (with factual change), translations both ways."""

from __future__ import annotations

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from delkit.backends.symbolic_belief import BeliefStructure, belief_from_kripke
from delkit.errors import ModelError
from delkit.logic.formula import K, Not, Prop, parse
from delkit.models.bisimulation import bisimilar
from delkit.models.update import product_update
from delkit.testing import event_models, formulas, kripke_models

PROPS = ("p", "q")
AGENTS = ("a", "b")
FRAMES = ("K", "KD45", "S5")


def _agree(model, formula) -> None:
    bs, states = belief_from_kripke(model)
    explicit = list(model.check(formula))
    assert [bs.truth(formula, s) for s in states] == explicit, formula
    assert bs.holds(formula) == model.holds(formula)


def _case(frame: str, max_worlds: int, depth: int):
    return st.tuples(kripke_models(PROPS, AGENTS, max_worlds, frame=frame, designated="some"),
                     formulas(PROPS, AGENTS, depth, allow_announce=True, allow_dynamic=True))


def _differential(frame: str, examples: int) -> None:
    @settings(max_examples=examples, deadline=None, suppress_health_check=list(HealthCheck))
    @given(_case(frame, 4, 3))
    def run(case) -> None:
        _agree(*case)

    run()


@pytest.mark.parametrize("frame", FRAMES)
def test_belief_structures_agree_with_explicit_fast(frame: str) -> None:
    _differential(frame, 30)


@pytest.mark.slow
@pytest.mark.parametrize("frame", FRAMES)
def test_belief_structures_agree_with_explicit_many(frame: str) -> None:
    """3 × 3,400 = 10,200 random (model, formula) cases."""
    _differential(frame, 3400)


@pytest.mark.parametrize("frame", FRAMES)
def test_belief_round_trip_and_transform(frame: str) -> None:
    @settings(max_examples=30, deadline=None, suppress_health_check=list(HealthCheck))
    @given(kripke_models(PROPS, AGENTS, 4, frame=frame, designated="some"),
           event_models(PROPS, AGENTS, 2, frame=frame))
    def run(model, events) -> None:
        bs, _ = belief_from_kripke(model)
        assert bisimilar(model, bs.to_kripke(PROPS))
        product = product_update(model, events)
        assert bisimilar(product, bs.transform(events).to_kripke(PROPS))

    run()


def test_belief_structure_by_hand_kd45_false_belief() -> None:
    """p is true, a believes ¬p (a sees only ¬p-states): B_a ¬p holds, K-axiom T fails, D holds."""
    bs = BeliefStructure.create(["p"], "T", {"a": "~p'"}, actual="p")
    assert bs.holds(K("a", Not(Prop("p"))))
    assert not bs.holds(parse("K_a p -> p") & K("a", Prop("p")))
    assert bs.holds(parse("~K_a F"))  # serial: a's beliefs are consistent
    model = bs.to_kripke()
    assert model.n_worlds == 2 and model.holds(K("a", Not(Prop("p"))))
    after = bs.announce("p")  # a hears p: now a sees no state at all, believes everything
    assert after.holds(K("a", Prop("p"))) and after.holds(parse("K_a F"))


def test_belief_structure_errors() -> None:
    with pytest.raises(Exception, match="unknown proposition"):
        BeliefStructure.create(["p"], "T", {"a": "r'"})
    with pytest.raises(ModelError, match="propositional"):
        BeliefStructure.create(["p"], "K_a p", {"a": "T"})
