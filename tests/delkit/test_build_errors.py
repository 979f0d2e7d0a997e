"""Bad relations given to ``KripkeModel.build`` are a ``ModelError`` naming the agent (never
a numpy ``IndexError``, never a silent wrap-around of a negative world), and parse errors list readable
tokens."""

from __future__ import annotations

import pytest

from delkit import KripkeModel, parse
from delkit.errors import ModelError, ParseError
from delkit.models.relation import Relation


@pytest.mark.parametrize(("relation", "fragment"), [
    ([[0, 7]], "world 7 out of range 0..1"),
    ([[0, -1]], "world -1 out of range 0..1"),          # used to wrap around to world 1
    ([[0, 1], [1]], "world 1 is in two blocks"),
    ({"pairs": [[0, 9]]}, "world 9 out of range 0..1"),
    ({"pairs": [[-1, 0]]}, "world -1 out of range 0..1"),
])
def test_bad_relations_are_model_errors_naming_the_agent(relation, fragment) -> None:
    with pytest.raises(ModelError) as info:
        KripkeModel.build([{"p"}, set()], {"a": [[0, 1]], "b": relation}, designated=[0])
    assert "relation of agent 'b'" in str(info.value) and fragment in str(info.value)
    assert isinstance(info.value, ValueError)               # still a ValueError for existing callers


def test_relation_constructors_check_their_points() -> None:
    with pytest.raises(ValueError, match="out of range"):
        Relation.from_blocks(3, [[0, 3]])
    assert Relation.from_blocks(3, [[0, 2]]).labels.tolist() == [0, 1, 0]


def test_parse_errors_name_anonymous_tokens_readably() -> None:
    with pytest.raises(ParseError) as info:
        parse("p q")
    assert "__ANON" not in str(info.value)
    assert {"->", "<->", "&", "|"} <= set(info.value.expected)


def test_a_model_with_no_worlds_is_not_written_since_it_cannot_be_read_back(tmp_path) -> None:
    from delkit import product_update, public_announcement
    from delkit.io.formats import dumps, loads, save

    m = KripkeModel.build([{"p"}], {"a": [[0]]}, designated=[0])
    empty = product_update(m, public_announcement("~p", ["a"]))    # no event applies
    assert empty.n_worlds == 0
    with pytest.raises(ModelError, match="no worlds cannot be written"):
        dumps(empty)
    with pytest.raises(ModelError):
        save(empty, tmp_path / "e.json")
    assert not (tmp_path / "e.json").exists()
    assert loads(dumps(m)).n_worlds == 1


@pytest.mark.parametrize(("entry", "fragment"), [
    ('"props": ["p", [1]]', "'props' must list names as strings, got [1]"),
    ('"props": ["p", "p"]', "'props' lists ['p'] more than once"),
    ('"agents": ["a", 3]', "'agents' must list names as strings, got 3"),
])
def test_model_file_with_non_string_symbols_is_a_model_file_error(entry, fragment) -> None:
    from delkit.io.formats import ModelFileError, loads

    text = ('{"delkit": "kripke-model", ' + entry + ', "worlds": [{"name": "u", "true": ["p"]}], '
            '"relations": {"a": [["u"]]}, "designated": ["u"]}')
    with pytest.raises(ModelFileError) as info:       # was a TypeError (unhashable list) from the reader
        loads(text, source="m.json")
    assert str(info.value).startswith("m.json: ") and fragment in str(info.value)


@pytest.mark.parametrize("worlds", [["rain", []], {"u": "rain", "v": []}])
def test_a_world_given_as_a_string_is_rejected_not_split_into_letters(worlds) -> None:
    with pytest.raises(ModelError, match="not the string 'rain'"):
        KripkeModel.build(worlds, {"a": [[0, 1]]}, designated=[0])
    assert KripkeModel.build([["rain"], []], {"a": [[0, 1]]}, designated=[0]).props == ("rain",)


@pytest.mark.parametrize(("make", "fragment"), [
    (lambda: __import__("delkit").public_announcement("p", "robot1"), "agents must be a list of agent names"),
    (lambda: __import__("delkit").sensing("p", ["a", "b"], full="a"), "full must be a list of agent names"),
    (lambda: __import__("delkit").semi_private_announcement("p", "robot1", ["robot1", "b"]),
     "group must be a list of agent names"),
    (lambda: __import__("delkit").public_announcement("p", ["a", "a"]), "duplicate agent names ['a', 'a']"),
])
def test_event_constructors_reject_agent_strings_and_duplicates(make, fragment) -> None:
    with pytest.raises(ModelError) as info:       # a string used to become one agent per letter
        make()
    assert fragment in str(info.value)


@pytest.mark.parametrize(("kw", "fragment"), [
    ({"agents": "ab"}, "agents must be a list, e.g. ['ab']"),
    ({"props": "pq"}, "props must be a list, e.g. ['pq']"),
    ({"designated": 0}, "designated must be a list, e.g. [0]"),
    ({"designated": "u"}, "designated must be a list, e.g. ['u']"),
])
def test_build_rejects_a_bare_name_or_index_where_a_list_is_expected(kw, fragment) -> None:
    args = {"designated": [0], **kw}
    with pytest.raises(ModelError, match=fragment.replace("[", r"\[")):
        KripkeModel.build({"u": {"p"}}, {"ab": [["u"]]}, **args)
