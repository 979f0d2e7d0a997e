"""Batch tasks run by several threads of one process (a Dask worker with ``threads_per_worker > 1``): each
task's output, CPU figure and time limit are its own."""

from __future__ import annotations

import threading
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import pytest

from delkit import resources
from planners import batch

BENCH = Path(__file__).resolve().parents[2].parent / "shared" / "benchmarks"


def test_two_threads_capture_only_their_own_output():
    barrier = threading.Barrier(2, timeout=10)

    def body(tag: str):
        def fn() -> int:
            print(f"{{\"tag\": \"{tag}\", \"part\": 1}}")
            barrier.wait()   # both tasks are inside their capture now
            print(f"{{\"tag\": \"{tag}\", \"part\": 2}}")
            barrier.wait()
            return 0
        return batch._capture(fn)

    with ThreadPoolExecutor(2) as pool:
        a, b = pool.submit(body, "a"), pool.submit(body, "b")
        (ca, ta, _), (cb, tb, _) = a.result(), b.result()
    assert ca == cb == 0
    assert ta.count('"tag": "a"') == 2 and '"b"' not in ta, ta
    assert tb.count('"tag": "b"') == 2 and '"a"' not in tb, tb


def test_a_thread_keeps_its_own_deadline_when_another_ends():
    barrier = threading.Barrier(2, timeout=10)
    seen: dict[str, float | None] = {}

    def short():
        with resources.deadline(0.5, "short"):
            barrier.wait()   # both deadlines active
        barrier.wait()       # the short one has ended

    def long():
        barrier.wait()
        with resources.deadline(100, "long"):
            barrier.wait()
            seen["left"] = resources.remaining()

    # the short one enters first, so a process-wide deadline would keep it for the long one and then drop it
    with ThreadPoolExecutor(2) as pool:
        f1 = pool.submit(short)
        time.sleep(0.05)
        f2 = pool.submit(long)
        f1.result(), f2.result()
    assert seen["left"] is not None and seen["left"] > 50, seen


@pytest.mark.skipif(not (BENCH / "mastar" / "CB_simple").is_dir(), reason="../shared/benchmarks is not available")
def test_plan_tasks_in_threads_all_keep_their_results():
    cb = BENCH / "mastar" / "CB_simple"
    files = [str(cb / f"CB_simple__pl_{k}.txt") for k in (2, 3, 4)] * 4
    with ThreadPoolExecutor(3) as pool:
        results = list(pool.map(lambda f: batch.plan_one(f, None, {}), files))
    assert [r.get("length") for r in results] == [2, 3, 4] * 4, results
    assert all(r["status"] == "solved" and r["cpu"] >= 0 for r in results)
