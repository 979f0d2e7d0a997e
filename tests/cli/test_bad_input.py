"""Bad input on the command line: every bad input is one ``delkit: error:`` line with exit status 2
that says where the problem is (option, properties file line, plan step)."""

from __future__ import annotations

import json

import pytest

from delkit.cli import main
from planners.demo import specs_dir

DOM, PROB, PLAN = (str(specs_dir() / "coin_in_the_box" / f) for f in ("domain.epddl", "problem.epddl",
                                                                       "problem.plan"))


def _run(capsys, argv: list[str]) -> tuple[int, str, str]:
    """Exit status, stdout and stderr of ``delkit ARGV`` run in-process."""
    rc = main(argv)
    captured = capsys.readouterr()
    return rc, captured.out, captured.err


def _one_error_line(err: str) -> str:
    lines = err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("delkit: error: "), err
    return lines[0]


@pytest.mark.parametrize(("argv", "fragment"), [
    (["plan", DOM, PROB, "--timeout", "abc"], "delkit plan: Invalid value for '--timeout'"),
    (["prove"], "delkit prove: Missing argument 'formula'"),
    (["puzzle", "muddy", "--bogus"], "No such option: --bogus"),
    (["no-such-command"], "No such command 'no-such-command'"),
])
def test_usage_errors_are_one_line_with_the_command_and_how_to_get_help(capsys, argv, fragment) -> None:
    rc, out, err = _run(capsys, argv)
    line = _one_error_line(err)
    assert rc == 2 and out == "" and fragment in line and line.endswith("--help'")


@pytest.mark.parametrize("option", [["--timeout", "-5"], ["--max-nodes", "-1"], ["--max-memory", "0"]])
def test_plan_rejects_impossible_limits_as_bad_input(capsys, option) -> None:
    rc, out, err = _run(capsys, ["plan", DOM, PROB, *option, "--json"])
    assert rc == 2 and out == "" and "impossible" in _one_error_line(err)


def test_check_names_the_properties_file_and_line(tmp_path, capsys) -> None:
    props = tmp_path / "p.props"
    props.write_text("# comment\nalways has_key_a\n\nsometimes opened\n")
    rc, _, err = _run(capsys, ["check", DOM, PROB, PLAN, "--properties", str(props)])
    assert rc == 2 and f"{props}:4:1: property 'sometimes opened'" in _one_error_line(err)

    props.write_text("always has_key_a\nat end  K_a (\n")       # formula error: column in the file's line
    rc, _, err = _run(capsys, ["check", DOM, PROB, PLAN, "--properties", str(props)])
    assert rc == 2 and f"{props}:2:14: unexpected end of formula" in _one_error_line(err)

    props.write_text("always has_key_a\n\nat end K_zz tail\n")    # unknown agent: which line, which formula
    rc, _, err = _run(capsys, ["check", DOM, PROB, PLAN, "--properties", str(props)])
    line = _one_error_line(err)
    assert rc == 2 and f"{props}:3: 'K_zz tail'" in line and "unknown agent(s) ['zz']" in line


def test_check_reports_the_mastar_error_that_got_further(capsys) -> None:
    rc, _, err = _run(capsys, ["check", DOM, PROB, PLAN, "-p", "always B(zz, tail)"])
    assert rc == 2 and "--property:1:10: unknown agent 'zz'" in _one_error_line(err)


def test_check_names_the_plan_file_and_step_of_an_unknown_action(tmp_path, capsys) -> None:
    plan = tmp_path / "p.plan"
    plan.write_text("signal_a_b\nopen_a\nfly_away\n")
    rc, _, err = _run(capsys, ["check", DOM, PROB, str(plan)])
    line = _one_error_line(err)
    assert rc == 2 and f"{plan}: step 3:" in line and "no action named 'fly_away'" in line


@pytest.mark.parametrize("command", ["run", "table"])
def test_consistency_rejects_zero_epochs(capsys, command) -> None:
    rc, out, err = _run(capsys, ["consistency", command, "--epochs", "0", "--json"])
    assert rc == 2 and out == "" and "--epochs must be at least 1" in _one_error_line(err)


def test_consistency_run_one_epoch_table_and_json(capsys) -> None:
    rc, out, _ = _run(capsys, ["consistency", "run", "--epochs", "1", "--algorithm", "enforce", "--json"])
    assert rc == 0 and json.loads(out)["results"][0]["config"]["epochs"] == 1
    rc, out, _ = _run(capsys, ["consistency", "run", "--epochs", "1", "--algorithm", "enforce"])
    assert rc == 0 and "ENFORCEAC" in out.upper()


def test_an_unwritable_output_path_in_any_command_is_one_line(tmp_path, capsys) -> None:
    """OSError from a path the user gave (here explore's --out under a file) is bad input, not a traceback."""
    blocker = tmp_path / "file"
    blocker.write_text("")
    rc, out, err = _run(capsys, ["explore", "sweep", "--robots", "2", "--maps", "1", "--methods", "ideal",
                                 "--case", "1", "--no-snapshots", "--out", str(blocker / "x")])
    line = _one_error_line(err)
    assert rc == 2 and str(blocker) in line and "Traceback" not in err


def test_a_formula_nested_too_deeply_is_one_line(capsys) -> None:
    rc, out, err = _run(capsys, ["prove", "~" * 2000 + "p"])
    assert rc == 2 and out == "" and "nested too deeply" in _one_error_line(err)


def test_a_modal_chain_too_deep_for_z3_is_one_line(capsys) -> None:
    """Found by the 5,000-input fuzz: z3's Python API reports the recursion limit as a ctypes.ArgumentError
    (400 nested K_a are parsed, but too deep for z3's term conversion)."""
    rc, out, err = _run(capsys, ["prove", "K_a " * 400 + "p"])
    assert rc == 2 and out == "" and "nested too deeply for z3" in _one_error_line(err)


def test_a_binary_handwritten_macro_is_one_line(tmp_path, capsys) -> None:
    """Found by the 5,000-input fuzz (was a UnicodeDecodeError traceback)."""
    binary = tmp_path / "m.txt"
    binary.write_bytes(b"\x00\x01\x9e\xff")
    rc, out, err = _run(capsys, ["epico", "macros", "--colors", "2", "--handwritten", str(binary), "--json"])
    assert rc == 2 and out == "" and "not UTF-8" in _one_error_line(err)


@pytest.mark.parametrize("where", ["plan", "properties", "mastar", "problem"])
def test_a_binary_file_is_one_line_not_a_unicode_traceback(tmp_path, capsys, where) -> None:
    binary = tmp_path / "binary.txt"
    binary.write_bytes(bytes(range(128, 256)))
    argv = {"plan": ["check", DOM, PROB, str(binary)],
            "properties": ["check", DOM, PROB, PLAN, "--properties", str(binary)],
            "mastar": ["plan", str(binary)],
            "problem": ["plan", DOM, str(binary)]}[where]
    rc, out, err = _run(capsys, argv)
    line = _one_error_line(err)
    assert rc == 2 and out == "" and f"{binary}: cannot read" in line and "not UTF-8 text" in line


@pytest.mark.parametrize(("prop", "keyword"), [("always", "always"), ("at end ", "at end"),
                                               ("eventually", "eventually")])
def test_a_property_without_a_formula_says_so(capsys, prop, keyword) -> None:
    rc, _, err = _run(capsys, ["check", DOM, PROB, PLAN, "-p", prop])
    assert rc == 2 and f"has no formula after '{keyword}'" in _one_error_line(err)


def test_explore_options_out_of_range_are_one_line_usage_errors(capsys):
    for argv in (["explore", "gap", "--instances", "0"], ["explore", "run", "--t-max", "-1"],
                 ["explore", "sweep", "--workers", "0"]):
        assert main(argv) == 2, argv
        err = capsys.readouterr().err
        assert "Traceback" not in err and err.strip().count("\n") == 0, err
