"""The classical level: optimal breakdown, BFS and clingo agree on optimal lengths, plans replay."""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from delkit.errors import PlanningError
from planners.classical import CState, apply, goal_for, reached, solve_bfs, solve_classical

COLS = ("red", "black", "green", "blue")


def _state(stacks, shared=()):
    blocks = [b for s in stacks for b in s] + list(shared)
    return CState.make({"robot1": stacks, "robot2": ((), (), ())}, tuple(shared), {b: b for b in blocks},
                       {b: "robot2" for b in shared})


layouts = st.permutations(COLS).flatmap(
    lambda p: st.tuples(st.integers(0, 4), st.integers(0, 4)).map(
        lambda cut: tuple(tuple(x) for x in (p[:min(cut)], p[min(cut):max(cut)], p[max(cut):])))).filter(
    lambda s: True)


@settings(max_examples=25, deadline=None)
@given(layouts, st.sampled_from(COLS))
def test_bfs_and_clingo_agree(stacks, color):
    s = _state(stacks)
    goal = goal_for(f"put_on_shared_robot1_{color}", s)
    a, b = solve_bfs(s, goal), solve_classical(s, goal)
    assert len(a.actions) == len(b.actions)  # both optimal
    for r in (a, b):
        cur = s
        for act in r.actions:
            cur = apply(cur, act)
        assert reached(cur, goal) and cur == r.state
    # depth of the block: one pick+place per block above it, then pick + put_on_barrier
    st_of = next(x for x in stacks if color in x)
    assert len(a.actions) == 2 * (len(st_of) - st_of.index(color) - 1) + 2


def test_take_from_shared():
    s = _state((("red",), (), ()), shared=("blue",))
    goal = goal_for("take_from_shared_robot1_robot2_blue", s)
    r = solve_bfs(s, goal)
    assert [a.name for a in r.actions] == ["take_from_barrier", "place"]
    assert r.state.barrier == ()


def test_errors():
    s = _state((("red",), (), ()))
    with pytest.raises(PlanningError, match="not an ontic task"):
        goal_for("sense_table_robot1", s)
    with pytest.raises(PlanningError, match="no blue block"):
        goal_for("take_from_shared_robot1_robot2_blue", s)
    with pytest.raises(PlanningError, match="no plan"):
        solve_bfs(s, goal_for("put_on_shared_robot1_black", s))


@settings(max_examples=8, deadline=None)
@given(layouts, st.sampled_from(COLS))
def test_pddl_reference_same_optimum(stacks, color):
    """specs/epico/classical.pddl solved by pyperplan's breadth-first search: same optimal length, put and
    take goals (the PDDL file and the planner's encoding describe the same arm)."""
    import logging
    from pathlib import Path

    pytest.importorskip("pyperplan")
    from pyperplan import grounding
    from pyperplan.pddl.parser import Parser
    from pyperplan.search.breadth_first_search import breadth_first_search

    from planners.classical import to_pddl

    logging.disable(logging.CRITICAL)
    dom = Path(__file__).resolve().parents[2] / "specs" / "epico" / "classical.pddl"
    s = _state(stacks)
    put = goal_for(f"put_on_shared_robot1_{color}", s)
    r = solve_bfs(s, put)
    take = goal_for(f"take_from_shared_robot1_robot1_{color}", r.state)
    for state, goal, ours in ((s, put, r), (r.state, take, solve_bfs(r.state, take))):
        import tempfile

        with tempfile.TemporaryDirectory() as d:
            pf = Path(d) / "p.pddl"
            pf.write_text(to_pddl(state, goal))
            parser = Parser(str(dom), str(pf))
            plan = breadth_first_search(grounding.ground(parser.parse_problem(parser.parse_domain())))
        assert plan is not None and len(plan) == len(ours.actions)
        assert [o.name.split()[0].strip("(") for o in plan] == [a.name for a in ours.actions]
