"""The plan checker's numpy-free replay (planners.replay) gives the numpy checker's answers: the whole
CheckResult (verdict, step, kind, reason with its worlds, agent, EPDDL's kept inconsistent beliefs) is equal
on every shared instance the checker's tests use — the mA* benchmark set with EFP's plans, the EPDDL (2026)
instances the planner tests plan, the E-PDDL spec — for their plans, broken variants of them and
properties with K, Kw, E, C and D (the groups' relations)."""

from __future__ import annotations

import csv
import itertools

import pytest

import planners.validate as V
from planners.demo import specs_dir
from planners.epistemic import Limits, bfs
from planners.lang import load_task, shared_benchmarks
from planners.lang.epddl_run import space_for
from planners.validate import check_plan, parse_plan_text, parse_property, read_plan

BENCH = shared_benchmarks()
COIN = specs_dir() / "coin_in_the_box"


def _agent(a: str) -> str:
    return f"{{{a}}}"


def _properties(task) -> list:
    """Properties over the task's first agents and fluents: each operator, some true, some false."""
    ags, ps = list(task.agents), list(task.props)
    a, b, p, q = ags[0], ags[min(1, len(ags) - 1)], ps[0], ps[min(1, len(ps) - 1)]
    g = ",".join(dict.fromkeys((a, b)))
    texts = [f"eventually {task.goal}", f"always ~K{_agent(a)} {p}", f"at end Kw{_agent(b)} {q}",
             f"always (E{{{g}}} {p} -> {p})", f"eventually C{{{g}}} ({p} | {q})", f"always ~D{{{g}}} {q}",
             f"at end M{_agent(a)} ~{p}"]
    return [parse_property(t, task) for t in texts]


def _variants(task, plan: list[str]) -> list[list[str]]:
    names = [x.name for x in task.actions]
    return [plan, plan[:-1], plan[1:], plan[::-1], names[:1] + plan, plan + names[-1:], []]


def _both(task, plan, props, monkeypatch, stats):
    ran = []
    real = V._check

    def spy(*args):
        out = real(*args)
        ran.append(args[-1])
        return out

    monkeypatch.setattr(V, "_check", spy)
    plain = check_plan(task, plan, props).to_json()
    stats["plain"] += ran == [True]
    monkeypatch.setattr(V, "plain_usable", lambda *a: False)
    ref = check_plan(task, plan, props).to_json()
    monkeypatch.undo()
    return plain, ref


def _compare(task, plan, monkeypatch) -> dict:
    stats = {"plain": 0, "runs": 0, "invalid": 0}
    props = _properties(task)
    for variant, pr in itertools.product(_variants(task, plan), [[], props, props[1:3], props[3:]]):
        plain, ref = _both(task, variant, pr, monkeypatch, stats)
        assert plain == ref, (variant, [str(x) for x in pr])
        stats["runs"] += 1
        stats["invalid"] += not ref["valid"]
    return stats


MASTAR = list(csv.DictReader((BENCH / "mastar" / "expected.csv").open())) if BENCH else []


@pytest.mark.skipif(BENCH is None, reason="../shared/benchmarks is not available")
def test_plain_replay_answers_as_numpy_on_mastar(monkeypatch) -> None:
    plain = runs = invalid = 0
    for row in MASTAR:
        task = load_task(BENCH / "mastar" / row["file"])
        st = _compare(task, parse_plan_text(row["efp_plan"]), monkeypatch)
        plain, runs, invalid = plain + st["plain"], runs + st["runs"], invalid + st["invalid"]
    assert len(MASTAR) >= 30 and invalid > runs // 4
    assert plain > runs * 3 // 4  # most of them ran without numpy (the rest grew past _CONTRACT_ABOVE worlds)


EPDDL = ["Coin-in-the-Box/instances/problem_2", "Consecutive-Numbers/instances/cn5", "Gossip", "ncn-1",
         "Active-Muddy-Child"]


@pytest.mark.skipif(BENCH is None, reason="../shared/benchmarks is not available")
@pytest.mark.parametrize("part", EPDDL)
def test_plain_replay_answers_as_numpy_on_epddl2026(part: str, monkeypatch) -> None:
    root = BENCH / "epddl2026"
    row = next(r for r in csv.DictReader((root / "expected.csv").open()) if part in r["problem"])
    task = load_task(root / row["domain"], root / row["problem"], [root / row["libraries"]] if row["libraries"] else [])
    res = bfs(space_for(task), Limits(timeout=60))
    assert res.status in ("solved", "unsolvable")
    plan = list(res.plan) if res.solved else [a.name for a in task.actions[:3]]  # unsolvable: some actions
    st = _compare(task, plan, monkeypatch)
    # explicit initial worlds with the user's names come as a numpy model: numpy replays those
    assert (st["plain"] > 0) == (task.plain_initial is not None)


def test_plain_replay_answers_as_numpy_on_the_epddl_spec(monkeypatch) -> None:
    for prob in ("problem", "common"):
        task = load_task(COIN / "domain.epddl", COIN / f"{prob}.epddl")
        props = [parse_property(ln.strip(), task) for ln in (COIN / f"{prob}.props").read_text().splitlines()
                 if ln.strip() and not ln.startswith("#")]
        stats = {"plain": 0}
        plan = read_plan(COIN / f"{prob}.plan")
        for variant in _variants(task, plan):
            plain, ref = _both(task, variant, props, monkeypatch, stats)
            assert plain == ref
        assert stats["plain"] == 7
        _compare(task, plan, monkeypatch)


def test_plain_replay_falls_back_to_numpy_past_the_contraction_size(monkeypatch) -> None:
    """A state past _CONTRACT_ABOVE worlds: the plain replay gives up and numpy (contracting) answers."""
    task = load_task(COIN / "domain.epddl", COIN / "problem.epddl")
    plan = read_plan(COIN / "problem.plan")
    monkeypatch.setattr(V, "_CONTRACT_ABOVE", 1)
    ran = []
    real = V._check
    monkeypatch.setattr(V, "_check", lambda *a: (ran.append(a[-1]), real(*a))[1])
    assert check_plan(task, plan).valid
    assert ran == [False]  # the initial state has more than one world: numpy from the start
    monkeypatch.setattr(V, "_CONTRACT_ABOVE", task.plain_initial.n_worlds)  # the first update grows past it
    ran.clear()
    res = check_plan(task, plan)
    assert res.valid and ran == [True, False]
