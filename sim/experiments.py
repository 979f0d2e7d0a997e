"""Seeded, reproducible sweeps of exploration missions (seed 000, §6: 15 maps × {2, 3, 5, 8} robots).

Runs go through a :class:`concurrent.futures.Executor`: a local :class:`~concurrent.futures.ProcessPoolExecutor`
by default, or a Dask ``distributed`` cluster when an address is given (``Client(address).get_executor()``
implements the same interface). Every run is a pure function of its :class:`~sim.explore.MissionConfig`,
so the same sweep gives the same CSV whatever the executor and the number of workers (only the
``wall_time`` column differs).
"""

from __future__ import annotations

import csv
import itertools
import os
from collections.abc import Callable, Iterable, Sequence
from concurrent.futures import Executor, ProcessPoolExecutor, as_completed
from contextlib import contextmanager
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from delkit.errors import SimulationError
from sim.explore import METHODS, MissionConfig, MissionResult, run_mission

__all__ = ["SweepSpec", "sweep_configs", "run_one", "run_sweep", "write_csv", "read_csv", "summarise",
           "paper_comparison", "PAPER", "executor", "allocation_gap"]

#: What the paper reports (§6.1, §6.2), in seconds.
PAPER = {
    "case1": {"std_epistemic": 11.0, "std_ideal": 14.0, "std_flock": 48.0, "flock_minus_epistemic": 13.0,
              "epistemic_minus_ideal": 11.0},
    "case2": {"flock_minus_epistemic": 35.0, "epistemic_minus_ideal": 16.0},
}


@dataclass(frozen=True)
class SweepSpec:
    """A grid of missions: cases × maps (seeds ``seed0 .. seed0+maps-1``) × team sizes × methods."""

    cases: tuple[int, ...] = (2,)
    robots: tuple[int, ...] = (2, 3, 5, 8)
    maps: int = 15
    methods: tuple[str, ...] = METHODS
    seed0: int = 0
    t_max: float = 1500.0
    #: MissionConfig fields set on every mission, e.g. (("wait_rule", "travel"),)
    overrides: tuple[tuple[str, object], ...] = ()
    #: rows carry MissionResult.diagnosis() under "diagnosis" (not written to the CSV)
    diagnose: bool = False

    def validate(self) -> None:
        bad = [m for m in self.methods if m not in METHODS]
        if bad:
            raise SimulationError(f"unknown method(s) {bad}; use {', '.join(METHODS)}")
        if self.maps < 1 or not self.robots:
            raise SimulationError("a sweep needs at least one map and one team size")


def sweep_configs(spec: SweepSpec) -> list[MissionConfig]:
    """All mission configurations of the sweep, in a fixed order."""
    spec.validate()
    extra = dict(spec.overrides)
    return [MissionConfig(case=c, n_robots=n, method=m, seed=spec.seed0 + s, t_max=spec.t_max, record=False,
                          **extra)
            for c, s, n, m in itertools.product(spec.cases, range(spec.maps), spec.robots, spec.methods)]


def run_one(cfg: MissionConfig) -> dict:
    """Run one mission and return its CSV row (picklable, for any executor)."""
    res: MissionResult = run_mission(replace(cfg, record=False))
    return res.row()


def run_one_diagnosed(cfg: MissionConfig) -> dict:
    """:func:`run_one` with the mission's diagnosis (exclusions, waits, task times) under ``"diagnosis"``."""
    res: MissionResult = run_mission(replace(cfg, record=False))
    return res.row() | {"diagnosis": res.diagnosis()}


@contextmanager
def executor(workers: int | None = None, dask: str | None = None, dask_timeout: float = 10.0):
    """A local process pool, or the executor of the Dask cluster at ``dask`` (e.g. ``tcp://127.0.0.1:8786``)."""
    if dask:
        from delkit.executors import dask_executor

        with dask_executor(dask, dask_timeout, option="--dask", error=SimulationError) as ex:
            yield ex
    else:
        with ProcessPoolExecutor(max_workers=workers or os.cpu_count() or 1) as pool:
            yield pool


def run_sweep(spec: SweepSpec, *, workers: int | None = None, dask: str | None = None,
              pool: Executor | None = None, progress: Callable[[int, int], None] | None = None,
              dask_timeout: float = 10.0) -> list[dict]:
    """Run every mission of ``spec``; rows come back in the order of :func:`sweep_configs`."""
    cfgs = sweep_configs(spec)
    rows: list[dict | None] = [None] * len(cfgs)

    def drive(ex: Executor) -> None:
        fn = run_one_diagnosed if spec.diagnose else run_one
        futures = {ex.submit(fn, c): k for k, c in enumerate(cfgs)}
        try:
            for done, fut in enumerate(as_completed(futures), 1):
                rows[futures[fut]] = fut.result()
                if progress is not None:
                    progress(done, len(cfgs))
        except BaseException:  # e.g. --timeout reached: the pool must not run the missions still queued,
            for fut in futures:  # nor keep running the current ones (its workers hold our stdout open)
                fut.cancel()
            from delkit import resources

            # the delkit program is about to leave: end a local pool's workers now (in-process callers let the
            # pool finish the running missions: terminating them under a live executor upsets its manager)
            for proc in list((getattr(ex, "_processes", None) or {}).values()) if resources.HARD_EXIT else []:
                proc.terminate()
            raise

    if pool is not None:
        drive(pool)
    else:
        with executor(workers, dask, dask_timeout) as ex:
            drive(ex)
    return [r for r in rows if r is not None]


def write_csv(rows: Sequence[dict], path: str | Path) -> Path:
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    rows = [{k: v for k, v in r.items() if k != "diagnosis"} for r in rows]  # nested: JSON, not CSV
    with path.open("w", newline="") as fh:
        w = csv.DictWriter(fh, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)
    return path


def read_csv(path: str | Path) -> list[dict]:
    conv = {"case": int, "n_robots": int, "seed": int, "mission_time": float, "distance": float,
            "tasks_done": int, "n_tasks": int, "communications": int, "explored": float, "wall_time": float,
            "collisions": int, "min_separation": float, "cascade_assigned": int, "cascade_delivered": int}
    out = []
    with Path(path).open() as fh:
        for row in csv.DictReader(fh):
            r: dict = dict(row)
            for k, f in conv.items():
                if k in r:
                    r[k] = f(r[k])
            for k in ("success", "all_home", "min_completers_ok"):
                if k in r:
                    r[k] = r[k] == "True"
            out.append(r)
    return out


def summarise(rows: Iterable[dict]) -> dict:
    """Mean/std/median mission time per (case, method, team size) and per (case, method) overall."""
    rows = list(rows)
    out: dict = {}
    keys = sorted({(r["case"], r["method"], r["n_robots"]) for r in rows})
    for case, method, n in keys:
        t = np.array([r["mission_time"] for r in rows if (r["case"], r["method"], r["n_robots"]) == (case, method, n)])
        out[(case, method, n)] = {"mean": float(t.mean()), "std": float(t.std(ddof=1)) if len(t) > 1 else 0.0,
                                  "median": float(np.median(t)), "runs": len(t)}
    for case, method in sorted({(k[0], k[1]) for k in keys}):
        sub = [v for k, v in out.items() if k[0] == case and k[1] == method and isinstance(k[2], int)]
        out[(case, method, "all")] = {"mean": float(np.mean([v["mean"] for v in sub])),
                                      "std": float(np.mean([v["std"] for v in sub])),
                                      "median": float(np.mean([v["median"] for v in sub])),
                                      "runs": int(sum(v["runs"] for v in sub))}
    return out


def paper_comparison(rows: Iterable[dict]) -> list[tuple[str, float | None, float]]:
    """(quantity, ours, paper) for the figures the paper quotes; std is averaged over team sizes."""
    s = summarise(rows)
    out: list[tuple[str, float | None, float]] = []

    def get(case: int, method: str, stat: str) -> float | None:
        v = s.get((case, method, "all"))
        return None if v is None else v[stat]

    for case in (1, 2):
        e, f, i = get(case, "epistemic", "mean"), get(case, "flock", "mean"), get(case, "ideal", "mean")
        paper = PAPER[f"case{case}"]
        out.append((f"case {case}: flock − epistemic mean [s]", None if e is None or f is None else f - e,
                    paper["flock_minus_epistemic"]))
        out.append((f"case {case}: epistemic − ideal mean [s]", None if e is None or i is None else e - i,
                    paper["epistemic_minus_ideal"]))
        for m in ("epistemic", "ideal", "flock"):
            # Case II: the paper gives no number, only "the variance of the proposed method was higher than that
            # of the flock and ideal methods" (NaN in the paper column)
            out.append((f"case {case}: std of {m} [s]", get(case, m, "std"), paper.get(f"std_{m}", float("nan"))))
    return out


def allocation_gap(instances: int = 20, *, robots: tuple[int, int] = (2, 4), tasks: tuple[int, int] = (2, 4),
                   seed: int = 0, size: float = 50.0, speed: float = 3.0) -> list[dict]:
    """Algorithms 1–2 vs the exact MILP on random small ST-MR-TA instances, on two objectives.

    Robots and tasks are uniform in a ``size`` × ``size`` square; N_τ ~ U{1..min(3, robots)}, λ_τ = 100;
    travel time is Euclidean / speed. Per instance: eq. 20's team utility of the heuristic and of the
    utility-optimal MILP (``gap`` = (optimum − heuristic) / |optimum|), and the makespan of the heuristic and of
    the makespan-optimal MILP (``makespan_gap`` = (heuristic − optimum) / optimum).
    """
    import time as _t

    from planners.allocation import Robot, Task, allocate, euclidean_cost, makespan, milp_allocation, team_utility

    rng = np.random.default_rng([seed, 2024])
    cost = euclidean_cost(speed)
    out = []
    for k in range(instances):
        nr = int(rng.integers(robots[0], robots[1] + 1))
        nt = int(rng.integers(tasks[0], tasks[1] + 1))
        rs = [Robot(i, tuple(rng.uniform(0, size, 2))) for i in range(nr)]
        ts = [Task(j, tuple(rng.uniform(0, size, 2)), int(rng.integers(1, min(3, nr) + 1))) for j in range(nt)]
        tmap = {t.id: t for t in ts}
        t0 = _t.perf_counter()
        alloc = allocate(rs, ts, cost, connected=[r.id for r in rs])
        t1 = _t.perf_counter()
        _, ub = milp_allocation(rs, ts, cost, objective="utility")
        t2 = _t.perf_counter()
        _, mb = milp_allocation(rs, ts, cost, objective="makespan")
        u_heur, u_opt = team_utility(rs, alloc.bundles, tmap, cost), team_utility(rs, ub, tmap, cost)  # re-timed
        m_heur, m_opt = alloc.makespan, makespan(rs, mb, tmap, cost)  # without the MILP's ε margins
        out.append({"instance": k, "robots": nr, "tasks": nt, "heuristic": u_heur, "optimal": u_opt,
                    "gap": (u_opt - u_heur) / abs(u_opt) if u_opt else 0.0, "heuristic_makespan": m_heur,
                    "optimal_makespan": m_opt, "makespan_gap": (m_heur - m_opt) / m_opt if m_opt > 0 else 0.0,
                    "heuristic_s": t1 - t0, "milp_s": t2 - t1})
    return out
