"""EPDDL action semantics: effects (``when``/``iff``: p' = pos ∨ (p ∧ ¬neg)), user-defined observability types
with ``if / else-if / else`` and ``default``, decided on the whole state before the update (plank: the last
type whose condition the state satisfies, the action type's first type when none does), applicability on
multi-pointed states."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from delkit.models.kripke import KripkeModel
from planners.lang.epddl2026 import load_epddl2026
from planners.task import apply_action

LIB = """(define (action-type-library mine)
  (:action-type three-way
    :events (?x ?y ?z)
    :observability-types (Seer Half Blind)
    :relations (Seer (:forall (?e - event) (?e ?e))
                Half (:and (:forall (?e ?f - event | (and (/= ?e ?z) (/= ?f ?z))) (?e ?f)) (?z ?z))
                Blind (:forall (?e - event) (?e ?z)))
    :designated (?x ?y)))"""

DOMAIN = """(define (domain acts)
  (:action-type-libraries mine)
  (:predicates (p) (q) (r))
  (:event ex :precondition (q)
     :effects (:and (when (q) (p)) (when (r) (not (p))) (iff (q) (r))))
  (:event ey :precondition (not (q)))
  (:event ez)
  (:action act
     :action-type (three-way (ex) (ey) (ez))
     :observability-conditions (:and (a Seer) (b (if (p) Seer else-if (q) Half else Blind)) (default Blind))))"""


def _task(tmp_path, init: str, goal: str = "(p)"):
    (tmp_path / "mine.epddl").write_text(LIB)
    (tmp_path / "d.epddl").write_text(DOMAIN)
    (tmp_path / "p.epddl").write_text(f"(define (problem x) (:domain acts) (:agents a b c)\n (:init {init})\n"
                                      f" (:goal {goal}))")
    return load_epddl2026(tmp_path / "d.epddl", tmp_path / "p.epddl")   # library found next to the domain


def test_effects_pos_or_kept_unless_neg(tmp_path) -> None:
    task = _task(tmp_path, "(:and (q))")
    act = task.action("act")
    em = act.build(tuple(False for _ in act.conditions))
    vals = np.array(list(itertools.product((False, True), repeat=3)), dtype=bool)
    flat = KripkeModel(("p", "q", "r"), (), vals, {}, ())
    p, q, r = vals[:, 0], vals[:, 1], vals[:, 2]
    post = em.post[0]
    assert (flat.check(post["p"]) == (q | (p & ~r))).all()    # when q: p, when r: not p
    assert (flat.check(post["r"]) == q).all()                  # iff q: r
    assert "q" not in post and em.post[1] == {} and em.post[2] == {}


def _b_relation(task, model):
    em = task.event_model(task.action("act"), model)
    return {(int(x), int(y)) for x, y in em.relations["b"].pairs()}


SEER, HALF, BLIND = {(0, 0), (1, 1), (2, 2)}, {(0, 0), (0, 1), (1, 0), (1, 1), (2, 2)}, {(0, 2), (1, 2), (2, 2)}


@pytest.mark.parametrize("init,expected", [
    ("(:and (p) (q) (not (r)))", SEER),                 # if (p)
    ("(:and (not (p)) (q) (not (r)))", HALF),           # else-if (q)
    ("(:and (not (p)) (not (q)) (r))", BLIND),          # else
    ("(:and (q))", SEER),   # p varies over the 4 designated worlds: no condition holds in the state: 1st type
])
def test_if_else_if_else(tmp_path, init: str, expected: set) -> None:
    task = _task(tmp_path, init)
    assert _b_relation(task, task.initial) == expected
    em = task.event_model(task.action("act"), task.initial)
    assert {(int(x), int(y)) for x, y in em.relations["a"].pairs()} == SEER       # (a Seer)
    assert {(int(x), int(y)) for x, y in em.relations["c"].pairs()} == BLIND      # (default Blind)


def test_condition_true_in_some_designated_world_only_gives_the_first_type(tmp_path) -> None:
    """Designated worlds {p} and {}: the state satisfies none of p, ¬p∧q, ¬p∧¬q, so b gets the first
    observability type of the action type (Seer) — plank's updater."""
    init = ":worlds (u v) :relations (a (:and (u u) (v v)) b (:and (u u) (v v)) c (:and (u v) (v u))) " \
           ":labels (u (:and (p)) v (:and)) :designated (u v)"
    task = _task(tmp_path, init)
    assert len(task.initial.designated) == 2
    assert _b_relation(task, task.initial) == SEER


def test_applicable_iff_every_designated_world_has_a_designated_event(tmp_path) -> None:
    # designated worlds {q} (event x) and {} (event y): applicable; the result keeps both, updated
    init = ":worlds (u v) :relations (a (:and (u u) (v v)) b (:and (u u) (v v)) c (:and (u u) (v v))) " \
           ":labels (u (:and (q)) v (:and)) :designated (u v)"
    task = _task(tmp_path, init)
    new = apply_action(task, task.action("act"), task.initial)
    assert new is not None and len(new.designated) == 2
    assert sorted(sorted(new.true_props(w)) for w in new.designated) == [[], ["p", "q", "r"]]
