"""mA* reader: statements, formula syntax, finitary-S5 initial state, error positions."""

from __future__ import annotations

import pytest

from delkit.errors import ParseError
from delkit.logic.formula import C, K, Not, Or, Prop, parse
from planners.lang.mastar import parse_mastar, parse_mastar_formula

SMALL = """
%%% Executed actions: tell %%%
fluent p, q;
action tell, look, move;
agent a, b;
executable tell if B(a, p), p;
tell announces p;
a observes tell;
b observes tell;
executable look if -B(a, q) , -B(a, -q);
look determines q;
a observes look;
b aware_of look;
move causes -p, q if p;
a observes move;
initially p, -q;
initially C([a,b], B(a,p) | B(a,-p));
goal B(b, p) & -B(b, q);
"""


def test_statements_become_actions() -> None:
    t = parse_mastar(SMALL, "small.txt")
    assert t.agents == ("a", "b") and t.props == ("p", "q")
    tell, look, move = (t.action(n) for n in ("tell", "look", "move"))
    assert tell.kind == "announcement" and tell.sensed[0][0] == Prop("p")
    assert look.kind == "sensing" and [a for a, _ in look.partial] == ["b"]
    assert move.kind == "ontic" and [(p, v) for p, v, _ in move.effects] == [("p", False), ("q", True)]
    assert all(c == Prop("p") for _, _, c in move.effects)
    assert t.goal == parse("K_b p & ~K_b q")


def test_finitary_s5_initial_state() -> None:
    """4 valuations of {p,q}; a knows whether p (its partition splits on p), b knows nothing."""
    t = parse_mastar(SMALL, "small.txt")
    m = t.initial
    assert m.n_worlds == 4 and m.is_s5()
    assert m.holds(parse("K_a p & ~K_b p & ~K_a q & ~K_a ~q"))
    assert m.holds(parse("C{a,b} (K_a p | K_a ~p)"))
    assert m.true_props(m.designated[0]) == {"p"}


def test_precedence_comma_is_lowest() -> None:
    t = parse_mastar(SMALL, "x")
    assert parse_mastar_formula("p | q , -p", t) == parse("(p | q) & ~p")
    assert parse_mastar_formula("-B(a, p) & q", t) == parse("~K_a p & q")
    assert parse_mastar_formula("C([a,b], (p, q) | (-p, -q))", t) == C(
        ("a", "b"), Or((parse("p & q"), parse("~p & ~q"))))
    assert parse_mastar_formula("B(a, -B(b, p))", t) == K("a", Not(K("b", Prop("p"))))


@pytest.mark.parametrize("text, line, col, needle", [
    ("fluent p;\nagent a;\naction x;\nx causes r;\ngoal p;", 4, 10, "unknown fluent 'r'"),
    ("fluent p;\nagent a;\naction x;\nz observes x;\ngoal p;", 4, 1, "unknown agent 'z'"),
    ("fluent p;\nagent a;\naction x;\nx causes p\ngoal p;", 5, 1, "expected"),
    ("fluent p;\nagent a;\naction x;\ngoal B(a p);", 4, 10, "expected"),
    ("fluent p;\nagent a;\naction x;\nx flies p;\ngoal p;", 4, 3, "causes"),
])
def test_errors_have_file_line_column(text: str, line: int, col: int, needle: str) -> None:
    with pytest.raises(ParseError) as ei:
        parse_mastar(text, "bad.txt")
    e = ei.value
    assert (e.source, e.line, e.column) == ("bad.txt", line, col)
    assert needle in str(e)
    assert str(e).startswith(f"bad.txt:{line}:{col}:")


def test_undetermined_actual_world_is_an_error() -> None:
    with pytest.raises(ParseError, match="do not determine the actual world"):
        parse_mastar("fluent p, q;\nagent a;\naction x;\ninitially p;\ngoal p;", "u.txt")


def test_unsupported_initial_statement_is_reported() -> None:
    # C(B(a, p)) is not produced by the finitary-S5 construction when p is not common knowledge
    text = "fluent p;\nagent a, b;\naction x;\ninitially p;\ninitially C([a,b], B(a, p));\ngoal p;"
    with pytest.raises(ParseError, match="not made true"):
        parse_mastar(text, "c.txt")
