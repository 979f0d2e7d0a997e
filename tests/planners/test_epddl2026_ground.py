"""EPDDL (2026) grounding: the task loaded from every problem of plank's suite (../shared/benchmarks/epddl2026,
expected.csv) is exactly the task the reference loader produced — same fluents, agents, initial model (valuation,
relations and their form, designated worlds, names), goal, and per ground action the same name, conditions,
place, kind and, for every truth assignment of its conditions, the same event model (events, pre, post in order,
relations and their form, designated events).

The reference is a file of SHA-256 digests of a canonical dump (``epddl2026_ground.json`` next to this file),
written from delkit's loader at commit 9fc2ada, before the grounder was rewritten for speed. A
legitimate change of what is grounded (not of how fast) regenerates it with

    PYTHONPATH=. python tests/planners/test_epddl2026_ground.py --write

and says why in the commit. ``--diff NAME`` prints the dump of one problem (to compare two checkouts).
"""

from __future__ import annotations

import csv
import hashlib
import itertools
import json
import sys
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings

from delkit.errors import ParseError
from delkit.logic.formula import is_propositional
from delkit.testing import formulas
from planners.lang import shared_benchmarks
from planners.lang.epddl2026 import _is_propositional, load_epddl2026

BENCH = shared_benchmarks()
DIGESTS = Path(__file__).with_name("epddl2026_ground.json")
MAX_BITS = 10   # every condition assignment of an action with at most this many conditions (all in the suite)


def _rows() -> list[dict]:
    if BENCH is None:
        return []
    return list(csv.DictReader((BENCH / "epddl2026" / "expected.csv").open()))


def _key(row: dict) -> str:
    return row["problem"].split("domains/")[1]


def _relation(r) -> str:
    if r.labels is not None:
        return "partition " + " ".join(map(str, r.labels.tolist()))
    return "pairs " + ";".join(" ".join(map(str, sorted(r.successors(w).tolist()))) for w in range(r.n))


def dump(task) -> list[str]:
    """A canonical text of a grounded EPDDL task, one line per fact (formulas by their repr)."""
    m = task.initial
    out = [f"task {task.name!r} source {task.source!r}", f"props {list(task.props)!r}",
           f"agents {list(task.agents)!r}", f"goal {task.goal!r}",
           f"init worlds {m.n_worlds} designated {list(m.designated)!r} names {m.names!r}",
           "init valuation " + np.asarray(m.valuation, dtype=np.uint8).tobytes().hex()]
    out += [f"init rel {a} {_relation(m.relations[a])}" for a in task.agents]
    for act in task.actions:
        out.append(f"action {act.name!r} kind {act.kind!r} where {act.where!r} executable {act.executable!r} "
                   f"conditions {list(act.conditions)!r}")
        n = len(act.conditions)
        assert n <= MAX_BITS, act.name
        for bits in itertools.product((False, True), repeat=n):
            em = act.build(bits)
            out.append(f" bits {bits!r} model {em.name!r} events {list(em.events)!r} designated "
                       f"{list(em.designated)!r} agents {list(em.agents)!r}")
            for e, pre, post in zip(em.events, em.pre, em.post, strict=True):
                out.append(f"  event {e} pre {pre!r} post {list(post.items())!r}")
            out += [f"  rel {a} {_relation(em.relations[a])}" for a in em.agents]
    return out


def _load(row: dict):
    base = BENCH / "epddl2026"
    return load_epddl2026(base / row["domain"], base / row["problem"],
                          [base / row["libraries"]] if row["libraries"] else [])


def _digest(row: dict) -> str:
    text = "\n".join(dump(_load(row)))
    return hashlib.sha256(text.replace(str(BENCH), "<BENCH>").encode()).hexdigest()


@pytest.mark.skipif(BENCH is None, reason="../shared/benchmarks is not available")
@pytest.mark.parametrize("row", _rows(), ids=_key)
def test_grounded_task_identical_to_reference(row: dict) -> None:
    want = json.loads(DIGESTS.read_text())
    assert _digest(row) == want[_key(row)]


@settings(max_examples=300, deadline=None)
@given(formulas(["p", "q"], ["a", "b"], max_depth=4))
def test_is_propositional_as_delkits(f) -> None:
    """The grounder's one-walk test for finitary-S5 theories agrees with delkit.logic.formula.is_propositional."""
    assert _is_propositional(f) == is_propositional(f)


def _cb(tmp_path: Path, domain=lambda s: s, library=lambda s: s) -> tuple:
    """Coin-in-the-Box problem_2 with its domain and library edited."""
    base = BENCH / "epddl2026" / "plank"
    dom, lib = tmp_path / "cb.epddl", tmp_path / "intermediate.epddl"
    dom.write_text(domain((base / "domains/Coin-in-the-Box/cb.epddl").read_text()))
    lib.write_text(library((base / "libraries/intermediate.epddl").read_text()))
    return dom, base / "domains/Coin-in-the-Box/instances/problem_2.epddl", [lib]


@pytest.mark.skipif(BENCH is None, reason="../shared/benchmarks is not available")
def test_default_without_a_type_is_a_statement_error(tmp_path) -> None:
    """``(default)`` was an IndexError (found while rewriting the observability conditions)."""
    files = _cb(tmp_path, domain=lambda s: s.replace("(default Oblivious)", "(default)", 1))
    with pytest.raises(ParseError, match=r"cb.epddl:33: expected \(agent Type\).*\(default Type\)"):
        load_epddl2026(*files)


@pytest.mark.skipif(BENCH is None, reason="../shared/benchmarks is not available")
def test_designated_event_not_among_the_events_is_named(tmp_path) -> None:
    """A designated event that is not an event of its action type was a ValueError."""
    def edit(s: str) -> str:
        i = s.index(":designated (?pos)", s.index("(:action-type private-ontic"))
        return s[:i] + ":designated (?zz)" + s[i + len(":designated (?pos)"):]
    files = _cb(tmp_path, library=edit)
    with pytest.raises(ParseError, match=r"intermediate.epddl:18: action type 'private-ontic': designated \?zz "
                                         r"not among its events \(\?pos \?nil\)"):
        load_epddl2026(*files)


@pytest.mark.skipif(BENCH is None, reason="../shared/benchmarks is not available")
def test_filter_on_a_parameter_list_without_variables_is_grounded(tmp_path) -> None:
    """``(:forall ( - agent | φ) ...)`` (no variable, a filter) was an IndexError; the filter is now tested
    as a whole, here reporting its unbound variable."""
    files = _cb(tmp_path, domain=lambda s: s.replace("(:forall (?j - agent | (/= ?i ?j))",
                                                     "(:forall ( - agent | (/= ?x ?j))", 1))
    with pytest.raises(ParseError, match=r"cb\.epddl:\d+: unbound variable \?x"):
        load_epddl2026(*files)


@pytest.mark.skipif(BENCH is None, reason="../shared/benchmarks is not available")
@pytest.mark.parametrize("decl", ["(:fact)", "(((deep)) ?i - agent)"])
def test_predicate_without_a_name_is_refused(tmp_path, decl: str) -> None:
    """``(:fact)`` was an IndexError, a bracketed predicate name a RecursionError when deeply nested."""
    files = _cb(tmp_path, domain=lambda s: s.replace("(has-key ?i - agent)", f"(has-key ?i - agent) {decl}", 1))
    with pytest.raises(ParseError, match=r"cb\.epddl:\d+: expected \(name \?x - type \.\.\.\) or \(:fact name"):
        load_epddl2026(*files)


def _main(argv: list[str]) -> None:
    if argv[:1] == ["--write"]:
        DIGESTS.write_text(json.dumps({_key(r): _digest(r) for r in _rows()}, indent=1) + "\n")
    elif argv[:1] == ["--diff"]:
        row = next(r for r in _rows() if argv[1] in r["problem"])
        print("\n".join(dump(_load(row))))
    else:
        raise SystemExit(__doc__)


if __name__ == "__main__":
    _main(sys.argv[1:])
