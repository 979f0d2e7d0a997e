"""``delkit consistency table`` and ``delkit consistency run`` (in-process)."""

from __future__ import annotations

import json

from delkit.cli import main
from sim.sar import SARConfig, run_episode


def test_table_json_has_every_row_beside_the_paper(capsys) -> None:
    rc = main(["consistency", "table", "--epochs", "12", "--seed", "2", "--json"])
    assert rc == 0
    out = json.loads(capsys.readouterr().out)
    rows = out["rows"]
    assert len(rows) == 21 and out["epochs"] == 12
    assert {r["algorithm"] for r in rows} == {"Baseline-I", "Baseline-II", "ENFORCEAC"}
    # the computed figures, not the paper's: row 2 is ENFORCEAC on the first input, as run_episode gives it
    first = rows[2]
    direct = run_episode(SARConfig(epochs=12, seed=2), "enforce")
    assert first["algorithm"] == "ENFORCEAC"
    assert (first["not_ac"], first["comm"], first["observations_sent"]) == (
        direct.not_ac, direct.comms, direct.observations_sent)
    assert first["comm"] < rows[1]["comm"]  # fewer messages than Baseline-I on the same input
    for r in rows:
        if r["comm_restr"] == 0 and r["algorithm"] != "Baseline-II":
            assert r["not_ac"] == 0
        if r["algorithm"] == "Baseline-II":
            assert r["comm"] == 0


def test_table_prints_a_rich_table(capsys) -> None:
    assert main(["consistency", "table", "--epochs", "5"]) == 0
    out = capsys.readouterr().out
    direct = run_episode(SARConfig(epochs=5, seed=0), "baseline1")
    assert "ENFORCEAC" in out and "Baseline-II" in out and str(direct.observations_sent) in out


def test_run_with_three_robots(capsys) -> None:
    rc = main(["consistency", "run", "--robots", "3", "--epochs", "15", "--algorithm", "enforce", "--json"])
    assert rc == 0
    (res,) = json.loads(capsys.readouterr().out)["results"]
    assert res["algorithm"] == "enforce" and res["config"]["robots"] == 3
    assert res["not_ac"] == 0 and res["violations"] == 0
    assert main(["consistency", "run", "--epochs", "5"]) == 0
    assert "Baseline-I" in capsys.readouterr().out


def test_bad_options_exit_2_with_one_line(capsys) -> None:
    assert main(["consistency", "run", "--primitives", "5"]) == 2
    err = capsys.readouterr().err
    assert "primitives must be 4 or 8" in err and "Traceback" not in err
    assert main(["consistency", "run", "--algorithm", "psychic"]) == 2
    assert "--algorithm" in capsys.readouterr().err
