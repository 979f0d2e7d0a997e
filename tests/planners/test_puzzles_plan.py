"""Muddy children planning (planners.puzzles): the planner's shortest plan is the literature's protocol —
the father's announcement, then M − 1 rounds of "nobody knows" (Fagin et al. 1995, §1.1)."""

from __future__ import annotations

import json

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from delkit.cli import main
from delkit.puzzles.muddy import solve_muddy
from planners.puzzles import literature_muddy_plan, muddy_planning_task, solve_muddy_plan
from planners.task import apply_steps


@settings(max_examples=12, deadline=None)
@given(st.integers(1, 5).flatmap(lambda n: st.tuples(st.just(n), st.integers(1, n))), st.sampled_from(["bfs", "astar"]))
def test_planner_finds_the_protocol(nm: tuple[int, int], search: str) -> None:
    n, m = nm
    res = solve_muddy_plan(n, m, search=search).result
    assert res.solved and res.plan == literature_muddy_plan(m)
    # the same number of rounds as the protocol run by the explicit engine (an independent computation)
    assert res.plan.count("nobody-knows") == solve_muddy(n, m).nobody_knows_rounds


@pytest.mark.parametrize(("n", "m"), [(3, 2), (4, 3)])
def test_shorter_sequences_fail(n: int, m: int) -> None:
    """BFS is optimal; check it: no sequence of fewer actions reaches the goal, and the plan does."""
    import itertools

    task = muddy_planning_task(n, m, individual=True)
    goal = task.goal
    for length in range(m):
        for seq in itertools.product(task.actions, repeat=length):
            run = apply_steps(task, seq, task.initial)
            assert run is None or not run[1][-1].holds(goal), [a.name for a in seq]
    run = apply_steps(task, [task.action(a) for a in literature_muddy_plan(m)], task.initial)
    assert run is not None and run[1][-1].holds(goal)
    assert solve_muddy_plan(n, m, individual=True).result.plan == literature_muddy_plan(m)


def test_cli_and_list(capsys) -> None:
    assert main(["puzzle", "muddy-plan", "-n", "4", "-m", "3", "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["plan"] == ["father", "nobody-knows", "nobody-knows"] and data["matches_literature"]
    assert main(["puzzle", "--list", "--json"]) == 0
    assert "muddy-plan" in [r["command"] for r in json.loads(capsys.readouterr().out)["puzzles"]]
    assert main(["puzzle", "muddy-plan", "-n", "3", "-m", "4"]) == 2
    assert "--muddy <= --children" in capsys.readouterr().err
