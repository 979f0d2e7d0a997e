"""The belief-content cover heuristic h_epi (A*'s default): admissible and consistent on random mA* tasks
(checked against exact goal distances), A* optimal (= BFS's length), and it prunes Grapevine."""

from __future__ import annotations

import math
from collections import deque
from pathlib import Path

import pytest
from hypothesis import HealthCheck, example, given, settings
from hypothesis import strategies as st

from planners.epistemic import Limits, best_first, bfs, make_space, plan
from planners.heuristics import content_conjuncts, h_cover, h_epi, prop_blocks
from planners.lang import load_task, shared_benchmarks
from planners.lang.mastar import parse_mastar
from planners.validate import check_plan

BENCH = shared_benchmarks()
SPECS = __import__("planners.demo", fromlist=["specs_dir"]).specs_dir()
ROOT = Path(__file__).resolve().parents[2]  # the checkout (bench/ lies beside planners/)
G5 = SPECS / "grapevine5" / "Grapevine_5__pl_6.txt"

PROPS = ("p", "q", "r")
AGENTS = ("a", "b")


@st.composite
def _literal(draw, props=PROPS) -> str:
    return ("-" if draw(st.booleans()) else "") + draw(st.sampled_from(props))


@st.composite
def _condition(draw) -> str:
    kind = draw(st.sampled_from(["none", "none", "lit", "belief"]))
    if kind == "lit":
        return f" if {draw(_literal())}"
    if kind == "belief":
        return f" if B({draw(st.sampled_from(AGENTS))},{draw(_literal())})"
    return ""


@st.composite
def _goal(draw) -> str:
    x, y = draw(st.sampled_from(AGENTS)), draw(st.sampled_from(AGENTS))
    lit = draw(_literal())
    return draw(st.sampled_from([f"B({x},{lit})", f"(-B({x},{lit}))", lit, f"B({x},B({y},{lit}))",
                                 f"B({x},({lit} | {draw(_literal())}))", f"(-B({x},(-B({y},{lit}))))"]))


@st.composite
def mastar_tasks(draw) -> str:
    """A small random mA* task: ontic / sensing / announcement actions with literal or compound contents,
    conditional effects and observers, an initial state with some common knowledge, a goal of belief
    literals (first-order and nested)."""
    n = draw(st.integers(2, 4))
    lines = [f"fluent {', '.join(PROPS)};", f"action {', '.join(f'x{i}' for i in range(n))};",
             f"agent {', '.join(AGENTS)};"]
    for i in range(n):
        a = f"x{i}"
        kind = draw(st.sampled_from(["ontic", "ontic", "sensing", "announcement", "announcement"]))
        exe = draw(st.sampled_from(["", "", f"executable {a} if {draw(_literal())};",
                                    f"executable {a} if B({draw(st.sampled_from(AGENTS))},{draw(_literal())});"]))
        if exe:
            lines.append(exe)
        if kind == "ontic":
            for _ in range(draw(st.integers(1, 2))):
                lines.append(f"{a} causes {draw(_literal())}{draw(_condition())};")
        elif kind == "sensing":
            lines.append(f"{a} determines {draw(st.sampled_from(PROPS))}{draw(_condition())};")
        else:
            content = draw(st.sampled_from([draw(_literal()), f"({draw(_literal())} | {draw(_literal())})",
                                            f"{draw(_literal())}, {draw(_literal())}"]))
            lines.append(f"{a} announces {content};")
        for ag in AGENTS:
            how = draw(st.sampled_from(["observes", "observes", "aware_of", "none"]))
            if how == "aware_of" and kind == "ontic":
                how = "observes"
            if how != "none":
                lines.append(f"{ag} {how} {a}{draw(_condition())};")
    actual = [draw(_literal(props=(p,))) for p in PROPS]
    lines.append(f"initially {', '.join(actual)};")
    sign = {p: not lit.startswith("-") for p, lit in zip(PROPS, actual, strict=True)}
    for p in PROPS:
        what = draw(st.sampled_from(["none", "known", "ag_knows", "corr", "corr"]))
        lit = actual[PROPS.index(p)]
        if what == "known":
            lines.append(f"initially C([a,b], {lit});")
        elif what == "ag_knows":
            ag = draw(st.sampled_from(AGENTS))
            lines.append(f"initially C([a,b], (B({ag},{p}) | B({ag},(-{p}))));")
        elif what == "corr" and p != "r":  # p and r correlated in everybody's view (true at the actual world)
            same = sign[p] == sign["r"]
            lines.append(f"initially C([a,b], (({p}, r) | (-{p}, -r)));" if same
                         else f"initially C([a,b], (({p}, -r) | (-{p}, r)));")
    goals = draw(st.lists(_goal(), min_size=1, max_size=3))
    lines += [f"goal {g};" for g in goals]
    return "\n".join(lines) + "\n"


def _distances(space, limit: int = 4000) -> tuple[list, dict, dict] | None:
    """All reachable states (None if more than ``limit``), their successor keys, exact goal distances."""
    s0, k0 = space.initial()
    states, succ = {k0: s0}, {}
    todo = deque([k0])
    while todo:
        k = todo.popleft()
        succ[k] = []
        for _, nxt, nk in space.successors(states[k]):
            succ[k].append(nk)
            if nk not in states:
                if len(states) >= limit:
                    return None
                states[nk] = nxt
                todo.append(nk)
    pred: dict = {k: [] for k in states}
    for k, ks in succ.items():
        for nk in ks:
            pred[nk].append(k)
    dist = {k: 0 for k, s in states.items() if space.is_goal(s)}
    todo = deque(dist)
    while todo:
        k = todo.popleft()
        for pk in pred[k]:
            if pk not in dist:
                dist[pk] = dist[k] + 1
                todo.append(pk)
    return list(states.items()), succ, dist


def _variant(task, kind: str):
    """The task itself, or with a macro of its first two actions, or with a general event-model action
    (a public announcement of the first fluent) — the heuristic must stay admissible with both."""
    import dataclasses

    from delkit.logic.formula import Prop
    from delkit.models.events import public_announcement
    from planners.task import EventAction, MacroSpec

    acts = tuple(task.actions)
    if kind == "macro":
        acts += (MacroSpec(f"{acts[0].name}+{acts[1].name}", (acts[0], acts[1])),)
    elif kind == "event":
        p = task.props[0]
        acts += (EventAction("shout", lambda bits: public_announcement(p, task.agents, name="shout"),
                             executable=Prop(p)),)
    return dataclasses.replace(task, actions=acts, _cache={})


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])
@given(mastar_tasks(), st.sampled_from(["plain", "plain", "macro", "event"]))
def test_h_epi_admissible_consistent_and_astar_optimal_on_random_tasks(text: str, kind: str) -> None:
    from delkit.errors import DelkitError

    try:
        task = _variant(parse_mastar(text, "random.txt"), kind)
        space = make_space(task)
        got = _distances(space)
    except DelkitError:
        return  # e.g. an initial statement the finitary-S5 construction cannot make true
    if got is None:
        return
    states, succ, dist = got
    h = h_epi(space)
    by_key = dict(states)
    for k, s in states:
        hv = h(s)
        d = dist.get(k, math.inf)
        assert hv <= d, (text, hv, d)                        # admissible (∞ only on dead ends)
        for nk in succ[k]:
            assert hv <= 1 + h(by_key[nk]) or hv == math.inf, text      # consistent
    a = plan(task, search="astar", limits=Limits(timeout=30))
    b = plan(task, search="bfs", limits=Limits(timeout=30))
    assert a.status == b.status and a.length == b.length, text


def test_content_argument_applies_to_grapevine_and_prunes() -> None:
    task = load_task(G5)
    space = make_space(task)
    s0, _ = space.initial()
    content = content_conjuncts(space)
    # B(a,sb), B(b,sc), B(c,sa), B(d,se), B(e,sd): five different announced secrets; -B(a,sc): only an
    # ontic change of sc could undo a's belief in it, and there is none
    assert {c[0] for c in content.values()} == {"pos", "neg"} and len(content) == 6
    assert h_epi(space)(s0) == 5.0 and h_cover(space)(s0) == 1.0
    after = space.step(s0, "share_c_sc_1")           # a hears sc: -B(a,sc) can never hold again
    assert h_epi(space)(after) == math.inf
    res = best_first(space, Limits(timeout=60), kind="astar")
    assert res.length == 6 and res.expanded <= 100
    assert check_plan(task, list(res.plan), []).valid


def test_content_argument_merges_correlated_blocks_and_refuses_epistemic_content() -> None:
    # announcing q can make a believe p when p and q are correlated in a's view: {p, q} is one block
    text = """fluent p, q, r; action tell, other; agent a, b;
    tell announces q; a observes tell;
    other announces r; a observes other;
    initially p, q, r; initially C([a,b], ((p, q) | (-p, -q)));
    goal B(a, p);"""
    task = parse_mastar(text, "corr.txt")
    space = make_space(task)
    assert content_conjuncts(space) == {0: ("pos", "a", frozenset({"p", "q"}))}
    assert plan(task, search="astar").length == 1
    # an effect with a condition joins the effect's and the condition's fluents
    task2 = parse_mastar("fluent p, q, r; action f; agent a; f causes p if q; a observes f; initially -p, q, r;"
                         "goal B(a, p);", "cond.txt")
    blocks = prop_blocks(task2)
    assert blocks["p"] == blocks["q"] == frozenset({"p", "q"}) and blocks["r"] == frozenset({"r"})
    # ... and so it must: after `f` (r := ⊤ where p) announcing r tells a that p
    task4 = parse_mastar("""fluent p, r; action f, t; agent a, b;
    f causes r if p; a observes f;
    executable t if r; t announces r; a observes t;
    initially p, -r; initially C([a,b], -r);
    goal B(a, p);""", "learn.txt")
    assert content_conjuncts(make_space(task4)) == {0: ("pos", "a", frozenset({"p", "r"}))}
    assert plan(task4, search="astar").length == 2 == plan(task4).length
    # an epistemic announcement: its truth at a world is not a function of the valuation -> no argument
    task3 = parse_mastar("fluent p, q; action t; agent a, b; executable t if B(b, q); t announces B(b, q);"
                         "a observes t; initially p, q; goal B(a, p);", "epi.txt")
    assert prop_blocks(task3) is None and set(content_conjuncts(make_space(task3))) == set()


def test_negative_belief_is_undone_only_by_an_observed_ontic_change() -> None:
    text = """fluent p, q; action flip, tell, peek; agent a, b;
    flip causes -p; a observes flip;
    tell announces q; a observes tell; b observes tell;
    peek causes -p; b observes peek;
    initially p, q; initially C([a,b], p);
    goal (-B(a, p)), B(b, q);"""
    task = parse_mastar(text, "neg.txt")
    space = make_space(task)
    s0, _ = space.initial()
    assert set(content_conjuncts(space)) == {0, 1}
    assert h_epi(space)(s0) == 2.0          # flip (the only action a observes that changes p) and tell
    assert plan(task, search="astar").length == 2 == plan(task).length


@pytest.mark.skipif(BENCH is None, reason="../shared/benchmarks is not available")
@pytest.mark.parametrize("name", ["Grapevine/Grapevine_4/Grapevine_4__pl_4.txt",
                                  "Grapevine/Grapevine_3/Grapevine_3__pl_4.txt"])
def test_astar_expands_a_fifth_of_bfs_on_grapevine(name: str) -> None:
    task = load_task(BENCH / "mastar" / name)
    b = bfs(make_space(task))
    a = best_first(make_space(task), kind="astar")
    assert a.length == b.length and a.expanded * 5 <= b.expanded


@pytest.mark.slow
def test_grapevine5_astar_matches_bfs() -> None:
    task = load_task(G5)
    assert plan(task, search="bfs", limits=Limits(timeout=1800)).length == 6 == plan(task, search="astar").length


def test_macros_and_event_actions_stay_admissible() -> None:
    base = parse_mastar("""fluent p, q; action tp, tq; agent a, b;
    tp announces p; a observes tp;
    tq announces q; b observes tq;
    initially p, q; initially C([a,b], (B(a,q) | B(a,-q))); initially C([a,b], (B(b,p) | B(b,(-p))));
    goal B(a, p), B(b, q);""", "two.txt")
    s0 = make_space(base).initial()[0]
    assert h_epi(make_space(base))(s0) == 2.0 == plan(base).length
    macro = _variant(base, "macro")              # tp+tq does both in one step
    assert h_epi(make_space(macro))(make_space(macro).initial()[0]) <= 1.0
    assert plan(macro, search="astar").length == 1 == plan(macro).length
    only_event = parse_mastar("""fluent p, q; action tq; agent a, b;
    tq announces q; b observes tq;
    initially p, q; goal B(a, p);""", "ev.txt")
    ev = _variant(only_event, "event")           # only the general event-model action informs a
    space = make_space(ev)
    assert content_conjuncts(space) == {} and h_epi(space)(space.initial()[0]) == 1.0
    assert plan(ev, search="astar").length == 1 == plan(ev).length


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])
@given(mastar_tasks(), st.sampled_from(["plain", "plain", "plain", "macro", "event"]),
       st.sampled_from(["fast", "del"]))
@example(text="fluent p, q, r;\naction x0, x1, x2;\nagent a, b;\nx0 announces p;\nx1 causes p;\n"
              "a observes x1 if B(a,p);\nb observes x1;\nx2 determines p;\na observes x2;\n"
              "initially -p, q, r;\ngoal B(a,q);\n", kind="event", engine="fast")  # found by hypothesis
def test_h_chain_admissible_consistent_dominates_h_epi_and_astar_optimal(text: str, kind: str, engine: str) -> None:
    from delkit.errors import DelkitError
    from planners.heuristics import h_chain

    try:
        task = _variant(parse_mastar(text, "random.txt"), kind)
        space = make_space(task, engine=engine)
        got = _distances(space, limit=1500)
    except DelkitError:
        return
    if got is None:
        return
    states, succ, dist = got
    h, h0 = h_chain(space), h_epi(space)
    by_key = dict(states)
    for k, s in states:
        hv = h(s)
        assert h0(s) <= hv <= dist.get(k, math.inf), (text, hv, dist.get(k))   # admissible, ≥ h_epi
        for nk in succ[k]:
            assert hv <= 1 + h(by_key[nk]) or hv == math.inf, text               # consistent
    fresh = make_space(task, engine=engine)
    a = best_first(fresh, Limits(timeout=30), kind="astar", h=h_chain(fresh))
    # BFS in the same semantics as the A* space (plan()'s default keeps states where an agent believes ⊥ for
    # event-model tasks, where B_a φ can then hold vacuously: a different task, found by hypothesis)
    b = plan(task, search="bfs", limits=Limits(timeout=30), engine=engine, allow_inconsistent=fresh.allow_inconsistent,
             consistent_beliefs=not fresh.allow_inconsistent)
    assert a.status == b.status and a.length == b.length, text


@pytest.mark.skipif(BENCH is None, reason="../shared/benchmarks is not available")
def test_h_chain_sees_the_executability_chain() -> None:
    from planners.heuristics import h_chain

    # open_a needs has_key_a, which only peek_up_key_a... gives: h_epi 1, the chain 2 = the optimum
    space = make_space(load_task(BENCH / "mastar" / "CB_simple" / "CB_simple__pl_2.txt"))
    s0, _ = space.initial()
    assert (h_epi(space)(s0), h_chain(space)(s0)) == (1.0, 2.0)


@pytest.mark.skipif(BENCH is None, reason="../shared/benchmarks is not available")
@pytest.mark.parametrize("name", ["Grapevine_3/Grapevine_3__pl_4.txt", "Grapevine_4/Grapevine_4__pl_4.txt",
                                  "Grapevine_4/Grapevine_4__pl_3.txt"])
def test_bfs_dead_end_pruning_keeps_the_plan(name: str) -> None:
    from planners.heuristics import dead_end_test

    task = load_task(BENCH / "mastar" / "Grapevine" / name)
    a = bfs(make_space(task), Limits(timeout=60))
    b = bfs(make_space(task), Limits(timeout=60), prune=False)
    assert a.plan == b.plan and a.status == b.status == "solved"
    assert a.expanded < b.expanded and a.dead_ends > b.dead_ends     # it prunes here
    space = make_space(task)
    test = dead_end_test(space)
    assert test is not None and not test(space.initial()[0])


@pytest.mark.slow
@pytest.mark.parametrize("name", ["cc_2_4_4/CC_2_4_4_s3__pl_7.txt", "cc_2_4_4_hard/CC_2_4_4_ATCM_s12__pl_7.txt"])
def test_cc_2_4_4_length_7_by_astar(name: str) -> None:
    res = plan(load_task(SPECS / name), search="astar", limits=Limits(timeout=900))
    assert res.length == 7


def test_cc_generator_reproduces_its_instances() -> None:
    import importlib.util

    path = ROOT / "bench" / "cc_tasks.py"
    spec = importlib.util.spec_from_file_location("cc_tasks", path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)  # type: ignore[union-attr]
    for seed in (3, 5):
        want = (SPECS / "cc_2_4_4" / f"CC_2_4_4_s{seed}__pl_7.txt").read_text()
        assert mod.draw(2, 4, 4, 3, seed) == want
    hard = {"absent": True, "tell": "room", "check": "room", "moves": "room"}
    for seed in (6, 12):
        want = (SPECS / "cc_2_4_4_hard" / f"CC_2_4_4{mod.hard_name(hard)}_s{seed}__pl_7.txt").read_text()
        assert mod.draw(2, 4, 4, 3, seed, **hard) == want
    small = parse_mastar(mod.draw(2, 2, 2, 2, 1), "cc.txt")
    assert plan(small, search="astar").length == plan(small, search="bfs").length == 2


@settings(max_examples=200, deadline=None, suppress_health_check=[HealthCheck.too_slow, HealthCheck.filter_too_much])
@given(mastar_tasks(), st.sampled_from(["plain", "plain", "plain", "macro", "event"]), st.sampled_from(["elim", "pdb"]))
def test_h_elim_and_h_pdb_admissible_consistent_dominate_h_chain_and_astar_optimal(text: str, kind: str,
                                                                                    name: str) -> None:
    from delkit.errors import DelkitError
    from planners.heuristics import h_chain, make_heuristic, transparent_props

    try:
        task = _variant(parse_mastar(text, "random.txt"), kind)
        space = make_space(task)
        got = _distances(space, limit=1500)
    except DelkitError:
        return
    if got is None:
        return
    states, succ, dist = got
    h, h0 = make_heuristic(name, space), h_chain(space)
    trans = transparent_props(space)
    pidx = {p: i for i, p in enumerate(task.props)}
    by_key = dict(states)
    for k, s in states:
        for ai, x in enumerate(task.agents):   # x's view agrees with the pointed world on its transparent fluents
            view = [s.val[w] for w in range(len(s.val)) if s.masks[ai][s.point] >> w & 1]
            assert all(not (v ^ s.val[s.point]) >> pidx[p] & 1 for p in trans[x] for v in view), (text, x)
        hv = h(s)
        assert h0(s) <= hv <= dist.get(k, math.inf), (text, hv, dist.get(k))   # admissible, ≥ h_chain
        for nk in succ[k]:
            assert hv <= 1 + h(by_key[nk]) or hv == math.inf, text               # consistent
    fresh = make_space(task)
    a = best_first(fresh, Limits(timeout=30), kind="astar", h=make_heuristic(name, fresh))
    b = plan(task, search="bfs", limits=Limits(timeout=30), allow_inconsistent=fresh.allow_inconsistent,
             consistent_beliefs=not fresh.allow_inconsistent)
    assert a.status == b.status and a.length == b.length, text


def _cc_module():
    import importlib.util

    spec = importlib.util.spec_from_file_location("cc_tasks", ROOT / "bench" / "cc_tasks.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)  # type: ignore[union-attr]
    return mod


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.integers(2, 3), st.integers(1, 2), st.integers(0, 10_000), st.booleans(),
       st.sampled_from(["public", "room"]), st.sampled_from(["private", "room"]), st.sampled_from(["elim", "pdb"]))
def test_h_elim_and_h_pdb_exact_distances_on_small_cc_tasks(rooms: int, boxes: int, seed: int, absent: bool,
                                                             tell: str, check: str, name: str) -> None:
    """Collaboration-and-Communication tasks (where tells, checks and moves chain): admissible and consistent
    against exact goal distances, and stronger than h_chain somewhere."""
    from planners.heuristics import h_chain, make_heuristic

    text = _cc_module().draw(2, rooms, boxes, min(2, 2 * boxes), seed, absent=absent, tell=tell, check=check)
    space = make_space(parse_mastar(text, "cc.txt"))
    got = _distances(space, limit=1200)
    if got is None:
        return
    states, succ, dist = got
    h, h0 = make_heuristic(name, space), h_chain(space)
    by_key = dict(states)
    for k, s in states:
        hv = h(s)
        assert h0(s) <= hv <= dist.get(k, math.inf), (text, hv, dist.get(k))
        for nk in succ[k]:
            assert hv <= 1 + h(by_key[nk]) or hv == math.inf, text


def test_h_pdb_is_stronger_on_cc() -> None:
    from planners.heuristics import h_chain, h_elim, h_pdb

    text = _cc_module().draw(2, 3, 1, 1, 3, absent=True)
    space = make_space(parse_mastar(text, "cc.txt"))
    states, _succ, dist = _distances(space, limit=3000)
    hs = [h_chain(space), h_elim(space), h_pdb(space)]
    sums = [sum(min(h(s), 99) for _, s in states) for h in hs]
    assert sums[0] < sums[1] < sums[2], sums
