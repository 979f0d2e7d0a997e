"""Inputs, outputs, batches, limits and signals: the guards, one test each, and the fuzz families.

Fast tests call the guards or ``main(argv)`` in-process; the ones that need the console script (signals,
closed stdout, the watchdog) start it as a process and are kept short. The sweeps of the families in
``fuzzsafety.py`` are slow (``make test-slow``); a quick in-process slice runs here.
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).parent))
import fuzzgen  # noqa: E402
import fuzzsafety  # noqa: E402
from fuzzkit import Runner, classify_error_text  # noqa: E402

from delkit.cli import main  # noqa: E402

REPO = Path(__file__).resolve().parents[2]
COIN = REPO / "specs" / "coin_in_the_box"
SLOW_SEARCH = fuzzsafety.SLOW_SEARCH


def run_cli(capsys, argv):
    rc = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return rc, out, err


def console(argv, *, timeout=60, **kw):
    """The console script as a process: (rc, out, err, wall from just before the start)."""
    env = {**os.environ, "PYTHONPATH": str(REPO), "DELKIT_PROGRESS": "0"}
    t0 = time.monotonic()
    p = subprocess.run([sys.executable, "-c", "from delkit.cli import run; run()", *map(str, argv)],
                       capture_output=True, text=True, env=env, timeout=timeout, **kw)
    return p.returncode, p.stdout, p.stderr, time.monotonic() - t0


# ----------------------------------------------------------------------------- outputs never replace inputs

def _coin(tmp_path: Path) -> list[Path]:
    files = []
    for name in ("domain.epddl", "problem.epddl", "problem.plan"):
        (tmp_path / name).write_bytes((COIN / name).read_bytes())
        files.append(tmp_path / name)
    return files


@pytest.mark.parametrize("link", ["same", "symlink", "hardlink", "dotdot", "symlinked-folder"])
@pytest.mark.parametrize("victim", [0, 1, 2])
def test_trace_json_never_replaces_an_input(tmp_path, capsys, link, victim):
    files = _coin(tmp_path)
    target = files[victim]
    before = [f.read_bytes() for f in files]
    if link == "same":
        out = target
    elif link == "symlink":
        out = tmp_path / "ln.json"
        out.symlink_to(target.name)
    elif link == "hardlink":
        out = tmp_path / "hl.json"
        os.link(target, out)
    elif link == "dotdot":
        (tmp_path / "sub").mkdir()
        out = Path(f"{tmp_path}/sub/../{target.name}")
    else:
        (tmp_path / "via").symlink_to(".")
        out = tmp_path / "via" / target.name
    rc, _, err = run_cli(capsys, ["check", *files, "--trace-json", out])
    assert rc == 2 and classify_error_text(err) is None, err
    assert "--trace-json would overwrite the input file" in err and "nothing was written" in err
    assert [f.read_bytes() for f in files] == before


def test_trace_json_to_a_fresh_file_is_written(tmp_path, capsys):
    files = _coin(tmp_path)
    rc, _, err = run_cli(capsys, ["check", *files, "--trace-json", tmp_path / "trace.json"])
    assert rc == 0, err
    assert json.loads((tmp_path / "trace.json").read_text())


@pytest.mark.parametrize("cmd", ["dot", "contract", "draw"])
def test_model_output_through_a_hard_link_is_refused(tmp_path, capsys, cmd):
    from delkit.io.formats import save
    from delkit.puzzles.muddy import muddy_model

    m = tmp_path / "m.json"
    save(muddy_model(2, 1), m)
    before = m.read_bytes()
    out = tmp_path / ("pic.svg" if cmd == "draw" else "copy.json")
    os.link(m, out)
    rc, _, err = run_cli(capsys, ["model", cmd, m, "-o", out])
    assert rc == 2 and "hard link" in err and classify_error_text(err) is None, err
    assert m.read_bytes() == before


def test_epico_solve_out_never_replaces_the_world(tmp_path, capsys):
    w = tmp_path / "w.json"
    w.write_text(json.dumps(fuzzgen.epico_world()))
    before = w.read_bytes()
    (tmp_path / "ln.json").symlink_to("w.json")
    for out in (w, tmp_path / "ln.json"):
        rc, _, err = run_cli(capsys, ["epico", "solve", "--goal", "alpha", "--colors", "1", "--world", w, "--out", out])
        assert rc == 2 and "--out would overwrite the input file" in err, err
    assert w.read_bytes() == before


def test_refuse_overwrite_input_compares_files_not_names(tmp_path):
    from delkit.errors import ParseError
    from delkit.paths import refuse_overwrite_input

    a = tmp_path / "a"
    a.write_text("x")
    os.link(a, tmp_path / "b")
    with pytest.raises(ParseError, match="hard link"):
        refuse_overwrite_input([tmp_path / "b"], [a])
    refuse_overwrite_input([tmp_path / "c", None, "-"], [a, None])  # a fresh file, no output, stdout: fine
    refuse_overwrite_input([a], [a], force=True)  # --force given


# ----------------------------------------------------------------------------- inputs: regular files only

@pytest.mark.parametrize("kind", ["fifo", "/dev/zero", "/dev/null", "dir", "big"])
@pytest.mark.parametrize("argv", [["plan", "{x}"], ["check", "{domain}", "{problem}", "{x}"],
                                  ["model", "show", "{x}"], ["smcdel", "{x}"],
                                  ["check", "{domain}", "{problem}", "{plan}", "--properties", "{x}"]])
def test_inputs_that_are_not_regular_files_are_refused_at_once(tmp_path, capsys, monkeypatch, kind, argv):
    files = _coin(tmp_path)
    if kind == "fifo":
        x = tmp_path / "in.fifo"
        os.mkfifo(x)
    elif kind == "dir":
        x = tmp_path / "folder"
        x.mkdir()
    elif kind == "big":
        x = tmp_path / "big.txt"
        x.write_text("; x\n" * 1000)
        monkeypatch.setenv("DELKIT_MAX_INPUT_MB", "0.001")
    else:
        x = Path(kind)
    sub = {"{x}": x, "{domain}": files[0], "{problem}": files[1], "{plan}": files[2]}
    if kind == "big" and argv[0] == "check" and "--properties" not in argv:
        sub.update({"{domain}": COIN / "domain.epddl"})  # the cap applies to every input: only the victim is big
    t0 = time.monotonic()
    rc, _, err = run_cli(capsys, [sub.get(a, a) for a in argv])
    assert time.monotonic() - t0 < 5  # a FIFO opened for reading would block here forever
    assert rc == 2 and classify_error_text(err) is None, err
    why = {"fifo": "FIFO", "/dev/zero": "a device", "/dev/null": "a device", "dir": "directory",
           "big": "DELKIT_MAX_INPUT_MB"}[kind]
    assert why in err, err


def test_check_input_stats_before_it_opens(tmp_path, monkeypatch):
    """A FIFO is refused from its stat alone: opening it would block (here: open is made to fail loudly)."""
    import builtins

    from delkit.errors import ParseError
    from delkit.paths import read_input

    x = tmp_path / "f"
    os.mkfifo(x)
    monkeypatch.setattr(builtins, "open", lambda *a, **k: pytest.fail("opened before the stat"))
    with pytest.raises(ParseError, match="FIFO"):
        read_input(x)


# ----------------------------------------------------------------------------- addresses, jobs, numbers

@pytest.mark.parametrize("value", ["", " ", "tls://127.0.0.1:1", "tcp://127.0.0.1:99999999999999999999",
                                   "tcp://127.0.0.1:0", "tcp://127.0.0.1", "ucx://127.0.0.1:1", "tcp://[::1:1"])
def test_malformed_scheduler_addresses_are_refused_without_contact(value, monkeypatch):
    import socket

    from delkit.errors import DelkitError
    from delkit.executors import parse_scheduler

    monkeypatch.setattr(socket, "create_connection", lambda *a, **k: pytest.fail("contacted"))
    with pytest.raises(DelkitError, match="--scheduler") as info:
        parse_scheduler(value)
    if value.startswith("tls"):
        assert "TLS" in str(info.value)


def test_a_private_address_is_parsed_not_contacted(monkeypatch):
    """The address of the report (a private range): parsing accepts it and contacts nothing; this test never
    connects anywhere (the only connection attempted in these tests is to 127.0.0.1)."""
    import socket

    from delkit.executors import parse_scheduler

    monkeypatch.setattr(socket, "create_connection", lambda *a, **k: pytest.fail("contacted"))
    assert parse_scheduler("tcp://10.255.255.1:8786") == ("10.255.255.1", 8786)
    assert parse_scheduler("[::1]:8786") == ("::1", 8786)


def test_loopback_scheduler_with_nothing_listening_is_one_line(tmp_path, capsys):
    files = _coin(tmp_path)
    rc, _, err = run_cli(capsys, ["plan", files[0], files[1], "--scheduler", "tcp://127.0.0.1:1"])
    assert rc == 2 and "cannot reach the Dask scheduler" in err and classify_error_text(err) is None, err


@pytest.mark.parametrize("value", ["+2", "1000000000", "0", "-1", "0x2", "2.0", "99999999999999999999"])
def test_jobs_must_be_plain_digits_in_range(tmp_path, capsys, value):
    files = _coin(tmp_path)
    rc, _, err = run_cli(capsys, ["plan", files[0], files[1], f"--jobs={value}"])
    assert rc == 2 and "--jobs" in err and classify_error_text(err) is None, err


@pytest.mark.parametrize("argv", [["puzzle", "number-triangle", "-n", "1000000000"],
                                  ["puzzle", "number-triangle", "-n", "99999999999999999999"],
                                  ["puzzle", "number-triangle", "-n", "99999999999999999999", "--explicit"],
                                  ["puzzle", "prisoners", "--seed", "-1"]])
def test_puzzle_numbers_are_bounded_before_anything_is_built(capsys, argv):
    rc, _, err = run_cli(capsys, argv)
    assert rc == 2 and classify_error_text(err) is None, err


def test_closed_stdout_is_one_line_not_a_traceback(tmp_path):
    files = _coin(tmp_path)
    env = {**os.environ, "PYTHONPATH": str(REPO)}
    p = subprocess.run([sys.executable, "-c", "from delkit.cli import run; run()", "check", *map(str, files), "--json"],
                       capture_output=False, stderr=subprocess.PIPE, text=True, env=env, timeout=60,
                       preexec_fn=lambda: os.close(1))
    assert p.returncode == 2 and classify_error_text(p.stderr) is None, p.stderr


# ----------------------------------------------------------------------------- limit answers

def test_limit_answer_is_json_with_the_search_counters(capsys):
    rc, out, _ = run_cli(capsys, ["plan", SLOW_SEARCH[0], "--timeout", "1.5", "--json"])
    rec = json.loads(out)
    assert rc == 3 and rec["status"] == "limit" and rec["expanded"] > 0 and rec["generated"] > 0, rec


def test_a_limit_outside_the_search_is_json_too(capsys):
    rc, out, err = run_cli(capsys, ["puzzle", "sum-product", "--limit", "6000", "--timeout", "0.5", "--json"])
    rec = json.loads(out)
    assert rc == 3 and rec["status"] == "limit" and rec["exit"] == 3 and "--timeout 0.5" in rec["reason"], (out, err)


def test_the_watchdog_prints_the_limit_record_with_the_live_counters(capsys, monkeypatch):
    """When the body is stuck, the watchdog's answer is the JSON record with the counters the work stored."""
    import io

    import delkit.resources as r

    monkeypatch.setattr(r, "JSON_LIMITS", True)
    monkeypatch.setattr(r, "_ANSWERED", [])
    out = io.StringIO()
    monkeypatch.setattr(sys, "stdout", out)
    exits = []
    monkeypatch.setattr(os, "_exit", lambda code: exits.append(code))
    r._watchdog(time.monotonic() - 1, "x: no answer within --timeout 1 s", [False], {"expanded": 7, "generated": 40},
                time.monotonic() - 1.2)
    rec = json.loads(out.getvalue())
    assert exits == [3] and rec["status"] == "limit" and rec["expanded"] == 7 and rec["seconds"] >= 1.2, rec


def test_spent_budget_is_exit_3_not_bad_input(capsys, monkeypatch):
    """Whatever the load: a deadline already passed when a limit is handed on is a reached limit (exit 3)."""
    import delkit.resources as r

    monkeypatch.setattr(r, "remaining", lambda: -0.011)
    with pytest.raises(r.TimeLimit):
        r.time_left()
    rc, _, err = run_cli(capsys, ["epico", "solve", "--goal", "alpha", "--colors", "1", "--timeout", "5"])
    assert rc == 3 and "impossible" not in err, err


def test_smcdel_has_a_timeout(tmp_path, capsys):
    big = tmp_path / "big.smcdel.txt"
    big.write_text("VARS " + ",".join(str(i) for i in range(1, 27)) + "\nLAW Top\nOBS alice: 1\nbob: 2\n"
                   + "VALID? alice knows whether 1\n" * 30000)  # seconds of work: far past 0.5 s on any machine
    rc, out, err = run_cli(capsys, ["smcdel", big, "--timeout", "0.5", "--json"])
    assert rc == 3 and json.loads(out)["status"] == "limit", err


def test_prove_and_check_have_a_default_limit():
    import inspect

    from planners.commands import run_check

    assert inspect.signature(run_check).parameters["timeout"].default == 60.0
    import typer.main

    from delkit.cli import _build_app

    group = typer.main.get_command(_build_app())
    for name in ("prove", "check", "smcdel"):
        opt = next(p for p in group.commands[name].params if p.name == "timeout")
        assert opt.default == 60.0 and "default 60" in opt.help, (name, opt.default, opt.help)


# ----------------------------------------------------------------------------- batches

def _batch_cmd(files, *extra):
    return ["plan", *files, "--json", *extra]


def test_batch_timeout_is_per_task_and_every_task_is_reported():
    """Four searches that cannot finish, on one worker, --timeout 0.5: the batch runs longer than 0.5 s
    (each task's limit is its own), every task has a limit record and the summary comes last."""
    tasks = [str(SLOW_SEARCH[0])] * 4
    rc, out, err, wall = console(_batch_cmd(tasks, "--timeout", "0.5", "--jobs", "1"), timeout=120)
    lines = [json.loads(ln) for ln in out.splitlines() if ln.startswith("{")]
    records, summary = lines[:-1], lines[-1]
    assert len(records) == 4 and summary.get("summary") and summary["tasks"] == 4, out
    assert all(r["status"] == "limit" and r["exit"] == 3 for r in records), records
    assert rc == 3 and "Traceback" not in err, err


@pytest.mark.parametrize("sig", ["SIGTERM", "SIGINT"])
def test_a_signal_to_the_main_process_ends_the_batch_and_its_workers(tmp_path, sig):
    env = {**os.environ, "PYTHONPATH": str(REPO), "DELKIT_FUZZ_TAG": f"test-{sig}-{os.getpid()}"}
    tasks = [str(COIN / "pb1_twin.txt")] + [str(SLOW_SEARCH[0])] * 5
    p = subprocess.Popen([sys.executable, "-c", "from delkit.cli import run; run()",
                          *_batch_cmd(tasks, "--timeout", "30", "--jobs", "2")],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env)
    first = p.stdout.readline()  # the quick task's record: the batch runs, a worker is searching (any load)
    p.send_signal(getattr(signal, sig))
    out, err = p.communicate(timeout=30)
    out = first + out
    time.sleep(0.3)
    left = fuzzsafety._tagged_pids(env["DELKIT_FUZZ_TAG"])
    for pid in left:
        os.kill(pid, signal.SIGKILL)
    assert not left, f"{len(left)} worker(s) left behind"
    assert p.returncode == 128 + getattr(signal, sig) and "Traceback" not in err, err
    lines = [json.loads(ln) for ln in out.splitlines() if ln.startswith("{")]
    assert len(lines) == 7 and lines[-1]["interrupted"] == sig, out
    assert sum(r["status"] == "interrupted" for r in lines[:-1]) >= 1


def test_batch_bad_task_errors_go_to_stderr_and_the_record(tmp_path, capsys):
    files = _coin(tmp_path)
    rc, out, err = run_cli(capsys, ["plan", files[0], files[1], tmp_path / "missing.txt", "--jobs", "1", "--json"])
    recs = [json.loads(ln) for ln in out.splitlines()]
    bad = [r for r in recs if r.get("status") == "error"]
    assert rc == 2 and len(bad) == 1 and "missing.txt" in err and "delkit: error:" in err, (out, err)


def test_pool_terminate_kills_running_runs():
    from delkit.executors import IsolatedPool, RunInterrupted

    pool = IsolatedPool(1)
    fut = pool.submit(time.sleep, 30)
    time.sleep(1.0)
    t0 = time.monotonic()
    pool.terminate("test")
    with pytest.raises(RunInterrupted):
        fut.result(timeout=5)
    assert time.monotonic() - t0 < 5


# ----------------------------------------------------------------------------- the families

IN_PROCESS = ("links", "devices", "addresses")


def test_quick_slice_of_the_file_and_address_families():
    with Runner() as runner:
        for i, family in enumerate(IN_PROCESS):
            tally = fuzzgen.run_fuzz(5, seed=300 + i, families=[family], runner=runner)
            assert tally.total == 5 and not tally.bad, f"{tally.report_bad()}\n{tally.table()}"


def test_family_registry_takes_families_from_another_module():
    from fuzzkit import Case
    from hypothesis import strategies as st

    def extra():
        return st.just(Case("extra", ("fuzzsafety:no_such_function",), mode="call"))

    fuzzgen.register_families({"extra-test": (extra, 1)})
    try:
        with pytest.raises(ValueError):
            fuzzgen.register_families({"extra-test": (extra, 2)})
        assert "extra-test" in fuzzgen.FAMILIES
    finally:
        fuzzgen.FAMILIES.pop("extra-test")


@pytest.mark.slow
def test_process_families_sweep():
    """Batches under limits and signals and single limit answers, as processes (about 3 s each)."""
    with Runner() as runner:
        tally = fuzzgen.run_fuzz(40, seed=2031, families=["batches", "limit-answers"], runner=runner)
    assert not tally.bad, f"{tally.report_bad()}\n{tally.table()}"


@pytest.mark.slow
def test_file_and_address_families_sweep():
    with Runner() as runner:
        tally = fuzzgen.run_fuzz(400, seed=2032, families=list(IN_PROCESS), runner=runner)
    assert not tally.bad, f"{tally.report_bad()}\n{tally.table()}"


def test_worker_watchdog_answers_for_a_stuck_task(monkeypatch):
    """A task stuck (here: sleeping) 0.3 s past its limit in a pool worker is answered by the worker's watchdog:
    the limit record with the counters the task stored, then the worker ends (os._exit, patched here)."""
    import delkit.executors as executors
    from delkit.resources import counters
    from planners.batch import _begin_task

    sent = []

    class Conn:
        def send(self, obj):
            sent.append(obj)

    monkeypatch.setattr(executors, "_CURRENT", [Conn()])
    exits = []
    monkeypatch.setattr(os, "_exit", lambda code: exits.append(code))
    disarm = _begin_task(0.2)
    counters()["expanded"] = 5
    time.sleep(1.5)
    disarm()
    assert exits == [0] and sent and sent[0][0] is True, (exits, sent)
    rec = sent[0][1]
    assert rec["status"] == "limit" and rec["exit"] == 3 and rec["expanded"] == 5 and rec["wall"] >= 0.5, rec
