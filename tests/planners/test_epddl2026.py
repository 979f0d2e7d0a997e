"""EPDDL (2026): plank's benchmark suite (../shared/benchmarks/epddl2026) is read, grounded and planned by BFS
with the lengths of expected.csv, every plan is validated by an independent replay, and errors name the file,
line and construct. The whole suite is slow (generic engine); a few instances run in the fast suite."""

from __future__ import annotations

import csv
import json
import re
import time

import pytest

from delkit.cli import main
from delkit.errors import ParseError
from planners.epistemic import Limits, bfs
from planners.lang import load_task, shared_benchmarks
from planners.lang.epddl2026 import LoadTimeout, load_epddl2026
from planners.lang.epddl_run import space_for
from planners.task import EventAction
from planners.validate import check_plan

BENCH = shared_benchmarks()
if BENCH is None:
    pytest.skip("../shared/benchmarks is not available", allow_module_level=True)
ROOT = BENCH / "epddl2026"
ROWS = list(csv.DictReader((ROOT / "expected.csv").open()))


def _row(part: str) -> dict:
    return next(r for r in ROWS if part in r["problem"])


def _files(row: dict) -> tuple:
    return ROOT / row["domain"], ROOT / row["problem"], [ROOT / row["libraries"]] if row["libraries"] else []


def _expect(row: dict, length: int | None) -> None:
    """``length`` against ``shortest_known``: exact, a range ``a-b``, ``none <= k`` (no plan) or unknown."""
    known = row["shortest_known"].strip()
    if re.fullmatch(r"\d+", known):
        assert length == int(known)
    elif re.fullmatch(r"\d+-\d+", known):
        lo, hi = map(int, known.split("-"))
        assert length is not None and lo <= length <= hi
    elif known.startswith("none"):
        assert length is None or length > int(known.split("<=")[1])


def _plan_and_check(row: dict, timeout: float = 60.0):
    dom, prob, libs = _files(row)
    t0 = time.monotonic()
    task = load_epddl2026(dom, prob, libs, deadline=t0 + timeout)
    res = bfs(space_for(task), Limits(timeout=max(0.0, timeout - (time.monotonic() - t0))))
    assert res.status in ("solved", "unsolvable"), res.reason
    if res.solved:
        chk = check_plan(task, list(res.plan))   # EPDDL mode: the task has event-model actions
        assert chk.valid, chk.reason
    return task, res


FAST = ["Coin-in-the-Box/instances/problem_2", "Consecutive-Numbers/instances/cn5", "Gossip", "ncn-1",
        "Active-Muddy-Child"]


@pytest.mark.parametrize("part", FAST)
def test_fast_instances_planned_with_expected_length(part: str) -> None:
    row = _row(part)
    _task, res = _plan_and_check(row)
    _expect(row, res.length)
    if part == "Gossip":
        assert res.status == "unsolvable"   # plank's BFS exhausts the state space too


def _slow_rows():
    # Selective-Communication included: BFS needs 53,694 expansions (length 7, optimal), ~14 s CPU
    for r in ROWS:
        yield pytest.param(r, id=r["problem"].split("domains/")[1])


@pytest.mark.slow
@pytest.mark.parametrize("row", list(_slow_rows()))
def test_every_problem_planned_within_60s(row: dict) -> None:
    _task, res = _plan_and_check(row, 60.0)
    _expect(row, res.length)


def test_selective_communication_plan_of_length_7_is_valid(tmp_path) -> None:
    """The optimal plan BFS finds (exhaustively: no plan of length <= 6) is valid; the file's Solution block
    is not (its last step leaves D and E ignorant)."""
    task = load_epddl2026(*_files(_row("Selective-Communication")))
    plan = ["left_D", "left_E", "right_A", "right_A", "left_E", "sense_E", "tell_E"]
    ok = check_plan(task, plan)
    assert ok.valid, ok.reason
    bad = check_plan(task, ["right_A", "left_C", "sense_C", "tell_C"])
    assert not bad.valid and bad.kind == "goal"
    # the explicit initial state gives B no relation (B believes ⊥): EPDDL (and plank) accept such states,
    # mA*'s semantics would refuse the first step
    assert task.initial.inconsistent_agents()
    dl = check_plan(task, plan, epddl=False)
    assert not dl.valid and dl.kind == "inconsistent-belief" and dl.step == 1 and dl.agent == "B"


def test_every_problem_grounds() -> None:
    for row in ROWS:
        task = load_epddl2026(*_files(row))
        assert task.actions and all(isinstance(a, EventAction) for a in task.actions)


def test_ncn_initial_state_without_enumerating_valuations() -> None:
    """33 fluents: plank enumerates 2^33 valuations; the worlds are the 9 consecutive triples."""
    task = load_epddl2026(*_files(_row("ncn-1")))
    assert len(task.props) == 33 and task.initial.n_worlds == 9 and len(task.initial.designated) == 1
    for w in range(9):  # every world: each agent has exactly one number, the three are consecutive
        nums = sorted(int(p.rsplit("_n", 1)[1]) for p in task.initial.true_props(w))
        assert len(nums) == 3 and nums == list(range(nums[0], nums[0] + 3))


def test_tiger_parameterless_actions_grounded_and_plank_semantics() -> None:
    """left/right (``:parameters ()``) are grounded; the unconstrained at-knight fluents of rooms 2-5 make
    20 × 2^10 worlds and 2^10 designated ones, and the knight can never move (some designated world has him
    in room 5 and room 1), so BFS proves the problem unsolvable."""
    row = _row("Tiger")
    task = load_epddl2026(*_files(row))
    names = {a.name for a in task.actions}
    assert {"left", "right"} <= names
    assert task.initial.n_worlds == 20 * 2 ** 10 and len(task.initial.designated) == 2 ** 10
    _task, res = _plan_and_check(row)
    assert res.status == "unsolvable"


def test_cn5_is_multi_pointed() -> None:
    task = load_epddl2026(*_files(_row("cn5")))
    assert len(task.initial.designated) == 2  # B has 4, A has 3 or 5


def test_selective_communication_keeps_its_k_frame() -> None:
    """SC's explicit state lists A twice and B never: B's relation is empty (plank's reading), not S5."""
    task = load_epddl2026(*_files(_row("Selective-Communication")))
    m = task.initial
    assert m.n_worlds == 2 and not m.relations["B"].has_successor().any()
    assert m.relations["A"].is_reflexive() and not m.is_s5()


def _cli(capsys, argv):
    rc = main([str(a) for a in argv])
    out = capsys.readouterr()
    return rc, out.out, out.err


def test_check_cli_valid_invalid_and_empty_plan(capsys, tmp_path) -> None:
    dom, prob, libs = _files(_row("Coin-in-the-Box/instances/problem_1"))
    lib = ["--library", libs[0]]
    good, bad, empty = tmp_path / "good.plan", tmp_path / "bad.plan", tmp_path / "empty.plan"
    good.write_text("open_A\npeek_A\n")
    bad.write_text("open_A\nsignal_B_A\npeek_A\n")
    empty.write_text("")
    rc, out, _ = _cli(capsys, ["check", dom, prob, good, *lib])
    assert rc == 0 and out.startswith("valid")
    rc, out, _ = _cli(capsys, ["check", dom, prob, bad, *lib, "--json"])
    data = json.loads(out)
    assert rc == 1 and data["step"] == 2 and data["kind"] == "not-applicable" and "looking_B" in data["reason"]
    rc, out, _ = _cli(capsys, ["check", dom, prob, empty, *lib])
    assert rc == 1 and "initial state" in out and "K_A tails" in out
    rc, _, err = _cli(capsys, ["check", dom, prob, tmp_path / "nope.plan", *lib])
    assert rc == 2 and "nope.plan" in err
    # temporal properties over the EPDDL task's ground fluents (one checker for every dialect)
    rc, out, _ = _cli(capsys, ["check", dom, prob, good, *lib, "-p", "eventually opened", "-p", "at end K_A tails"])
    assert rc == 0 and "2 properties hold" in out
    rc, out, _ = _cli(capsys, ["check", dom, prob, good, *lib, "-p", "always ~opened", "--json"])
    data = json.loads(out)
    assert rc == 1 and data["kind"] == "property" and data["step"] == 1


def test_plan_cli_epddl(capsys) -> None:
    dom, prob, libs = _files(_row("Coin-in-the-Box/instances/problem_2"))
    rc, out, _ = _cli(capsys, ["plan", dom, prob, "--library", libs[0], "--json"])
    data = json.loads(out)
    assert rc == 0 and data["length"] == 4


def test_library_found_next_to_domain_and_grapevine_needs_it(capsys) -> None:
    row = _row("Grapevine")
    dom, prob, libs = _files(row)
    with pytest.raises(ParseError, match=r"gra\.epddl:\d+: .*unknown action type 'public-ontic'.*--library"):
        load_task(dom, prob)
    assert load_task(dom, prob, libs).actions
    # the Coin-in-the-Box domain declares `intermediate`: found in ../../libraries without --library
    dom, prob, _ = _files(_row("Coin-in-the-Box/instances/problem_1"))
    assert load_task(dom, prob).actions


def test_errors_name_file_line_and_construct(tmp_path) -> None:
    dom = tmp_path / "d.epddl"
    prob = tmp_path / "p.epddl"
    prob.write_text("(define (problem p) (:domain d) (:agents a)\n (:init (:and (q)))\n (:goal (q)))")
    dom.write_text("(define (domain d)\n (:predicates (q))\n (:derived (q) (q)))")
    with pytest.raises(ParseError, match=r"d\.epddl:3: unsupported domain section :derived"):
        load_epddl2026(dom, prob)
    dom.write_text("(define (domain d)\n (:predicates (q))\n (:event e :precondition (r)))\n")
    dom.write_text("(define (domain d)\n (:predicates (q))\n (:event e :precondition (r))\n"
                   " (:action act :action-type (basic (e))))")
    with pytest.raises(ParseError, match=r"d\.epddl:3: unknown predicate 'r'"):
        load_epddl2026(dom, prob)
    prob.write_text("(define (problem p) (:domain d) (:agents a)\n (:init (:and ([C. All] (and (q) (not (q))))))"
                    "\n (:goal (q)))")
    dom.write_text("(define (domain d)\n (:predicates (q))\n (:event e)\n (:action act :action-type (basic (e))))")
    with pytest.raises(ParseError, match=r"p\.epddl:2: no world satisfies the initial common knowledge"):
        load_epddl2026(dom, prob)


def test_deadline_is_honoured_while_grounding() -> None:
    with pytest.raises(LoadTimeout):
        load_epddl2026(*_files(_row("Blocks-World")), deadline=time.monotonic() - 1.0)


def test_unknown_requirement_is_refused_with_its_line(tmp_path) -> None:
    dom, prob = tmp_path / "d.epddl", tmp_path / "p.epddl"
    dom.write_text("(define (domain d)\n (:requirements :typing\n   :negative-precondition)\n (:predicates (q))\n"
                   " (:event e) (:action act :action-type (basic (e))))")
    prob.write_text("(define (problem p) (:domain d) (:agents a) (:init (:and (q))) (:goal (q)))")
    with pytest.raises(ParseError, match=r"d\.epddl:3: unknown requirement ':negative-precondition'"):
        load_epddl2026(dom, prob)


def test_deadline_is_honoured_inside_one_big_quantifier(tmp_path) -> None:
    """One action whose precondition quantifies over 60^3 bindings (seconds of grounding): the limit must be
    checked inside the quantifier's enumeration, not only between actions."""
    objs = " ".join(f"o{i}" for i in range(60))
    (tmp_path / "d.epddl").write_text(
        "(define (domain big) (:requirements :typing :facts)\n (:types obj)\n"
        " (:predicates (p) (:fact f ?x ?y ?z - obj))\n"
        " (:event e :precondition (forall (?u ?v ?w - obj) (not (f ?u ?v ?w))) :effects (p))\n"
        " (:action go :parameters () :action-type (basic (e))))")
    (tmp_path / "p.epddl").write_text(f"(define (problem big1) (:domain big) (:agents a) (:objects {objs} - obj)\n"
                                      " (:init (:and (not (p)))) (:goal (p)))")
    t0 = time.monotonic()
    with pytest.raises(LoadTimeout):
        load_epddl2026(tmp_path / "d.epddl", tmp_path / "p.epddl", deadline=t0 + 0.05)
