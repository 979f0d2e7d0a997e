"""Novelty search, the ``--search auto`` portfolio, the semantics of inconsistent beliefs, and the generated
frontier families: plans validate, optimal lengths agree across searches, limits hold, vacuous goals are
flagged and ``--consistent-beliefs`` prunes."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from delkit.errors import PlanningError
from planners.epistemic import Limits, plan, portfolio
from planners.generators.frontier import generate
from planners.lang import load_task
from planners.spaces import make_space
from planners.validate import check_plan


def _task(tmp_path: Path, family: str, *size: int):
    inst = generate(family, *size)
    d, p, lib = inst.write(tmp_path / inst.name)
    return inst, load_task(d, p, [lib])


# a belief goal that one step makes hold only vacuously: b has no accessible world once e happens (a's view
# of the event keeps b's edge to nothing: b is related to no event)
_VAC_DOMAIN = ("(define (domain vac) (:predicates (p)) (:event e :effects (p))"
               " (:action act :action-type (basic (e))))")
_VAC_PROBLEM = ("(define (problem v) (:domain vac) (:agents a b)\n (:init :worlds (w1)\n"
                " :relations (a (:and (w1 w1)))\n :labels (w1 (:and))\n :designated (w1))\n"
                " (:goal (and (p) ([b] (not (p))))))")


def _vac_task(tmp_path: Path):
    from planners.lang.epddl2026 import load_epddl2026

    d, p = tmp_path / "d.epddl", tmp_path / "p.epddl"
    d.write_text(_VAC_DOMAIN)
    p.write_text(_VAC_PROBLEM)
    return d, p, load_epddl2026(d, p)


FAMILY_SMALL = [("spy-linear", 3, 1), ("spy-sensing", 2, 1), ("hotel-distributed", 2), ("ugv-coordination", 3, 1),
                ("ugv-coordination", 2, 2)]


@pytest.mark.parametrize("family_size", FAMILY_SMALL, ids=lambda fs: "-".join(map(str, fs)))
def test_generated_known_plan_validates_and_bfs_finds_the_stated_optimum(tmp_path, family_size) -> None:
    """Each family's known plan is valid, reaches the goal non-vacuously, and BFS's optimum is the stated one."""
    inst, task = _task(tmp_path, *family_size)
    verdict = check_plan(task, list(inst.plan))
    assert verdict.valid, verdict.reason
    assert not verdict.inconsistent_beliefs
    assert len(inst.plan) >= inst.optimum
    res = plan(task, search="bfs", limits=Limits(timeout=60))
    assert res.solved and res.length == inst.optimum
    assert res.vacuous == ()


@pytest.mark.parametrize("family_size", FAMILY_SMALL[:4], ids=lambda fs: "-".join(map(str, fs)))
def test_every_search_validates_and_optimal_ones_agree_on_generated_tasks(tmp_path, family_size) -> None:
    """Differential: novelty, GBFS and the portfolio find valid plans; BFS, A* and the portfolio's proven
    optimum have the same length (one semantics: the reference one)."""
    inst, task = _task(tmp_path, *family_size)
    lengths = {}
    for search in ("bfs", "astar", "gbfs", "novelty", "auto"):
        res = plan(task, search=search, limits=Limits(timeout=60))
        assert res.solved, (search, res.reason)
        assert check_plan(task, list(res.plan)).valid, search
        assert res.semantics == "reference"
        lengths[search] = res.length
    assert lengths["bfs"] == lengths["astar"] == lengths["auto"] == inst.optimum
    assert min(lengths["gbfs"], lengths["novelty"]) >= inst.optimum


@settings(max_examples=8, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(family=st.sampled_from(["spy-linear", "spy-sensing"]), chain=st.integers(1, 3), decoys=st.integers(0, 2),
       consistent=st.booleans())
def test_novelty_plans_validate_and_optimal_lengths_agree_in_both_semantics(tmp_path, family, chain, decoys,
                                                                           consistent) -> None:
    """Property: on random spy instances, in either semantics, the novelty plan validates and BFS and the
    portfolio give the same optimal length."""
    inst = generate(family, chain, decoys)
    d, p, lib = inst.write(tmp_path / f"{inst.name}-{consistent}")
    task = load_task(d, p, [lib])
    nov = plan(task, search="novelty", consistent_beliefs=consistent)
    assert nov.solved and check_plan(task, list(nov.plan)).valid
    b = plan(task, search="bfs", consistent_beliefs=consistent)
    a = plan(task, search="auto", consistent_beliefs=consistent)
    assert b.length == a.length == inst.optimum
    assert a.optimal is True and b.semantics == a.semantics == ("consistent" if consistent else "reference")


def test_novelty_ranks_states_by_novelty_before_goal_count() -> None:
    """BFWS's order: a state that makes an atom new (w = 1) is expanded before one that does not, whatever
    their goal counts; unit test of the novelty table on a hand-made space."""
    from planners.epistemic import novelty_search

    class Space:
        # s0 -> a (goal count 1, repeats s0's atoms) and b (goal count 2, a new atom); b -> goal; a -> dead
        task = None
        dead_ends = 0
        succ = {"s0": [("to_a", "a"), ("to_b", "b")], "a": [("a_loop", "a2")], "a2": [], "b": [("win", "g")],
                "g": []}
        gcount = {"s0": 2, "a": 1, "a2": 1, "b": 2, "g": 0}
        atoms = {"s0": ("x",), "a": ("x",), "a2": ("x",), "b": ("y",), "g": ("z",)}

        def initial(self):
            return "s0", "s0"

        def successors(self, s):
            for name, t in self.succ[s]:
                yield name, t, t

        def is_goal(self, s):
            return s == "g"

        def goal_count(self, s):
            return self.gcount[s]

    sp = Space()
    res = novelty_search(sp, atoms=lambda s: sp.atoms[s], width=1)
    # novelty partitions by goal count: a (#g 1) is new in its table, so both a and b have w = 1; a's lower
    # goal count goes first, then a2 (w 2: x seen with #g 1) ranks behind b
    assert res.plan == ("to_b", "win")
    assert res.expanded == 3


def test_portfolio_respects_the_time_limit_and_reports_each_phase(tmp_path) -> None:
    """The portfolio's phases share one budget: with a tiny timeout on a task BFS cannot finish, every phase
    stops within it, the result is a limit (or a satisficing plan), and every phase run is listed."""
    inst, task = _task(tmp_path, "hotel-distributed", 5)
    res = plan(task, search="auto", limits=Limits(timeout=1.0))
    assert res.seconds < 1.6
    assert res.phases and sum(ph["seconds"] for ph in res.phases) <= 1.25   # one budget, not one per phase
    first = res.phases[0]
    assert first["search"] == "novelty" and (first["status"] == "solved" or first["seconds"] <= 0.3 + 0.1)
    if res.solved:
        assert res.optimal is False and check_plan(task, list(res.plan)).valid
    else:
        assert res.status == "limit"


def test_portfolio_names_the_phase_that_answered_and_proves_optimality(tmp_path) -> None:
    """A satisficing phase finds the first plan; A* proves (or improves) it; ``search`` names the phase whose
    plan is returned and ``optimal`` says A* finished."""
    inst, task = _task(tmp_path, "ugv-coordination", 4, 1)
    res = plan(task, search="auto", limits=Limits(timeout=60))
    assert [ph["search"] for ph in res.phases] == ["novelty", "astar"]
    assert res.optimal is True and res.length == inst.optimum
    winner = [ph for ph in res.phases if ph["improved"]][-1]["search"]
    assert res.search == "auto:" + winner


def test_portfolio_without_a_plan_in_its_optimal_phase_is_not_proven(tmp_path, monkeypatch) -> None:
    """When the optimal phase stops at a limit, the satisficing plan is returned with optimal False."""
    import planners.epistemic as ep

    inst, task = _task(tmp_path, "spy-linear", 4, 2)
    real = ep.run_search

    def astar_at_limit(space, kind, limits):
        if kind == "astar":
            return ep.SearchResult("limit", None, 5, 9, 0.01, "astar", "no plan within limits: test")
        return real(space, kind, limits)

    monkeypatch.setattr(ep, "run_search", astar_at_limit)
    res = portfolio(lambda: make_space(task, allow_inconsistent=True), Limits(timeout=60))
    assert res.solved and res.optimal is False and res.search == "auto:novelty"
    assert [(ph["search"], ph["status"]) for ph in res.phases] == [("novelty", "solved"), ("astar", "limit")]


def test_vacuous_goal_is_flagged_in_the_reference_semantics_and_pruned_when_consistent(tmp_path) -> None:
    """Hand-made: after ``act`` b believes ⊥, so ``[b] ~p`` holds only vacuously. The reference semantics (the
    EPDDL default, as plank) finds the plan and flags the conjunct; ``--consistent-beliefs`` prunes the state:
    no plan exists."""
    _, _, task = _vac_task(tmp_path)
    ref = plan(task)
    assert ref.plan == ("act",) and ref.semantics == "reference"
    assert ref.vacuous == ({"conjunct": "K_b ~p", "agents": ["b"]},)
    con = plan(task, consistent_beliefs=True)
    assert con.status == "unsolvable" and con.semantics == "consistent" and con.vacuous == ()
    for search in ("gbfs", "astar", "novelty", "auto"):  # one function decides for every search
        assert plan(task, search=search).vacuous == ref.vacuous
        assert plan(task, search=search, consistent_beliefs=True).status == "unsolvable"


def test_non_vacuous_goal_is_not_flagged(tmp_path) -> None:
    """The flag needs an inconsistent believer the conjunct mentions: ``p`` alone is not vacuous."""
    d, p, _ = _vac_task(tmp_path)
    from planners.lang.epddl2026 import load_epddl2026

    p.write_text(_VAC_PROBLEM.replace("(and (p) ([b] (not (p))))", "(p)"))
    res = plan(load_epddl2026(d, p))
    assert res.plan == ("act",) and res.vacuous == ()


def test_cli_reports_vacuous_goals_in_text_and_json_and_prunes_with_consistent_beliefs(tmp_path, capsys) -> None:
    from delkit.cli import main

    d, p, _ = _vac_task(tmp_path)
    assert main(["plan", str(d), str(p)]) == 0
    assert "vacuous: the goal conjunct K_b ~p holds only because b" in capsys.readouterr().out
    assert main(["plan", str(d), str(p), "--json", "--search", "auto"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["vacuous"] == [{"conjunct": "K_b ~p", "agents": ["b"]}] and out["semantics"] == "reference"
    assert out["optimal"] is True and out["search"].startswith("auto:")
    assert main(["plan", str(d), str(p), "--consistent-beliefs", "--json"]) == 1
    assert json.loads(capsys.readouterr().out)["status"] == "unsolvable"


def test_consistent_beliefs_and_allow_inconsistent_together_are_refused(tmp_path) -> None:
    from delkit.cli import main

    d, p, task = _vac_task(tmp_path)
    with pytest.raises(PlanningError, match="contradict"):
        plan(task, consistent_beliefs=True, allow_inconsistent=True)
    assert main(["plan", str(d), str(p), "--consistent-beliefs", "--allow-inconsistent"]) == 2


def test_unknown_search_is_refused_with_the_choices() -> None:
    from planners.task import Task  # noqa: F401  (the error comes before the task is looked at)

    with pytest.raises(PlanningError, match="novelty, auto"):
        plan(None, search="dfs")  # type: ignore[arg-type]


def test_generator_refuses_impossible_sizes() -> None:
    with pytest.raises(ValueError, match="chain=0"):
        generate("spy-linear", 0)
    with pytest.raises(ValueError, match="cells=1"):
        generate("ugv-coordination", 1)
    with pytest.raises(ValueError, match="unknown family"):
        generate("blocks", 3)


@pytest.mark.parametrize("family_size", [("spy-linear", 4, 2), ("spy-sensing", 4, 2), ("hotel-distributed", 3),
                                         ("ugv-coordination", 4, 2)], ids=lambda fs: "-".join(map(str, fs)))
def test_committed_frontier_specs_are_the_generators_output(tmp_path, family_size) -> None:
    """specs/frontier holds small generated instances with their known plans: regenerated, they are the same."""
    specs = Path(__file__).resolve().parents[2] / "specs" / "frontier"
    inst = generate(*family_size)
    for path in inst.write(tmp_path):
        assert (specs / path.name).read_text() == path.read_text(), path.name
    assert (specs / f"{inst.name}.plan").read_text().split() == list(inst.plan)


def test_novelty_beliefs_as_atoms_guide_the_search_on_a_task_that_only_informs(tmp_path) -> None:
    """On spy-linear (actions change beliefs only, never a valuation) the agents' beliefs about the goal's
    propositions are the atoms that become new: novelty expands about one state per step, BFS every state
    of the levels before the goal."""
    from planners.epistemic import bfs, novelty_search

    inst, task = _task(tmp_path, "spy-linear", 7, 5)
    nov = novelty_search(make_space(task, allow_inconsistent=True))
    full = bfs(make_space(task, allow_inconsistent=True))
    assert nov.length == full.length == inst.optimum
    assert nov.expanded <= 2 * inst.optimum < full.expanded
