"""The puzzles on the symbolic backend: the same answers as the explicit engine, and SMCDEL's formulas."""

from __future__ import annotations

import itertools
import json

import pytest

from delkit.cli import main
from delkit.logic.formula import Not, Prop
from delkit.puzzles.dining import smcdel_dining_check, solve_dining
from delkit.puzzles.drinking import check_thirsty, drinking_structure, solve_drinking, thirsty_formula
from delkit.puzzles.sum_product import smcdel_sum_product, solve_sum_product


@pytest.mark.parametrize("n", [1, 2, 3, 4])
def test_drinking_symbolic_answers_equal_explicit(n: int) -> None:
    for wants in itertools.product((False, True), repeat=n):
        assert solve_drinking(wants, symbolic=True).answers == solve_drinking(wants).answers


@pytest.mark.parametrize("n", [2, 3, 5])
def test_thirsty_formula_true_exactly_when_all_want(n: int) -> None:
    assert check_thirsty(n, symbolic=True)[0] and check_thirsty(n, symbolic=False)[0]
    for k in range(n):  # any logician without thirst makes it false (she knows not all want)
        wants = tuple(i != k for i in range(n))
        assert not drinking_structure(wants).holds(thirsty_formula(n))


def test_thirsty_formula_deep_stack_symbolic() -> None:
    """SMCDEL's formula for 300 logicians nests 299 announcements: no RecursionError, right answer."""
    assert check_thirsty(300)[0]


@pytest.mark.parametrize(("n", "payer", "coins"), [(3, 0, 5), (3, None, 2), (4, 2, 9), (5, 4, 17), (6, None, 33)])
def test_dining_symbolic_equals_explicit(n: int, payer: int | None, coins: int) -> None:
    e, s = solve_dining(n, payer, coins), solve_dining(n, payer, coins, symbolic=True)
    keep = ("common_knows_whether_paid", "someone_paid_known", "learned_payer", "anonymous")
    assert {k: e.as_dict()[k] for k in keep} == {k: s.as_dict()[k] for k in keep}
    assert s.anonymous and s.common_knows_whether_paid


@pytest.mark.parametrize("n", [3, 4, 7, 12])
def test_smcdel_dining_formula_is_valid(n: int) -> None:
    assert smcdel_dining_check(n)[0]


def test_sum_product_symbolic_equals_explicit_and_smcdel_formula() -> None:
    e, s = solve_sum_product(), solve_sum_product(symbolic=True)
    assert s.solutions == e.solutions == ((4, 13),)
    assert s.worlds == e.worlds
    assert smcdel_sum_product()[0] == [(4, 13)]


def test_cli_symbolic_puzzles_beyond_the_explicit_caps(capsys) -> None:
    assert main(["puzzle", "drinking", "--n", "40", "--symbolic", "--formula", "--json"]) in (0, None)
    out = json.loads(capsys.readouterr().out)
    assert out["holds"] is True and "imports excluded" in out["timed"]
    assert main(["puzzle", "dining", "--n", "14", "--payer", "3", "--symbolic", "--json"]) in (0, None)
    out = json.loads(capsys.readouterr().out)
    assert out["anonymous"] and out["common_knows_whether_paid"]
    assert out["learned_payer"] == [i == 3 for i in range(14)]  # only the payer knows who paid
    assert main(["puzzle", "drinking", "--n", "40", "--json"]) == 2
    assert "--symbolic" in capsys.readouterr().err


def test_not_all_thirsty_formula_is_false_at_actual() -> None:
    ks = drinking_structure((True, False))
    assert ks.holds(Not(Prop("w1")))


@pytest.mark.parametrize("estimate", [1, None, 1 << 40])
def test_muddy_answer_does_not_depend_on_the_memory_estimate(estimate) -> None:
    """The puzzles size their managers (``new_manager(memory_estimate=…)``): the estimate only moves CUDD's
    eager-collection threshold (clamped to 2 MiB … 1 GiB), never the answer — below the threshold CUDD
    collects garbage in the middle of the rounds."""
    from delkit.backends.symbolic import KnowledgeStructure, new_manager
    from delkit.puzzles.muddy import at_least_one, run_rounds

    n, m = 24, 17
    props = [f"m{i}" for i in range(n)]
    mgr = new_manager(memory_estimate=estimate)
    f = KnowledgeStructure.create(props, observed={f"c{i}": [q for q in props if q != p] for i, p in
                                                   enumerate(props)},
                                  actual=" & ".join(props[:m] + [f"~{p}" for p in props[m:]]), bdd=mgr)
    _, nobody, muddy_round, clean_round, _ = run_rounds(f.announce(at_least_one(n)), n, m,
                                                        size=KnowledgeStructure.node_size)
    assert (nobody, muddy_round, clean_round) == (m - 1, m, m + 1)


@pytest.mark.parametrize("n", [0, 1, 2, 3, 5, 9])
def test_exactly_one_is_smcdels_pairwise_law(n: int) -> None:
    """The dining structure's law (:func:`exactly_one`, O(n) shared subformulas) is SMCDEL's
    ``⋁ P_i ∧ ⋀_{i<j} ¬(P_i ∧ P_j)``: the same BDD, and the truth table agrees with a count of the true parts."""
    from delkit.backends.symbolic import KnowledgeStructure
    from delkit.logic.formula import conj, disj
    from delkit.puzzles.dining import exactly_one

    ps = [Prop(f"P{i}") for i in range(n + 1)]
    pairwise = conj([disj(ps)] + [Not(ps[i] & ps[j]) for i in range(n + 1) for j in range(i + 1, n + 1)])
    ks = KnowledgeStructure.create([p.name for p in ps])
    assert ks.evaluate(exactly_one(ps)) == ks.evaluate(pairwise)
    if n <= 5:
        for bits in itertools.product([False, True], repeat=n + 1):
            state = {p.name: b for p, b in zip(ps, bits, strict=True)}
            assert ks.truth(exactly_one(ps), state) == (sum(bits) == 1)
