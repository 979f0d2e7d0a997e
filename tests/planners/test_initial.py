"""Initial states without enumerating every valuation, limits honoured while building them,
and mA* files that declare a name twice."""

from __future__ import annotations

import itertools
import json
import time

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import planners.lang.initial as initial
from delkit.cli import main
from delkit.logic.formula import And, Formula, Iff, Implies, Not, Or, Prop
from delkit.models.kripke import KripkeModel
from planners.lang.initial import LoadTimeout, models
from planners.lang.mastar import load_mastar

PROPS = ("p0", "p1", "p2", "p3", "p4", "p5")


def _formula():
    atom = st.sampled_from(PROPS).map(Prop)
    return st.recursive(atom, lambda c: st.one_of(
        c.map(Not), st.tuples(c, c).map(lambda t: And(t)), st.tuples(c, c).map(lambda t: Or(t)),
        st.tuples(c, c).map(lambda t: Implies(*t)), st.tuples(c, c).map(lambda t: Iff(*t))), max_leaves=5)


def _brute(fs: list[Formula]) -> set[tuple[bool, ...]]:
    val = np.array(list(itertools.product((False, True), repeat=len(PROPS))), dtype=bool)
    flat = KripkeModel(PROPS, (), val, {}, ())
    keep = np.ones(len(val), dtype=bool)
    for f in fs:
        keep &= flat.check(f)
    return {tuple(r) for r in val[keep].tolist()}


@settings(max_examples=80, deadline=None)
@given(fs=st.lists(_formula(), max_size=4), mode=st.sampled_from(("numpy", "bdd", "split")))
def test_models_equal_brute_force(monkeypatch_session, fs, mode) -> None:
    """Components enumerated by numpy, by the BDD, or split on a disjunction (then propagated, numpy for the
    rest) give exactly the satisfying valuations, each once."""
    monkeypatch_session.setattr(initial, "_NUMPY_VARS", 0 if mode == "bdd" else 16)
    monkeypatch_session.setattr(initial, "_SPLIT_VARS", 0 if mode == "split" else 16)
    got = models(PROPS, fs)
    rows = [tuple(r) for r in got.tolist()]
    assert len(rows) == len(set(rows)) and set(rows) == _brute(fs)


@pytest.fixture(scope="module")
def monkeypatch_session():
    mp = pytest.MonkeyPatch()
    yield mp
    mp.undo()


def _cc_like(tmp_path, boxes: int, rooms: int):
    """A CC-like mA* file: 2 agents whose positions are common knowledge, ``boxes`` boxes each in exactly one
    of ``rooms`` rooms (unknown to both): 2·rooms + boxes·rooms fluents, rooms^boxes worlds."""
    ag = [f"at_{a}_{r}" for a in "ab" for r in range(1, rooms + 1)]
    bx = [[f"at_b{b}_{r}" for r in range(1, rooms + 1)] for b in range(1, boxes + 1)]
    fl = ag + [f for row in bx for f in row]
    lines = ["fluent " + ", ".join(fl) + ";", "action left_a;", "agent a, b;",
             "executable left_a if at_a_2;", "left_a causes at_a_1;", "left_a causes -at_a_2;",
             "a observes left_a;", "b observes left_a;"]
    pointed = [f"{'' if f in ('at_a_2', 'at_b_2') else '-'}{f}" for f in ag]
    pointed += [f"{'' if r == 0 else '-'}{row[r]}" for row in bx for r in range(rooms)]
    lines.append("initially " + ", ".join(pointed) + ";")
    for f in ag:
        lines.append(f"initially C([a,b], {'' if f in ('at_a_2', 'at_b_2') else '-'}{f});")
    for row in bx:
        one = " | ".join("(" + ", ".join(("" if j == i else "-") + row[j] for j in range(rooms)) + ")"
                         for i in range(rooms))
        lines.append(f"initially C([a,b], {one});")
    lines.append("goal at_a_1;")
    p = tmp_path / f"CC_2_{boxes}_{rooms}.txt"
    p.write_text("\n".join(lines) + "\n")
    return p


def test_cc_like_initial_state_is_the_product_of_small_components(tmp_path) -> None:
    """4 boxes in 4 rooms (24 fluents, 16 unfixed): the old construction enumerated 2^16 valuations."""
    task = load_mastar(_cc_like(tmp_path, 4, 4))
    m = task.initial
    assert len(task.props) == 24 and m.n_worlds == 4 ** 4
    for row in range(1, 5):  # every world puts every box in exactly one room
        cols = [task.props.index(f"at_b{row}_{r}") for r in range(1, 5)]
        assert (m.valuation[:, cols].sum(axis=1) == 1).all()


def test_component_over_many_fluents_uses_the_bdd(tmp_path) -> None:
    """One box in one of 30 rooms: 2^30 valuations (the old construction refused above 2^24), 30 worlds."""
    task = load_mastar(_cc_like(tmp_path, 1, 30))
    assert task.initial.n_worlds == 30


def test_deadline_honoured_during_initial_state_construction(tmp_path, capsys) -> None:
    """A 20-fluent instance whose initial state (786,432 worlds) takes a while to build: `--timeout 0.05` ends
    with 'no plan within the limits' (exit 3) soon after the limit, not after the construction (0.2 s on an idle
    machine, seconds under load: the limit is 0.05 s)."""
    fl = [f"p{i}" for i in range(20)]
    spec = tmp_path / "big.txt"
    spec.write_text("fluent " + ", ".join(fl) + ";\naction noop;\nagent a, b;\nexecutable noop;\nnoop causes p0;\n"
                    "a observes noop;\ninitially " + ", ".join(fl) + ";\ninitially C([a,b], p0 | p1);\n"
                    "goal B(a, p0);\n")
    with pytest.raises(LoadTimeout):
        load_mastar(spec, deadline=time.monotonic() - 1)
    t0 = time.monotonic()
    rc = main(["plan", str(spec), "--timeout", "0.05", "--json"])
    elapsed = time.monotonic() - t0
    data = json.loads(capsys.readouterr().out)
    assert rc == 3 and data["status"] == "limit" and "initial state" in data["reason"]
    assert elapsed < 0.05 + 5.0   # generous margin for a loaded machine; unlimited, the build takes longer
    t0 = time.monotonic()
    load_mastar(spec)
    assert time.monotonic() - t0 > 0.05   # the limit really cut a longer construction short


DUP = """fluent p, q, p;
action a;
agent x, y;
executable a;
a causes p;
x observes a;
y observes a;
initially -p, -q;
initially C([x,y], -p);
initially C([x,y], -q);
goal B(x, p);
"""


def test_duplicate_fluent_accepted_with_a_warning(tmp_path, capsys) -> None:
    spec = tmp_path / "dup.txt"
    spec.write_text(DUP)
    rc = main(["plan", str(spec), "--json"])
    cap = capsys.readouterr()
    assert rc == 0 and json.loads(cap.out)["plan"] == ["a"]
    warn = [ln for ln in cap.err.splitlines() if "warning" in ln]
    assert len(warn) == 1 and f"{spec}:1:" in warn[0] and "'p'" in warn[0] and "declared twice" in warn[0]
    rc = main(["plan", str(spec), "--strict"])
    cap = capsys.readouterr()
    assert rc == 2 and "declared twice" in cap.err and "warning" not in cap.err


def test_name_declared_as_two_kinds_is_still_an_error(tmp_path, capsys) -> None:
    spec = tmp_path / "clash.txt"
    spec.write_text(DUP.replace("agent x, y;", "agent x, y, q;"))
    assert main(["plan", str(spec)]) == 2
    assert "declared twice" in capsys.readouterr().err
