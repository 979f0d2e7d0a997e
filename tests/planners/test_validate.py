"""The plan/property checker: first failing step, reasons, properties, plan file formats."""

from __future__ import annotations

import pytest

from delkit.errors import DelkitError, ParseError
from planners.demo import specs_dir
from planners.lang import load_task
from planners.validate import check_plan, parse_plan_text, parse_property

D = specs_dir() / "coin_in_the_box"


@pytest.fixture(scope="module")
def coin():
    return load_task(D / "domain.epddl", D / "problem.epddl")


def test_valid_plan(coin) -> None:
    assert check_plan(coin, ["signal_a_b", "open_a", "peek_b"]).to_json() == {"valid": True, "steps": 3}


def test_precondition_failure_names_agent_and_world(coin) -> None:
    res = check_plan(coin, ["open_a", "peek_b"])
    assert not res.valid and res.step == 2 and res.action == "peek_b" and res.kind == "precondition"
    # b did not see the box open (not looking): it considers a closed-box world possible
    assert res.agent == "b" and "opened" in res.reason and res.world is not None
    assert "opened" not in res.world.split("{")[1]


def test_goal_failure(coin) -> None:
    res = check_plan(coin, ["open_a", "peek_a"])
    assert not res.valid and res.kind == "goal" and res.agent == "b"


def test_announcing_a_false_formula_is_not_applicable() -> None:
    from planners.lang.mastar import parse_mastar

    task = parse_mastar("""fluent p; action lie; agent a, b;
        lie announces p; a observes lie; b observes lie;
        initially -p; goal B(b, p);""", "lie.txt")
    res = check_plan(task, ["lie"])
    assert not res.valid and res.kind == "not-applicable" and res.step == 1


def test_properties(coin) -> None:
    plan = ["signal_a_b", "open_a", "peek_b"]
    ok = [parse_property(t, coin) for t in ("always ~K_c tail", "eventually opened", "at end K_b tail",
                                            "always B(a, has_key_a)")]
    assert check_plan(coin, plan, ok).valid
    res = check_plan(coin, plan, [parse_property("always ~opened", coin)])
    assert not res.valid and res.step == 2 and res.kind == "property"
    res = check_plan(coin, plan, [parse_property("eventually K_c tail", coin)])
    assert not res.valid and "never holds" in res.reason
    res = check_plan(coin, plan, [parse_property("at end K_a tail", coin)])
    assert not res.valid and res.step == 3 and res.agent == "a"


def test_property_errors(coin) -> None:
    with pytest.raises(ParseError, match="always"):
        parse_property("sometimes p", coin)
    with pytest.raises(DelkitError):
        parse_property("always K_z tail", coin)
    with pytest.raises(DelkitError):
        parse_property("always nosuchfluent", coin)


def test_unknown_action(coin) -> None:
    with pytest.raises(DelkitError, match="no action named"):
        check_plan(coin, ["open_a", "fly"])


def test_plan_text_formats() -> None:
    assert parse_plan_text("open_a\n# c\npeek_a ; x\n") == ["open_a", "peek_a"]
    assert parse_plan_text("open_a, peek_a, shout_tail_a") == ["open_a", "peek_a", "shout_tail_a"]
    assert parse_plan_text("%%% Executed actions: open_a peek_a %%%") == ["open_a", "peek_a"]
    assert parse_plan_text("(signal a b)\n(open a)") == ["signal_a_b", "open_a"]
