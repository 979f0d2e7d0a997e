"""delkit.io.formats: JSON and DOT round trips (property-based) and the error messages on malformed files."""

from __future__ import annotations

import json
import re

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from delkit import DelkitError, KripkeModel, ParseError, bisimilar, parse, sensing
from delkit.io.formats import (
    ModelFileError,
    dumps,
    event_model_from_dict,
    from_dot,
    load,
    load_event_model,
    load_model,
    loads,
    model_from_dict,
    model_to_dict,
    save,
    save_dot,
    to_dot,
)
from delkit.models.events import EventModel
from delkit.testing import event_models, kripke_models

PROPS, AGENTS = ("p", "q", "r_1"), ("a", "b")
CFG = settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
models = st.sampled_from(["S5", "KD45", "K"]).flatmap(
    lambda fr: kripke_models(PROPS, AGENTS, 5, frame=fr, designated="some"))
evmodels = st.sampled_from(["S5", "KD45"]).flatmap(lambda fr: event_models(PROPS, AGENTS, 3, frame=fr))


def same_model(a: KripkeModel, b: KripkeModel) -> bool:
    return (a.props == b.props and a.agents == b.agents and (a.valuation == b.valuation).all()
            and a.designated == b.designated
            and all(a.relations[x].equals(b.relations[x]) and a.relations[x].is_partition == b.relations[x].is_partition
                    for x in a.agents))


def same_events(a: EventModel, b: EventModel) -> bool:
    return (a.events == b.events and a.agents == b.agents and a.pre == b.pre and a.post == b.post
            and a.designated == b.designated and a.name == b.name
            and all(a.relations[x].equals(b.relations[x]) for x in a.agents))


@CFG
@given(models)
def test_kripke_json_round_trip(m):
    back = loads(dumps(m))
    assert same_model(m, back)
    assert dumps(back) == dumps(m)
    assert same_model(m, loads(dumps(m, indent=None)))


@CFG
@given(models)
def test_kripke_dot_round_trip(m):
    back = from_dot(to_dot(m))
    assert same_model(m, back)


@CFG
@given(evmodels)
def test_event_model_json_and_dot_round_trip(e):
    assert same_events(e, loads(dumps(e)))
    assert same_events(e, from_dot(to_dot(e)))


def test_named_worlds_and_the_documented_example(tmp_path):
    doc = {
        "delkit": "kripke-model", "version": 1, "props": ["p", "q"], "agents": ["a", "b"],
        "worlds": [{"name": "w0", "true": ["p"]}, {"name": "w1", "true": []}],
        "relations": {"a": {"blocks": [["w0", "w1"]]}, "b": {"pairs": [["w0", "w0"], ["w1", "w0"]]}},
        "designated": ["w0"],
    }
    m = model_from_dict(doc)
    assert m.holds("p & ~K_a p & K_b p")
    assert m.relations["a"].is_partition and not m.relations["b"].is_partition
    named = dict(doc, worlds=[{"name": "here", "true": ["p"]}, {"name": "there"}],
                 relations={"a": [["here", "there"]], "b": {"pairs": [[0, 0], ["there", "here"]]}},
                 designated=[0])
    m2 = model_from_dict(named)
    assert m2.names == ("here", "there") and bisimilar(m, m2)
    assert model_to_dict(m2)["designated"] == ["here"]
    path = tmp_path / "m.json"
    save(m2, path)
    assert same_model(load_model(path), m2) and load_model(path).names == ("here", "there")
    save_dot(m2, tmp_path / "m.dot")
    assert same_model(load(tmp_path / "m.dot"), m2)


def test_duplicate_world_names_are_replaced_on_export():
    m = KripkeModel.build([{"p"}, set()], {"a": [[0, 1]]})
    dup = KripkeModel(m.props, m.agents, m.valuation, m.relations, m.designated, ("x", "x"))
    back = loads(dumps(dup))
    assert [w["name"] for w in model_to_dict(dup)["worlds"]] == ["w0", "w1"] and same_model(back, dup)


def test_event_model_file_with_formulas(tmp_path):
    e = sensing("p & q", ["a", "b"], full=["a"], partial=[], name="peek")
    path = tmp_path / "e.json"
    save(e, path)
    back = load_event_model(path)
    assert same_events(e, back) and back.pre[0] == parse("p & q")
    with pytest.raises(ModelFileError, match="holds an event model, expected a Kripke model"):
        load_model(path)


# ----------------------------------------------------------------------------- errors


def err(text: str, source: str = "bad.json") -> str:
    with pytest.raises(DelkitError) as info:
        loads(text, source=source)
    msg = str(info.value)
    assert msg.startswith(source)
    assert "\n" not in msg
    return msg


def test_json_syntax_error_has_line_and_column():
    with pytest.raises(ParseError) as info:
        loads('{\n  "delkit": "kripke-model",\n  "worlds": [,]\n}', source="m.json")
    assert (info.value.line, info.value.column) == (3, 14)
    assert str(info.value).startswith("m.json:3:14: invalid JSON")


BASE = {"delkit": "kripke-model", "worlds": [{"name": "u", "true": ["p"]}, {"name": "v"}],
        "relations": {"a": [["u", "v"]]}, "designated": ["u"]}


@pytest.mark.parametrize(("change", "pattern"), [
    ({"delkit": "kripke"}, r'"delkit" must be one of .*add "delkit": "kripke-model"'),
    ({"version": 7}, r"schema version 7 is not supported"),
    ({"worlds": []}, r"no worlds; list at least one world"),
    ({"worlds": [{"name": "u"}, {"name": "u"}]}, r"duplicate world name\(s\) \['u'\]"),
    ({"worlds": [{"name": "u", "true": "p"}]}, r"world 'u': 'true' must be a list"),
    ({"worlds": ["u"]}, r"world #0 must be an object"),
    ({"relations": {"a": [["u", "x"]]}}, r"relation of 'a' block #0: unknown world 'x' \(known: u, v\)"),
    ({"relations": {"a": [["u", "v"], ["v"]]}}, r"world 'v' is in blocks #0 and #1"),
    ({"relations": {"a": {"pairs": [["u"]]}}}, r"pair #0 must be a two-element list"),
    ({"relations": {"a": {"edges": []}}}, r'must be \{"blocks"'),
    ({"relations": {"a": [["u", "v"]]}, "agents": ["a", "b"]}, r"no relation for agent\(s\) \['b'\]"),
    ({"props": ["q"]}, r"proposition\(s\) \['p'\] true that are not in \"props\""),
    ({"designated": [5]}, r"designated: world index 5 out of range 0..1"),
    ({"designated": "u"}, r"'designated' must be a list"),
])
def test_schema_errors_say_what_and_how_to_fix(change, pattern):
    msg = err(json.dumps({**BASE, **change}))
    assert re.search(pattern, msg), msg


def test_missing_key_and_bad_formula_in_event_model():
    assert "has no 'worlds' entry; add \"worlds\"" in err(json.dumps({"delkit": "kripke-model"}))
    ev = {"delkit": "event-model", "events": [{"name": "e", "pre": "p &"}], "relations": {"a": [["e"]]},
          "designated": ["e"]}
    with pytest.raises(ParseError) as info:
        event_model_from_dict(ev, source="e.json")
    assert "e.json (precondition of event 'e')" in str(info.value) and info.value.column == 4
    ev["events"] = [{"name": "e", "pre": "p", "post": {"p": "K_a q"}}]
    with pytest.raises(ModelFileError, match="postcondition of 'p' must be propositional"):
        event_model_from_dict(ev, source="e.json")


def test_file_errors(tmp_path):
    with pytest.raises(ModelFileError, match="no such file"):
        load(tmp_path / "missing.json")
    with pytest.raises(ModelFileError, match="is a directory"):
        load(tmp_path)
    (tmp_path / "bin.json").write_bytes(b"\xff\xfe\x00")
    with pytest.raises(ModelFileError, match="not UTF-8"):
        load(tmp_path / "bin.json")


def test_dot_errors():
    with pytest.raises(ParseError) as info:
        from_dot('digraph "M" {\n  "a" -> ;\n}', source="m.dot")
    assert info.value.line == 2 and str(info.value).startswith("m.dot:2:")
    with pytest.raises(ModelFileError, match="no delkit_kind attribute.*JSON schema"):
        from_dot('digraph G { a -> b; }', source="other.dot")
    good = to_dot(KripkeModel.build([{"p"}, set()], {"a": {"pairs": [(0, 1)]}}))
    with pytest.raises(ModelFileError, match="has agent 'z'"):
        from_dot(good.replace('delkit_agent="a"', 'delkit_agent="z"'), source="m.dot")
    # comments and other attribute layouts that DOT allows are read
    tweaked = "// a comment\n" + good.replace("node [shape=ellipse];", "node [shape=ellipse]; /* c */ rankdir=LR")
    assert bisimilar(from_dot(tweaked), from_dot(good))
