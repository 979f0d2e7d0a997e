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
from delkit.smcdel import answer, check_file, parse_smcdel, structure

SPECS = Path(__file__).resolve().parents[2] / "specs" / "smcdel"

EXPECTED = {
    "muddy3": [True, True, [[1], [2], [3]], True],
    "drinking3": [True, True, True, True, [[1, 2, 3]]],
    "dining3": [True, True, True, True],
    "private": [True, True, False, [[]], True, True, True, True],
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
        if q.kind == "valid":
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
