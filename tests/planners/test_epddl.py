"""E-PDDL reader: grounding, observers, twins with mA*, the project's own specs, error positions."""

from __future__ import annotations

from pathlib import Path

import pytest

from delkit.errors import ParseError
from delkit.logic.formula import TOP, parse
from planners.demo import specs_dir
from planners.epistemic import plan
from planners.lang import load_task, shared_benchmarks
from planners.lang.epddl import parse_epddl
from planners.lang.mastar import load_mastar
from planners.validate import check_plan, parse_property, read_plan

SPECS = specs_dir()
BENCH = shared_benchmarks()


def test_grounding_names_and_observers() -> None:
    t = load_task(SPECS / "coin_in_the_box" / "domain.epddl", SPECS / "coin_in_the_box" / "problem.epddl")
    assert {"open_a", "peek_b", "signal_a_c", "shout_tail_c"} <= {a.name for a in t.actions}
    peek = t.action("peek_b")
    assert peek.kind == "sensing"
    assert dict(peek.full) == {"b": TOP}
    # forall (diff (?o) (?ag)) (when (looking ?o) (?o)): the other agents, if looking
    assert dict(peek.partial) == {"a": parse("looking_a"), "c": parse("looking_c")}
    assert t.action("open_a").executable == parse("K_a has_key_a & has_key_a")
    assert t.initial.holds(parse("C{a,b,c} (has_key_a & ~opened & looking_a & ~looking_b)"))


@pytest.mark.parametrize("problem, mastar", [("problem", "Coin_in_the_Box__pl_3.txt"),
                                             ("common", "Coin_in_the_Box__pl_5.txt")])
def test_own_coin_spec_matches_mastar_benchmark(problem: str, mastar: str) -> None:
    if BENCH is None:
        pytest.skip("../shared/benchmarks is not available")
    ours = load_task(SPECS / "coin_in_the_box" / "domain.epddl", SPECS / "coin_in_the_box" / f"{problem}.epddl")
    twin = load_mastar(BENCH / "mastar" / "Coin_In_The_Box" / mastar)
    a, b = plan(ours), plan(twin)
    assert a.solved and b.solved and a.length == b.length
    assert check_plan(twin, list(a.plan)).valid  # the same grounded action names
    assert check_plan(ours, list(b.plan)).valid


def test_epddl_benchmark_and_its_mastar_twin() -> None:
    if BENCH is None:
        pytest.skip("../shared/benchmarks is not available")
    d = BENCH / "epddl" / "coin_in_the_box"
    e = load_task(d / "coininthebox.epddl", d / "pb1.epddl")
    m = load_task(SPECS / "coin_in_the_box" / "pb1_twin.txt")
    assert set(e.props) == set(m.props) and {a.name for a in e.actions} == {a.name for a in m.actions}
    a, b = plan(e), plan(m)
    assert a.solved and a.length == b.length == 2
    assert check_plan(m, list(a.plan)).valid and check_plan(e, list(b.plan)).valid


# the hand-written specs: a folder with domain.epddl, problems with .plan and .props beside them (the generated
# instances of specs/frontier carry their own domains and are checked by tests/planners/test_frontier_search.py)
SPEC_PROBLEMS = sorted(p for p in SPECS.glob("*/*.epddl")
                       if p.name != "domain.epddl" and (p.parent / "domain.epddl").is_file())


@pytest.mark.parametrize("problem", SPEC_PROBLEMS, ids=[f"{p.parent.name}/{p.stem}" for p in SPEC_PROBLEMS])
def test_own_specs_plan_and_check(problem: Path) -> None:
    """Each spec's plan file is optimal (BFS agrees on its length) and satisfies its properties."""
    task = load_task(problem.parent / "domain.epddl", problem)
    steps = read_plan(problem.with_suffix(".plan"))
    props = [parse_property(ln, task) for ln in problem.with_suffix(".props").read_text().splitlines()
             if ln.strip() and not ln.startswith("#")]
    assert props
    res = check_plan(task, steps, props)
    assert res.valid, res.reason
    found = plan(task)
    assert found.length == len(steps)
    assert check_plan(task, list(found.plan)).valid
    assert not check_plan(task, steps[:-1]).valid


def test_all_four_domains_present() -> None:
    assert {p.parent.name for p in SPEC_PROBLEMS} >= {"coin_in_the_box", "grapevine", "selective_communication",
                                                      "collaboration_communication"}


DOM = """(define (domain d)
  (:predicates (p) (q ?ag - agent))
  (:action act :act_type ontic :parameters (?ag - agent)
    :precondition ([?ag](p)) :effect (q ?ag) :observers (?ag)))"""
PROB = """(define (problem x) (:domain d) (:agents a b)
  (:init (p) ([a b](p)))
  (:goal ([a](q a))))"""


def test_small_domain_plans() -> None:
    t = parse_epddl(DOM, PROB)
    assert plan(t).plan == ("act_a",)


@pytest.mark.parametrize("dom, prob, line, needle", [
    (DOM.replace("(q ?ag)", "(r ?ag)"), PROB, 4, "unknown predicate 'r'"),
    (DOM, PROB.replace("(:goal ([a](q a)))", "(:goal ([z](q a)))"), 3, "not an agent"),
    (DOM.replace(":act_type ontic", ":act_type magic"), PROB, 3, "unknown :act_type"),
    (DOM + ")", PROB, 4, "unbalanced"),
])
def test_errors_have_positions(dom: str, prob: str, line: int, needle: str) -> None:
    with pytest.raises(ParseError) as ei:
        parse_epddl(dom, prob, domain_source="d.epddl", problem_source="p.epddl")
    assert ei.value.line == line and needle in str(ei.value)
    assert ei.value.column is not None and ei.value.source in ("d.epddl", "p.epddl")
