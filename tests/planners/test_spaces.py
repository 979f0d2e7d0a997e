"""The planner's state spaces on delkit's backends: macros (composed event models), general event-model
actions and multi-pointed states — each compared with the reference semantics (numpy backend, steps in
sequence) and on small hand-checked cases."""

from __future__ import annotations

import dataclasses

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from delkit.models.bisimulation import bisimilar, contract
from delkit.models.events import sensing
from delkit.models.kripke import KripkeModel
from planners.demo import specs_dir
from planners.epistemic import Limits, bfs, plan
from planners.lang import load_task
from planners.spaces import CompactSpace, DelSpace
from planners.task import ActionSpec, EventAction, MacroSpec, Task, apply_action, build_event_model
from planners.validate import check_plan

D = specs_dir()
COIN = (D / "coin_in_the_box" / "domain.epddl", D / "coin_in_the_box" / "common.epddl")
GRAPE = (D / "grapevine" / "domain.epddl", D / "grapevine" / "problem.epddl")


def _with_macros(task: Task, max_pairs: int = 400) -> Task:
    """``task`` plus every ordered pair (and some triples) of its actions as a macro."""
    acts = [a for a in task.actions if isinstance(a, ActionSpec)]
    macros = [MacroSpec(f"{a.name}+{b.name}", (a, b)) for a in acts for b in acts][:max_pairs]
    macros += [MacroSpec(f"{a.name}+{b.name}+{a.name}", (a, b, a)) for a in acts[:4] for b in acts[:4]]
    return dataclasses.replace(task, actions=tuple(acts) + tuple(macros), _cache={})


def _as_event_actions(task: Task) -> Task:
    """``task`` with every mA* action re-expressed as an EventAction (conditions: observers, sensed)."""
    ags = task.agents

    def convert(act: ActionSpec) -> EventAction:
        nf, npart = len(act.full), len(act.partial)
        conds = tuple(c for _, c in act.full) + tuple(c for _, c in act.partial) + tuple(c for _, c in act.sensed)

        def build(bits: tuple[bool, ...], act: ActionSpec = act) -> object:
            full = frozenset(a for (a, _), b in zip(act.full, bits[:nf], strict=True) if b)
            part = frozenset(a for (a, _), b in zip(act.partial, bits[nf:nf + npart], strict=True) if b) - full
            sensed = tuple(f for (f, _), b in zip(act.sensed, bits[nf + npart:], strict=True) if b)
            return build_event_model(act, ags, full, part, sensed if act.kind != "ontic" else ())

        return EventAction(act.name, build, conds, act.executable)

    return dataclasses.replace(task, actions=tuple(convert(a) for a in task.actions), _cache={})


@pytest.mark.parametrize("spec", [COIN, GRAPE], ids=["coin", "grapevine"])
@settings(max_examples=20, deadline=None)
@given(walk=st.lists(st.integers(0, 10**6), min_size=1, max_size=4))
def test_macro_composed_equals_sequence(spec, walk) -> None:
    """Along random walks: the compact space's macro step (one composed event model) ≅ the reference
    (steps in sequence with product_update), and applicable in exactly the same states."""
    task = _with_macros(load_task(*spec))
    space = CompactSpace(task)
    s, _ = space.initial()
    m = contract(task.initial)
    for r in walk:
        succ = [(a, apply_action(task, a, m)) for a in task.actions]
        names_ref = sorted(a.name for a, new in succ if new is not None)
        names_fast = sorted(a.name for a in task.actions if space.step(s, a.name) is not None)
        assert names_ref == names_fast
        live = [(a, new) for a, new in succ if new is not None and isinstance(a, MacroSpec)]
        if not live:
            break
        act, new = live[r % len(live)]
        s2 = space.step(s, act.name)
        assert bisimilar(space.to_kripke(s2), new)
        s, m = s2, contract(new)


def test_macros_never_change_plan_validity_or_length_bound() -> None:
    """With macros the optimum counts a macro as one action: never longer than without, and the flattened
    plan is valid without macros."""
    task = load_task(*COIN)
    base = plan(task)
    mt = _with_macros(task)
    res = plan(mt, limits=Limits(timeout=60))
    assert res.solved and res.length <= base.length
    assert check_plan(mt, list(res.plan)).valid
    by = {a.name: a for a in mt.actions}
    flat = [st.name for n in res.plan for st in (by[n].steps if isinstance(by[n], MacroSpec) else (by[n],))]
    assert check_plan(task, flat).valid
    assert len(flat) >= base.length


@pytest.mark.parametrize("spec", [COIN, GRAPE], ids=["coin", "grapevine"])
def test_event_actions_search_exactly_like_ma_star_actions(spec) -> None:
    """The same actions given as general event models: identical plans and node counts on both engines."""
    task = load_task(*spec)
    ev = _as_event_actions(task)
    for engine in ("fast", "del"):
        a = plan(task, engine=engine)
        b = plan(ev, engine=engine)
        assert (a.plan, a.expanded, a.generated) == (b.plan, b.expanded, b.generated)
        assert check_plan(ev, list(b.plan)).valid


def _coin_task(designated: tuple[int, ...], goal: str) -> Task:
    """Hand-checked: one agent a, a coin p; worlds {p}, {} indistinguishable for a; a may look."""
    from delkit.logic.formula import parse

    m = KripkeModel.build([{"p"}, set()], {"a": [[0, 1]]}, designated=list(designated))
    look = EventAction("look", lambda bits: sensing("p", ["a"], full=["a"], name="look"))
    return Task("coin", ("p",), ("a",), m, (look,), parse(goal))


@pytest.mark.parametrize("engine", ["fast", "del"])
def test_multi_pointed_states_hand_checked(engine) -> None:
    # both worlds designated (a state that does not fix the coin): after looking, a knows whether p in
    # every designated world — a plan of length 1 that a BFS must not miss
    assert plan(_coin_task((0, 1), "Kw_a p"), engine=engine).plan == ("look",)
    # K_a p must hold in every designated world; in the ¬p world it never does: no plan exists
    assert plan(_coin_task((0, 1), "K_a p"), engine=engine).status == "unsolvable"
    # single-pointed at p: looking makes a know p
    assert plan(_coin_task((0,), "K_a p"), engine=engine).plan == ("look",)
    # the goal holds initially in no designated world / in all: empty plan only when in all
    assert plan(_coin_task((0, 1), "p | ~p"), engine=engine).plan == ()


def test_multi_pointed_spaces_agree() -> None:
    task = _coin_task((0, 1), "Kw_a p")
    a, b = bfs(CompactSpace(task)), bfs(DelSpace(task))
    assert (a.plan, a.expanded, a.generated) == (b.plan, b.expanded, b.generated)


@pytest.mark.parametrize("engine", ["fast", "del"])
def test_group_d_goal_hand_checked(engine) -> None:
    """w0 (p) sees w1 for a and w2 for b (both ¬p, bisimilar): D_{a,b} p holds at w0 and K_a p, K_b p do not.
    A plain contraction would merge w1, w2 and lose D_{a,b} p (the goal would look false and the planner
    would search instead of answering the empty plan); 'tell' announces p to a and b privately, after which
    both know p."""
    from delkit.logic.formula import parse
    from delkit.models.events import private_announcement

    m = KripkeModel.build([{"p"}, set(), set()], {"a": {"pairs": [(0, 0), (0, 1), (1, 1), (2, 2)]},
                                                    "b": {"pairs": [(0, 0), (0, 2), (1, 1), (2, 2)]}},
                          designated=[0])
    tell = EventAction("tell", lambda bits: private_announcement("p", ["a", "b"], ["a", "b"], name="tell"))

    def task(goal: str) -> Task:
        return Task("d", ("p",), ("a", "b"), m, (tell,), parse(goal))

    assert plan(task("D{a,b} p"), engine=engine).plan == ()
    assert plan(task("D{a,b} p & ~K_a p"), engine=engine).plan == ()
    assert plan(task("K_a p & K_b p & D{a,b} p"), engine=engine).plan == ("tell",)


def test_checker_explains_a_failed_goal_at_the_designated_world_where_it_fails() -> None:
    """Multi-pointed: the goal p holds in designated world 0 and fails in 1; the explanation names world 1."""
    task = _coin_task((0, 1), "p")
    res = check_plan(task, [])
    assert not res.valid and res.kind == "goal"
    assert "w1" in res.reason and "w0" not in res.reason


def _epddl_runs(limit_worlds: int = 64):
    import csv

    from planners.lang import shared_benchmarks

    bench = shared_benchmarks()
    if bench is None:
        return []
    base = bench / "epddl2026"
    rows = list(csv.DictReader((base / "expected.csv").open()))
    return [(base / r["domain"], base / r["problem"], [base / r["libraries"]] if r["libraries"] else [])
            for r in rows if not any(x in r["problem"] for x in ("Tiger", "Selective"))]


@pytest.mark.parametrize("run", _epddl_runs(), ids=lambda r: "/".join(r[1].parts[-3:]))
def test_literal_index_never_drops_an_applicable_action(run) -> None:
    """The successor generator (actions filed by a required literal of their designated preconditions) keeps
    every action that applies: on the first 150 states of a BFS of each EPDDL benchmark problem, each action
    with a successor is among the enabled ones — multi-pointed states included."""
    from planners.lang.epddl2026 import load_epddl2026

    task = load_epddl2026(*run[:2], run[2])
    space = CompactSpace(task, allow_inconsistent=True)
    s, key = space.initial()
    frontier, seen, pruned = [s], {key}, 0
    while frontier and len(seen) < 150:
        s = frontier.pop(0)
        vals = tuple(sorted({s.val[p] for p in s.points}))
        enabled = set(space._enabled(vals))
        pruned += len(task.actions) - len(enabled)
        for i, entry in enumerate(space._acts):
            new = space.apply_entry(s, entry)
            assert new is None or i in enabled, (entry[1].name, s)
            if new is not None and new.key not in seen:
                seen.add(new.key)
                frontier.append(new)
    assert pruned > 0 or len(task.actions) < 8


def test_declared_designated_preconditions_are_checked() -> None:
    """An EventAction whose declared designated_pre differs from its event model's is refused when built."""
    from delkit.errors import PlanningError
    from delkit.logic.formula import Prop

    task = _coin_task((0,), "K_a p")
    look = task.actions[0]
    bad = dataclasses.replace(look, designated_pre=(Prop("p"),))   # sensing's designated event requires ⊤
    wrong = dataclasses.replace(task, actions=(bad,), _cache={})
    with pytest.raises(PlanningError, match="designated_pre"):
        plan(wrong)
    good = dataclasses.replace(look, designated_pre=tuple(
        look.build(()).pre[d] for d in look.build(()).designated))
    assert plan(dataclasses.replace(task, actions=(good,), _cache={})).plan == ("look",)


def test_event_model_for_bits_refuses_a_wrong_number_of_truth_values() -> None:
    from delkit.errors import PlanningError

    task = _coin_task((0,), "K_a p")
    with pytest.raises(PlanningError, match="0 condition"):
        task.event_model_for_bits(task.actions[0], (True,))
