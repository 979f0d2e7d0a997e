"""Benchmark of the communication-restricted exploration simulator (seed 000, Case Studies I and II).

1. One 8-robot Case II mission with the epistemic team: wall time vs simulated time (target ≥ 20×).
2. The full sweep: 2 cases × 15 maps × {2, 3, 5, 8} robots × {epistemic, flock, ideal} = 360 missions through a
   process pool with 2 workers (target < 15 min); mission-time statistics beside the paper's figures.
3. Allocation heuristics (Algorithms 1–2) vs the exact MILP on random small instances: optimality gap.

4. Ablations (3 maps, Case II, 5 robots): the paper's APF (η_g = 1, robot–robot repulsion, no cruise term) vs
   with our former cruise term, without robot repulsion, with η_g = 3; flock formation radius 3 / 4 / 4.5 m.

Every sweep row also carries the minimum robot–robot separation and Algorithm 3's cascade (assigned/delivered).

Usage: ``python bench/explore.py [--maps 15] [--workers 2] [--out DIR] [--gap 30] [--no-ablation]``.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import numpy as np  # noqa: E402

from sim.experiments import (  # noqa: E402
    SweepSpec,
    allocation_gap,
    paper_comparison,
    run_sweep,
    summarise,
    write_csv,
)
from sim.explore import MissionConfig, run_mission  # noqa: E402


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--maps", type=int, default=15)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--out", type=Path, default=Path(os.environ.get("TMPDIR", "/tmp")) / "delkit-explore-bench")
    ap.add_argument("--gap", type=int, default=30, help="random instances for the MILP gap study")
    ap.add_argument("--no-sweep", action="store_true")
    ap.add_argument("--no-ablation", action="store_true")
    args = ap.parse_args()
    print(f"machine: {platform.node()} {os.cpu_count()} cores, python {platform.python_version()}, "
          f"{time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, load {os.getloadavg()[0]:.1f}")

    print("\n== one 8-robot Case II mission (epistemic) ==")
    print("(timed region: Mission construction + run, record=False, eq. 14/18 model checks on)")
    print(f"{'seed':>4} {'simulated [s]':>14} {'wall [s]':>9} {'CPU [s]':>8} {'speed-up wall':>14} {'CPU':>6}")
    ratios, cratios = [], []
    for seed in range(3):
        t0, c0 = time.perf_counter(), time.process_time()
        res = run_mission(MissionConfig(case=2, n_robots=8, method="epistemic", seed=seed, record=False))
        wall, cpu = time.perf_counter() - t0, time.process_time() - c0
        ratios.append(res.mission_time / wall)
        cratios.append(res.mission_time / cpu)
        print(f"{seed:>4} {res.mission_time:>14.1f} {wall:>9.2f} {cpu:>8.2f} {res.mission_time / wall:>13.1f}× "
              f"{res.mission_time / cpu:>5.1f}×")
    print(f"median speed-up {np.median(ratios):.1f}× wall, {np.median(cratios):.1f}× CPU (target ≥ 20×)")

    if not args.no_sweep:
        spec = SweepSpec(cases=(1, 2), robots=(2, 3, 5, 8), maps=args.maps)
        n = len(spec.cases) * spec.maps * len(spec.robots) * len(spec.methods)
        print(f"\n== full sweep: {n} missions, {args.workers} worker processes ==")
        import resource

        t0 = time.perf_counter()
        ru0 = resource.getrusage(resource.RUSAGE_CHILDREN)
        rows = run_sweep(spec, workers=args.workers)
        wall = time.perf_counter() - t0
        ru1 = resource.getrusage(resource.RUSAGE_CHILDREN)
        cpu = (ru1.ru_utime + ru1.ru_stime) - (ru0.ru_utime + ru0.ru_stime)
        print(f"CPU time of the worker processes {cpu:.0f} s = {cpu / 60:.1f} min "
              f"({cpu / max(wall, 1e-9):.2f} cores busy on average); load average now "
              f"{' / '.join(f'{x:.1f}' for x in os.getloadavg())} (1 / 5 / 15 min)")
        print(f"wall time {wall:.1f} s = {wall / 60:.1f} min (target < 15 min); "
              f"failures {sum(not r['success'] for r in rows)}, collisions {sum(r['collisions'] for r in rows)}, "
              f"tasks done {sum(r['tasks_done'] for r in rows)}/{sum(r['n_tasks'] for r in rows)}, "
              f"all home in {sum(r['all_home'] for r in rows)}/{len(rows)}")
        args.out.mkdir(parents=True, exist_ok=True)
        write_csv(rows, args.out / "runs.csv")
        from sim.plots import box_plot

        for c in spec.cases:
            box_plot(rows, args.out / f"case{c}_boxplot.png", case=c)
        s = summarise(rows)
        print(f"\n{'case':>4} {'method':>10} {'robots':>6} {'mean [s]':>9} {'std [s]':>8} {'median':>7} {'runs':>5}")
        for k, v in s.items():
            print(f"{k[0]:>4} {k[1]:>10} {k[2]!s:>6} {v['mean']:>9.1f} {v['std']:>8.1f} {v['median']:>7.1f} "
                  f"{v['runs']:>5}")
        print(f"\n{'case':>4} {'method':>10} {'min robot–robot separation [m]':>32} {'median':>7} "
              f"{'cascade assigned/delivered':>27}")
        for c in spec.cases:
            for m in spec.methods:
                sel = [r for r in rows if r["case"] == c and r["method"] == m]
                sep = np.array([r["min_separation"] for r in sel])
                print(f"{c:>4} {m:>10} {sep.min():>32.3f} {np.median(sep):>7.3f} "
                      f"{sum(r['cascade_assigned'] for r in sel):>13}/{sum(r['cascade_delivered'] for r in sel)}")
        print(f"\n{'quantity':<40} {'ours':>8} {'paper':>8}")
        for q, o, p in paper_comparison(rows):
            print(f"{q:<40} {'–' if o is None else f'{o:.1f}':>8} {p:>8.1f}")
        (args.out / "summary.json").write_text(json.dumps(
            {"wall_s": wall, "rows": len(rows), "comparison": paper_comparison(rows)}, indent=1))
        print(f"CSV and box plots in {args.out}")

    if not args.no_ablation:
        ablation(args.workers)

    if args.gap <= 0:
        return 0
    print(f"\n== allocation: Algorithms 1–2 vs exact MILP, {args.gap} random instances (2–4 robots, 2–4 tasks) ==")
    rows = allocation_gap(args.gap, seed=0)
    for key, name in (("gap", "eq. 20 team utility"), ("makespan_gap", "makespan (second comparison)")):
        g = np.array([r[key] for r in rows])
        print(f"{name:<30} mean gap {100 * g.mean():.1f} %, median {100 * np.median(g):.1f} %, max "
              f"{100 * g.max():.1f} %, optimal in {100 * (g < 1e-6).mean():.0f} % of instances")
    print(f"heuristic {1000 * np.mean([r['heuristic_s'] for r in rows]):.1f} ms, utility MILP "
          f"{1000 * np.mean([r['milp_s'] for r in rows]):.0f} ms per instance")
    return 0


def _ablation_row(cfg: MissionConfig) -> dict:
    res = run_mission(cfg)
    return {"mission_time": res.mission_time, "success": res.success, "min_separation": res.min_separation}


def ablation(workers: int, maps: int = 3) -> None:
    """Which modelling choice moves the numbers: Case II, 5 robots, maps 0..maps-1."""
    from concurrent.futures import ProcessPoolExecutor

    variants = [("paper APF (default)", {}), ("+ cruise term (former default)", {"cruise": True}),
                ("no robot–robot repulsion", {"robot_repulsion": False}),
                ("former: cruise, no robot repulsion", {"cruise": True, "robot_repulsion": False}),
                ("η_g = 3", {"eta_g": 3.0})]
    jobs = [(name, m, MissionConfig(case=2, n_robots=5, method=m, seed=s, record=False, **kw))
            for name, kw in variants for m in ("epistemic", "flock", "ideal") for s in range(maps)]
    jobs += [(f"flock radius {r} m", "flock", MissionConfig(case=2, n_robots=5, method="flock", seed=s, record=False,
                                                             flock_radius=r))
             for r in (4.0, 4.5) for s in range(maps)]
    t0 = time.perf_counter()
    with ProcessPoolExecutor(workers) as ex:
        out = list(ex.map(_ablation_row, [j[2] for j in jobs]))
    print(f"\n== ablation: Case II, 5 robots, maps 0–{maps - 1} ({len(jobs)} missions, "
          f"{time.perf_counter() - t0:.0f} s) ==")
    print(f"{'variant':<36} {'method':>10} {'mean [s]':>9} {'std [s]':>8} {'ok':>4} {'min sep [m]':>12}")
    keys = list(dict.fromkeys((j[0], j[1]) for j in jobs))
    for name, m in keys:
        sel = [o for j, o in zip(jobs, out, strict=True) if (j[0], j[1]) == (name, m)]
        t = np.array([o["mission_time"] for o in sel])
        print(f"{name:<36} {m:>10} {t.mean():>9.1f} {t.std(ddof=1):>8.1f} {sum(o['success'] for o in sel):>4} "
              f"{min(o['min_separation'] for o in sel):>12.3f}")


if __name__ == "__main__":
    raise SystemExit(main())
