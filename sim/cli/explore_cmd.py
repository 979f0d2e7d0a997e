"""``delkit explore``: communication-restricted exploration with epistemic task allocation (seed 000).

* ``delkit explore run``   — one mission (Case Study I or II) with the epistemic, flock or ideal team;
* ``delkit explore sweep`` — maps × team sizes × methods through a ``concurrent.futures`` executor (local
  processes, or a Dask cluster with ``--dask``): CSV of every run, box plots (Figures 6/8), snapshots (5/7);
* ``delkit explore gap``   — optimality gap of Algorithms 1–2 against the exact MILP on small instances.

Heavy imports stay inside the commands so that ``delkit --help`` stays fast.
"""

from __future__ import annotations

import json
from pathlib import Path

import typer


def _progress(quiet: bool = False):
    from delkit.progress import progress

    return progress(quiet=quiet)


def _int_list(text: str, what: str) -> tuple[int, ...]:
    from delkit.errors import SimulationError

    try:
        values = tuple(int(x) for x in text.split(",") if x.strip())
    except ValueError:
        raise SimulationError(f"{what} must be comma-separated integers, e.g. 2,3,5,8 (got {text!r})") from None
    if not values:
        raise SimulationError(f"{what} is empty")
    return values


def register(app: typer.Typer) -> None:
    """Attach ``delkit explore {run, sweep, gap}``."""
    sub = typer.Typer(help="Communication-restricted exploration and epistemic task allocation (Bramblett and Bezzo).",
                      no_args_is_help=True)
    app.add_typer(sub, name="explore")

    @sub.command("run")
    def run(
        case: int = typer.Option(2, "--case", help="1: one task, unknown N_τ; 2: unknown number of tasks."),
        robots: int = typer.Option(3, "--robots", help="Team size N_a."),
        method: str = typer.Option("epistemic", "--method", help="epistemic | flock | ideal."),
        seed: int = typer.Option(0, "--seed", min=0, max=2**63 - 1,
                                    help="Map, tasks and motion noise all come from this seed."),
        map_file: Path | None = typer.Option(None, "--map", help="A MovingAI .map grid instead of a random map."),
        t_max: float = typer.Option(1500.0, "--t-max", min=1.0, help="Give up after this many simulated seconds."),
        png: Path | None = typer.Option(None, "--png", help="Write snapshots of the mission (as Figures 5/7)."),
        status_model: bool = typer.Option(True, "--status-model/--no-status-model",
                                          help="Model-check eqs. 14/18 on the delkit status model that drives "
                                               "the epistemic team (any N)."),
        as_json: bool = typer.Option(False, "--json", help="Print one JSON object."),
    ) -> None:
        """Run one mission and report mission time, distance, tasks done and communications."""
        from delkit.paths import refuse_overwrite_input
        from sim.explore import Mission, MissionConfig

        refuse_overwrite_input([png], [map_file], option="--png")  # the snapshots never replace the map
        cfg = MissionConfig(case=case, n_robots=robots, method=method, seed=seed,
                            map_path=str(map_file) if map_file else None, t_max=t_max,
                            status_model=status_model, record=png is not None)
        if map_file is not None:  # tasks are placed at least 2 m from the border: a tiny map has no room
            from delkit.errors import SimulationError
            from sim.grid import read_movingai

            w, h = read_movingai(map_file, cfg.resolution).size
            if w <= 6 or h <= 6:
                raise SimulationError(f"{map_file}: the map is {w:g} m × {h:g} m at {cfg.resolution:g} m per cell; a "
                                      f"mission needs more than 6 m × 6 m (home is at (3, 3) m, tasks keep 2 m "
                                      f"from the border)")
        mission = Mission(cfg)
        with _progress(as_json) as bar:
            task = bar.add_task(f"{method} mission (simulated s)", total=t_max)
            res = mission.run(lambda t, _tot: bar.update(task, completed=t))
        out = res.row()
        if out["min_separation"] == float("inf"):
            out["min_separation"] = None  # one robot: no pair to measure (JSON has no Infinity)
        out["task_completers"] = [list(c) for c in res.task_completers]
        if status_model:
            out["epistemic_checks"] = {k: {"passed": p, "total": t} for k, p, t in res.epistemic_checks}
        if png is not None and res.history is not None:
            from sim.plots import snapshots

            snapshots(res.history, png, comm_range=cfg.comm_range, lidar_range=cfg.lidar_range,
                      title=f"Case {case}, {robots} robots, {method}, seed {seed}")
            out["png"] = str(png)
        if as_json:
            print(json.dumps(out))
        else:
            from rich.console import Console
            from rich.table import Table

            t = Table(title=f"Case Study {'I' if case == 1 else 'II'} — {robots} robots, {method}, seed {seed}")
            t.add_column("quantity")
            t.add_column("value", justify="right")
            for k in ("mission_time", "distance", "tasks_done", "n_tasks", "communications", "success",
                      "all_home", "collisions", "min_separation", "cascade_assigned", "cascade_delivered",
                      "explored", "wall_time"):
                t.add_row(k, str(out[k]))
            if status_model:
                for k, p, tot in res.epistemic_checks:
                    t.add_row(f"delkit check {k}", f"{p}/{tot}")
            Console().print(t)
            if png is not None:
                print(f"snapshots: {png}")
        if not res.success:
            raise typer.Exit(1)

    @sub.command("sweep")
    def sweep(
        case: str = typer.Option("2", "--case", help="Case study, or a list such as 1,2."),
        robots: str = typer.Option("2,3,5,8", "--robots", help="Team sizes, comma-separated."),
        maps: int = typer.Option(15, "--maps", help="Number of random maps (seeds 0..maps-1)."),
        methods: str = typer.Option("epistemic,flock,ideal", "--methods", help="Methods, comma-separated."),
        workers: int | None = typer.Option(None, "--workers", min=1, max=1024,
                                            help="Local worker processes (default: all cores)."),
        dask: str | None = typer.Option(None, "--dask", help="Address of a Dask scheduler, e.g. tcp://host:8786."),
        out: Path = typer.Option(Path("explore-sweep"), "--out", help="Output directory (CSV, PNGs, JSON)."),
        snapshots_too: bool = typer.Option(True, "--snapshots/--no-snapshots",
                                           help="Also draw one epistemic mission per case (Figures 5/7)."),
        timeout: float = typer.Option(0.0, "--timeout", min=0.0, help="Wall-clock limit of the whole sweep in "
                                      "seconds from the start of the process (0 or inf: none); reaching it "
                                      "is exit status 3."),
        as_json: bool = typer.Option(False, "--json", help="Print one JSON object."),
    ) -> None:
        """Run a sweep; write runs.csv, summary.json, box plots and snapshots into --out."""
        from delkit.errors import SimulationError
        from sim.experiments import SweepSpec, paper_comparison, run_sweep, summarise, write_csv
        from sim.plots import box_plot

        names = tuple(m.strip() for m in methods.split(",") if m.strip())
        if not names:
            raise SimulationError(f"--methods {methods!r} names no method; give a comma-separated list such as "
                                  f"epistemic,flock,ideal")
        spec = SweepSpec(cases=_int_list(case, "--case"), robots=_int_list(robots, "--robots"), maps=maps,
                         methods=names)
        spec.validate()
        from sim.explore import MissionConfig

        for c in spec.cases:  # every combination is checked here, before any worker process starts
            for n in spec.robots:
                for m in spec.methods:
                    MissionConfig(case=c, n_robots=n, method=m).validate()
        total = len(spec.cases) * maps * len(spec.robots) * len(spec.methods)
        from delkit.resources import require

        require(4096.0 * total, f"a sweep of {total} missions (their configurations and result rows)",
                "use fewer --maps, --robots, --methods or --case values")
        from delkit.resources import deadline

        with deadline(timeout, f"explore sweep of {total} missions"), _progress(as_json) as bar:
            task = bar.add_task("missions", total=total)
            rows = run_sweep(spec, workers=workers, dask=dask, progress=lambda d, _t: bar.update(task, completed=d))
        out.mkdir(parents=True, exist_ok=True)
        csv_path = write_csv(rows, out / "runs.csv")
        files = [str(csv_path)]
        for c in spec.cases:
            files.append(str(box_plot(rows, out / f"case{c}_boxplot.png", case=c)))
        if snapshots_too:
            from sim.explore import MissionConfig, run_mission
            from sim.plots import snapshots

            for c in spec.cases:
                n = max(spec.robots)
                res = run_mission(MissionConfig(case=c, n_robots=n, method="epistemic", seed=spec.seed0))
                if res.history is not None:
                    files.append(str(snapshots(res.history, out / f"case{c}_snapshots.png",
                                               title=f"Case {c}, {n} robots, epistemic, seed {spec.seed0}")))
        summ = summarise(rows)
        comparison = paper_comparison(rows)
        summary = {"runs": len(rows), "failures": sum(not r["success"] for r in rows),
                   "collisions": sum(r["collisions"] for r in rows),
                   "groups": [{"case": k[0], "method": k[1], "robots": k[2], **v} for k, v in summ.items()],
                   # the paper gives no Case II spreads: null, not NaN (which is not JSON)
                   "paper": [{"quantity": q, "ours": o, "paper": None if p != p else p} for q, o, p in comparison],
                   "files": files}
        (out / "summary.json").write_text(json.dumps(summary, indent=1))
        if as_json:
            print(json.dumps(summary))
            return
        from rich.console import Console
        from rich.table import Table

        t = Table(title=f"Mission time [s] over {maps} maps")
        for col in ("case", "method", "robots", "mean", "std", "median", "runs"):
            t.add_column(col, justify="right")
        for k, v in summ.items():
            t.add_row(str(k[0]), k[1], str(k[2]), f"{v['mean']:.1f}", f"{v['std']:.1f}", f"{v['median']:.1f}",
                      str(v["runs"]))
        Console().print(t)
        p = Table(title="Beside the paper")
        for col in ("quantity", "ours", "paper"):
            p.add_column(col, justify="right")
        for q, o, pp in comparison:
            p.add_row(q, "–" if o is None else f"{o:.1f}", "–" if pp != pp else f"{pp:.1f}")
        Console().print(p)
        print(f"wrote {', '.join(files)}")

    @sub.command("gap")
    def gap(
        instances: int = typer.Option(20, "--instances", min=1, help="Number of random instances."),
        seed: int = typer.Option(0, "--seed", min=0, max=2**63 - 1),
        as_json: bool = typer.Option(False, "--json", help="Print one JSON object."),
    ) -> None:
        """Optimality gap of SSI bundling + makespan minimisation against the exact MILP (HiGHS), on eq. 20's
        team utility (``gap``) and on the makespan (``makespan_gap``)."""
        import numpy as np

        from sim.experiments import allocation_gap

        rows = allocation_gap(instances, seed=seed)
        g = np.array([r["gap"] for r in rows])
        mg = np.array([r["makespan_gap"] for r in rows])
        summary = {"instances": instances, "objective": "eq. 20 team utility", "mean_gap": float(g.mean()),
                   "median_gap": float(np.median(g)), "max_gap": float(g.max()),
                   "optimal_fraction": float((g < 1e-6).mean()), "makespan_mean_gap": float(mg.mean()),
                   "makespan_max_gap": float(mg.max()), "makespan_optimal_fraction": float((mg < 1e-6).mean()),
                   "rows": rows}
        if as_json:
            print(json.dumps(summary))
            return
        print(f"{instances} instances (2–4 robots, 2–4 tasks)\n  eq. 20 utility: mean gap {100 * g.mean():.1f} %, "
              f"median {100 * np.median(g):.1f} %, max {100 * g.max():.1f} %, heuristic optimal in "
              f"{100 * (g < 1e-6).mean():.0f} % of instances\n  makespan: mean gap {100 * mg.mean():.1f} %, max "
              f"{100 * mg.max():.1f} %, optimal in {100 * (mg < 1e-6).mean():.0f} %")
