"""Differential tests of the symbolic toolbox (SMCDEL's ``optimize``, generated substructures, ``formOf``
and distributed knowing whether): explicit ≡ symbolic (≡ compact for Dkw) on random S5 models and formulas.

Each property runs a cheap number of examples in the fast suite and ``SLOW_EXAMPLES`` under ``make
test-slow`` (3 properties × 1,700 = 5,100 cases).
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from delkit.backends.compact import CompactEngine
from delkit.backends.symbolic import KnowledgeStructure, form_of, from_kripke, transformer_from_event_model
from delkit.logic.formula import Dkw, Not, Or, Prop, parse
from delkit.models.bisimulation import bisimilar
from delkit.models.kripke import KripkeModel
from delkit.testing import event_models, formulas, kripke_models, propositional_formulas

P, A = ("p", "q", "r"), ("a", "b", "c")
FAST, SLOW_EXAMPLES = 40, 1700
GROUPS = st.lists(st.sampled_from(A), min_size=1, max_size=3, unique=True)
ENGINE = CompactEngine(P, A, groups=[["a", "b"], ["a", "c"], ["b", "c"], ["a", "b", "c"]])


def _s5(designated: str = "some", max_worlds: int = 6):
    return kripke_models(P, A, max_worlds, frame="S5", designated=designated)


def _cases(n: int):
    return settings(max_examples=n, deadline=None, suppress_health_check=[HealthCheck.too_slow])


def _dkw_oracle(m: KripkeModel, group, truth: np.ndarray) -> np.ndarray:
    """Dkw_G φ at w, straight from the definition: every world w reaches by ⋂_{a∈G} R_a has φ's value at w
    (S5: reflexive, so 'all agree' is 'all agree with w')."""
    rel = np.ones((m.n_worlds, m.n_worlds), dtype=bool)
    for a in group:
        rel &= m.relations[a].to_matrix().toarray().astype(bool)
    return np.array([bool((truth[rel[w]] == truth[w]).all()) for w in range(m.n_worlds)])


def _truth_per_world(ks: KnowledgeStructure, states, f) -> np.ndarray:
    return np.array([ks.truth(f, s) for s in states])


# ----------------------------------------------------------------------------- formOf

def _form_of_roundtrip(data) -> None:
    m = data.draw(_s5())
    f = data.draw(formulas(P, A, 3))
    ks, states = from_kripke(m)
    u = ks.evaluate(f) & ks.law
    g = form_of(ks.bdd, u)
    assert ks.evaluate(g) & ks.law == u  # the same BDD back ...
    # ... and, read by the explicit checker on the structure's own model, the same worlds as φ
    km = ks.to_kripke()
    index = {tuple(s[v] for v in ks.vocabulary): i for i, s in enumerate(ks.states())}
    explicit = km.check(g)
    assert [bool(explicit[index[tuple(s[v] for v in ks.vocabulary)]]) for s in states] == list(m.check(f))


@_cases(FAST)
@given(data=st.data())
def test_form_of_explicit_equals_symbolic(data) -> None:
    _form_of_roundtrip(data)


@pytest.mark.slow
@_cases(SLOW_EXAMPLES)
@given(data=st.data())
def test_form_of_explicit_equals_symbolic_slow(data) -> None:
    _form_of_roundtrip(data)


@_cases(FAST)
@given(f=propositional_formulas(P + ("s",), 4))
def test_form_of_propositional(f) -> None:
    ks = KnowledgeStructure.create(P + ("s",))
    g = ks.form_of(ks.evaluate(f))
    assert ks.evaluate(g) == ks.evaluate(f)


# ----------------------------------------------------------------------------- minimisation, generated

def _minimise_and_generate(data) -> None:
    m = data.draw(_s5())
    ks, _ = from_kripke(m)
    if data.draw(st.booleans()):  # a product update adds event and copy variables, many of them redundant
        em = data.draw(event_models(P, A, 3, frame="S5", postconditions=True))
        x, _ = transformer_from_event_model(em, ks)
        ks = ks.transform(x)
    small = ks.minimise(keep=P)
    gen = ks.generated()
    assert len(small.vocabulary) <= len(ks.vocabulary)
    assert set(P) <= set(small.vocabulary)
    assert small.count_states() == ks.count_states()  # dropped variables are functions of the kept ones
    full = ks.to_kripke(props=P)
    assert bisimilar(small.to_kripke(props=P), full)
    assert bisimilar(gen.to_kripke(props=P), full)
    assert gen.count_states() <= ks.count_states()
    for f in data.draw(st.lists(formulas(P, A, 3), min_size=1, max_size=3)):
        assert small.holds(f) == ks.holds(f) == gen.holds(f)


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
    ks = KnowledgeStructure.create(["p", "q", "r", "s"], "(p <-> ~q) & s", {"a": ["p"], "b": ["q", "r"]},
                                   actual="p & r")
    small = ks.minimise(keep=["p"])
    assert small.vocabulary == ("p", "r")  # s is determined, q ↔ ¬p
    assert set(small.observed["b"]) == {"p", "r"}  # b observed q, now the equivalent p
    assert small.count_states() == ks.count_states() == 4
    assert small.holds("K_b p | K_b ~p") and ks.holds("K_b p | K_b ~p")


def test_generated_keeps_only_reachable_states() -> None:
    ks = KnowledgeStructure.create(["p", "q"], observed={"a": ["p"], "b": ["p"]}, actual="p & q")
    gen = ks.generated()
    assert gen.count_states() == 2 and ks.count_states() == 4
    assert gen.form_of() == Prop("p")


# ----------------------------------------------------------------------------- Dkw

def _dkw(data) -> None:
    m = data.draw(_s5(designated="all"))
    group = data.draw(GROUPS)
    f = data.draw(formulas(P, A, 2))
    truth = m.check(f)
    want = _dkw_oracle(m, group, truth)
    d = Dkw(group, f)
    assert list(m.check(d)) == list(want)  # explicit checker
    ks, states = from_kripke(m)
    assert list(_truth_per_world(ks, states, d)) == list(want)  # BDDs
    # compact contracts to bisimulation classes for the agents and the declared groups' relations
    assert ENGINE.holds(ENGINE.from_kripke(m), d) == bool(want.all())


@_cases(FAST)
@given(data=st.data())
def test_dkw_explicit_equals_symbolic(data) -> None:
    _dkw(data)


@pytest.mark.slow
@_cases(SLOW_EXAMPLES)
@given(data=st.data())
def test_dkw_explicit_equals_symbolic_slow(data) -> None:
    _dkw(data)


def test_dkw_syntax_and_smcdel_reader() -> None:
    f = parse("Dkw{a,b} (p & q)")
    assert f == Or((parse("D{a,b} (p & q)"), parse("D{a,b} ~(p & q)")))
    assert parse(str(f)) == f
    assert parse("Ckw{a} p") == Or((parse("C{a} p"), parse("C{a} ~p")))
    assert Dkw(["a"], Prop("p")) == Or((parse("D{a} p"), parse("D{a} " + str(Not(Prop("p"))))))
    from delkit.io.smcdel import answer, parse_smcdel

    spec = parse_smcdel("VARS 1,2\nLAW Top\nOBS alice: 1\n    bob: 2\n"
                        "VALID? (alice,bob) distknow whether (1 & 2)\nVALID? alice distknow whether 2\n"
                        "VALID? alice,bob distknow that (1 | ~1)\n")
    assert [a["answer"] for a in answer(spec)] == [True, False, True]
