"""SSI bundling, makespan minimisation, gossip auction and the exact MILP (planners.allocation)."""

from __future__ import annotations

import itertools

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from delkit.errors import PlanningError
from planners.allocation import (
    Robot,
    Task,
    allocate,
    bundle_cost,
    euclidean_cost,
    gossip_auction,
    makespan,
    milp_allocation,
    minimise_makespan,
    schedule,
    ssi_bundles,
)

COST = euclidean_cost(1.0)


def test_ssi_bids_are_equation_22_and_top_n_win():
    robots = [Robot(0, (0.0, 0.0)), Robot(1, (10.0, 0.0)), Robot(2, (20.0, 0.0))]
    tasks = [Task(0, (9.0, 0.0), n_required=2, reward=50.0)]
    a = ssi_bundles(robots, tasks, COST)
    assert a.bids[(0, 0)] == pytest.approx(50 - 9)
    assert a.bids[(1, 0)] == pytest.approx(50 - 1)
    assert a.bids[(2, 0)] == pytest.approx(50 - 11)
    assert a.bundles == {0: (0,), 1: (0,), 2: ()}
    # a second task is bid on with the bundle's cost: S_j^{B ⊕ τ} includes the first leg
    b = ssi_bundles(robots, tasks + [Task(1, (9.0, 5.0), 1, 50.0)], COST)
    assert b.bids[(1, 1)] == pytest.approx(50 - (1 + 5))


def test_ssi_bids_on_behalf_of_disconnected_robots():
    robots = [Robot(0, (0.0, 0.0)), Robot(1, (5.0, 0.0))]
    a = ssi_bundles(robots, [Task(0, (1.0, 0.0))], COST, informer={0: 0, 1: 0})
    assert a.bid_by == {0: 0, 1: 0}


def test_too_few_robots_is_an_error():
    with pytest.raises(PlanningError, match="needs 3 robots"):
        ssi_bundles([Robot(0, (0, 0))], [Task(0, (1, 1), 3)], COST)


def test_schedule_waits_for_all_robots_and_detects_deadlock():
    robots = [Robot(0, (0.0, 0.0)), Robot(1, (10.0, 0.0))]
    tasks = {0: Task(0, (0.0, 0.0), 2), 1: Task(1, (10.0, 0.0), 2)}
    s = schedule(robots, {0: (0, 1), 1: (0, 1)}, tasks, COST)
    assert s.start[0] == pytest.approx(10.0)  # robot 1 needs 10 s to come
    assert s.start[1] == pytest.approx(20.0)
    assert makespan(robots, {0: (0, 1), 1: (1, 0)}, tasks, COST) == float("inf")


def _instance(seed: int, nr: int, nt: int):
    rng = np.random.default_rng(seed)
    robots = [Robot(i, tuple(rng.uniform(0, 20, 2))) for i in range(nr)]
    tasks = [Task(j, tuple(rng.uniform(0, 20, 2)), int(rng.integers(1, nr + 1))) for j in range(nt)]
    return robots, tasks


@settings(max_examples=30, deadline=None)
@given(st.integers(0, 10_000), st.integers(1, 4), st.integers(1, 4))
def test_makespan_minimisation_never_worsens_and_keeps_locked_order(seed, nr, nt):
    robots, tasks = _instance(seed, nr, nt)
    first = ssi_bundles(robots, tasks, COST)
    tmap = {t.id: t for t in tasks}
    locked = {0: first.bundles[0]}
    better = minimise_makespan(robots, first.bundles, tasks, COST, locked)
    assert makespan(robots, better, tmap, COST) <= makespan(robots, first.bundles, tmap, COST) + 1e-9
    assert better[0] == first.bundles[0]
    for t in tasks:  # every task still has exactly N_τ robots
        assert sum(t.id in b for b in better.values()) == t.n_required


def test_gossip_auction_informs_everyone_with_a_cascade():
    pos = {0: (0.0, 0.0), 1: (10.0, 0.0), 2: (20.0, 0.0), 3: (30.0, 0.0)}
    g = gossip_auction([0], [1, 2, 3], pos, COST)
    told = [x for b in g.values() for x in b]
    assert sorted(told) == [1, 2, 3]
    # robot 0 tells robot 1 first (closest); robot 1, once told, takes part (the cascade)
    assert g[0][0] == 1
    assert len(g) >= 2


def test_allocate_chains_algorithms_1_to_3():
    robots, tasks = _instance(3, 4, 3)
    a = allocate(robots, tasks, COST, connected=[0])
    need = {j for j, b in a.bundles.items() if b} - {0}
    told = {x for b in a.gossip.values() for x in b}
    assert told == need
    assert a.makespan == pytest.approx(makespan(robots, a.bundles, {t.id: t for t in tasks}, COST))


def _brute_force(robots, tasks):
    best = float("inf")
    tmap = {t.id: t for t in tasks}
    choices = [list(itertools.combinations([r.id for r in robots], t.n_required)) for t in tasks]
    for assign in itertools.product(*choices):
        per = {r.id: [t.id for t, who in zip(tasks, assign, strict=True) if r.id in who] for r in robots}
        for orders in itertools.product(*[list(itertools.permutations(per[r.id])) for r in robots]):
            best = min(best, makespan(robots, dict(zip([r.id for r in robots], orders, strict=True)), tmap, COST))
    return best


@pytest.mark.parametrize("seed", range(4))
def test_milp_is_exact_on_tiny_instances(seed):
    robots, tasks = _instance(seed, 2, 3)
    opt, bundles = milp_allocation(robots, tasks, COST)
    truth = _brute_force(robots, tasks)
    assert makespan(robots, bundles, {t.id: t for t in tasks}, COST) == pytest.approx(truth, rel=1e-6, abs=1e-6)
    heur = allocate(robots, tasks, COST, connected=[0]).makespan
    assert heur >= truth - 1e-6


def test_bundle_cost_is_the_travel_time():
    r = Robot(0, (0.0, 0.0))
    tasks = {0: Task(0, (3.0, 4.0)), 1: Task(1, (3.0, 0.0), duration=2.0)}
    assert bundle_cost(r, [], tasks, COST) == 0.0
    assert bundle_cost(r, [0, 1], tasks, COST) == pytest.approx(5 + 4 + 2)
