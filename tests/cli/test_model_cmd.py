"""In-process tests of `delkit model ...` and `delkit prove`."""

from __future__ import annotations

import json

import pytest

from delkit import KripkeModel, bisimilar, compose, ontic, public_announcement, sensing
from delkit.cli import main
from delkit.io.formats import load, load_model, save

MUDDY2 = {
    # two muddy children, both muddy (world "mm"); each sees the other's forehead
    "delkit": "kripke-model", "version": 1, "props": ["m1", "m2"], "agents": ["c1", "c2"],
    "worlds": [{"name": "mm", "true": ["m1", "m2"]}, {"name": "mc", "true": ["m1"]},
               {"name": "cm", "true": ["m2"]}, {"name": "cc", "true": []}],
    "relations": {"c1": {"blocks": [["mm", "cm"], ["mc", "cc"]]}, "c2": {"blocks": [["mm", "mc"], ["cm", "cc"]]}},
    "designated": ["mm"],
}


@pytest.fixture
def muddy(tmp_path):
    path = tmp_path / "muddy.json"
    path.write_text(json.dumps(MUDDY2))
    return path


def test_check_human_output_and_exit_codes(muddy, capsys):
    assert main(["model", "check", str(muddy), "~K_c1 m1 & ~K_c2 m2"]) == 0
    out = capsys.readouterr().out
    assert "holds at the designated world(s) mm" in out and "true at 4 of 4" in out
    # after the father's announcement and one round of "nobody knows", both know (muddy children, m = 2)
    f = "[!(m1 | m2)] [!(~Kw_c1 m1 & ~Kw_c2 m2)] (K_c1 m1 & K_c2 m2)"
    assert main(["model", "check", str(muddy), f]) == 0
    assert main(["model", "check", str(muddy), "[!(m1 | m2)] K_c1 m1"]) == 1
    assert "does NOT hold" in capsys.readouterr().out


def test_check_json(muddy, capsys):
    assert main(["model", "check", str(muddy), "K_c1 m2", "--json"]) == 0
    d = json.loads(capsys.readouterr().out)
    assert d == {"formula": "K_c1 m2", "holds": True, "designated": ["mm"], "true_at": ["mm", "cm"],
                 "n_worlds": 4, "inconsistent_beliefs": []}


def test_check_with_an_event_model_file(muddy, tmp_path, capsys):
    ev = tmp_path / "father.json"
    save(public_announcement("m1 | m2", ["c1", "c2"], name="father"), ev)
    assert main(["model", "check", str(muddy), "[F,e] C{c1,c2} (m1 | m2)", "--event", f"F={ev}"]) == 0
    assert main(["model", "check", str(muddy), "[F,e] p", "--event", "F"]) == 2
    assert "write NAME=FILE.json" in capsys.readouterr().err


@pytest.mark.parametrize(("args", "message"), [
    (["model", "check", "{muddy}", "K_c3 m1"], "unknown agent(s) ['c3']"),
    (["model", "check", "{muddy}", "K_c1 (m1"], "<formula>:1:9: unexpected end of formula"),
    (["model", "check", "{muddy}", "K_c1 zz"], "unknown proposition(s) ['zz']"),
    (["model", "check", "{tmp}/nope.json", "p"], "nope.json: no such file"),
    (["model", "check", "{muddy}", "[X,e] p"], "unknown event model 'X'"),
    (["prove", "K_a p", "--logic", "S4"], "--logic 'S4': use one of S5, KD45, K"),
    (["prove", "K_a (p"], "unexpected end of formula"),
])
def test_bad_input_is_one_line_and_exit_2(args, message, muddy, tmp_path, capsys):
    args = [a.format(muddy=muddy, tmp=tmp_path) for a in args]
    assert main(args) == 2
    err = capsys.readouterr().err.strip()
    assert err.startswith("delkit: error:") and message in err and "\n" not in err


def test_malformed_model_file(tmp_path, capsys):
    bad = tmp_path / "bad.json"
    bad.write_text('{"delkit": "kripke-model",\n "worlds": [}')
    assert main(["model", "check", str(bad), "p"]) == 2
    assert f"{bad}:2:13: invalid JSON" in capsys.readouterr().err


def test_dot_to_stdout_and_file(muddy, tmp_path, capsys):
    assert main(["model", "dot", str(muddy)]) == 0
    out = capsys.readouterr().out
    assert out.startswith("digraph") and '"mm" -> "cm" [label="c1"' in out
    target = tmp_path / "m.dot"
    assert main(["model", "dot", str(muddy), "-o", str(target)]) == 0
    assert bisimilar(load(target), load(muddy))
    # the DOT file is itself a model file for the other commands
    assert main(["model", "check", str(target), "K_c2 m1"]) == 0


def test_contract(tmp_path, capsys):
    # two copies of the same world: contraction merges them
    m = KripkeModel.build([{"p"}, {"p"}, set()], {"a": [[0, 1, 2]]}, designated=[0])
    src = tmp_path / "dup.json"
    save(m, src)
    out = tmp_path / "small.json"
    assert main(["model", "contract", str(src), "-o", str(out)]) == 0
    assert "contracted 3 world(s) to 2" in capsys.readouterr().err
    small = load_model(out)
    assert small.n_worlds == 2 and bisimilar(small, m)
    assert main(["model", "contract", str(src)]) == 0
    assert json.loads(capsys.readouterr().out)["delkit"] == "kripke-model"


def test_show(muddy, capsys):
    assert main(["model", "show", str(muddy)]) == 0
    out = capsys.readouterr().out
    assert "4 worlds" in out and "frame: S5, KD45" in out


def test_prove_valid_and_invalid(capsys):
    assert main(["prove", "K_a p -> K_a K_a p"]) == 0  # one agent: a proof (small-model bound)
    assert capsys.readouterr().out == "K_a p -> K_a K_a p: valid\n"
    assert main(["prove", "C{a,b} p -> K_a K_b p"]) == 0
    assert "no counter-model with at most 4 world(s) (S5)" in capsys.readouterr().out
    assert main(["prove", "p -> p | q"]) == 0
    assert ": valid" in capsys.readouterr().out
    assert main(["prove", "K_a p -> p", "--logic", "KD45", "--worlds", "3", "--json"]) == 1
    d = json.loads(capsys.readouterr().out)
    assert d["valid"] is False and d["logic"] == "KD45"
    from delkit.io.formats import model_from_dict

    cm = model_from_dict(d["counter_model"])
    assert cm.is_kd45() and not cm.holds("K_a p -> p")
    assert main(["prove", "K_a p & K_b p -> C{a,b} p", "-k", "3"]) == 1
    assert "NOT valid in S5" in capsys.readouterr().out


def test_macro_check(tmp_path, capsys):
    look = sensing("m1", ["c1", "c2"], full=["c1"], name="look")
    wipe = ontic({"m1": False}, ["c1", "c2"], full=["c1", "c2"], name="wipe")
    for name, obj in (("look", look), ("wipe", wipe), ("good", compose(look, wipe, prune=True)),
                      ("bad", compose(wipe, look))):
        save(obj, tmp_path / f"{name}.json")
    steps = [str(tmp_path / "look.json"), str(tmp_path / "wipe.json")]
    assert main(["model", "macro", str(tmp_path / "good.json"), *steps]) == 0
    assert "equals the composition of 2 step(s)" in capsys.readouterr().out
    assert main(["model", "macro", str(tmp_path / "bad.json"), *steps, "--json"]) == 1
    d = json.loads(capsys.readouterr().out)
    assert d["equivalent"] is False and any("not an event of the sequence" in p for p in d["problems"])
    assert main(["model", "macro", str(tmp_path / "good.json"), str(tmp_path / "nope.json")]) == 2


SPECS = __import__("pathlib").Path(__file__).resolve().parents[2] / "specs"


@pytest.mark.parametrize("args, language, reads", [
    (["model", "check", "{smcdel}", "1"], "SMCDEL's input language", "JSON model format (.json) or DOT"),
    (["model", "contract", "{smcdel}"], "SMCDEL's input language", "JSON model format (.json) or DOT"),
    (["model", "draw", "{epddl}", "-o", "{tmp}/x.svg"], "E-PDDL/EPDDL planning", "SMCDEL's language"),
    (["model", "diff", "{epddl}", "{smcdel}"], "E-PDDL/EPDDL planning", "SMCDEL's language"),
    (["model", "macro", "{epddl}", "{smcdel}"], "E-PDDL/EPDDL planning", "JSON model format (.json) or DOT"),
    (["model", "check", "{text}", "p"], "not a file this command reads", "it starts with 'hello world'"),
])
def test_a_file_in_another_language_is_named_with_the_formats_read(args, language, reads, tmp_path, capsys):
    """Regression: `model check FILE.smcdel.txt` and `model draw problem.epddl` said `invalid JSON: Expecting
    value`; now the message says what the file is, which formats the command reads and what reads it."""
    (tmp_path / "t.txt").write_text("hello world\n")
    files = {"smcdel": SPECS / "smcdel" / "muddy3.smcdel.txt", "epddl": SPECS / "coin_in_the_box" / "problem.epddl",
             "text": tmp_path / "t.txt", "tmp": tmp_path}
    assert main([a.format(**files) for a in args]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "invalid JSON" not in err
    assert language in err and reads in err


def test_smcdel_text_is_drawn_whatever_its_file_name(tmp_path, capsys):
    copy = tmp_path / "muddy.txt"  # SMCDEL's language, told by its VARS/LAW, not by a .smcdel.txt name
    copy.write_text((SPECS / "smcdel" / "muddy3.smcdel.txt").read_text())
    assert main(["model", "draw", str(copy), "-o", str(tmp_path / "m.svg")]) == 0
    assert (tmp_path / "m.svg").read_text().startswith("<svg")
