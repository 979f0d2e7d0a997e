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
    team_utility,
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


def _bid_on_behalf_ok(ssi) -> bool:
    """Robot 0 bids for the disconnected robot 1 from 1's *believed* state (at 9 m), not from its own."""
    robots = [Robot(0, (0.0, 0.0)), Robot(1, (9.0, 0.0))]
    a = ssi(robots, [Task(0, (10.0, 0.0), 1, 50.0)], COST, informer={0: 0, 1: 0})
    return a.bundles == {0: (), 1: (0,)} and a.bids[(1, 0)] == pytest.approx(50 - 1) and a.bid_by[1] == 0


def test_ssi_bids_on_behalf_of_disconnected_robots():
    assert _bid_on_behalf_ok(ssi_bundles)


def test_a_broken_ssi_is_caught():
    """Mutation check: bidding from the informer's own position (not the belief) must fail the test above."""

    def from_informer(robots, tasks, cost, informer=None, initial=None, context=()):
        pos = {r.id: r.xy for r in robots}
        moved = [Robot(r.id, pos[(informer or {}).get(r.id, r.id)]) for r in robots]
        return ssi_bundles(moved, tasks, cost, informer, initial, context)

    assert not _bid_on_behalf_ok(from_informer)


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


def _cascade_ok(auction) -> bool:
    pos = {0: (0.0, 0.0), 1: (10.0, 0.0), 2: (20.0, 0.0), 3: (30.0, 0.0)}
    g = auction([0], [1, 2, 3], pos, COST)
    told = sorted(x for b in g.values() for x in b)
    # robot 0 tells robot 1 first (closest); robot 1, once told, takes part (the cascade) and tells 3
    return told == [1, 2, 3] and g.get(0, ())[:1] == (1,) and g.get(1, ()) == (3,)


def test_gossip_auction_informs_everyone_with_a_cascade():
    assert _cascade_ok(gossip_auction)


def test_a_gossip_auction_without_cascade_is_caught():
    def no_cascade(informed, must_know, positions, cost, ready=None):
        return {informed[0]: tuple(sorted(must_know, key=lambda g: cost(positions[informed[0]], positions[g])))}

    assert not _cascade_ok(no_cascade)


def test_makespan_minimisation_resolves_a_deadlock():
    robots = [Robot(0, (0.0, 0.0)), Robot(1, (10.0, 0.0))]
    tasks = [Task(0, (0.0, 5.0), 2), Task(1, (10.0, 5.0), 2)]
    tmap = {t.id: t for t in tasks}
    dead = {0: (0, 1), 1: (1, 0)}
    assert makespan(robots, dead, tmap, COST) == float("inf")
    fixed = minimise_makespan(robots, dead, tasks, COST)
    assert np.isfinite(makespan(robots, fixed, tmap, COST))
    # mutation check: a "minimiser" that returns its input leaves the deadlock
    assert makespan(robots, dict(dead), tmap, COST) == float("inf")


def test_allocate_chains_algorithms_1_to_3():
    robots, tasks = _instance(3, 4, 3)
    a = allocate(robots, tasks, COST, connected=[0])
    need = {j for j, b in a.bundles.items() if b} - {0}
    told = {x for b in a.gossip.values() for x in b}
    assert told == need
    assert a.makespan == pytest.approx(makespan(robots, a.bundles, {t.id: t for t in tasks}, COST))


def _all_bundles(robots, tasks):
    """Every allocation: each task to a team of its required size, each robot's tasks in every order."""
    choices = [list(itertools.combinations([r.id for r in robots], t.n_required)) for t in tasks]
    for assign in itertools.product(*choices):
        per = {r.id: [t.id for t, who in zip(tasks, assign, strict=True) if r.id in who] for r in robots}
        for orders in itertools.product(*[list(itertools.permutations(per[r.id])) for r in robots]):
            yield dict(zip([r.id for r in robots], orders, strict=True))


def _brute_force(robots, tasks):
    tmap = {t.id: t for t in tasks}
    return min((makespan(robots, b, tmap, COST) for b in _all_bundles(robots, tasks)), default=float("inf"))


@pytest.mark.parametrize("seed", range(4))
def test_milp_is_exact_on_tiny_instances(seed):
    robots, tasks = _instance(seed, 2, 3)
    opt, bundles = milp_allocation(robots, tasks, COST, objective="makespan")
    truth = _brute_force(robots, tasks)
    assert makespan(robots, bundles, {t.id: t for t in tasks}, COST) == pytest.approx(truth, rel=1e-6, abs=1e-6)
    heur = allocate(robots, tasks, COST, connected=[0]).makespan
    assert heur >= truth - 1e-6


def _brute_force_utility(robots, tasks):
    tmap = {t.id: t for t in tasks}
    return max((team_utility(robots, b, tmap, COST) for b in _all_bundles(robots, tasks)), default=float("-inf"))


@pytest.mark.parametrize("seed", range(4))
def test_utility_milp_is_eq_20_on_tiny_instances(seed):
    robots, tasks = _instance(seed, 2, 3)
    tmap = {t.id: t for t in tasks}
    value, bundles = milp_allocation(robots, tasks, COST, objective="utility")
    truth = _brute_force_utility(robots, tasks)
    assert team_utility(robots, bundles, tmap, COST) == pytest.approx(truth, rel=1e-6, abs=1e-3)
    assert value == pytest.approx(truth, rel=1e-4, abs=0.05)  # the MILP's ε precedence margins
    heur = allocate(robots, tasks, COST, connected=[0])
    assert team_utility(robots, heur.bundles, tmap, COST) <= truth + 1e-6


def test_unknown_milp_objective_is_an_error():
    robots, tasks = _instance(0, 2, 2)
    with pytest.raises(PlanningError, match="objective"):
        milp_allocation(robots, tasks, COST, objective="speed")


def test_bundle_cost_is_the_travel_time():
    r = Robot(0, (0.0, 0.0))
    tasks = {0: Task(0, (3.0, 4.0)), 1: Task(1, (3.0, 0.0), duration=2.0)}
    assert bundle_cost(r, [], tasks, COST) == 0.0
    assert bundle_cost(r, [0, 1], tasks, COST) == pytest.approx(5 + 4 + 2)
