"""SMCDEL's second gossip variant (GossipKw): secrets as facts, experts know every secret. Literature answer
(Tijdeman 1971; Baker & Shostak 1972): the least number of calls making everyone an expert is 1, 3, 4 for
n = 2, 3, 4; both backends; the belief transformer and the event model give the same product."""

from __future__ import annotations

import itertools

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from delkit.logic.formula import K, Prop
from delkit.puzzles.gossip import kw_after, kw_experts, kw_minimum_calls, solve_gossip_kw


def literature(n: int) -> int:
    return {2: 1, 3: 3}.get(n, 2 * n - 4)


@pytest.mark.parametrize("symbolic", [True, False])
@pytest.mark.parametrize("n", [2, 3])
def test_least_calls(n: int, symbolic: bool) -> None:
    seq, shorter_fail, _ = kw_minimum_calls(n, symbolic=symbolic)
    assert len(seq) == literature(n) and shorter_fail
    assert kw_after(n, list(seq), symbolic=symbolic).holds(kw_experts(n))


def test_four_agents_witness_and_three_calls_fail() -> None:
    """01 23 02 13 makes four agents experts; three calls never do (up to renaming: the first is 01)."""
    n = 4
    assert kw_after(n, [(0, 1), (2, 3), (0, 2), (1, 3)]).holds(kw_experts(n))
    for rest in [((2, 3), (0, 2)), ((0, 2), (1, 3)), ((0, 2), (0, 3)), ((0, 2), (1, 2)), ((2, 3), (1, 3))]:
        assert not kw_after(n, [(0, 1), *rest]).holds(kw_experts(n)), rest


@pytest.mark.slow
def test_four_agents_least_calls() -> None:
    r = solve_gossip_kw(4)
    assert len(r.calls) == literature(4) and r.shorter_fail and not r.everyone_knows_all_experts


@settings(max_examples=15, deadline=None)
@given(st.lists(st.sampled_from([(0, 1), (0, 2), (1, 2)]), max_size=3))
def test_symbolic_equals_explicit(calls: list[tuple[int, int]]) -> None:
    """The belief transformer (2n event variables) and the explicit product with the event model agree on
    every agent's knowledge of every secret and of others' knowledge."""
    n = 3
    sym, exp = kw_after(n, calls, symbolic=True), kw_after(n, calls, symbolic=False)
    for a, b, k in itertools.product(map(str, range(n)), map(str, range(n)), range(n)):
        for f in (K(a, Prop(f"s{k}")), K(a, K(b, Prop(f"s{k}")))):
            assert sym.holds(f) == exp.holds(f), (calls, f)


def test_cli(capsys) -> None:
    import json

    from delkit.cli import main

    for engine in ("--symbolic", "--explicit"):
        assert main(["puzzle", "gossip", "--variant", "kw", "--n", "3", engine, "--json"]) == 0
        data = json.loads(capsys.readouterr().out)
        assert data["minimum_calls"] == literature(3) and data["variant"] == "kw"
    assert main(["puzzle", "gossip", "--variant", "kw", "--n", "4", "--explicit"]) == 2
    assert main(["puzzle", "gossip", "--variant", "xx"]) == 2


def test_what_the_variants_know_about_experts() -> None:
    """After 01 23 02 13 (docs/puzzles.md): knowing whether, agent 0 knows exactly that 0 and 2 are experts
    (they exchanged everything in call 02; 0 cannot tell that call 13 happened); GossipS5, where a call
    shows who called but not what was said, leaves no agent knowing that even she has every secret."""
    from delkit.logic.formula import conj
    from delkit.puzzles.gossip import after_calls

    seq = [(0, 1), (2, 3), (0, 2), (1, 3)]
    kw, s5 = kw_after(4, seq), after_calls(4, seq)

    def kw_expert(b: int):
        return conj(K(str(b), Prop(f"s{j}")) for j in range(4))

    def s5_expert(b: int):
        return conj(Prop(f"h_{b}_{j}") for j in range(4) if j != b)

    assert [b for b in range(4) if kw.holds(K("0", kw_expert(b)))] == [0, 2]
    assert [b for b in range(4) if kw.holds(K("3", kw_expert(b)))] == [1, 3]
    assert s5.holds(s5_expert(0)) and not any(s5.holds(K(str(a), s5_expert(a))) for a in range(4))
