"""`delkit demo` runs its sections end to end and reports each one."""

from __future__ import annotations

import json

from delkit.cli import main


def test_demo_puzzles_planning_and_consistency_sections(tmp_path, capsys):
    rc = main(["demo", "--out", str(tmp_path), "--only", "puzzles", "--only", "planning", "--only", "consistency",
               "--json"])
    out = json.loads(capsys.readouterr().out)
    assert rc == 0 and out["ok"] is True
    titles = [s["section"] for s in out["sections"]]
    assert len(titles) == 3 and all(s["ok"] for s in out["sections"])
    puzzles = json.loads((tmp_path / "puzzles.json").read_text())
    answers = {r["puzzle"].split(":")[0].split(" (")[0]: r["answer"] for r in puzzles}
    assert answers["sum and product"] == [[4, 13]]
    assert (tmp_path / "demo.json").exists() and (tmp_path / "planner.json").exists()


def test_version(capsys):
    assert main(["version"]) == 0
    assert capsys.readouterr().out.strip().count(".") == 2
