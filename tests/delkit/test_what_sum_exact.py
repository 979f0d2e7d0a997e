"""What Sum decided exactly: the unbounded decision and its finite argument (a threshold past which the
infinite families are settled at once), the bounded models agreeing with it wherever the bound provably does
not matter, and the catalogue, the summary table and the command line giving the same answer."""

from __future__ import annotations

import json

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from delkit.cli import main
from delkit.logic.formula import Not
from delkit.puzzles import CATALOGUE, summary_table
from delkit.puzzles.what_sum import (
    _decode,
    _Large,
    _width,
    decide,
    exact_solutions,
    knows_own,
    solve_what_sum,
    support,
    what_sum_structure,
)


def test_exact_answer_is_the_literature_answer() -> None:
    """van Ditmarsch & Kooi 2015, ch. 4: Anne says 50, Bill has 20 and Cath 30, and nothing else."""
    assert exact_solutions(50).solutions == ((50, 20, 30),)


def _scan(a: int, reach: int) -> tuple:
    """Every candidate (a, b, c) with b, c <= reach, decided one by one (no threshold argument)."""
    cands = {(a, x, a - x) for x in range(1, a)} | {(a, x, x + a) for x in range(1, reach)} | \
        {(a, x + a, x) for x in range(1, reach)}
    return tuple(sorted(t for t in cands if max(t) <= reach and decide(t)[1]))


@settings(max_examples=25, deadline=None)
@given(st.integers(1, 60))
def test_exact_solutions_equal_a_plain_scan_far_past_the_threshold(a) -> None:
    exact = exact_solutions(a)
    assert exact.solutions == _scan(a, 2 * exact.threshold + 2 * a)


@settings(max_examples=40, deadline=None)
@given(st.integers(1, 60), st.integers(1, 400))
def test_a_family_decided_formally_is_decided_so_for_every_b_past_the_threshold(a, step) -> None:
    """The formal run (b as a large number) settles every comparison for all b > T: each concrete b > T takes
    the same branches, so both verdicts (left after the three announcements, Anne knows) are the formal ones."""
    limit = [0]
    big_a, b = _Large(0, a, limit), _Large(1, 0, limit)
    families = [(big_a, b, b + big_a), (big_a, b + big_a, b)]
    formal = [decide(f) for f in families]
    t = limit[0]
    x = t + step
    assert [decide((a, x, x + a)), decide((a, x + a, x))] == formal


def test_the_threshold_is_needed() -> None:
    """Below the threshold the families' triples are not all decided alike (the argument is not vacuous)."""
    a = 50
    limit = [0]
    big_a, b = _Large(0, a, limit), _Large(1, 0, limit)
    formal = decide((big_a, b, b + big_a))
    assert any(decide((a, x, x + a)) != formal for x in range(1, limit[0] + 1))


def _bounded_verdicts(bound: int) -> dict[tuple[int, int, int], tuple[bool, bool]]:
    """The bounded knowledge structure's verdicts (left after the three "I don't know"s, Anne knows) per triple."""
    w = _width(bound)
    ks = what_sum_structure(bound)
    everything = {_decode(s, w) for s in ks.states()}
    for who in ("anne", "bill", "cath"):
        ks = ks.announce(Not(knows_own(who, bound)))
    left = {_decode(s, w) for s in ks.states()}
    knows = {_decode(s, w) for s in ks.states(ks.evaluate(knows_own("anne", bound)))}
    return {t: (t in left, t in knows) for t in everything}


@pytest.mark.parametrize("bound", [24, 40, 50, 64])
def test_bounded_model_agrees_with_the_unbounded_decision_where_the_bound_does_not_matter(bound) -> None:
    verdicts = _bounded_verdicts(bound)
    within = [t for t in verdicts if support(t) <= bound]
    assert within  # the check is about something
    assert all(verdicts[t] == decide(t) for t in within)
    # ... and the bound does matter elsewhere: some triple near it is decided differently
    assert any(verdicts[t] != decide(t) for t in verdicts if support(t) > bound)


@pytest.mark.parametrize(("anne", "bound"), [(10, 40), (20, 64), (50, 64)])
def test_certified_bounded_solutions_are_exact_solutions(anne, bound) -> None:
    """The bounded model finds spurious solutions near its bound (Anne 10, bound 40: (10, 2, 12) …) and misses
    real ones; the certified ones are exactly its solutions the bound cannot have touched."""
    r = solve_what_sum(bound, anne)
    truth = exact_solutions(anne).solutions
    assert set(r.certified) <= set(truth)
    assert set(r.certified) == {t for t in r.solutions if support(t) <= bound}
    assert {t for t in truth if support(t) <= bound} <= set(r.certified)


def test_support_bounds_the_triples_inspected() -> None:
    """The support is at most 16 · max(t) (four steps, each at most doubling the largest number)."""
    for t in [(50, 20, 30), (3, 1, 2), (10, 4, 6), (7, 30, 37), (1, 1, 2)]:
        assert max(t) <= support(t) <= 16 * max(t)


def test_catalogue_summary_and_command_line_agree(capsys) -> None:
    entry = next(p for p in CATALOGUE if p["command"] == "what-sum")
    assert "(50, 20, 30)" in entry["answer"] and "only" in entry["answer"]
    assert main(["puzzle", "what-sum", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["solutions"] == [[50, 20, 30]] and data["exact"] is True
    row = next(r for r in summary_table() if r["command"] == "what-sum")
    assert row["ok"] and row["answer"] == [[50, 20, 30]]
    assert main(["puzzle", "what-sum", "--bound", "50", "--json"]) == 0
    bounded = json.loads(capsys.readouterr().out)
    assert bounded["exact"] is False and bounded["unbounded_solutions"] == [[50, 20, 30]]
