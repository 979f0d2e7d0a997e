"""Minimisation and generated substructures of belief structures (``BeliefStructure.minimise`` /
``generated``, SMCDEL's ``optimize`` for ``SMCDEL.Symbolic.K``): differential tests against the structure
they come from, on random K/KD45 models (encoded with ``belief_from_kripke``) and their product updates with
random event models (which add event bits and copies of changed variables, many of them redundant).

The property runs a few examples in the fast suite and ``SLOW_EXAMPLES`` under ``make test-slow``."""

from __future__ import annotations

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from delkit.backends.symbolic_belief import BeliefStructure, belief_from_kripke
from delkit.logic.formula import TOP, Prop
from delkit.models.bisimulation import bisimilar
from delkit.testing import event_models, formulas, kripke_models

P, A = ("p", "q", "r"), ("a", "b")
FAST, SLOW_EXAMPLES = 30, 1700


def _cases(n: int):
    return settings(max_examples=n, deadline=None, suppress_health_check=[HealthCheck.too_slow])


def _minimise_and_generate(data) -> None:
    frame = data.draw(st.sampled_from(["K", "KD45"]))
    m = data.draw(kripke_models(P, A, 5, frame=frame, designated="some"))
    bs, _ = belief_from_kripke(m)
    for _ in range(data.draw(st.integers(0, 2))):
        bs = bs.transform(data.draw(event_models(P, A, 3, frame=frame, postconditions=True)))
    small = bs.minimise(keep=P)
    gen = bs.generated()
    both = gen.minimise(keep=P)
    assert set(P) <= set(small.vocabulary) and len(small.vocabulary) <= len(bs.vocabulary)
    assert small.count_states() == bs.count_states()  # the dropped variables are functions of the kept ones
    assert gen.count_states() <= bs.count_states()
    full = bs.to_kripke(props=P)
    for other in (small, gen, both):
        assert bisimilar(other.to_kripke(props=P), full)
    for f in data.draw(st.lists(formulas(P, A, 3), min_size=1, max_size=3)):
        assert small.holds(f) == bs.holds(f) == gen.holds(f) == both.holds(f), f


@_cases(FAST)
@given(data=st.data())
def test_minimise_and_generated_are_bisimilar(data) -> None:
    _minimise_and_generate(data)


@pytest.mark.slow
@_cases(SLOW_EXAMPLES)
@given(data=st.data())
def test_minimise_and_generated_are_bisimilar_slow(data) -> None:
    _minimise_and_generate(data)


def test_minimise_drops_determined_and_equivalent_variables() -> None:
    bs = BeliefStructure.create(["p", "q", "r", "s"], "(p <-> ~q) & s",
                                {"a": "q' <-> q", "b": "p' & r' & ~q"}, actual="p & r")
    small = bs.minimise(keep=["p"])
    assert small.vocabulary == ("p", "r")  # s is determined, q ↔ ¬p
    assert small.count_states() == bs.count_states() == 4
    for f in ("K_a p", "K_a ~p", "K_b r", "~K_b F", "K_a K_b p"):
        assert small.holds(f) == bs.holds(f), f
    assert small.holds("K_a p") and small.holds("K_b (p & r)")


def test_generated_keeps_only_reachable_states() -> None:
    bs = BeliefStructure.create(["p", "q"], "T", {"a": "p' <-> p", "b": "q' & p'"}, actual="p & q")
    gen = bs.generated()
    assert gen.count_states() == 2 and bs.count_states() == 4
    assert gen.form_of() == Prop("p") and bs.form_of() == TOP
