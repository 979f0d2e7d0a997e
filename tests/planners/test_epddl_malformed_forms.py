"""Malformed E-PDDL forms ((not) with a stray token, (when c) without an effect, (forall)
without a body) are ParseErrors at the form, not AttributeError / ValueError / IndexError tracebacks."""

from __future__ import annotations

import pytest

from delkit.errors import ParseError
from planners.demo import specs_dir
from planners.lang import load_task

SPEC = specs_dir() / "selective_communication"


@pytest.mark.parametrize(("old", "new", "fragment"), [
    ("(not (at ?from))", "(not ?(at ?from))", "expected (not (predicate arg ...))"),
    ("(not (at ?from))", "(not (at ?from) (at ?to))", "expected (not (predicate arg ...))"),
    ("(when (hears ?o ?r) (?o))", "(when (hears ?o ?r))", "expected (when CONDITION EFFECT)"),
    ("(forall (?o - agent) (?o))", "(forall (?o - agent))", "expected (forall (?x - type ...) BODY)"),
])
def test_malformed_forms_are_parse_errors(tmp_path, old, new, fragment) -> None:
    text = (SPEC / "domain.epddl").read_text()
    assert old in text
    bad = tmp_path / "domain.epddl"
    bad.write_text(text.replace(old, new, 1))
    with pytest.raises(ParseError) as info:
        load_task(bad, SPEC / "problem.epddl")
    assert fragment in str(info.value) and str(info.value).startswith(f"{bad}:")


@pytest.mark.parametrize("head", ["(domain (coin_in_the_box))", "(domain coin_in_the_box extra)"])
def test_define_name_that_is_not_one_plain_name(tmp_path, head) -> None:
    spec = specs_dir() / "coin_in_the_box"
    text = (spec / "domain.epddl").read_text()
    assert "(domain coin_in_the_box)" in text
    bad = tmp_path / "domain.epddl"
    bad.write_text(text.replace("(domain coin_in_the_box)", head, 1))
    with pytest.raises(ParseError, match=r"expected \(domain NAME\) with one plain name"):
        load_task(bad, spec / "problem.epddl")
