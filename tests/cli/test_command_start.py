"""Where a command's --timeout counts from: the process start only in the delkit process itself (the console
script), the call otherwise; and a library call after a command is not charged with that command's start."""

from __future__ import annotations

import time

import delkit.resources as resources
from delkit.cli import main
from planners.commands import run_check
from planners.demo import specs_dir

COIN = specs_dir() / "coin_in_the_box"
FILES = [COIN / "domain.epddl", COIN / "problem.epddl", COIN / "problem.plan"]


def test_a_host_process_that_ran_long_is_not_charged_to_its_first_command(monkeypatch, capsys):
    # a test runner or a notebook that started 1000 s ago calls main() for the first time
    monkeypatch.setattr(resources, "_BEGUN_PID", None)
    monkeypatch.setattr(resources, "process_start", lambda: time.monotonic() - 1000.0)
    assert main(["check", *map(str, FILES), "--timeout", "60"]) == 0, capsys.readouterr().err
    # (the console script's own process still counts from its start: tests/fuzz/test_limits.py, in subprocesses)


def test_a_library_call_after_a_command_counts_from_its_own_start(monkeypatch, capsys):
    # a command that started long ago (as the first command of a long-lived process would): once it has
    # returned, run_check's default limit (60 s) counts from run_check's own call
    begin = resources.begin_command

    def long_ago() -> None:
        begin()
        resources._LOCAL.t0 = time.monotonic() - 1000.0

    monkeypatch.setattr(resources, "begin_command", long_ago)
    assert main(["check", *map(str, FILES), "--timeout", "0"]) == 0, capsys.readouterr().err
    assert run_check(FILES) == 0
