"""Batch mode (``delkit plan FILE... --jobs N``) and its executor: each task's answer equals the single
command's, limits hold per task, and a crash, a hang or a memory blow-up fails only its own task."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import time
from pathlib import Path

import pytest

from delkit.executors import IsolatedPool, RunKilled, WorkerDied
from planners.batch import check_units, plan_units
from planners.demo import specs_dir
from planners.lang import shared_benchmarks

ROOT = Path(__file__).resolve().parents[2]
BENCH = shared_benchmarks()
COIN = specs_dir() / "coin_in_the_box"


def _delkit(*argv: str) -> subprocess.CompletedProcess:
    code = "import sys; from delkit.cli import main; sys.exit(main())"
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    return subprocess.run([sys.executable, "-c", code, *argv], capture_output=True, text=True, env=env,
                          check=False, timeout=300)


def test_isolated_pool_survives_crash_hang_and_memory_blowup() -> None:
    pool = IsolatedPool(2, hard_timeout=2.0, memory_mb=1024)
    try:
        t0 = time.monotonic()
        futs = {"abort": pool.submit(os.abort), "hang": pool.submit(time.sleep, 60),
                "memory": pool.submit(bytearray, 8 << 30), "exit": pool.submit(os._exit, 7)}
        ok = [pool.submit(pow, 2, k) for k in range(6)]
        assert [f.result(timeout=60) for f in ok] == [2 ** k for k in range(6)]
        with pytest.raises(WorkerDied, match="SIGABRT"):
            futs["abort"].result(timeout=60)
        with pytest.raises(WorkerDied, match="status 7"):
            futs["exit"].result(timeout=60)
        with pytest.raises(RunKilled):
            futs["hang"].result(timeout=60)
        with pytest.raises(MemoryError):
            futs["memory"].result(timeout=60)
        assert time.monotonic() - t0 < 30           # the hang was killed at its 2 s limit, not waited for
        assert pool.submit(pow, 3, 3).result(timeout=60) == 27  # the pool still works
    finally:
        pool.shutdown()


def test_units_pair_domains_with_their_problems(tmp_path) -> None:
    dom, prob = COIN / "domain.epddl", COIN / "problem.epddl"
    mastar = COIN / "pb1_twin.txt"
    assert plan_units([mastar, dom, prob, COIN / "common.epddl", mastar]) == \
        [(mastar, None), (dom, prob), (dom, COIN / "common.epddl"), (mastar, None)]
    plan = COIN / "problem.plan"
    assert check_units([dom, prob, plan, mastar, tmp_path / "x.plan"]) == [[dom, prob, plan],
                                                                             [mastar, tmp_path / "x.plan"]]


@pytest.mark.skipif(BENCH is None, reason="../shared/benchmarks is not available")
def test_batch_answers_equal_single_runs_and_limits_hold_per_task(tmp_path) -> None:
    files = sorted((BENCH / "mastar" / "Coin_In_The_Box").glob("*.txt"))[:4]
    bad = tmp_path / "bad.txt"
    bad.write_text("fluent p;\nthis is not mA*\n")
    proc = _delkit("plan", *map(str, files), str(bad), str(COIN / "domain.epddl"), str(COIN / "problem.epddl"),
                   "--jobs", "2", "--json", "--max-nodes", "20")
    lines = [json.loads(ln) for ln in proc.stdout.splitlines()]
    summary = lines.pop()
    assert summary["summary"] and summary["tasks"] == len(files) + 2
    by = {(ln["file"], ln["problem"]): ln for ln in lines}
    for f in files:
        single = _delkit("plan", str(f), "--json", "--max-nodes", "20")
        want = json.loads(single.stdout)
        got = by[(str(f), None)]
        assert (got["status"], got["length"], got["expanded"], got["exit"]) == \
               (want["status"], want["length"], want["expanded"], single.returncode)
    assert any(ln["status"] == "limit" and ln["exit"] == 3 for ln in lines)  # --max-nodes held per task
    assert by[(str(bad), None)]["exit"] == 2 and "bad.txt" in by[(str(bad), None)]["reason"]
    assert by[(str(COIN / "domain.epddl"), str(COIN / "problem.epddl"))]["status"] == "solved"
    assert proc.returncode == 2  # the worst task: bad input


@pytest.mark.skipif(BENCH is None, reason="../shared/benchmarks is not available")
def test_batch_table_and_check_batch(tmp_path) -> None:
    cb = BENCH / "mastar" / "CB_simple"
    proc = _delkit("plan", str(cb / "CB_simple__pl_2.txt"), str(cb / "CB_simple__pl_3.txt"), "--jobs", "1")
    assert proc.returncode == 0, proc.stderr
    assert "2/2 solved" in proc.stdout and "CB_simple__pl_3.txt" in proc.stdout and proc.stderr == ""
    good, wrong = tmp_path / "good.plan", tmp_path / "wrong.plan"
    good.write_text("peek_up_key_a\nopen_a\n")
    wrong.write_text("open_a\n")
    proc = _delkit("check", str(cb / "CB_simple__pl_2.txt"), str(good), str(cb / "CB_simple__pl_2.txt"), str(wrong),
                   "--json", "-j", "2")
    lines = [json.loads(ln) for ln in proc.stdout.splitlines()]
    assert [ln.get("valid") for ln in lines[:-1]].count(True) == 1 and lines[-1]["valid"] == 1
    assert proc.returncode == 1


@pytest.mark.slow
@pytest.mark.skipif(BENCH is None, reason="../shared/benchmarks is not available")
def test_batch_on_a_dask_cluster() -> None:
    distributed = pytest.importorskip("distributed")
    cb = BENCH / "mastar" / "CB_simple"
    with distributed.LocalCluster(n_workers=1, threads_per_worker=2, processes=False,
                                  dashboard_address=None, protocol="tcp") as cluster:
        proc = _delkit("plan", str(cb / "CB_simple__pl_2.txt"), str(cb / "CB_simple__pl_3.txt"), "--json",
                       "--scheduler", cluster.scheduler_address)
    lines = [json.loads(ln) for ln in proc.stdout.splitlines()]
    assert proc.returncode == 0, proc.stderr
    assert sorted(ln["length"] for ln in lines[:-1]) == [2, 3] and lines[-1]["workers"].startswith("dask")
    bad = _delkit("plan", str(cb / "CB_simple__pl_2.txt"), str(cb / "CB_simple__pl_3.txt"),
                  "--scheduler", "tcp://127.0.0.1:9")
    assert bad.returncode == 2 and bad.stderr.count("\n") == 1 and "Dask scheduler" in bad.stderr
