"""``delkit smcdel``: SMCDEL's input language, answered on the symbolic backend.

The files in ``specs/smcdel/`` are delkit's own equivalents of SMCDEL's bundled examples (muddy children,
drinking logicians, dining cryptographers) plus a group-announcement example; the expected answers are
SMCDEL's documented answers for its examples (and hand-derived for the private announcement). Every
answer is also cross-checked against the explicit engine on the translated Kripke model.
"""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from delkit.cli import main
from delkit.errors import ParseError
from delkit.io.smcdel import answer, check_file, parse_smcdel, structure

SPECS = Path(__file__).resolve().parents[2] / "specs" / "smcdel"

EXPECTED = {
    "muddy3": [True, True, [[1], [2], [3]], True],
    "drinking3": [True, True, True, True, [[1, 2, 3]]],
    "dining3": [True, True, True, True],
    "private": [True, True, False, [[]], True, True, True, True],
    # belief structures (delkit's REL extension). Sally-Anne: the first answer is SMCDEL's documented one
    # (SMCDEL.Examples.SallyAnne: Sally believes the marble is in the basket); the rest follow from the story.
    # Muddy children: the first three are SMCDEL's tests of its belief-structure version; the rest must equal
    # the answers of the S5 file muddy3 (checked below).
    "sallyanne": [True, True, True, True, True, [[1, 2], [1, 3]], True],
    "muddy3-belief": [True, True, True, True, True, [[1], [2], [3]], True],
}


@pytest.mark.parametrize("name", sorted(EXPECTED))
def test_smcdel_examples_give_the_documented_answers(name: str) -> None:
    rows = check_file(str(SPECS / f"{name}.smcdel.txt"))
    assert [r["answer"] for r in rows] == EXPECTED[name]


@pytest.mark.parametrize("name", sorted(EXPECTED))
def test_smcdel_answers_agree_with_the_explicit_engine(name: str) -> None:
    spec = parse_smcdel((SPECS / f"{name}.smcdel.txt").read_text())
    ks = structure(spec)
    model = ks.to_kripke()
    states = ks.states()
    for q, row in zip(spec.queries, answer(spec), strict=True):
        truth = list(model.check(q.formula))
        if q.kind == "true":
            at = [i for i, s in enumerate(states) if {int(v) for v, val in s.items() if val} == set(q.state)]
            assert row["answer"] == truth[at[0]]
        elif q.kind == "valid":
            assert row["answer"] == all(truth)
        elif q.kind == "where":
            where = sorted(sorted(int(v) for v, val in s.items() if val) for s, t in zip(states, truth, strict=True)
                           if t)
            assert row["answer"] == where


def test_smcdel_cli_json_and_text(capsys) -> None:
    assert main(["smcdel", str(SPECS / "muddy3.smcdel.txt"), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["queries"][2]["answer"] == [[1], [2], [3]] and out["queries"][2]["line"] == 18
    assert main(["smcdel", str(SPECS / "muddy3.smcdel.txt")]) == 0
    text = capsys.readouterr().out
    assert "At which states is" in text and "[1]\n[2]\n[3]" in text


@pytest.mark.parametrize(("text", "where", "message"), [
    ("VARS 1,2\nLAW Top\nOBS a: 1\nVALID? a knows that (1 & )\n", (4, 26), "unexpected ')'"),
    ("VARS 1,2\nLAW Top\nOBS a: 1\nVALID? b knows that 2\n", (4, 8), "unknown agent 'b'"),
    ("VARS 1,2\nLAW Top\nOBS a: 1\nVALID? a knows that 3\n", (4, 21), "variable 3 is not declared"),
    ("VARS 1,2\nLAW Top\nOBS a: 7\n", (3, 5), "observes [7]"),
    ("VARS 1\nLAW Top\nOBS a: 1\nVALID? K a\n", (4, 11), "unexpected end of file"),
])
def test_smcdel_errors_have_line_and_column(text: str, where: tuple[int, int], message: str) -> None:
    with pytest.raises(ParseError) as info:
        parse_smcdel(text, source="f.smcdel.txt")
    assert (info.value.line, info.value.column) == where
    assert message in str(info.value)


def test_smcdel_cli_error_is_one_line(tmp_path, capsys) -> None:
    bad = tmp_path / "bad.smcdel.txt"
    bad.write_text("VARS 1\nLAW Top\nOBS a: 1\nVALID? a knows that (1 &\n")
    assert main(["smcdel", str(bad)]) == 2
    err = capsys.readouterr().err
    assert err.startswith("delkit: error: ") and err.count("\n") == 1 and ":4:25:" in err


def test_belief_file_is_a_belief_structure_and_matches_the_s5_file() -> None:
    from delkit.backends.symbolic_belief import BeliefStructure

    spec = parse_smcdel((SPECS / "muddy3-belief.smcdel.txt").read_text())
    assert isinstance(structure(spec), BeliefStructure) and spec.relations is not None
    s5 = [r["answer"] for r in check_file(str(SPECS / "muddy3.smcdel.txt"))]
    assert [r["answer"] for r in answer(spec)][3:] == s5
    # the relations written as formulas over V and V' give the S5 model of the OBS file
    from delkit.models.bisimulation import diff

    obs = structure(parse_smcdel((SPECS / "muddy3.smcdel.txt").read_text()))
    assert diff(structure(spec), obs).bisimilar


def _sally_anne_story():
    """The four steps of the story as event models (factual change), applied to the initial model."""
    from delkit import EventModel, KripkeModel

    agents = ["anne", "sally"]
    start = KripkeModel.build([{"1"}], {a: [[0]] for a in agents}, designated=[0], props=["1", "2"])

    def public(post: dict) -> EventModel:
        return EventModel.build({"e": {"post": post}}, {a: [["e"]] for a in agents}, ["e"])

    # Anne moves the marble (or nothing happens); Anne sees which, Sally takes it that nothing happened
    move = EventModel.build({"move": {"post": {"2": "F"}}, "skip": {}},
                            {"anne": [["move"], ["skip"]], "sally": {"pairs": [("move", "skip"), ("skip", "skip")]}},
                            ["move"])
    return start, [public({"2": "T"}), public({"1": "F"}), move, public({"1": "T"})]


def test_sally_anne_file_is_the_result_of_the_story() -> None:
    """The belief structure written in sallyanne.smcdel.txt is bisimilar (on variables 1, 2, at the actual
    state {1,3}) to the story computed step by step — explicitly (product update) and symbolically (products
    of the belief structure with the event models)."""
    from delkit import product_update
    from delkit.backends.symbolic_belief import belief_from_kripke
    from delkit.models.bisimulation import diff

    spec = parse_smcdel((SPECS / "sallyanne.smcdel.txt").read_text())
    written = structure(spec).to_kripke()
    states = structure(spec).states()
    actual = [i for i, s in enumerate(states) if s == {"1": True, "2": False, "3": True}]
    written = written.with_designated(actual)
    start, steps = _sally_anne_story()
    explicit = start
    symbolic, _ = belief_from_kripke(start)
    for e in steps:
        explicit = product_update(explicit, e)
        symbolic = symbolic.transform(e)
    assert diff(explicit, written, props=["1", "2"]).bisimilar
    assert diff(symbolic.to_kripke(["1", "2"]), written, props=["1", "2"]).bisimilar
    # and the false belief, on the story itself
    from delkit.logic.formula import K, Not, Prop, conj

    marble_in_basket = Prop("2")
    assert explicit.holds(conj([K("sally", marble_in_basket), Not(marble_in_basket), K("anne", Not(marble_in_basket))]))


def test_primed_variables_only_in_rel_lines() -> None:
    with pytest.raises(ParseError) as info:
        parse_smcdel("VARS 1\nLAW Top\nREL a: 1'\nVALID? a believes that 1'\n", source="b.smcdel.txt")
    assert (info.value.line, info.value.column) == (4, 24) and "outside a REL line" in str(info.value)
    with pytest.raises(ParseError, match="variable 2 is not declared"):
        parse_smcdel("VARS 1\nLAW Top\nREL a: 2'\n")
