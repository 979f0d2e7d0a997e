"""e-PICO end to end (seed 004): generate → epistemic plan → flatten → classical breakdown → plan/1."""

from __future__ import annotations

import pytest

from arms.plan import parse_plan, symbolic_trace
from planners.epico import GOALS, EpicoError, defined, generate
from planners.hierarchy import epistemic_task, solve
from planners.validate import check_plan


def _accepts(sol) -> None:
    """delkit check accepts the flat plan, arms.plan accepts the primitive plan, the trace ends in the goal."""
    task, ptask, _ = epistemic_task(sol.instance, macros=sol.macros)
    res = check_plan(task, list(sol.flat_plan))
    assert res.valid, res.reason
    assert check_plan(ptask, list(sol.epistemic_plan)).valid  # the checker replays the macros themselves
    states = symbolic_trace(parse_plan(sol.primitive_plan))
    final = states[-1]
    on_table = [b for b, p in final.places.items() if p.kind == "barrier"]
    assert not [b for b, p in final.places.items() if p.kind == "held"]
    if sol.instance.goal in ("beta", "delta"):
        assert on_table == []  # the shared table is free at the end
    # every block the knower learnt about was on the shared table at some point
    announced = {a["args"][0] for a in sol.primitive_plan["actions"] if a["action"] == "announce"}
    need = 1 if sol.instance.goal in ("alpha", "beta") else 2
    assert len({sol.instance.layout.colors[b] for b in announced}) >= need


def test_alpha_two_colours_end_to_end():
    inst = generate("alpha", 2)
    for macros in (False, True):
        sol = solve(inst, macros=macros)
        _accepts(sol)
        assert sol.classical_calls == 1
    assert any(n.startswith("pspb_and_announce") for n in sol.epistemic_plan)
    assert len(sol.epistemic_plan) < len(sol.flat_plan)


def test_consistent_beliefs_every_step():
    """No vacuous success: replaying the flat plan with delkit's product update, every agent keeps an
    accessible world at the actual world after every step."""
    from delkit.update import product_update

    sol = solve(generate("delta", 2), macros=True)
    task, _, _ = epistemic_task(sol.instance, macros=False)
    m = task.initial
    for name in sol.flat_plan:
        act = task.action(name)
        m = product_update(m, task.event_model(act, m))
        assert m.inconsistent_agents() == [], name


def test_listing5_red_under_black():
    """The seed's Listing 5: red under black → pick / place / pick / put_on_barrier."""
    sol = solve(generate("alpha", 4), macros=True)
    put = next(t for t in sol.tasks if t.task == "put_on_shared_robot1_red")
    assert [a["action"] for a in put.actions] == ["pick", "place", "pick", "put_on_barrier"]
    assert [a["args"][0] for a in put.actions] == ["black", "black", "red", "red"]
    assert put.actions[0]["args"] == ["black", "red", 1, 1]


@pytest.mark.parametrize("goal,calls", [("alpha", 1), ("beta", 2), ("gamma", 3), ("delta", 4)])
def test_table2_call_counts(goal, calls):
    assert solve(generate(goal, 2), macros=True).classical_calls == calls


def test_nd_and_bad_input():
    assert not defined("gamma", 1) and defined("alpha", 1)
    with pytest.raises(EpicoError, match="not defined"):
        generate("delta", 1)
    with pytest.raises(EpicoError, match="unknown goal"):
        generate("epsilon", 2)
    with pytest.raises(EpicoError, match="colors"):
        generate("alpha", 9)


def test_random_layouts_and_known():
    """Random layouts solve; ``known`` (what a robot already observed) makes the sensing unnecessary."""
    for seed in range(3):
        _accepts(solve(generate("beta", 3, seed=seed)))
    inst = generate("alpha", 2)
    sol = solve(inst, known={"robot1": ["red", "black"]})
    assert not any(n.startswith("sense") for n in sol.flat_plan)
    _accepts(sol)


@pytest.mark.slow
@pytest.mark.parametrize("goal", GOALS)
@pytest.mark.parametrize("colors", [1, 2, 3, 4])
def test_table1_every_cell(goal, colors):
    """Every defined cell of Table 1, macros off and on: same validity, fewer or equal search steps."""
    if not defined(goal, colors):
        pytest.skip("ND")
    inst = generate(goal, colors)
    off, on = solve(inst, macros=False), solve(inst, macros=True)
    for sol in (off, on):
        _accepts(sol)
    assert len(on.flat_plan) == len(off.flat_plan)  # BFS: both optimal in primitive epistemic steps
    assert len(on.epistemic_plan) <= len(off.epistemic_plan)
    assert on.classical_calls == off.classical_calls == {"alpha": 1, "beta": 2, "gamma": 3, "delta": 4}[goal]


def test_oblivious_variant_only_succeeds_vacuously():
    """With the other robot oblivious of put_on_shared (the reading that makes Listing 3's announcement
    contradict its beliefs), no consistent plan exists; allowing inconsistent states 'finds' one in which
    robot2 believes ⊥ — the vacuous success the checker rejects."""
    from planners.epistemic import Limits, plan
    from planners.hierarchy import process_e_plan
    from planners.lang.epddl import parse_epddl

    inst = generate("alpha", 2)
    dom = inst.domain_text.replace("""    :effect (when (hold ?ag ?c) (occup_by ?ag ?c))
    :observers (forall (?ag2 - agent) (?ag2)))""", """    :effect (occup_by ?ag ?c)
    :observers (?ag))""")
    assert dom != inst.domain_text
    task = parse_epddl(dom, inst.problem_text)
    assert plan(task, limits=Limits(timeout=30)).status == "unsolvable"
    vac = plan(task, limits=Limits(timeout=30), allow_inconsistent=True)
    assert vac.solved
    res = check_plan(task, list(vac.plan))
    assert not res.valid and res.kind == "inconsistent-belief" and res.agent == "robot2"
    with pytest.raises(EpicoError, match="believing ⊥"):
        process_e_plan(task, vac.plan, inst.classical_init)


def test_replan_from_observed_layout():
    """The arms' replanning path: a world object after a fault (red already on the shared table, robot1
    knows its colours) → Layout.from_world → generate(layout=...) → solve: no sensing, no second put."""
    from planners.epico import Layout

    inst = generate("beta", 2)
    assert Layout.from_world(inst.layout.to_world()) == inst.layout
    world = inst.layout.to_world()
    world["stacks"]["robot1"] = [["black"], [], []]
    world["barrier"] = ["red"]
    lay = Layout.from_world(world, owners={"red": "robot1"})
    sol = solve(generate("beta", 2, layout=lay), known={"robot1": ["red", "black"]})
    assert not any(n.startswith(("sense", "put_on_shared")) for n in sol.flat_plan)
    assert sol.classical_calls == 1  # only the take
    _accepts(sol)
