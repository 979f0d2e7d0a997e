"""The one-pass truth set of "nobody knows" (⋀_a ¬Kw_a x_a with V ∖ O_a = {x_a}) equals the per-agent
quantifications it replaces, and muddy children keeps the literature answer."""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from delkit.backends.symbolic import KnowledgeStructure, muddy_symbolic
from delkit.logic.formula import Formula, Kw, Not, Prop, conj, disj

VARS = tuple(f"x{i}" for i in range(5))


def _law(clauses: list[list[tuple[int, bool]]]) -> Formula:
    """A propositional law: a disjunction of cubes over VARS (empty: ⊤)."""
    if not clauses:
        return conj([])
    return disj(conj(Prop(VARS[i]) if pos else Not(Prop(VARS[i])) for i, pos in cube) for cube in clauses)


_cubes = st.lists(st.lists(st.tuples(st.integers(0, len(VARS) - 1), st.booleans()), min_size=1, max_size=4),
                  max_size=6)


def _structure(law: Formula, blind: dict[str, set[str]], bdd: object = None) -> KnowledgeStructure:
    """Agents a_x (one per variable x), each observing everything but ``blind[a_x]`` (on manager ``bdd``)."""
    observed = {a: [v for v in VARS if v not in hidden] for a, hidden in blind.items()}
    return KnowledgeStructure.create(VARS, law, observed, bdd=bdd)


def _reference(ks: KnowledgeStructure, formula: Formula) -> object:
    """The conjunction evaluated conjunct by conjunct (the general rule of ¬Kw: one quantification each)."""
    out = ks.law
    for g in formula.args:
        out = out & ks.evaluate(g)
    return out


@settings(max_examples=60, deadline=None)
@given(_cubes, st.sets(st.sampled_from(VARS), min_size=1))
def test_nobody_knows_one_pass_equals_per_agent_quantification(cubes, chosen) -> None:
    law = _law(cubes)
    ks = _structure(law, {f"a_{x}": {x} for x in VARS})
    f = conj(Not(Kw(f"a_{x}", Prop(x))) for x in sorted(chosen))
    if len(chosen) == 1:
        f = conj([f, f])  # a one-conjunct conj collapses to the conjunct; keep an And
    assert ks._flip_variables(f) == frozenset(chosen)  # the one-pass rule applies
    reference = _reference(_structure(law, {f"a_{x}": {x} for x in VARS}, ks.bdd), f)
    assert (ks.law & ks.evaluate(f)) == reference


@settings(max_examples=40, deadline=None)
@given(_cubes, st.sampled_from(VARS[1:]))
def test_nobody_knows_with_a_wider_blind_spot_takes_the_general_rule(cubes, extra) -> None:
    """An agent blind to two variables: ¬Kw_a x is ∃-over-the-rest, not ∀x θ; the one-pass rule must not apply."""
    law = _law(cubes)
    blind = {f"a_{x}": {x} for x in VARS}
    blind["a_x0"] = {"x0", extra}
    ks = _structure(law, blind)
    f = conj(Not(Kw(f"a_{x}", Prop(x))) for x in VARS)
    assert ks._flip_variables(f) is None
    assert (ks.law & ks.evaluate(f)) == _reference(_structure(law, blind, ks.bdd), f)


def test_nobody_knows_truth_set_is_shared_by_announced_structures() -> None:
    """The pass's memo lives with the observations: an announced structure reuses it and stays right."""
    ks = _structure(_law([[(0, True)], [(1, True)], [(2, False), (3, True)]]), {f"a_{x}": {x} for x in VARS})
    f = conj(Not(Kw(f"a_{x}", Prop(x))) for x in VARS)
    for _ in range(4):
        fresh = _structure(ks.form_of(), {f"a_{x}": {x} for x in VARS}, ks.bdd)
        assert (ks.law & ks.evaluate(f)) == (ks.law & _reference(fresh, f))
        ks = ks.announce(f)


@settings(max_examples=25, deadline=None)
@given(st.integers(1, 40).flatmap(lambda n: st.tuples(st.just(n), st.integers(1, n))))
def test_muddy_symbolic_literature_answer(nm) -> None:
    """Fagin et al. §1.1: "nobody knows" m − 1 times, the muddy children know in round m, the clean in m + 1."""
    n, m = nm
    r = muddy_symbolic(n, m)
    assert (r.nobody_knows_rounds, r.muddy_know_round, r.clean_know_round) == (m - 1, m, None if m == n else m + 1)


@pytest.mark.parametrize("n", [100, 150])
def test_muddy_symbolic_large_all_muddy(n: int) -> None:
    r = muddy_symbolic(n, n)
    assert (r.nobody_knows_rounds, r.muddy_know_round) == (n - 1, n)
