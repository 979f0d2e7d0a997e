"""Announcement protocols: the 100 prisoners (bounded), letter passing, coin flip and the number triangle — their
literature answers, explicit ≡ symbolic, and the CLI."""

from __future__ import annotations

import itertools
import json

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from delkit.cli import main
from delkit.errors import ModelError
from delkit.logic.formula import K, Kw, Not, Prop
from delkit.models.bisimulation import bisimilar


def _json(capsys, argv: list[str]) -> dict:
    assert main(argv) == 0
    return json.loads(capsys.readouterr().out)


# ----------------------------------------------------------------------------- number triangle


@pytest.mark.parametrize(("n", "m"), [(1, 1), (2, 1), (2, 2), (3, 2), (5, 5), (10, 4), (100, 37), (5000, 1234)])
def test_triangle_some_gives_m_minus_one_nobody_knows(n: int, m: int) -> None:
    """Literature (Fagin et al. §1.1; Gierasimczuk & Szymanik 2011): with "at least one of you", M − 1
    rounds of "nobody knows", then the muddy children know (and the clean ones do not yet), on a model of
    n + 1 factual states."""
    from delkit.puzzles.number_triangle import triangle_run

    r = triangle_run(n, m, "some")
    assert r.nobody_knows_rounds == m - 1 and r.muddy_know is True
    assert r.clean_know is (None if m == n else False)
    assert r.states[0] == n and r.states[-1] == n - m + 1


@pytest.mark.parametrize(("n", "m"), [(1, 1), (3, 1), (4, 3), (6, 6), (8, 5)])
def test_triangle_agrees_with_the_classical_per_child_protocol(n: int, m: int) -> None:
    """The same rounds as :func:`solve_muddy` on 2^n worlds, where each child answers for itself."""
    from delkit.puzzles.muddy import solve_muddy
    from delkit.puzzles.number_triangle import triangle_run

    classic, tri = solve_muddy(n, m), triangle_run(n, m)
    assert tri.nobody_knows_rounds == classic.nobody_knows_rounds
    assert classic.muddy_know_round == tri.nobody_knows_rounds + 1


def _all_quantifiers(n: int):
    for bits in itertools.product((False, True), repeat=n + 1):
        counts = [k for k in range(n + 1) if bits[k]]
        if counts:
            yield ",".join(map(str, counts)), counts


def _outcome(r):
    return r.nobody_knows_rounds, r.muddy_know, r.clean_know, r.states


@pytest.mark.parametrize("n", [1, 2, 3, 4])
def test_triangle_equals_classical_model_and_structure_for_every_quantifier(n: int) -> None:
    """Every quantifier Q ⊆ {0..n} and every true M: the triangle (2n + 1 points), the classical explicit
    model (2^n worlds) and the knowledge structure give the same rounds, the same knowers and the same
    surviving counts."""
    from delkit.puzzles.number_triangle import classic_run, triangle_run

    for spec, counts in _all_quantifiers(n):
        for m in counts:
            tri = _outcome(triangle_run(n, m, spec))
            assert tri == _outcome(classic_run(n, m, spec)) == _outcome(classic_run(n, m, spec, symbolic=True)), \
                (spec, m)


@pytest.mark.parametrize("n", [5, 6, 7, pytest.param(9, marks=pytest.mark.slow)])
def test_triangle_equals_classical_model_every_quantifier_larger(n: int) -> None:
    from delkit.puzzles.number_triangle import classic_run, triangle_run

    for spec, counts in _all_quantifiers(n):
        for m in counts:
            assert _outcome(triangle_run(n, m, spec)) == _outcome(classic_run(n, m, spec)), (spec, m)


@settings(max_examples=60, deadline=None)
@given(st.integers(1, 3000), st.data())
def test_triangle_at_least_k(n: int, data) -> None:
    """"At least k of you are muddy": the muddy children know after M − k rounds of "nobody knows" (k ≥ 1;
    k = 1 is the classical puzzle); with k = 0 (no information) nobody ever knows."""
    from delkit.puzzles.number_triangle import triangle_run

    k = data.draw(st.integers(0, n))
    m = data.draw(st.integers(k, n))
    r = triangle_run(n, m, f"at-least-{k}")
    if k == 0:
        assert not r.someone_knows
    else:
        assert r.muddy_know and r.nobody_knows_rounds == m - k


@settings(max_examples=200, deadline=None)
@given(st.integers(1, 40), st.data())
def test_triangle_first_knowers_follow_the_nearest_false_count(n: int, data) -> None:
    """For any Q: with L the largest count below M where Q fails and U the smallest above, the muddy children
    are the first to know, after M − L − 1 "nobody knows", iff L exists and is at least as near as U; the
    clean ones after U − M − 1 iff U is at least as near; nobody ever knows without L and U. In particular
    (Gierasimczuk & Szymanik 2011, Theorem 1, for the increasing quantifiers, where U never exists) the
    muddy children come to know iff Q fails at some L < M."""
    from delkit.puzzles.number_triangle import triangle_run

    q = data.draw(st.lists(st.booleans(), min_size=n + 1, max_size=n + 1))
    m = data.draw(st.sampled_from([k for k in range(n + 1) if q[k]] or [None]))
    if m is None:
        return
    spec = ",".join(str(k) for k in range(n + 1) if q[k])
    r = triangle_run(n, m, spec)
    lo = max((k for k in range(m) if not q[k]), default=None)
    hi = min((k for k in range(m + 1, n + 1) if not q[k]), default=None)
    d_lo = None if lo is None else m - lo
    d_hi = None if hi is None else hi - m
    if d_lo is None and d_hi is None:
        assert not r.someone_knows
        return
    best = min(d for d in (d_lo, d_hi) if d is not None)
    assert r.nobody_knows_rounds == best - 1
    assert bool(r.muddy_know) == (d_lo == best)
    assert bool(r.clean_know) == (d_hi == best)


def test_triangle_bad_input() -> None:
    from delkit.puzzles.number_triangle import classic_run, triangle_run

    with pytest.raises(ModelError, match="false when 2 of 8"):
        triangle_run(8, 2, "at-least-3")
    with pytest.raises(ModelError, match="unknown quantifier"):
        triangle_run(8, 2, "many")
    with pytest.raises(ModelError, match="above the 3 children"):
        triangle_run(3, 1, "1,4")
    with pytest.raises(ModelError, match="at most 14"):
        classic_run(20, 3)


def test_cli_number_triangle(capsys) -> None:
    data = _json(capsys, ["puzzle", "number-triangle", "-n", "12", "-m", "5", "--json"])
    assert data["nobody_knows_rounds"] == 4 and data["muddy_know"] and data["triangle_points"] == 25
    data = _json(capsys, ["puzzle", "number-triangle", "-n", "6", "-m", "5", "-q", "at-least-3", "--explicit",
                          "--json"])
    assert data["engine"] == "explicit" and data["nobody_knows_rounds"] == 2
    assert _json(capsys, ["puzzle", "number-triangle", "-n", "6", "-m", "5", "-q", "at-least-3", "--symbolic",
                          "--json"])["nobody_knows_rounds"] == 2
    assert main(["puzzle", "number-triangle", "-n", "6", "-m", "1", "-q", "even"]) == 2
    assert main(["puzzle", "number-triangle", "--explicit", "--symbolic"]) == 2


# ----------------------------------------------------------------------------- coin flip


@pytest.mark.parametrize("engine", ["explicit", "symbolic", "belief"])
@pytest.mark.parametrize("heads", [True, False])
@pytest.mark.parametrize("mode", ["partial", "oblivious"])
def test_coin_flip_literature_claims(engine: str, heads: bool, mode: str) -> None:
    """Bob sees the outcome; Anne knows that he knows it (partial), or keeps believing heads — and that Bob
    does too — (oblivious); Bob knows what Anne believes."""
    from delkit.puzzles.coin_flip import solve_coin_flip

    if engine == "symbolic" and mode == "oblivious":
        with pytest.raises(ModelError, match="KD45"):
            solve_coin_flip(heads, mode, engine=engine)
        return
    r = solve_coin_flip(heads, mode, engine=engine)
    assert r.ok, r.claims
    assert r.states == (2 if mode == "partial" else 3)


def test_coin_flip_what_anne_does_not_know() -> None:
    """The flip really hides the outcome from Anne (partial): she knows neither side; oblivious, her belief is
    false after tails and the model is KD45, not S5."""
    from delkit.puzzles.coin_flip import after_flips

    part = after_flips([("b", "partial", False)])
    assert part.is_s5()
    assert not part.holds(K("a", Prop("heads"))) and not part.holds(K("a", Not(Prop("heads"))))
    obl = after_flips([("b", "oblivious", False)])
    assert obl.holds(Not(Prop("heads"))) and obl.holds(K("a", Prop("heads")))
    assert obl.is_kd45() and not obl.is_s5()


_FORMULAS = ["heads", "K_a heads", "K_b heads", "Kw_a heads", "Kw_b heads", "K_a Kw_b heads", "K_b Kw_a heads",
             "K_a K_b heads", "K_b K_a heads", "C{a,b} Kw_b heads", "C{a,b} Kw_a heads", "K_a ~K_b ~heads"]


@settings(max_examples=40, deadline=None)
@given(st.lists(st.tuples(st.sampled_from("ab"), st.sampled_from(["partial", "oblivious"]), st.booleans()),
                min_size=1, max_size=3))
def test_coin_flips_explicit_equal_symbolic(flips) -> None:
    """Any sequence of flips, each shown to a or b: explicit ≡ belief structures (any observers) ≡ knowledge
    structures (partial observers only), formula by formula and up to bisimulation."""
    from delkit.puzzles.coin_flip import after_flips

    explicit = after_flips(flips)
    engines = ["belief"] + (["symbolic"] if all(m == "partial" for _, m, _ in flips) else [])
    for engine in engines:
        sym = after_flips(flips, engine)
        assert [explicit.holds(f) for f in _FORMULAS] == [sym.holds(f) for f in _FORMULAS], engine
        assert bisimilar(explicit, sym.to_kripke(props=("heads",))), engine


def test_cli_coin_flip(capsys) -> None:
    data = _json(capsys, ["puzzle", "coin-flip", "--json"])
    assert data["all_claims_hold"] and data["engine"] == "explicit" and data["outcome"] == "tails"
    data = _json(capsys, ["puzzle", "coin-flip", "--oblivious", "--symbolic", "--outcome", "heads", "--json"])
    assert data["all_claims_hold"] and data["engine"] == "belief"
    assert _json(capsys, ["puzzle", "coin-flip", "--symbolic", "--json"])["engine"] == "symbolic"
    assert main(["puzzle", "coin-flip", "--outcome", "edge"]) == 2


# ----------------------------------------------------------------------------- letter passing


def test_letter_passing_three_agents_who_knows_what() -> None:
    """SMCDEL's task (agents 1, 2, 3; the letter with 1, for 3): after 1→2 agent 2 knows the address, 3 does
    not even know whether it is for it; after 2→3 the goal holds and is common knowledge."""
    from delkit.puzzles.letter_passing import solve_letter_passing

    for engine in ("explicit", "symbolic"):
        s = solve_letter_passing(3, engine=engine).steps
        assert [x["know_addressee"] for x in s] == [[1], [1, 2], [1, 2, 3]]
        assert [x["unsure_whether_for_them"] for x in s] == [[2, 3], [3], []]
        assert [x["goal"] for x in s] == [False, False, True]
        assert [x["know_goal"] for x in s] == [[], [], [1, 2, 3]]
        assert [x["common_knowledge_of_goal"] for x in s] == [False, False, True]


@pytest.mark.parametrize(("n", "to"), [(3, 2), (4, 4), (5, 3), (6, 6), (7, 2)])
def test_letter_passing_line(n: int, to: int) -> None:
    """Along a line (n ≥ 3: with two agents the address is known to both from the start): the letter arrives
    after to − 1 passes and not before; after pass s the agents 1..s+1 know the address, the others not even
    whether it is for them; at the end the agents 1..to know the goal is reached, and it is common knowledge
    iff nobody beyond the addressee is left wondering."""
    from delkit.puzzles.letter_passing import solve_letter_passing

    r = solve_letter_passing(n, to)
    assert len(r.plan) == to - 1
    for s, x in enumerate(r.steps):
        assert x["holder"] == s + 1 and x["holder_known_to_all"]
        assert x["know_addressee"] == list(range(1, s + 2))
        assert x["unsure_whether_for_them"] == list(range(s + 2, n + 1))
        assert x["goal"] == (s == to - 1)
    assert r.steps[-1]["know_goal"] == list(range(1, to + 1))
    assert r.steps[-1]["common_knowledge_of_goal"] == (to == n)


@settings(max_examples=15, deadline=None)
@given(st.integers(2, 7), st.data())
def test_letter_passing_explicit_equals_symbolic(n: int, data) -> None:
    from delkit.models.update import product_update
    from delkit.puzzles.letter_passing import letter_start, pass_event, pass_transformer, solve_letter_passing

    to = data.draw(st.integers(2, n))
    assert solve_letter_passing(n, to).steps == solve_letter_passing(n, to, engine="symbolic").steps
    exp, sym = letter_start(n, to), letter_start(n, to, "symbolic")
    for i in range(1, to):
        exp = product_update(exp, pass_event(n, i, i + 1))
        sym = sym.transform(pass_transformer(n, i, i + 1, f"x{i}"))
    assert bisimilar(exp, sym.to_kripke(props=exp.props))


def test_letter_passing_receiver_reads_privately() -> None:
    """After 1→2 agent 3 knows that 2 knows the address (the pass is public), not the address itself."""
    from delkit.models.update import product_update
    from delkit.puzzles.letter_passing import knows_addressee, letter_start, pass_event

    m = product_update(letter_start(3, 3), pass_event(3, 1, 2))
    assert m.holds(K("3", knows_addressee(3, 2))) and not m.holds(knows_addressee(3, 3))
    assert not m.holds(Kw("3", Prop("for3")))


def test_cli_letter_passing(capsys) -> None:
    data = _json(capsys, ["puzzle", "letter-passing", "--agents", "4", "--json"])
    assert data["plan"] == ["1->2", "2->3", "3->4"] and data["goal_after_plan"]
    data = _json(capsys, ["puzzle", "letter-passing", "--agents", "4", "--to", "2", "--symbolic", "--json"])
    assert data["passes"] == 1 and data["engine"] == "symbolic"
    assert main(["puzzle", "letter-passing", "--agents", "3", "--to", "1"]) == 2
    assert main(["puzzle", "letter-passing", "--agents", "99"]) == 2


# ----------------------------------------------------------------------------- prisoners


def test_prisoners_smcdel_story() -> None:
    """SMCDEL's story (3 prisoners, interviews 2, 1, 3, 1): the counter knows on day 4, not on day 3 (when
    everyone has been interviewed but he has counted one switch)."""
    from delkit.puzzles.prisoners import run_schedule

    for engine in ("explicit", "symbolic"):
        knows, visited, _ = run_schedule(3, [2, 1, 3, 1], engine, stop=False)
        assert knows == [False, False, False, True] and visited == [False, False, True, True]


def _histories(n: int, days: int):
    """The multi-pointed model of all schedules of ``days`` days (no reduction) and each world's schedule."""
    from delkit.models.update import product_update
    from delkit.puzzles.prisoners import _start_model, day_event

    model = _start_model(n)
    hist: list[tuple[int, ...]] = [()]
    for _ in range(days):
        ev = day_event(n, None)
        model, pairs = product_update(model, ev, return_pairs=True)
        hist = [hist[int(w)] + (1 if ev.events[int(e)].startswith("1") else int(ev.events[int(e)]),)
                for w, e in pairs]
    return model, hist


@pytest.mark.parametrize(("n", "days"), [(2, 6), (3, 6), (4, 5)])
def test_prisoners_counter_knows_exactly_at_count_n_minus_1(n: int, days: int) -> None:
    """Every schedule of ``days`` days at once: the counter knows that everyone has been interviewed iff his
    count has reached n − 1 (n ≥ 3) — the protocol is correct and he could not know earlier; with two
    prisoners he knows as soon as both have been interviewed (he notices the days he is not called)."""
    from delkit.puzzles.prisoners import counter_knows, everyone_visited, protocol_run

    model, hist = _histories(n, days)
    assert len(set(hist)) == n ** days == model.n_worlds
    knows, visited = model.check(counter_knows(n)), model.check(everyone_visited(n))
    assert not np.any(knows & ~visited)  # sound
    for w, h in enumerate(hist):
        announce, first_all = protocol_run(n, list(h))
        if n >= 3:
            assert bool(knows[w]) == (announce is not None), h
        else:
            assert bool(knows[w]) == (first_all is not None), h


@settings(max_examples=15, deadline=None)
@given(st.integers(2, 5), st.lists(st.integers(0, 10**6), min_size=1, max_size=30))
def test_prisoners_explicit_equals_symbolic(n: int, raw: list[int]) -> None:
    """Day by day on any schedule: the reduced knowledge structure and the contracted explicit model agree on
    whether the counter knows and whether everyone has been interviewed."""
    from delkit.puzzles.prisoners import protocol_run, run_schedule

    sched = [1 + r % n for r in raw]
    exp = run_schedule(n, sched, "explicit", stop=False)
    sym = run_schedule(n, sched, "symbolic", stop=False)
    img = run_schedule(n, sched, "image", stop=False)
    assert exp[:2] == sym[:2] == img[:2]
    announce, _ = protocol_run(n, sched)
    if n >= 3:
        assert (exp[0].index(True) + 1 if any(exp[0]) else None) == announce


def test_prisoners_reduction_is_bisimilar() -> None:
    """The reduced structure (generated substructure, fixed and unobserved variables removed) against the
    plain product of the transformers: same truth of the counter's knowledge each day, bisimilar models."""
    from delkit.puzzles.prisoners import counter_knows, day_transformer, prisoners_start, reduce_structure

    n, sched = 3, [2, 2, 1, 3, 3, 1, 2]
    full = red = prisoners_start(n)
    keep = full.vocabulary
    for d, who in enumerate(sched):
        full = full.transform(day_transformer(n, who, f"f{d}"))
        red = reduce_structure(red.transform(day_transformer(n, who, f"r{d}")), keep)
        assert set(red.vocabulary) <= set(keep)
        assert full.holds(counter_knows(n)) == red.holds(counter_knows(n))
        assert bisimilar(full.generated().to_kripke(props=keep), red.to_kripke(props=keep))


def test_prisoners_image_is_the_reduced_structure() -> None:
    """The direct image (interleaved variables) holds, day by day, exactly the states of the reduced product
    of the transformers."""
    from delkit.puzzles.prisoners import ImageStructure, day_transformer, prisoners_start, reduce_structure

    n, sched = 4, [3, 1, 2, 2, 4, 1, 1, 3, 2, 1, 4, 1]
    red, img = prisoners_start(n), ImageStructure(n)
    keep = red.vocabulary
    for d, who in enumerate(sched):
        red = reduce_structure(red.transform(day_transformer(n, who, f"{d}")), keep)
        img.day(who)
        key = sorted(tuple(s[v] for v in keep) for s in red.states())
        assert key == sorted(tuple(s[v] for v in keep) for s in img.states()), d


@pytest.mark.parametrize("n", [12, 30])
def test_prisoners_many_until_the_counter_knows(n: int) -> None:
    """More prisoners on the image engine: the counter knows on the day his count reaches n − 1, not before,
    and everyone has been interviewed by then."""
    from delkit.puzzles.prisoners import solve_prisoners

    r = solve_prisoners(n, 5000, 7, engine="image")
    assert r.knows_day is not None and r.knows_day == r.announce_day and r.sound
    assert r.visited_day <= r.knows_day


@pytest.mark.slow
def test_prisoners_one_hundred() -> None:
    """The title case: 100 prisoners, a random schedule, until the counter knows (about 12,000 days)."""
    from delkit.puzzles.prisoners import solve_prisoners

    r = solve_prisoners(100, 20_000, 1, engine="image")
    assert r.knows_day is not None and r.knows_day == r.announce_day and r.sound


def test_prisoners_expected_days() -> None:
    """The Markov chain of the protocol gives n(n − 1) + n·H_{n−1} days; 100 prisoners: about 28.5 years."""
    from delkit.puzzles.prisoners import expected_days, expected_days_closed

    for n in range(2, 40):
        assert expected_days(n) == expected_days_closed(n)
    assert 28.4 < float(expected_days(100)) / 365.25 < 28.6


def test_prisoners_bad_input() -> None:
    from delkit.puzzles.prisoners import solve_prisoners

    with pytest.raises(ModelError, match="2..9 on the explicit"):
        solve_prisoners(12, engine="explicit")
    with pytest.raises(ModelError, match="2..7 on the symbolic"):
        solve_prisoners(8)
    with pytest.raises(ModelError, match="prisoners are 1..3"):
        solve_prisoners(3, schedule=[1, 4])
    with pytest.raises(ModelError, match="--days"):
        solve_prisoners(3, 0)


def test_cli_prisoners(capsys) -> None:
    data = _json(capsys, ["puzzle", "prisoners", "-n", "3", "--schedule", "2,1,3,1", "--json"])
    assert data["counter_knows_day"] == data["counter_announces_day"] == 4 and data["sound"]
    data = _json(capsys, ["puzzle", "prisoners", "-n", "4", "--seed", "3", "--symbolic", "--json"])
    assert data["knows_exactly_when_count_reaches_n_minus_1"] and data["engine"] == "symbolic"
    assert main(["puzzle", "prisoners", "-n", "30"]) == 2
    data = _json(capsys, ["puzzle", "prisoners", "-n", "20", "--symbolic", "--days", "3000", "--json"])
    assert data["engine"] == "image" and data["counter_knows_day"] == data["counter_announces_day"]
    assert main(["puzzle", "prisoners", "--schedule", "1,x"]) == 2


def test_cli_list_has_the_new_puzzles(capsys) -> None:
    names = {p["command"] for p in _json(capsys, ["puzzle", "--list", "--json"])["puzzles"]}
    assert {"prisoners", "letter-passing", "coin-flip", "number-triangle"} <= names


def test_catalogue_docs_anchors_exist() -> None:
    """Every catalogue entry's docs link points at a heading of docs/puzzles.md (GitHub's anchor rule)."""
    import re
    from pathlib import Path

    from delkit.puzzles import CATALOGUE

    text = (Path(__file__).resolve().parents[2] / "docs" / "puzzles.md").read_text(encoding="utf-8")
    anchors = {re.sub(r"[^\w\- ]", "", h.strip().lower()).replace(" ", "-")
               for h in re.findall(r"^#+ (.+)$", text, flags=re.M)}
    for row in CATALOGUE:
        if row["command"] in ("prisoners", "letter-passing", "coin-flip", "number-triangle"):
            assert row["docs"].split("#", 1)[1] in anchors, row["docs"]
