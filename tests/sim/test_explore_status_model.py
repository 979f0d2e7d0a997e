"""The statuses as a delkit epistemic state: eq. 14 after a global and eq. 18 after a local announcement."""

from __future__ import annotations

import itertools

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from delkit.logic.formula import K
from sim.status_model import STATUSES, FactoredStatusModel, StatusModel, agent, eq14, eq18, status_prop


def _all_edges(n):
    return [(i, j) for i, j in itertools.product(range(n), repeat=2) if i != j]


def test_initial_statuses_are_common_knowledge():
    m = StatusModel.initial(3)
    assert m.model.n_worlds == 1
    assert m.holds(eq14(m.statuses, _all_edges(3)))


def test_unobserved_change_breaks_eq14_and_global_announcement_restores_it():
    m = StatusModel.initial(3)
    m.change(0, "task", group=[0, 1])  # robot 2 is out of range
    assert m.knows_status(0, 0) and m.knows_status(1, 0)  # eq. 17: K_0 σ_0, and the group perceives it
    assert not m.knows_status(2, 0)
    assert not m.holds(eq14(m.statuses, _all_edges(3)))
    # a false belief (the paper's Fig. 1): robot 2 believes robot 0 still explores; KD45, not S5
    assert m.holds(K(agent(2), status_prop(0, "exploring")))
    assert not m.model.is_s5() and m.model.is_kd45()
    m.announce_global()
    assert m.holds(eq14(m.statuses, _all_edges(3)))
    assert m.model.n_worlds == 1


def test_local_announcement_gives_eq18_and_leaves_outsiders_unchanged():
    m = StatusModel.initial(3)
    m.change(1, "gossiping", group=[1])
    m.change(2, "task", group=[2])
    before = [[m.holds(K(agent(k), status_prop(j, m.statuses[j]))) for j in range(3)] for k in range(3)]
    assert not m.holds(eq18(m.statuses, [1, 2]))
    m.announce_local([1, 2])
    assert m.holds(eq18(m.statuses, [1, 2]))
    after = [[m.holds(K(agent(k), status_prop(j, m.statuses[j]))) for j in range(3)] for k in range(3)]
    assert after[0] == before[0]  # robot 0 was not connected: its knowledge is unchanged
    assert not m.knows_status(0, 2)


@settings(max_examples=25, deadline=None)
@given(st.lists(st.tuples(st.integers(0, 2), st.sampled_from(STATUSES), st.sets(st.integers(0, 2))),
                min_size=1, max_size=6),
       st.sets(st.integers(0, 2), min_size=2, max_size=3))
def test_eq18_after_any_history(changes, group):
    m = StatusModel.initial(3)
    for i, s, g in changes:
        m.change(i, s, group=g)
    m.announce_local(sorted(group))
    assert m.holds(eq18(m.statuses, sorted(group)))
    m.announce_global()
    assert m.holds(eq14(m.statuses, _all_edges(3)))


def test_perceive_a_proposition():
    m = StatusModel.initial(2)
    m.perceive(0, status_prop(1, "exploring"))
    assert m.knows_status(0, 1)


@pytest.mark.parametrize("n", [2, 4])
def test_sizes(n):
    m = StatusModel.initial(n)
    m.change(n - 1, "home", group=[n - 1])
    assert m.model.n_worlds <= 4 ** n


events = st.lists(st.tuples(st.integers(0, 2), st.sampled_from(STATUSES), st.sets(st.integers(0, 2))),
                  min_size=1, max_size=7)


@settings(max_examples=30, deadline=None)
@given(events)
def test_factored_model_agrees_with_the_joint_model(changes):
    """Every second-order belief B_i B_j σ_k of the factored model (one delkit model per robot) is the one
    the joint model (all statuses in one model) gives."""
    joint, fact = StatusModel.initial(3), FactoredStatusModel(3)
    for k, s, g in changes:
        joint.change(k, s, group=g)
        fact.tell(k, s, set(g) | {k})  # g ∪ {k} = everyone takes the one-world shortcut
    table = fact.believed()
    for i, j, k in itertools.product(range(3), repeat=3):
        for idx, s in enumerate(STATUSES):
            q = status_prop(k, s)
            f = K(agent(i), q) if i == j else K(agent(i), K(agent(j), q))
            assert joint.holds(f) == fact.holds(k, f)
            assert joint.holds(f) == (table[i, j, k] == idx), (i, j, k, s)


@settings(max_examples=20, deadline=None)
@given(events, st.sets(st.integers(0, 2), min_size=2, max_size=3))
def test_factored_eq18_then_eq14(changes, group):
    fact = FactoredStatusModel(3)
    for k, s, g in changes:
        fact.tell(k, s, set(g) | {k})
    group = sorted(group)
    for k in group:
        fact.tell(k, fact.statuses[k], group)
    assert fact.check_eq18(group)
    for k in range(3):
        fact.tell(k, fact.statuses[k], range(3))
    assert fact.check_eq14(_all_edges(3))
    assert fact.false_beliefs() == 0 and fact.n_worlds() == [1, 1, 1]


def test_factored_false_belief_and_revision_with_eight_robots():
    fact = FactoredStatusModel(8)
    fact.tell(3, "task", [3, 4])
    assert fact.believed()[0, 0, 3] == STATUSES.index("exploring")  # robot 0 was out of range: false belief
    assert fact.believed()[4, 0, 3] == STATUSES.index("exploring")  # 4 believes 0 still believes σ_3 = exploring
    assert fact.believed()[4, 4, 3] == STATUSES.index("task")
    assert fact.false_beliefs() == 6
    assert not fact.check_eq18([0, 3])
    fact.tell(3, "task", [0, 3])  # robot 0 meets robot 3: its belief is revised, not contradicted
    assert fact.believed()[0, 0, 3] == STATUSES.index("task") and fact.check_eq18([0, 3])


def test_ruleset1_suspicion_is_a_private_possibly_false_belief_revised_on_meeting():
    from delkit.logic.formula import K, Or
    from sim.status_model import BUSY, FactoredStatusModel, agent, status_prop

    m = FactoredStatusModel(4)
    m.tell(2, "task", {2, 3})  # robot 2 goes to a task; 3 sees it, 0 and 1 are oblivious
    m.suspect(0, 2)  # robot 0 does not find 2 where it believed: "2 must be busy"
    busy = Or(tuple(status_prop(2, s) for s in BUSY))
    assert m.holds(2, K(agent(0), busy)) and not m.holds(2, K(agent(0), status_prop(2, "task")))
    assert m.believes_busy(0, 2) and not m.believes_busy(1, 2) and not m.believes_busy(3, 2)
    assert m.holds(2, K(agent(1), status_prop(2, "exploring")))  # 1 keeps its (now false) belief
    assert m.holds(2, K(agent(0), K(agent(1), status_prop(2, "exploring"))))  # 0 knows 1 saw nothing
    assert m.holds(2, status_prop(2, "task"))  # the world did not change
    assert m.false_beliefs() == 1  # robot 1's "exploring"; robot 0's "busy" is true (2 is at a task)
    m.tell(2, "exploring", {2, 3})  # 2 returns to exploring out of 0's range: 0's suspicion is now false
    assert m.believes_busy(0, 2) and m.false_beliefs() == 1  # now robot 0's "busy" is the false one
    m.tell(2, "exploring", {0, 2, 3})  # 0 meets 2: announce revises the belief
    assert not m.believes_busy(0, 2) and m.considers(0, 2) == frozenset({"exploring"})
