"""Epistemic search: optimality, heuristics, limits and failure statuses, and the specialised state
representation checked differentially against delkit (random walks, hypothesis)."""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from delkit.backends.compact import from_kripke
from delkit.logic.formula import D as Dist
from delkit.models.bisimulation import bisimilar, contract
from delkit.models.update import product_update
from delkit.testing import formulas
from planners.demo import specs_dir
from planners.epistemic import DelSpace, Limits, bfs, make_space, plan
from planners.lang import load_task, shared_benchmarks
from planners.spaces import CompactSpace
from planners.validate import check_plan

BENCH = shared_benchmarks()
D = specs_dir()

# (spec, problem) pairs with a known BFS optimum, from the project's own specs (always present)
OWN = [(D / "coin_in_the_box" / "domain.epddl", D / "coin_in_the_box" / "common.epddl", 5),
       (D / "grapevine" / "domain.epddl", D / "grapevine" / "problem.epddl", 2),
       (D / "selective_communication" / "domain.epddl", D / "selective_communication" / "problem.epddl", 4),
       (D / "collaboration_communication" / "domain.epddl", D / "collaboration_communication" / "problem.epddl", 3)]


@pytest.mark.parametrize("dom, prob, n", OWN, ids=[p.parent.name for _, p, _ in OWN])
def test_searches(dom, prob, n) -> None:
    task = load_task(dom, prob)
    assert plan(task, search="bfs").length == n
    assert plan(task, search="astar").length == n  # admissible heuristic: optimal
    g = plan(task, search="gbfs")
    assert g.solved and g.length >= n and check_plan(task, list(g.plan)).valid


@pytest.mark.parametrize("dom, prob, n", OWN[:2], ids=["coin", "grapevine"])
def test_generic_and_fast_spaces_search_identically(dom, prob, n) -> None:
    task = load_task(dom, prob)
    a = bfs(DelSpace(task))
    b = bfs(CompactSpace(task))
    assert (a.plan, a.expanded, a.generated, a.distinct_states) == (b.plan, b.expanded, b.generated,
                                                                    b.distinct_states)


def test_limits_give_a_failure_not_an_empty_plan() -> None:
    task = load_task(D / "coin_in_the_box" / "domain.epddl", D / "coin_in_the_box" / "common.epddl")
    r = plan(task, limits=Limits(max_expanded=3))
    assert r.status == "limit" and r.plan is None and r.length is None and r.expanded == 3
    assert "no plan within limits" in r.reason and r.to_json()["plan"] is None
    r = plan(task, limits=Limits(timeout=0.0))
    assert r.status == "limit" and "time limit" in r.reason
    r = plan(task, search="astar", limits=Limits(max_expanded=2))
    assert r.status == "limit"
    r = plan(task, limits=Limits(max_memory_mb=1.0))  # below any Python process: stops at once
    assert r.status == "limit" and "memory limit" in r.reason and r.plan is None


def test_goal_true_initially_is_an_explicit_empty_plan() -> None:
    from dataclasses import replace

    from delkit.logic.formula import parse

    task = load_task(D / "coin_in_the_box" / "domain.epddl", D / "coin_in_the_box" / "problem.epddl")
    t2 = replace(task, goal=parse("K_a has_key_a"), _cache={})
    r = plan(t2)
    assert r.status == "solved" and r.plan == () and "initially" in r.reason


def test_unsolvable_is_reported() -> None:
    from planners.lang.mastar import parse_mastar

    task = parse_mastar("""fluent p, q; action set_p, tell; agent a, b;
        set_p causes p; a observes set_p;
        executable tell if B(a, p); tell announces p; a observes tell; b observes tell;
        initially -p, -q; initially C([a,b], -p); goal B(b, q);""", "unsolvable.txt")
    r = plan(task, limits=Limits(timeout=60))
    assert r.status == "unsolvable" and r.plan is None and r.expanded >= 1
    assert "exhausted" in r.reason
    # without BFS's dead-end pruning (h_epi: B(b, q) can never be made true) the whole space is searched
    full = bfs(make_space(task), Limits(timeout=60), prune=False)
    assert full.status == "unsolvable" and full.expanded > r.expanded


def _bench_tasks():
    if BENCH is None:
        return []
    m = BENCH / "mastar"
    return [m / "Coin_In_The_Box" / "Coin_in_the_Box__pl_7.txt", m / "CC" / "CC_2_2_3" / "CC_2_2_3__pl_8.txt",
            m / "Grapevine" / "Grapevine_3" / "Grapevine_3__pl_4.txt", m / "SC" / "SC_4_2" / "SC_4_2__pl_8.txt",
            m / "CB_simple" / "CB_oblivious__pl_6.txt", m / "Assemble" / "Assemble_B2" / "Assemble_B2__pl_5.txt"]


TASKS = {str(p): None for p in _bench_tasks()}


def _task(path: str):
    if TASKS.get(path) is None:
        TASKS[path] = load_task(path)
    return TASKS[path]


@pytest.mark.skipif(BENCH is None, reason="../shared/benchmarks is not available")
@settings(max_examples=25, deadline=None)
@given(idx=st.integers(0, 5), walk=st.lists(st.integers(0, 10**6), min_size=1, max_size=6))
def test_random_walks_fast_equals_delkit(idx: int, walk: list[int]) -> None:
    """Along a random walk of executable actions: CompactSpace state ≅ contract(M ⊗ E) (bisimilar), same
    executability of every action, and the canonical key is equal iff the models are bisimilar."""
    task = _task(list(TASKS)[idx])
    space = CompactSpace(task)
    s, _ = space.initial()
    m = contract(task.initial)
    for r in walk:
        execs = [a for a in task.actions if m.holds(a.executable)]
        assert [a.name for a in execs] == [a.name for a in task.actions if space.holds(s, a.executable)]
        if not execs:
            break
        act = execs[r % len(execs)]
        em = task.event_model(act, m)
        new = product_update(m, em)
        s2 = space.step(s, act.name)
        if not new.designated:
            assert s2 is None
            break
        m2 = contract(new)
        assert bisimilar(space.to_kripke(s2), m2)
        assert from_kripke(m2).key == s2.key
        assert (s2.key == s.key) == bisimilar(m2, m)
        s, m = s2, m2


# ----------------------------------------------------------------------------- random goals
# (backend truth / canonical keys on random models: tests/delkit/test_backends.py)


@settings(max_examples=15, deadline=None)
@given(goal=formulas(("tail", "opened"), ("a", "b", "c"), 2, allow_group=True))
def test_random_goals_plan_found_implies_independent_replay_reaches_goal(goal) -> None:
    """For random goals on Coin in the Box: every plan BFS finds is valid under the independent checker,
    and no shorter plan exists among its prefixes."""
    from dataclasses import replace

    task = load_task(D / "coin_in_the_box" / "domain.epddl", D / "coin_in_the_box" / "problem.epddl")
    t2 = replace(task, goal=goal, _cache={})
    res = plan(t2, limits=Limits(max_expanded=150, timeout=10))
    if res.solved:
        assert check_plan(t2, list(res.plan)).valid
        for k in range(len(res.plan)):
            assert not check_plan(t2, list(res.plan[:k])).valid
    else:
        assert res.plan is None and res.status in ("limit", "unsolvable")


def test_group_distributed_knowledge_goals_are_planned_with_collective_bisimulation():
    """D_{a,b} is not bisimulation-invariant; the planner keeps each mentioned group's intersection relation
    (collective bisimulation), so such goals are planned: both engines agree (the numpy one does not contract
    at all), the plan replays under the independent checker, and no shorter prefix reaches the goal."""
    import dataclasses

    from delkit.logic.formula import K, Not, Prop

    task = load_task(D / "coin_in_the_box" / "domain.epddl", D / "coin_in_the_box" / "problem.epddl")
    a, b = task.agents[:2]
    tail = Prop("tail")
    for goal in (Dist((a, b), tail) & Not(K(a, tail)) & Not(K(b, tail)), Dist((a, b), tail), Dist(task.agents, tail)):
        t2 = dataclasses.replace(task, goal=goal, _cache={})
        res = {e: plan(t2, engine=e, limits=Limits(timeout=60)) for e in ("fast", "del")}
        assert res["fast"].status == res["del"].status
        assert res["fast"].length == res["del"].length
        if res["fast"].solved:
            p = list(res["fast"].plan)
            assert check_plan(t2, p).valid
            assert all(not check_plan(t2, p[:k]).valid for k in range(len(p)))


@pytest.mark.parametrize("hard_exit", [False, True])
def test_search_leaves_the_collector_as_it_found_it(monkeypatch, hard_exit) -> None:
    """After a search the collector is enabled again; only in the console script (HARD_EXIT: os._exit soon)
    are the surviving objects frozen out of it, so that its next pass does not traverse the whole space."""
    import gc

    from delkit import resources
    from planners.epistemic import bfs, make_space
    from planners.lang import load_task

    monkeypatch.setattr(resources, "HARD_EXIT", hard_exit)
    space = make_space(load_task(specs_dir() / "coin_in_the_box" / "domain.epddl",
                                 specs_dir() / "coin_in_the_box" / "problem.epddl"))
    gc.collect()
    before = gc.get_freeze_count()
    try:
        assert bfs(space).status == "solved"
        assert gc.isenabled()
        assert (gc.get_freeze_count() > before) == hard_exit
    finally:
        gc.unfreeze()
