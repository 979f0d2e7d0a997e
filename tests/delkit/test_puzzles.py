"""Literature answers of the epistemic puzzles, each solved with delkit's explicit DEL engine."""

from __future__ import annotations

import itertools
import json

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from delkit.cli import main
from delkit.errors import ModelError
from delkit.logic.formula import C, K, Kw, Not, Prop
from delkit.puzzles import (
    solve_cheryl,
    solve_dining,
    solve_drinking,
    solve_muddy,
    solve_russian_cards,
    solve_sum_product,
    summary_table,
)
from delkit.puzzles._common import knows_which, value_of
from delkit.puzzles.cheryl import cheryl_model
from delkit.puzzles.dining import anonymity_formula, dining_model, said
from delkit.puzzles.muddy import at_least_one, muddy_model, nobody_knows
from delkit.puzzles.russian_cards import is_good, russian_cards_model
from delkit.puzzles.sum_product import sum_product_model

# ----------------------------------------------------------------------------- muddy children


@pytest.mark.parametrize(("n", "m"), [(1, 1), (2, 1), (2, 2), (3, 1), (3, 2), (3, 3), (4, 2), (5, 5), (6, 3),
                                      (8, 1), (9, 7)])
def test_muddy_children_know_after_m_minus_one_rounds(n: int, m: int) -> None:
    r = solve_muddy(n, m)
    assert r.nobody_knows_rounds == m - 1
    assert r.muddy_know_round == m
    assert r.clean_know_round == (None if m == n else m + 1)
    assert r.worlds[0] == 2 ** n - 1


def test_muddy_initial_model_is_the_bitmask_cube() -> None:
    model = muddy_model(4, 2)
    assert model.n_worlds == 16 and model.designated == (3,)
    # child 0 confuses exactly the worlds that differ in bit 0
    assert model.successors("c0", 5) == [4, 5]
    assert model.holds(Not(Kw("c0", Prop("m0"))))  # before the father speaks, nobody knows
    assert model.holds(K("c0", Prop("m1")))  # child 0 sees child 1's muddy forehead


def test_muddy_father_announcement_makes_single_muddy_child_know() -> None:
    model = muddy_model(3, 1).announce(at_least_one(3))
    assert model.holds(Kw("c0", Prop("m0")))
    assert not model.holds(nobody_knows(3))
    # ... while without the father nobody would learn anything from "nobody knows"
    silent = muddy_model(3, 1)
    assert silent.announce(nobody_knows(3)).n_worlds == silent.n_worlds


@settings(max_examples=25, deadline=None)
@given(st.integers(1, 9).flatmap(lambda n: st.tuples(st.just(n), st.integers(1, n))))
def test_muddy_explicit_and_symbolic_agree_with_the_literature(nm: tuple[int, int]) -> None:
    from delkit.backends.symbolic import muddy_symbolic

    n, m = nm
    e, s = solve_muddy(n, m), muddy_symbolic(n, m)
    expected = (m - 1, m, None if m == n else m + 1)
    assert (e.nobody_knows_rounds, e.muddy_know_round, e.clean_know_round) == expected
    assert (s.nobody_knows_rounds, s.muddy_know_round, s.clean_know_round) == expected


def test_muddy_too_many_children_for_explicit_points_to_symbolic(capsys) -> None:
    with pytest.raises(ModelError, match="--symbolic"):
        muddy_model(40, 3)
    assert main(["puzzle", "muddy", "--children", "40", "--muddy", "3"]) == 2
    assert "--symbolic" in capsys.readouterr().err


def test_muddy_n14_is_fast_enough_for_the_benchmark() -> None:
    r = solve_muddy(14, 14)
    assert r.nobody_knows_rounds == 13
    assert r.seconds < 5.0  # generous: the benchmark target is 1 s; this only catches a blow-up


# ----------------------------------------------------------------------------- sum and product


def test_sum_and_product_unique_solution_4_13() -> None:
    r = solve_sum_product()
    assert r.solutions == ((4, 13),)
    # intermediate sizes reported by van Ditmarsch, Ruan & Verbrugge (2008): 145 and 86 pairs
    assert r.worlds == (2352, 145, 86, 1)


def test_sum_and_product_model_relations() -> None:
    model = sum_product_model(100)
    assert model.n_worlds == 2352
    nx = sum(p.startswith("x") for p in model.props)
    xs, ys = value_of(model.valuation[:, :nx]), value_of(model.valuation[:, nx:])
    world = {(int(x), int(y)): w for w, (x, y) in enumerate(zip(xs, ys, strict=True))}
    assert len(world) == 2352 and min(xs) == 2 and max(xs + ys) == 100
    assert model.successors("S", world[(2, 5)]) == sorted([world[(2, 5)], world[(3, 4)]])
    assert world[(3, 4)] in model.successors("P", world[(2, 6)])
    assert model.holds(knows_which("P", model.props), [world[(2, 3)]])  # product 6 = 2·3 only


# ----------------------------------------------------------------------------- Cheryl


def test_cheryl_birthday_is_july_16() -> None:
    r = solve_cheryl()
    assert r.solutions == ("July 16",)
    assert r.worlds == (10, 5, 3, 1)


def test_cheryl_initial_knowledge() -> None:
    model = cheryl_model()
    assert not model.check(knows_which("Albert", model.props)).any()
    bernard = model.check(knows_which("Bernard", model.props))
    assert sorted(model.world_name(int(w)) for w in np.flatnonzero(bernard)) == ["June 18", "May 19"]


# ----------------------------------------------------------------------------- Russian cards


def test_russian_cards_102_safe_announcements() -> None:
    r = solve_russian_cards()
    assert len(r.safe_announcements) == 102
    assert r.by_size == {5: 60, 6: 36, 7: 6}
    assert all((0, 1, 2) in x for x in r.safe_announcements)
    assert ((0, 1, 2), (0, 3, 4), (0, 5, 6), (1, 3, 5), (2, 4, 6)) in r.safe_announcements


def test_russian_cards_model_has_140_deals() -> None:
    model = russian_cards_model()
    assert model.n_worlds == 140
    assert model.world_name(model.designated[0]) == "012|345|6"


@pytest.mark.slow
def test_russian_cards_exhaustive_five_hand_announcements() -> None:
    """Without the clique pruning: every 5-hand announcement containing 012 (46376) through the checker."""
    model = russian_cards_model()
    others = [h for h in itertools.combinations(range(7), 3) if h != (0, 1, 2)]
    good = [x for x in itertools.combinations(others, 4) if is_good(model, tuple(sorted(((0, 1, 2), *x))))]
    assert len(good) == 60


@settings(max_examples=30, deadline=None)
@given(st.lists(st.sampled_from(list(itertools.combinations(range(7), 3))), min_size=4, max_size=6, unique=True))
def test_russian_cards_candidates_outside_cliques_are_not_good(others: list[tuple[int, ...]]) -> None:
    """The clique pruning is sound: announcements with two hands sharing two cards are never good."""
    hands = tuple(sorted({(0, 1, 2), *others}))
    shares_two = any(len(set(h) & set(g)) >= 2 for h, g in itertools.combinations(hands, 2))
    if shares_two:
        assert not is_good(russian_cards_model(), hands)


# ----------------------------------------------------------------------------- drinking logicians


@pytest.mark.parametrize("n", [2, 3, 4])
def test_drinking_logicians_all_valuations(n: int) -> None:
    for wants in itertools.product([True, False], repeat=n):
        answers = solve_drinking(wants).answers
        first_no = next((i for i, w in enumerate(wants) if not w), None)
        if first_no is None:
            assert answers == ("I don't know",) * (n - 1) + ("yes",)
        else:
            assert answers[:first_no] == ("I don't know",) * first_no
            assert answers[first_no:] == ("no",) * (n - first_no)


# ----------------------------------------------------------------------------- dining cryptographers


@pytest.mark.parametrize("n", [3, 4])
def test_dining_cryptographers_reveal_whether_not_who(n: int) -> None:
    for payer in [None, *range(n)]:
        for coins in range(1 << n):
            r = solve_dining(n, payer, coins)
            assert r.common_knows_whether_paid and r.someone_paid_known
            assert r.anonymous
            if payer is None:
                assert all(r.learned_payer)
            else:
                assert r.learned_payer == tuple(i == payer for i in range(n))


def test_dining_before_announcements_nobody_knows_whether_paid() -> None:
    model = dining_model(3, 1, 0)
    paid = Prop("p0") | Prop("p1") | Prop("p2")
    assert not model.holds(Kw("d0", paid))
    assert model.holds(anonymity_formula(3, 0))
    # the parity of all announced bits is whether someone paid, in every world
    parity = np.logical_xor.reduce([model.check(said(i, 3)) for i in range(3)])
    assert (parity == model.check(paid)).all()
    assert not model.holds(C(model.agents, paid))


# ----------------------------------------------------------------------------- summary and CLI


def test_summary_table_all_ok() -> None:
    from delkit.puzzles import N_PUZZLES

    seen: list[str] = []
    rows = summary_table(lambda row: seen.append(row["puzzle"]))
    assert len(rows) == N_PUZZLES  # N_PUZZLES is the progress display's total
    assert seen == [r["puzzle"] for r in rows]
    assert all(r["ok"] for r in rows), rows
    # every puzzle of the catalogue (`delkit puzzle --list`) is run by `delkit puzzle all` and the demo
    from delkit.puzzles import CATALOGUE

    assert {c["command"] for c in CATALOGUE} == {r["command"] for r in rows}


def _json(capsys, argv: list[str]) -> dict:
    rc = main(argv)
    out = capsys.readouterr().out
    assert rc == 0, out
    return json.loads(out)


def test_cli_muddy_json(capsys) -> None:
    data = _json(capsys, ["puzzle", "muddy", "--children", "6", "--muddy", "4", "--json"])
    assert data["nobody_knows_rounds"] == 3
    assert isinstance(data["seconds"], float)


def test_cli_muddy_symbolic_json(capsys) -> None:
    data = _json(capsys, ["puzzle", "muddy", "--children", "20", "--muddy", "5", "--symbolic", "--json"])
    assert data["nobody_knows_rounds"] == 4


def test_cli_sum_product_cheryl_russian(capsys) -> None:
    assert _json(capsys, ["puzzle", "sum-product", "--json"])["solutions"] == [[4, 13]]
    assert _json(capsys, ["puzzle", "cheryl", "--json"])["solutions"] == ["July 16"]
    assert _json(capsys, ["puzzle", "russian-cards", "--json"])["safe_announcements"] == 102


def test_cli_drinking_dining(capsys) -> None:
    assert _json(capsys, ["puzzle", "drinking", "--wants", "111", "--json"])["answers"][-1] == "yes"
    assert _json(capsys, ["puzzle", "dining", "--payer", "2", "--json"])["anonymous"] is True


def test_cli_table_output(capsys) -> None:
    assert main(["puzzle", "cheryl"]) == 0
    assert "July 16" in capsys.readouterr().out


def test_cli_bad_input_exits_2(capsys) -> None:
    assert main(["puzzle", "muddy", "--children", "3", "--muddy", "4", "--json"]) == 2
    assert "--muddy" in capsys.readouterr().err
    assert main(["puzzle", "drinking", "--wants", "12"]) == 2


# ----------------------------------------------------------------------------- gossip, What Sum

def test_gossip_four_calls_make_four_experts() -> None:
    """Literature (Tijdeman 1971; Baker & Shostak 1972): 2n − 4 = 4 calls suffice for n = 4 (01, 23, 02, 13);
    the first three of them do not."""
    from delkit.puzzles.gossip import after_calls, all_experts

    assert after_calls(4, [(0, 1), (2, 3), (0, 2), (1, 3)]).holds(all_experts(4))
    assert not after_calls(4, [(0, 1), (2, 3), (0, 2)]).holds(all_experts(4))
    assert not after_calls(4, [(0, 1), (0, 2), (0, 3), (0, 1)]).holds(all_experts(4))  # a star needs 5


def test_gossip_calls_are_private_to_the_callers() -> None:
    """After the call 01, agent 0 knows it has 1's secret; agent 2 knows that some call happened but not
    which one (SMCDEL's GossipS5 observations)."""
    from delkit.logic.formula import disj
    from delkit.puzzles.gossip import after_calls

    ks = after_calls(4, [(0, 1)])
    assert ks.holds(K("0", Prop("h_0_1"))) and ks.holds(K("1", Prop("h_1_0")))
    assert ks.holds(Not(K("2", Prop("h_0_1")))) and ks.holds(Not(K("2", Not(Prop("h_0_1")))))
    some_call = disj(Prop(f"h_{i}_{j}") for i in range(4) for j in range(4) if i != j)
    assert ks.holds(K("2", some_call))


def test_gossip_least_calls_small() -> None:
    from delkit.puzzles.gossip import solve_gossip

    assert [len(solve_gossip(n).calls) for n in (2, 3)] == [1, 3]


@pytest.mark.slow
def test_gossip_least_calls_four_agents() -> None:
    """2n − 4 = 4 for n = 4, and every shorter sequence fails (the search checks them all)."""
    from delkit.puzzles.gossip import solve_gossip

    r = solve_gossip(4)
    assert len(r.calls) == 4 and r.shorter_fail


def test_what_sum_backends_agree_with_smcdel_count() -> None:
    """SMCDEL's encoding with numbers up to 50: 330 states survive the three "I don't know"s (the figure
    SMCDEL's test suite checks), on both backends, the first (1, 3, 2)."""
    from delkit.puzzles.what_sum import solve_what_sum

    sym, exp = solve_what_sum(50), solve_what_sum(50, symbolic=False)
    assert sym.states == exp.states == 330
    assert sym.solutions == exp.solutions


@pytest.mark.slow
def test_what_sum_literature_state_survives() -> None:
    """van Ditmarsch & Kooi's answer (50, 20, 30): after the three "I don't know"s Anne knows her number 50
    there (at bound 200; at bound ≤ 150 the model's edge removes it, and the bounded model keeps other
    triples too — docs/puzzles.md)."""
    from delkit.puzzles.what_sum import solve_what_sum

    assert (50, 20, 30) in solve_what_sum(200).solutions


def test_cli_puzzle_list_and_new_puzzles(capsys) -> None:
    data = _json(capsys, ["puzzle", "--list", "--json"])
    assert {"gossip", "what-sum", "muddy", "dining"} <= {p["command"] for p in data["puzzles"]}
    assert _json(capsys, ["puzzle", "gossip", "--n", "3", "--json"])["minimum_calls"] == 3
    assert _json(capsys, ["puzzle", "what-sum", "--bound", "50", "--json"])["states_after_three_dont_knows"] == 330
    assert main(["puzzle", "gossip", "--n", "9"]) == 2


def test_door_mat_literature_claims() -> None:
    """SMCDEL's DoorMat (Gattinger 2018): tryTake gets Bob the key but Bob does not know beforehand that it
    will; after Anne announces that the key is under the mat he does, and the two-step plan works."""
    from delkit.puzzles.door_mat import solve_door_mat

    r = solve_door_mat()
    assert r.goal_after_try and not r.bob_knows_beforehand
    assert r.bob_knows_after_announcement and r.goal_after_announcement_and_try and r.bob_knows_goal_after_try


def test_door_mat_explicit_equals_symbolic() -> None:
    """The transformer read back as an event model: the explicit product update gives the same answers."""
    from delkit.backends.symbolic import event_model_from_transformer
    from delkit.models.bisimulation import bisimilar
    from delkit.models.update import product_update
    from delkit.puzzles.door_mat import door_mat_start, try_take

    start, x = door_mat_start(), try_take("1")
    explicit = product_update(start.to_kripke(), event_model_from_transformer(x, start))
    symbolic = start.transform(x)
    for f in ("bob_has", "K_bob bob_has", "K_anne bob_has", "K_anne K_bob bob_has | K_anne ~K_bob bob_has"):
        assert explicit.holds(f) == symbolic.holds(f)
    assert bisimilar(explicit, symbolic.to_kripke(props=("key", "bob_has")))


def test_cli_door_mat(capsys) -> None:
    data = _json(capsys, ["puzzle", "door-mat", "--json"])
    assert data["goal_after_try"] and not data["bob_knows_beforehand_that_try_works"]
