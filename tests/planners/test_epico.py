"""e-PICO end to end (seed 004): generate → epistemic plan → flatten → classical breakdown → plan/1."""

from __future__ import annotations

import json

import pytest

from planners.epico import GOALS, ROBOTS, EpicoError, Reading, defined, generate, reading_of
from planners.hierarchy import epistemic_task, solve
from planners.primitive import parse_plan, symbolic_trace
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
    announced = {a["args"][0] for a in sol.primitive_plan["actions"] if a["action"] == "announce" and a.get("args")}
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
    from delkit.models.update import product_update

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


def test_default_is_the_papers_reading(capsys):
    """§4.4: "Initially, they do not know what blocks they are able to manipulate" — both robots. The
    default instance models both robots' colours (4^n worlds), says so, and the reduced reading is asked
    for by name."""
    from delkit.cli import main

    inst = generate("alpha", 2)
    assert inst.owners == ROBOTS and inst.reading == Reading() and inst.reading.name == "paper"
    assert "robot1 robot2 - owner" in inst.problem_text
    task, _, _ = epistemic_task(inst, macros=False)
    assert task.initial.n_worlds == 4 ** 2
    reduced = generate("alpha", 2, owners=("robot1",))
    assert reduced.reading.name == "owner robot1"
    assert epistemic_task(reduced, macros=False)[0].initial.n_worlds == 2 ** 2
    assert solve(inst).to_json()["reading"]["name"] == "paper"
    with pytest.warns(DeprecationWarning):
        assert generate("alpha", 2, symmetric=False).owners == ("robot1",)
    assert main(["epico", "table", "--colors", "1", "--json"]) in (0, None)
    data = json.loads(capsys.readouterr().out)
    assert data["reading"]["name"] == "paper" and {c["reading"] for c in data["cells"]} == {"paper"}
    assert main(["epico", "solve", "--goal", "alpha", "--colors", "1", "--owner", "robot1"]) in (0, None)
    out = capsys.readouterr().out
    assert out.startswith("owner robot1 reading: robot1's colours unknown (2^n worlds")
    assert main(["epico", "table", "--colors", "1"]) in (0, None)
    out = capsys.readouterr().out
    assert out.lstrip().startswith("paper reading:") and "Legend:" in out and "ND = not defined" in out


def _table1(goal: str, colors: int, reading: Reading) -> None:
    """A Table-1 cell, macros off and on: both plans accepted by the DEL checker (and the primitive plan by
    the block-world trace), equally long when flattened (BFS is optimal), Table 2's call counts."""
    if not defined(goal, colors):
        pytest.skip("ND")
    inst = generate(goal, colors, reading=reading)
    off, on = solve(inst, macros=False), solve(inst, macros=True)
    for sol in (off, on):
        _accepts(sol)
    assert len(on.flat_plan) == len(off.flat_plan)  # BFS: both optimal in primitive epistemic steps
    assert len(on.epistemic_plan) <= len(off.epistemic_plan)
    assert on.search["expanded"] <= off.search["expanded"]
    assert on.classical_calls == off.classical_calls == {"alpha": 1, "beta": 2, "gamma": 3, "delta": 4}[goal]


READINGS = {"paper": Reading(), "owner robot1": reading_of(("robot1",))}


@pytest.mark.parametrize("reading", READINGS)
@pytest.mark.parametrize("goal", GOALS)
@pytest.mark.parametrize("colors", [1, 2, 3])
def test_table1_cells(goal, colors, reading):
    _table1(goal, colors, READINGS[reading])


@pytest.mark.slow
@pytest.mark.parametrize("reading", READINGS)
@pytest.mark.parametrize("goal", GOALS)
def test_table1_four_colours(goal, reading):
    _table1(goal, 4, READINGS[reading])


@pytest.mark.parametrize("goal", ["gamma", "delta"])
def test_per_colour_sensing(goal):
    """Per-colour sensing: one sense_color per colour the plan needs (γ, δ: two)."""
    inst = generate(goal, 2, sensing="color")
    for macros in (False, True):
        sol = solve(inst, macros=macros)
        _accepts(sol)
        assert sum(n.startswith("sense_color_") for n in sol.flat_plan) == 2
        assert not any(n.startswith("sense_table") for n in sol.flat_plan)


@pytest.mark.slow
@pytest.mark.parametrize("goal", GOALS)
def test_per_colour_sensing_four_colours(goal):
    _table1(goal, 4, reading_of(sensing="color"))


def test_handover_prose_macro():
    """The hand-over reading: the owner cannot tell whether the other robot cleared the shared table, so it
    must be told before it puts again — γ and δ plans take and announce (the §5 prose macro), and with the
    macro they use take_and_announce; the announcement is what lets the owner's second put be executable."""
    from planners.task import EventAction

    inst = generate("gamma", 2, takes="handover")
    task, _, _ = epistemic_task(inst, macros=False)
    take = task.action("take_from_shared_robot2_robot1_red")
    assert isinstance(take, EventAction)
    assert not task.executable(task.action("take_from_shared_robot1_robot1_red"), task.initial)  # owner never
    off = solve(inst, macros=False)
    i = off.flat_plan.index("take_from_shared_robot2_robot1_red")
    assert off.flat_plan[i + 1] == "announce_table_free_robot2"
    on = solve(inst, macros=True)
    assert "take_and_announce_robot2_robot1_red" in on.epistemic_plan
    for sol in (off, on):
        _accepts(sol)
    # without the announcement the owner's next put is not executable (it does not know the table is free)
    bad = off.flat_plan[:i + 1] + off.flat_plan[i + 2:]
    res = check_plan(task, list(bad))
    assert not res.valid and res.step == i + 2, res.reason


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


@pytest.mark.parametrize("reading", [Reading(), reading_of(("robot1",)), reading_of(sensing="color"),
                                     reading_of(takes="handover")], ids=lambda r: r.name)
def test_successors_equal_the_product(reading):
    """The compact space's shortcuts (a sensing/announcement that cannot change the state yields it, a
    refinement instead of a product when nobody is oblivious, commuting sensings read from known
    transitions, one-event public actions without the pair table) give the state delkit's product update
    gives, along a breadth-first search (where the commutation shortcut fires) and random walks."""
    import random

    from delkit.models.update import product_update
    from planners.epistemic import Limits, bfs
    from planners.spaces import CompactSpace

    rng = random.Random(7)
    cases = (("beta", False), ("beta", True)) if reading.sensing == "color" else (("delta", False), ("gamma", True))
    for goal, macros in cases:  # (per-colour sensing: the smaller goal keeps the test at a few seconds)
        inst = generate(goal, 2, reading=reading)
        _, ptask, _ = epistemic_task(inst, macros=macros)
        sp = CompactSpace(ptask)
        inner = sp.successors
        checked = []

        def succ(s, inner=inner, sp=sp, checked=checked):
            k = sp.to_kripke(s)
            out = list(inner(s))
            for name, nxt, key in out:
                entry = sp._acts[sp._index[name]]
                em = sp._macro_model(s, entry) if entry[0] == "macro" else sp.event_model(s, entry)
                assert nxt.key == key == sp.engine.from_kripke(product_update(k, em)).key, name
                checked.append(name)
            yield from out

        sp.successors = succ
        assert bfs(sp, Limits(timeout=120)).solved
        s, _ = sp.initial()
        for _ in range(6):
            nxt = list(sp.successors(s))
            s = rng.choice(nxt)[1]
        assert len(checked) > 20


def test_big_public_updates_equal_the_product():
    """Four colours (256 worlds: the compact backend's one-event public update without the pair table, and
    the refinement shortcut): along a plan of δ, every successor equals delkit's product update."""
    from delkit.models.update import product_update
    from planners.spaces import CompactSpace

    inst = generate("delta", 4)
    task, _, _ = epistemic_task(inst, macros=False)
    sp = CompactSpace(task)
    s, _ = sp.initial()
    plan = solve(inst, macros=False).flat_plan
    kinds = set()
    for step in plan[:5]:
        k = sp.to_kripke(s)
        for name, _nxt, key in sp.successors(s):
            entry = sp._acts[sp._index[name]]
            assert key == sp.engine.from_kripke(product_update(k, sp.event_model(s, entry))).key, name
            kinds.add(entry[1].kind)
        s = sp.step(s, step)
    assert kinds == {"ontic", "sensing", "announcement"} and len(s.val) > 64


# ----------------------------------------------------------------------------- plans from a robot's perspective

_TELL_DOMAIN = """(define (domain tell)
  (:requirements :strips :mep)
  (:predicates (p) (q))
  (:action press_b
    :act_type ontic
    :precondition (p)
    :effect (q)
    :observers (forall (?x - agent) (?x)))
  (:action tell
    :act_type announcement
    :parameters (?ag - agent)
    :precondition (and (p) ([?ag](p)))
    :effect (p)
    :observers (forall (?x - agent) (?x))))
"""
#: p is true, a knows whether p, b does not; b must press (its precondition p is not a knowledge condition)
_TELL_PROBLEM = """(define (problem tell1)
  (:domain tell)
  (:agents a b)
  (:init (p) ([a b](not (q))) ([a b](or ([a](p)) ([a](not (p))))))
  (:goal (q)))
"""


def _tell_task():
    from planners.lang.epddl import parse_epddl

    return parse_epddl(_TELL_DOMAIN, _TELL_PROBLEM)


def test_perspective_actor_must_know_its_step_is_applicable():
    """Hand-checked: b's press is applicable in the actual world (the external planner's plan), but b does not
    know p, so from a's perspective (a knows p) a must tell b first; from b's perspective there is no plan (b
    considers ¬p possible, where nobody can make q true)."""
    from planners.hierarchy import perspective_check, plan_from_perspective

    task = _tell_task()
    assert check_plan(task, ["press_b"]).valid
    chk = perspective_check(task, ["press_b"], "a")
    assert not chk.valid and chk.step == 0 and chk.actor == "b" and "b does not know" in chk.reason
    res = plan_from_perspective(task, "a")
    assert res.solved and res.plan == ("tell_a", "press_b")
    assert perspective_check(task, res.plan, "a").valid and check_plan(task, list(res.plan)).valid
    assert plan_from_perspective(task, "b").status == "unsolvable"


_GUESS_DOMAIN = """(define (domain guess)
  (:requirements :strips :mep)
  (:predicates (p) (q))
  (:action press_a
    :act_type ontic
    :effect (when (p) (q))
    :observers (forall (?x - agent) (?x))))
"""
#: p is true and nobody knows it; a's press makes q true exactly where p is
_GUESS_PROBLEM = """(define (problem guess1)
  (:domain guess)
  (:agents a b)
  (:init (p) ([a b](not (q))))
  (:goal (q)))
"""


def test_perspective_goal_in_every_world():
    """Hand-checked: a's press reaches q in the actual world (p), not in the world a considers possible where p is
    false: valid for the external planner, not from a's perspective, and no plan from a's perspective exists."""
    from planners.hierarchy import perspective_check, plan_from_perspective
    from planners.lang.epddl import parse_epddl

    task = parse_epddl(_GUESS_DOMAIN, _GUESS_PROBLEM)
    assert check_plan(task, ["press_a"]).valid
    chk = perspective_check(task, ["press_a"], "a")
    assert not chk.valid and chk.step == 1 and "goal fails" in chk.reason and "q is false" not in chk.reason
    assert len(chk.worlds) == 2
    assert plan_from_perspective(task, "a", max_depth=4).status == "unsolvable"


def test_perspective_external_plan_fails_for_the_robot():
    """α, 1 colour, the paper's reading: the external planner's plan (robot1 senses, puts its red block, announces
    it) is valid in the actual world, but robot1 considers possible that it has no red block: from its
    perspective the put is not known applicable, and no plan exists (in the world where nobody has a block
    nothing reaches α)."""
    from planners.hierarchy import perspective_check, plan_from_perspective

    inst = generate("alpha", 1)
    task, _, _ = epistemic_task(inst, macros=False)
    sol = solve(inst, macros=False)
    assert check_plan(task, list(sol.flat_plan)).valid
    assert sol.search["perspective"] == "external" and "e-PICO paper" in sol.search["perspective_meaning"]
    chk = perspective_check(task, sol.flat_plan, "robot1")
    assert not chk.valid and chk.action.startswith("put_on_shared_robot1") and "hold_robot1_red is false" in chk.reason
    assert plan_from_perspective(task, "robot1").status == "unsolvable"
    with pytest.raises(EpicoError, match="robot1's perspective.*fails from robot1's perspective at step 2"):
        solve(inst, macros=True, perspective="robot1")


def test_perspective_of_the_robot_that_knows():
    """Once robot1 knows its colours (``known``, e.g. after sensing), a plan from robot1's perspective exists
    (put red, announce); robot2, who does not know robot1's colours, cannot count on it."""
    from planners.hierarchy import perspective_check

    inst = generate("alpha", 2)
    sol = solve(inst, macros=True, known={"robot1": ["red", "black"]}, perspective="robot1")
    _accepts(sol)
    assert sol.search["perspective"] == "robot1" and "Engesser" in sol.search["perspective_meaning"]
    task, ptask, _ = epistemic_task(inst.with_known({"robot1": ["red", "black"]}), macros=True)
    assert perspective_check(ptask, sol.epistemic_plan, "robot1").valid
    other = perspective_check(ptask, sol.epistemic_plan, "robot2")
    assert not other.valid and other.actor == "robot1"


@pytest.mark.parametrize("seed", range(6))
def test_perspective_plans_are_external_plans(seed):
    """Every plan found from a robot's perspective is valid for the external planner (the actual world is among
    the worlds the robot considers possible), on random layouts with random knowledge."""
    import random

    from planners.hierarchy import perspective_check, plan_from_perspective

    rng = random.Random(seed)
    goal = rng.choice(["alpha", "beta"])
    inst = generate(goal, 2, seed=seed)
    agent = rng.choice(ROBOTS)
    known = {r: [c for c in ("red", "black") if rng.random() < 0.6] for r in ROBOTS}
    inst = inst.with_known(known)
    task, _, _ = epistemic_task(inst, macros=False)
    res = plan_from_perspective(task, agent)
    if res.solved:
        assert check_plan(task, list(res.plan)).valid
        assert perspective_check(task, res.plan, agent).valid
    else:
        assert res.status == "unsolvable"


def test_perspective_cli(capsys):
    from delkit.cli import main

    assert main(["epico", "solve", "--goal", "alpha", "--colors", "2", "--known", "robot1:red,black",
                 "--perspective", "robot1", "--json"]) in (0, None)
    assert json.loads(capsys.readouterr().out)["search"]["perspective"] == "robot1"
    assert main(["epico", "solve", "--goal", "alpha", "--colors", "1"]) in (0, None)
    assert "plan reading: external planner (the e-PICO paper's reading)" in capsys.readouterr().out
    try:
        rc = main(["epico", "solve", "--perspective", "robot3"])
    except SystemExit as exc:
        rc = exc.code
    assert rc not in (0, None) and "--perspective 'robot3'" in capsys.readouterr().err
