"""An E-PDDL atom whose argument is not an object of the predicate's type (a typo in
:init, :goal or an action) is a ParseError at that atom, not a KeyError from the initial-state builder."""

from __future__ import annotations

import pytest

from delkit.errors import ParseError
from planners.demo import specs_dir
from planners.lang import load_task

SPEC = specs_dir() / "collaboration_communication"


@pytest.mark.parametrize(("atom", "fragment"), [
    ("(next r1 r9)", "argument 2 of 'next' is 'r9', which is not an object of type 'room'"),
    ("(next -r2 r1)", "argument 1 of 'next' is '-r2'"),
])
def test_unknown_object_in_init_is_a_parse_error_at_the_atom(tmp_path, atom, fragment) -> None:
    text = (SPEC / "problem.epddl").read_text()
    assert "(next r2 r1)" in text
    bad = tmp_path / "problem.epddl"
    bad.write_text(text.replace("(next r2 r1)", atom, 1))
    with pytest.raises(ParseError) as info:
        load_task(SPEC / "domain.epddl", bad)
    assert fragment in str(info.value) and info.value.line is not None
    assert str(info.value).startswith(f"{bad}:")


def test_the_unchanged_spec_still_loads() -> None:
    task = load_task(SPEC / "domain.epddl", SPEC / "problem.epddl")
    assert "next_r2_r1" in task.props
