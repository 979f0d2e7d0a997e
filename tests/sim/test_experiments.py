"""Sweeps through concurrent.futures executors (local processes, Dask LocalCluster), CSV, plots, CLI, demo."""

from __future__ import annotations

import json

import pytest

from delkit.cli import main
from sim.experiments import (
    SweepSpec,
    allocation_gap,
    paper_comparison,
    read_csv,
    run_one,
    run_sweep,
    summarise,
    sweep_configs,
    write_csv,
)

TINY = SweepSpec(cases=(1,), robots=(2,), maps=1, t_max=600.0)


def _strip(rows):
    return [{k: v for k, v in r.items() if k != "wall_time"} for r in rows]


def test_tiny_sweep_is_reproducible_and_complete(tmp_path):
    rows = run_sweep(TINY, workers=2)
    assert [(r["method"], r["n_robots"], r["seed"]) for r in rows] == [
        (c.method, c.n_robots, c.seed) for c in sweep_configs(TINY)]
    assert all(r["success"] and r["tasks_done"] == r["n_tasks"] for r in rows)
    # the measurements every row carries: robot–robot separation, Algorithm 3's cascade delivered in full
    assert all(0 < r["min_separation"] < 50 and r["cascade_delivered"] == r["cascade_assigned"] for r in rows)
    serial = [run_one(c) for c in sweep_configs(TINY)]
    assert _strip(rows) == _strip(serial)  # same seed, same result, whatever the executor
    path = write_csv(rows, tmp_path / "runs.csv")
    assert _strip(read_csv(path)) == _strip(rows)
    s = summarise(rows)
    assert s[(1, "epistemic", 2)]["runs"] == 1
    assert any(q.startswith("case 1") for q, _, _ in paper_comparison(rows))


def test_sweep_through_a_dask_local_cluster():
    distributed = pytest.importorskip("distributed")
    spec = SweepSpec(cases=(2,), robots=(2,), maps=1, methods=("ideal",), t_max=600.0)
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=False,
                                  dashboard_address=None) as cluster:
        rows = run_sweep(spec, dask=cluster.scheduler_address)
    assert _strip(rows) == _strip([run_one(c) for c in sweep_configs(spec)])


def test_unreachable_dask_scheduler_is_a_clear_error():
    pytest.importorskip("distributed")
    from delkit.errors import SimulationError

    with pytest.raises(SimulationError, match="Dask scheduler"):
        run_sweep(TINY, dask="tcp://127.0.0.1:9", dask_timeout=1.0)


def test_allocation_gap_is_non_negative():
    rows = allocation_gap(4, robots=(2, 3), tasks=(2, 3), seed=1)
    assert len(rows) == 4
    assert all(r["gap"] >= -1e-6 for r in rows)


def test_cli_run_json(capsys):
    rc = main(["explore", "run", "--case", "1", "--robots", "2", "--seed", "1", "--json"])
    out = json.loads(capsys.readouterr().out)
    assert rc == 0 and out["success"] and out["tasks_done"] == 1
    assert set(out) >= {"mission_time", "distance", "tasks_done", "communications"}


def test_cli_run_png_and_bad_method(tmp_path, capsys):
    png = tmp_path / "snap.png"
    assert main(["explore", "run", "--case", "1", "--robots", "2", "--method", "ideal", "--png", str(png)]) == 0
    assert png.stat().st_size > 10_000
    capsys.readouterr()
    assert main(["explore", "run", "--method", "nope"]) == 2
    assert "unknown method" in capsys.readouterr().err


def test_cli_sweep_writes_csv_and_figures(tmp_path, capsys):
    out = tmp_path / "sw"
    rc = main(["explore", "sweep", "--case", "1", "--robots", "2", "--maps", "1", "--workers", "2",
               "--out", str(out), "--json"])
    assert rc == 0
    summary = json.loads(capsys.readouterr().out)
    assert summary["runs"] == 3 and summary["failures"] == 0
    assert (out / "runs.csv").exists() and (out / "case1_boxplot.png").exists()
    assert (out / "case1_snapshots.png").exists()


def test_demo_entry_point(tmp_path):
    from sim.demo import run_demo

    row = run_demo(tmp_path)
    assert row["success"] and (tmp_path / "explore_demo.png").exists()
    assert all(v.split("/")[0] == v.split("/")[1] for v in row["epistemic_checks"].values())


@pytest.mark.slow
def test_small_sweep_two_maps_two_sizes_dask():
    distributed = pytest.importorskip("distributed")
    spec = SweepSpec(cases=(1, 2), robots=(2, 3), maps=2)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, dashboard_address=None) as cluster:
        rows = run_sweep(spec, dask=cluster.scheduler_address)
    assert len(rows) == 24 and all(r["success"] for r in rows)
