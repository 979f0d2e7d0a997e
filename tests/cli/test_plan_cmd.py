"""``delkit plan`` and ``delkit check`` in-process: JSON output and exit statuses (0 / 1 / 2 / 3)."""

from __future__ import annotations

import json

import pytest

from delkit.cli import main
from planners.demo import specs_dir
from planners.lang import shared_benchmarks

D = specs_dir() / "coin_in_the_box"
DOM, PROB, PLAN = str(D / "domain.epddl"), str(D / "problem.epddl"), str(D / "problem.plan")


def _run(capsys, argv: list[str]) -> tuple[int, str, str]:
    rc = main(argv)
    out = capsys.readouterr()
    return rc, out.out, out.err


def test_plan_json(capsys) -> None:
    rc, out, _ = _run(capsys, ["plan", DOM, PROB, "--json"])
    data = json.loads(out)
    assert rc == 0 and data["status"] == "solved"
    assert data["plan"] == ["signal_a_b", "open_a", "peek_b"] and data["length"] == 3
    assert {"expanded", "generated", "seconds"} <= set(data)


@pytest.mark.parametrize("search", ["gbfs", "astar"])
def test_plan_other_searches(capsys, search: str) -> None:
    rc, out, _ = _run(capsys, ["plan", DOM, PROB, "--search", search, "--json"])
    assert rc == 0 and json.loads(out)["length"] >= 3


def test_plan_mastar_benchmark(capsys) -> None:
    bench = shared_benchmarks()
    if bench is None:
        pytest.skip("../shared/benchmarks is not available")
    f = bench / "mastar" / "SC" / "SC_4_2" / "SC_4_2__pl_8.txt"
    rc, out, _ = _run(capsys, ["plan", str(f), "--json"])
    assert rc == 0 and json.loads(out)["length"] == 8


def test_plan_limit_is_a_failure(capsys) -> None:
    rc, out, _ = _run(capsys, ["plan", DOM, str(D / "common.epddl"), "--max-nodes", "2", "--json"])
    data = json.loads(out)
    assert rc == 3 and data["status"] == "limit" and data["plan"] is None


def test_check_valid_and_properties(capsys) -> None:
    rc, out, _ = _run(capsys, ["check", DOM, PROB, PLAN, "--properties", str(D / "problem.props"),
                               "--property", "eventually K_b tail", "--json"])
    assert rc == 0 and json.loads(out)["valid"] is True


def test_check_invalid_reports_step(capsys, tmp_path) -> None:
    bad = tmp_path / "bad.plan"
    bad.write_text("open_a\npeek_b\n")
    rc, out, _ = _run(capsys, ["check", DOM, PROB, str(bad), "--json"])
    data = json.loads(out)
    assert rc == 1 and data["valid"] is False and data["step"] == 2 and data["agent"] == "b"
    assert data["kind"] == "precondition"
    rc, out, _ = _run(capsys, ["check", DOM, PROB, PLAN, "--property", "always ~opened"])
    assert rc == 1 and "INVALID at step 2" in out


def test_check_bad_input_exit_2(capsys, tmp_path) -> None:
    rc, _, err = _run(capsys, ["check", DOM, PROB, str(tmp_path / "missing.plan")])
    assert rc == 2 and "missing.plan" in err
    bad = tmp_path / "x.txt"
    bad.write_text("fluent p;\nagent a;\naction x;\nx causes r;\ngoal p;")
    rc, _, err = _run(capsys, ["plan", str(bad)])
    assert rc == 2 and "x.txt:4:10" in err
    rc, _, err = _run(capsys, ["check", DOM, PROB, PLAN, "--property", "sometimes p"])
    assert rc == 2
    rc, _, err = _run(capsys, ["check", DOM, PROB, PLAN, str(tmp_path / "extra")])
    assert rc == 2


def test_check_accepts_efp_plan_from_expected_csv(capsys, tmp_path) -> None:
    import csv

    bench = shared_benchmarks()
    if bench is None:
        pytest.skip("../shared/benchmarks is not available")
    rows = {r["file"]: r for r in csv.DictReader((bench / "mastar" / "expected.csv").open())}
    name = "CC/CC_2_2_3/CC_2_2_3__pl_8.txt"
    plan_file = tmp_path / "efp.plan"
    plan_file.write_text(rows[name]["efp_plan"])
    rc, out, _ = _run(capsys, ["check", str(bench / "mastar" / name), str(plan_file), "--json"])
    assert rc == 0 and json.loads(out) == {"valid": True, "steps": 8}
    plan_file.write_text(", ".join(rows[name]["efp_plan"].split(", ")[:-1]))
    rc, out, _ = _run(capsys, ["check", str(bench / "mastar" / name), str(plan_file), "--json"])
    assert rc == 1 and json.loads(out)["kind"] == "goal"
