"""Parallel BFS of one task (``delkit plan FILE --jobs N``): the same plan as the serial BFS — same length,
same actions (same generation order and duplicate detection) — on the shared mA* instances."""

from __future__ import annotations

import csv

import pytest

from planners.epistemic import Limits, bfs
from planners.lang import load_task, shared_benchmarks
from planners.lang.epddl_run import space_for
from planners.parallel import parallel_bfs

BENCH = shared_benchmarks()
ROWS = list(csv.DictReader((BENCH / "mastar" / "expected.csv").open())) if BENCH else []
QUICK = {"CB_simple__pl_4.txt", "Coin_in_the_Box__pl_5.txt", "Grapevine_3__pl_3.txt", "SC_4_2__pl_5.txt"}


def _same_as_serial(row: dict, jobs: int = 2, **how) -> None:
    path = BENCH / "mastar" / row["file"]
    par, _ = parallel_bfs(path, None, jobs, timeout=120, **how)
    ser = bfs(space_for(load_task(path)), Limits(timeout=120))
    assert par.status == ser.status == "solved"
    assert par.length == ser.length == int(row["expected_length"])
    assert par.plan == ser.plan
    assert par.expanded >= ser.expanded  # every state serial BFS expands before its goal, and perhaps a few more


@pytest.mark.skipif(BENCH is None, reason="../shared/benchmarks is not available")
@pytest.mark.parametrize("row", [r for r in ROWS if r["file"].rsplit("/", 1)[-1] in QUICK],
                         ids=lambda r: r["file"].rsplit("/", 1)[-1])
def test_parallel_bfs_equals_serial_bfs(row: dict) -> None:
    _same_as_serial(row)


@pytest.mark.skipif(BENCH is None, reason="../shared/benchmarks is not available")
@pytest.mark.parametrize("row", [r for r in ROWS if r["file"].rsplit("/", 1)[-1] in QUICK],
                         ids=lambda r: r["file"].rsplit("/", 1)[-1])
@pytest.mark.parametrize("share", [True, False], ids=["shared-goal", "unshared"])
def test_parallel_bfs_in_rounds_and_three_parts_equals_serial_bfs(row: dict, share: bool) -> None:
    """Layers expanded in several rounds, in three parts; without the shared goal bound (as on Dask) the round
    after a goal expands every part's states up to the goal's parent."""
    _same_as_serial(row, jobs=3, rounds=4, share_goal=share)


@pytest.mark.slow
@pytest.mark.skipif(BENCH is None, reason="../shared/benchmarks is not available")
@pytest.mark.parametrize("row", ROWS, ids=lambda r: r["file"].rsplit("/", 1)[-1])
def test_parallel_bfs_equals_serial_bfs_on_every_shared_instance(row: dict) -> None:
    _same_as_serial(row)


@pytest.mark.slow
@pytest.mark.skipif(BENCH is None, reason="../shared/benchmarks is not available")
@pytest.mark.parametrize("row", ROWS, ids=lambda r: r["file"].rsplit("/", 1)[-1])
def test_parallel_bfs_in_unshared_rounds_equals_serial_bfs_on_every_shared_instance(row: dict) -> None:
    _same_as_serial(row, jobs=3, rounds=6, share_goal=False)


@pytest.mark.skipif(BENCH is None, reason="../shared/benchmarks is not available")
def test_parallel_bfs_limits() -> None:
    path = BENCH / "mastar" / "Coin_In_The_Box" / "Coin_in_the_Box__pl_7.txt"
    res, _ = parallel_bfs(path, None, 2, max_nodes=30)
    assert res.status == "limit" and "expanded-node limit" in res.reason


@pytest.mark.slow
@pytest.mark.skipif(BENCH is None, reason="../shared/benchmarks is not available")
def test_parallel_bfs_on_a_dask_cluster() -> None:
    """The parts as actors of a Dask cluster (``scheduler``): the serial plan again."""
    distributed = pytest.importorskip("distributed")
    path = BENCH / "mastar" / "Grapevine" / "Grapevine_3" / "Grapevine_3__pl_3.txt"
    with distributed.LocalCluster(n_workers=1, threads_per_worker=2, processes=False, dashboard_address=None,
                                  protocol="tcp") as cluster:
        par, _ = parallel_bfs(path, None, 3, timeout=120, scheduler=cluster.scheduler_address)
    ser = bfs(space_for(load_task(path)), Limits(timeout=120))
    assert par.status == "solved" and par.plan == ser.plan


@pytest.mark.slow
@pytest.mark.skipif(BENCH is None, reason="../shared/benchmarks is not available")
def test_cli_one_task_jobs_and_scheduler_is_a_parallel_search_on_the_cluster() -> None:
    """``delkit plan TASK --jobs N --scheduler ADDR``: one parallel search whose parts are the cluster's actors
    (not the batch runner, which would search serially on one worker)."""
    import json
    import os
    import subprocess
    import sys
    from pathlib import Path

    distributed = pytest.importorskip("distributed")
    path = BENCH / "mastar" / "Grapevine" / "Grapevine_3" / "Grapevine_3__pl_3.txt"
    repo = Path(__file__).resolve().parents[2]
    with distributed.LocalCluster(n_workers=1, threads_per_worker=2, processes=False, dashboard_address=None,
                                  protocol="tcp") as cluster:
        proc = subprocess.run([sys.executable, "-c", "import sys; from delkit.cli import main; sys.exit(main())",
                               "plan", str(path), "--jobs", "2", "--scheduler", cluster.scheduler_address,
                               "--json"], capture_output=True, text=True, timeout=300,
                              env={**os.environ, "PYTHONPATH": str(repo)})
    assert proc.returncode == 0, proc.stderr
    out = json.loads(proc.stdout.splitlines()[-1])
    assert "summary" not in out and out.get("processes", out.get("jobs")) == 2, out
    ser = bfs(space_for(load_task(path)), Limits(timeout=120))
    assert out["plan"] == list(ser.plan)


@pytest.mark.skipif(BENCH is None, reason="../shared/benchmarks is not available")
def test_local_parts_expand_a_layer_in_one_phase() -> None:
    """Local parts share the goal bound: one phase (barrier) per layer, the goal's layer included; Dask-like
    unshared rounds need more phases."""
    path = BENCH / "mastar" / "Coin_In_The_Box" / "Coin_in_the_Box__pl_7.txt"
    ser = bfs(space_for(load_task(path)), Limits(timeout=120))
    st: dict = {}
    par, _ = parallel_bfs(path, None, 2, timeout=120, stats=st)
    assert par.plan == ser.plan and st["phases"] == st["layers"] == len(ser.plan)
    assert len(st["parts_cpu"]) == len(st["start_cpu"]) == 2
    st2: dict = {}
    par2, _ = parallel_bfs(path, None, 2, timeout=120, stats=st2, rounds=4, share_goal=False)
    assert par2.plan == ser.plan and st2["phases"] > st2["layers"]


def test_the_shared_goal_bound_keeps_the_least_path() -> None:
    """:class:`planners.parallel._Bound`: what one process offers another reads; only a lesser path replaces
    the bound; a path longer than the array is not shared."""
    from planners.parallel import _Bound

    array = _Bound.new()
    writer, reader = _Bound(array), _Bound(array)
    assert reader.read() is None
    writer.offer((3, 1, 4))
    assert reader.read() == (3, 1, 4)
    writer.offer((3, 2, 0))  # greater: ignored
    assert reader.read() == (3, 1, 4)
    reader.offer((2, 9, 9))  # lesser: kept, whoever offers it
    assert writer.read() == reader.read() == (2, 9, 9)
    writer.offer(tuple(range(_Bound.SIZE + 1)))
    assert reader.read() == (2, 9, 9)


@pytest.mark.skipif(BENCH is None, reason="../shared/benchmarks is not available")
def test_a_part_records_the_commuting_transitions_another_part_computed() -> None:
    """A part's state space memoises the transitions of commuting actions (it predicts a sensing's successor
    from them); the transitions another part computed toward this part's states are sent along and recorded."""
    from delkit.backends.compact import state_of_key
    from planners.parallel import _Part

    path = BENCH / "mastar" / "Grapevine" / "Grapevine_3" / "Grapevine_3__pl_3.txt"
    parts = [_Part(i, 2, str(path), None, [], False, "auto", False) for i in range(2)]
    assert parts[0].commute and parts[1].commute
    inbox: list[list] = [[], []]
    for layer in range(2):
        res = [p.step(inbox[p.me], layer > 0, 1, None, None, float("inf")) for p in parts]
        inbox = [[(src, res[src][0][d]) for src in range(2) if res[src][0][d] is not None] for d in range(2)]
    for p in parts:
        p.step(inbox[p.me], False, 1, 0, None, float("inf"))  # merge only
    for me, other in ((0, 1), (1, 0)):
        theirs = {k: z for k, z in parts[other].space._succ.items() if parts[other]._owner(state_of_key(z)) == me}
        assert theirs and all(parts[me].space._succ.get(k) == z for k, z in theirs.items())
