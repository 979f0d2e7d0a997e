"""``delkit plan --plan-out FILE`` writes a JSON plan file that ``delkit check`` and ``delkit view`` read; the
plan file never replaces an input (compared by os.path.samefile: symlinks and hard links included)."""

from __future__ import annotations

import json
import os
import shutil
from pathlib import Path

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from delkit.cli import main
from delkit.errors import ParseError
from planners.plan_file import parse_plan_json, plan_document

ROOT = Path(__file__).resolve().parents[2]
COIN = ROOT / "specs" / "coin_in_the_box"


@pytest.fixture
def task(tmp_path):
    for name in ("domain.epddl", "problem.epddl"):
        shutil.copy(COIN / name, tmp_path / name)
    return tmp_path / "domain.epddl", tmp_path / "problem.epddl"


def test_plan_out_is_read_by_check_and_view(task, tmp_path, capsys):
    dom, prob = task
    out = tmp_path / "plan.json"
    assert main(["plan", str(dom), str(prob), "--timeout", "0", "--json", "--plan-out", str(out)]) == 0
    printed = json.loads(capsys.readouterr().out)
    doc = json.loads(out.read_text())
    assert doc["plan"] == printed["plan"] and doc["format"] == "delkit-plan" and printed["plan_file"] == str(out)
    assert main(["check", str(dom), str(prob), str(out), "--json"]) == 0
    verdict = json.loads(capsys.readouterr().out)
    assert verdict["valid"] is True
    from delkit.view.document import load_document

    view = load_document([dom, prob, out])
    assert len(view.frames) == len(doc["plan"]) + 1
    assert [f.title.split(": ", 1)[1] for f in view.frames[1:]] == doc["plan"]


def test_check_reads_the_output_of_plan_json(task, tmp_path, capsys):
    dom, prob = task
    assert main(["plan", str(dom), str(prob), "--timeout", "0", "--json"]) == 0
    (tmp_path / "printed.json").write_text(capsys.readouterr().out)
    assert main(["check", str(dom), str(prob), str(tmp_path / "printed.json")]) == 0


@pytest.mark.parametrize("link", ["same path", "symlink", "hard link", "relative path"])
def test_plan_out_never_replaces_an_input(task, tmp_path, capsys, link):
    dom, prob = task
    before = prob.read_bytes()
    if link == "same path":
        out = prob
    elif link == "symlink":
        out = tmp_path / "sym.json"
        out.symlink_to(prob)
    elif link == "hard link":
        out = tmp_path / "hard.json"
        os.link(prob, out)
    else:
        out = Path(os.path.relpath(prob))
    assert main(["plan", str(dom), str(prob), "--timeout", "0", "--plan-out", str(out)]) == 2
    assert "would overwrite the input file" in capsys.readouterr().err
    assert prob.read_bytes() == before


def test_plan_out_is_refused_for_a_directory_and_a_batch(task, tmp_path, capsys):
    dom, prob = task
    assert main(["plan", str(dom), str(prob), "--timeout", "0", "--plan-out", str(tmp_path)]) == 2
    assert "is a directory" in capsys.readouterr().err
    assert main(["plan", str(dom), str(prob), "--timeout", "0", "--plan-out", str(tmp_path / "p.json"),
                 "--jobs", "2"]) == 2
    assert "one task" in capsys.readouterr().err
    assert not (tmp_path / "p.json").exists()


@pytest.mark.parametrize("text, says", [("{not json", "not JSON"), ('{"plan": null, "status": "unsolvable"}',
                                                                     "records no plan"),
                                        ('{"steps": []}', 'no "plan" field'), ('{"plan": [1, 2]}', "list of action"),
                                        ('{"plan": "open_a"}', "list of action"), ('{"plan": [""]}', "list of action")])
def test_bad_json_plan_files_are_exit_2_with_the_reason(task, tmp_path, capsys, text, says):
    dom, prob = task
    (tmp_path / "bad.json").write_text(text)
    assert main(["check", str(dom), str(prob), str(tmp_path / "bad.json")]) == 2
    assert says in capsys.readouterr().err


@settings(max_examples=60, deadline=None)
@given(st.lists(st.text(alphabet=st.characters(blacklist_categories=("Cs",)), min_size=1).filter(str.strip),
                max_size=8))
def test_a_plan_file_reads_back_the_plan_it_was_written_with(plan):
    doc = plan_document("t", ["d", "p"], {"plan": plan, "length": len(plan), "search": "bfs", "status": "solved"})
    assert parse_plan_json(json.dumps(doc), "plan.json") == [a.strip() for a in plan]


def test_parse_errors_point_into_the_file():
    with pytest.raises(ParseError) as e:
        parse_plan_json('{\n  "plan": [,]\n}', "p.json")
    assert e.value.line == 2
