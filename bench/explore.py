"""Benchmark of the communication-restricted exploration simulator (seed 000, Case Studies I and II).

1. One 8-robot Case II mission with the epistemic team: wall time vs simulated time (target ≥ 20×).
2. The full sweep: 2 cases × 15 maps × {2, 3, 5, 8} robots × {epistemic, flock, ideal} = 360 missions through a
   process pool with 2 workers (target < 15 min); mission-time statistics beside the paper's figures.
3. Allocation heuristics (Algorithms 1–2) vs the exact MILP on random small instances: optimality gap.

Usage: ``python bench/explore.py [--maps 15] [--workers 2] [--out DIR] [--gap 30]``. Prints plain tables.
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
    args = ap.parse_args()
    print(f"machine: {platform.node()} {os.cpu_count()} cores, python {platform.python_version()}, "
          f"{time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, load {os.getloadavg()[0]:.1f}")

    print("\n== one 8-robot Case II mission (epistemic) ==")
    print(f"{'seed':>4} {'simulated [s]':>14} {'wall [s]':>9} {'speed-up':>9}")
    ratios = []
    for seed in range(3):
        t0 = time.perf_counter()
        res = run_mission(MissionConfig(case=2, n_robots=8, method="epistemic", seed=seed, record=False))
        wall = time.perf_counter() - t0
        ratios.append(res.mission_time / wall)
        print(f"{seed:>4} {res.mission_time:>14.1f} {wall:>9.2f} {res.mission_time / wall:>8.1f}×")
    print(f"median speed-up {np.median(ratios):.1f}× (target ≥ 20×)")

    if not args.no_sweep:
        spec = SweepSpec(cases=(1, 2), robots=(2, 3, 5, 8), maps=args.maps)
        n = len(spec.cases) * spec.maps * len(spec.robots) * len(spec.methods)
        print(f"\n== full sweep: {n} missions, {args.workers} worker processes ==")
        t0 = time.perf_counter()
        rows = run_sweep(spec, workers=args.workers)
        wall = time.perf_counter() - t0
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
        print(f"\n{'quantity':<40} {'ours':>8} {'paper':>8}")
        for q, o, p in paper_comparison(rows):
            print(f"{q:<40} {'–' if o is None else f'{o:.1f}':>8} {p:>8.1f}")
        (args.out / "summary.json").write_text(json.dumps(
            {"wall_s": wall, "rows": len(rows), "comparison": paper_comparison(rows)}, indent=1))
        print(f"CSV and box plots in {args.out}")

    print(f"\n== allocation: Algorithms 1–2 vs exact MILP, {args.gap} random instances (2–4 robots, 2–4 tasks) ==")
    rows = allocation_gap(args.gap, seed=0)
    for key, name in (("gap", "eq. 20 team utility"), ("makespan_gap", "makespan (second comparison)")):
        g = np.array([r[key] for r in rows])
        print(f"{name:<30} mean gap {100 * g.mean():.1f} %, median {100 * np.median(g):.1f} %, max "
              f"{100 * g.max():.1f} %, optimal in {100 * (g < 1e-6).mean():.0f} % of instances")
    print(f"heuristic {1000 * np.mean([r['heuristic_s'] for r in rows]):.1f} ms, utility MILP "
          f"{1000 * np.mean([r['milp_s'] for r in rows]):.0f} ms per instance")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
