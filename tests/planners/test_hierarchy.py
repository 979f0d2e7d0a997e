"""The hierarchy (Listing 1 corrected): anchoring, errors naming the task, CLI, MuJoCo execution."""

from __future__ import annotations

import json

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from delkit.cli import main
from planners.classical import CAction, ClassicalResult, apply
from planners.epico import EpicoError, generate
from planners.hierarchy import epistemic_task, process_e_plan, solve
from planners.validate import check_plan


def test_ontic_task_that_cannot_be_done_is_named():
    """A classical state without robot1's red block: the classical call fails and names the task."""
    inst = generate("alpha", 2)
    task, _, _ = epistemic_task(inst, macros=False)
    sol = solve(inst, macros=False)
    c0 = inst.classical_init
    stacks = {r: tuple(tuple(b for b in s if b != "red") for s in st) for r, st in c0.stacks}
    from planners.classical import CState

    bad = CState.make(stacks, (), c0.colors)
    with pytest.raises(EpicoError, match=r"task 2 \(put_on_shared_robot1_red\)"):
        process_e_plan(task, sol.flat_plan, bad)


def test_anchoring_failure(monkeypatch):
    """A classical plan that puts the wrong colour on the shared table is caught by the anchoring check."""
    import planners.hierarchy as h

    def wrong(state, goal, **_):
        acts = [CAction(goal.robot, "pick", ("black", "red", 1, 1)), CAction(goal.robot, "put_on_barrier", ("black",))]
        cur = state
        for a in acts:
            cur = apply(cur, a)
        return ClassicalResult(goal, tuple(acts), cur, 0.0, 2)

    monkeypatch.setattr(h, "solve_bfs", wrong)
    with pytest.raises(EpicoError, match="anchoring failed: occup_by_robot1_red"):
        solve(generate("alpha", 2), macros=False)


@settings(max_examples=6, deadline=None)
@given(st.sampled_from(["alpha", "beta", "gamma", "delta"]), st.integers(2, 3), st.integers(0, 10_000))
def test_macros_never_change_validity(goal, colors, seed):
    """Random layouts: the plan found with macros, flattened, is valid exactly as the one without; both
    optimal in primitive epistemic steps."""
    inst = generate(goal, colors, seed)
    task, _, _ = epistemic_task(inst, macros=False)
    off, on = solve(inst, macros=False), solve(inst, macros=True)
    assert check_plan(task, list(off.flat_plan)).valid and check_plan(task, list(on.flat_plan)).valid
    assert len(on.flat_plan) == len(off.flat_plan)


def test_cli_generate_solve_check(tmp_path, capsys):
    """delkit epico generate / solve, then delkit check accepts the flat plan on the generated files."""
    out = tmp_path / "g"
    assert main(["epico", "generate", "--goal", "beta", "--colors", "2", "--out", str(out)]) == 0
    capsys.readouterr()
    plan = tmp_path / "plan.json"
    assert main(["epico", "solve", "--goal", "beta", "--colors", "2", "--json", "--out", str(plan)]) == 0
    res = json.loads(capsys.readouterr().out)
    assert res["classical_calls"] == 2 and json.loads(plan.read_text())["format"] == "delkit.arms.plan/1"
    flat = tmp_path / "flat.plan"
    flat.write_text("\n".join(res["flat_plan"]))
    assert main(["check", str(out / "domain.epddl"), str(out / "problem.epddl"), str(flat)]) == 0
    assert "valid" in capsys.readouterr().out
    flat.write_text("\n".join(res["flat_plan"][1:]))  # without sensing: robot1 cannot put a block it does not know
    assert main(["check", str(out / "domain.epddl"), str(out / "problem.epddl"), str(flat)]) == 1


def test_cli_errors(capsys):
    assert main(["epico", "solve", "--goal", "gamma", "--colors", "1"]) == 2
    assert "not defined" in capsys.readouterr().err
    assert main(["epico", "solve", "--goal", "zeta"]) == 2
    assert main(["epico", "solve", "--classical", "magic"]) == 2


@pytest.mark.slow
def test_primitive_plan_runs_in_mujoco(tmp_path):
    """δ with 2 colours: the primitive plan executes in MuJoCo (arms run), every action succeeds."""
    from arms.executor import run_plan
    from arms.plan import parse_plan

    sol = solve(generate("delta", 2))
    res, _ = run_plan(parse_plan(sol.primitive_plan))
    assert res.success, res.failure


def test_cli_replan_from_world(tmp_path, capsys):
    """delkit epico solve --world (a world observed after a fault) --owner --known: plan from there."""
    inst = generate("beta", 2)
    world = inst.layout.to_world()
    world["stacks"]["robot1"] = [["black"], [], []]
    world["barrier"] = ["red"]
    wf = tmp_path / "world.json"
    wf.write_text(json.dumps({"format": "delkit.arms.plan/1", "world": world, "actions": []}))
    assert main(["epico", "solve", "--goal", "beta", "--colors", "2", "--world", str(wf), "--owner", "red=robot1",
                 "--known", "robot1:red,black", "--json"]) == 0
    res = json.loads(capsys.readouterr().out)
    assert res["flat_plan"][0].startswith("announce_block_on_barrier_robot1_red") and res["classical_calls"] == 1
    assert main(["epico", "solve", "--world", str(wf), "--owner", "red"]) == 2
    assert main(["epico", "solve", "--known", "robot1"]) == 2


@pytest.mark.parametrize("goal,colors,takes", [("beta", 1, "seen"), ("gamma", 2, "seen"), ("beta", 2, "handover")])
def test_tree_search_same_plans_more_nodes(goal, colors, takes):
    """The tree search (BFS without duplicate detection, the e-PICO paper's planner's default) finds plans as
    short as delkit's BFS, macros off and on, accepted by the checker, and expands at least as many states;
    without macros, on plans of 4 steps or more, strictly more (the duplicates BFS detects)."""
    from planners.hierarchy import EpicoLimits

    inst = generate(goal, colors, takes=takes)
    for macros in (False, True):
        bfs = solve(inst, macros=macros)
        tree = solve(inst, macros=macros, limits=EpicoLimits(search="tree", timeout=30))
        assert tree.search["search"] == "tree"
        assert len(tree.epistemic_plan) == len(bfs.epistemic_plan)
        assert len(tree.flat_plan) == len(bfs.flat_plan)
        task, _, _ = epistemic_task(inst, macros=False)
        assert check_plan(task, list(tree.flat_plan)).valid
        assert tree.search["expanded"] >= bfs.search["expanded"]
        if not macros:
            assert tree.search["expanded"] > bfs.search["expanded"]
