"""Heuristics: the observer-cover bound is admissible and consistent, and strictly informative when
goal conjuncts concern agents that no single action informs together."""

from __future__ import annotations

import math

import pytest

from planners.epistemic import Limits, plan
from planners.heuristics import cover_sets, h_cover, h_gc
from planners.lang import load_task, shared_benchmarks
from planners.lang.mastar import parse_mastar
from planners.spaces import CompactSpace
from planners.validate import parse_plan_text

PRIVATE = """
fluent p, q, r;
action look_a, look_b, tell;
agent a, b, c;
look_a determines p; a observes look_a;
look_b determines q; b observes look_b;
executable tell if B(a, p), p; tell announces p; a observes tell; c observes tell;
initially p, q, -r;
goal B(a, p), B(b, q), B(c, p);
"""


def test_cover_is_informative_and_exact_here() -> None:
    task = parse_mastar(PRIVATE, "private.txt")
    space = CompactSpace(task)
    s0, _ = space.initial()
    from planners.epistemic import goal_conjuncts

    covers = cover_sets(task, goal_conjuncts(task.goal))
    assert covers == [0b001, 0b010, 0b101]  # look_a: B_a p; look_b: B_b q; tell: B_a p and B_c p
    assert h_cover(space)(s0) == 2.0  # {look_b, tell} cover all three; one action cannot
    assert h_gc(space)(s0) == 3.0
    res = plan(task, search="astar")
    assert res.length == 3 == plan(task).length  # tell needs B(a,p) first: look_a, tell, look_b


def test_untouchable_fluent_conjunct_is_a_dead_end() -> None:
    task = parse_mastar(PRIVATE.replace("goal B(a, p), B(b, q), B(c, p);", "goal B(a, p), r;"), "dead.txt")
    space = CompactSpace(task)
    s0, _ = space.initial()
    assert h_cover(space)(s0) == math.inf
    r = plan(task, search="astar", limits=Limits(timeout=10))
    assert r.status == "unsolvable" and r.expanded == 0


BENCH = shared_benchmarks()


@pytest.mark.skipif(BENCH is None, reason="../shared/benchmarks is not available")
@pytest.mark.parametrize("name", ["CC/CC_2_2_3/CC_2_2_3__pl_8.txt", "Coin_In_The_Box/Coin_in_the_Box__pl_7.txt",
                                  "SC/SC_4_2/SC_4_2__pl_8.txt", "Grapevine/Grapevine_3/Grapevine_3__pl_4.txt",
                                  "Assemble/Assemble_B2/Assemble_B2__pl_5.txt"])
def test_cover_admissible_and_consistent_along_optimal_plans(name: str) -> None:
    import csv

    rows = {r["file"]: r for r in csv.DictReader((BENCH / "mastar" / "expected.csv").open())}
    task = load_task(BENCH / "mastar" / name)
    space = CompactSpace(task)
    h = h_cover(space)
    steps = parse_plan_text(rows[name]["efp_plan"])
    s, _ = space.initial()
    for i, a in enumerate(steps):
        assert h(s) <= len(steps) - i  # admissible: at most the remaining optimal cost
        for _, nxt, _ in space.successors(s):  # consistent on every edge out of the plan's states
            assert h(s) <= 1 + h(nxt)
        s = space.step(s, a)
    assert h(s) == 0


def test_astar_equals_bfs_length_on_own_specs() -> None:
    from planners.demo import specs_dir

    for prob in sorted(specs_dir().glob("*/*.epddl")):
        if prob.name == "domain.epddl" or not (prob.parent / "domain.epddl").is_file():
            continue  # specs/frontier: generated instances with their own domains (test_frontier_search.py)
        task = load_task(prob.parent / "domain.epddl", prob)
        assert plan(task, search="astar").length == plan(task).length
