"""Benchmark of the communication-restricted exploration simulator (seed 000, Case Studies I and II).

1. One 8-robot Case II mission with the epistemic team: wall time vs simulated time (target ≥ 20×).
2. The full sweep: 2 cases × 15 maps × {2, 3, 5, 8} robots × {epistemic, flock, ideal} = 360 missions through a
   process pool with 2 workers (target < 15 min); mission-time statistics beside the paper's figures.
3. Allocation heuristics (Algorithms 1–2) vs the exact MILP on random small instances: optimality gap.

4. Ablations (3 maps, Case II, 5 robots): the paper's APF (η_g = 1, robot–robot repulsion, no cruise term) vs
   with our former cruise term, without robot repulsion, with η_g = 3; flock formation radius 3 / 4 / 4.5 m.

Every sweep row also carries the minimum robot–robot separation and Algorithm 3's cascade (assigned/delivered).

5. ``--diagnose``: the sweep with per-mission diagnosis; every epistemic mission more than 2× its
   ideal twin gets a timeline and the rule it is attributed to (:mod:`sim.diagnosis`), is re-run with each rule
   changed alone, and the whole sweep is re-run with the parameters the paper implies (``PAPER_IMPLIED``):
   Figs. 6 and 8 side by side — ours as before, ours with those parameters, the paper.

Usage: ``python bench/explore.py [--maps 15] [--workers 2] [--out DIR] [--gap 30] [--no-ablation] [--diagnose]``.
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
    ap.add_argument("--diagnose", action="store_true", help="diagnosis and paper-implied parameters only")
    ap.add_argument("--methods", default="epistemic,ideal,flock", help="--diagnose: teams of the default sweep")
    args = ap.parse_args()
    print(f"machine: {platform.node()} {os.cpu_count()} cores, python {platform.python_version()}, "
          f"{time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, load {os.getloadavg()[0]:.1f}")

    if args.diagnose:
        return diagnose(args.maps, args.workers, args.out, tuple(args.methods.split(",")))

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


#: the reading of §5.3.2 that the rest of the paper implies (each measured alone in --diagnose):
#: look for j where it was last believed and then where j itself goes (its common-belief particle), exclude j
#: only once both were visited, and wait at a task as long as a gossip round trip takes
#: (wait_rule='travel', the round-trip time-out, is measured alone: it makes robots give up too early)
PAPER_IMPLIED = (("gossip_target", "both"), ("exclude_rule", "visited"))
SINGLE_CHANGES = [("gossip_target = common", (("gossip_target", "common"),)),
                  ("gossip_target = both", (("gossip_target", "both"),)),
                  ("exclude_rule = visited", (("exclude_rule", "visited"),)),
                  ("wait_rule = travel", (("wait_rule", "travel"),)),
                  ("all three (PAPER_IMPLIED)", PAPER_IMPLIED)]


def _sweep(spec: SweepSpec, workers: int, label: str) -> list[dict]:
    import resource

    t0, ru0 = time.perf_counter(), resource.getrusage(resource.RUSAGE_CHILDREN)
    rows = run_sweep(spec, workers=workers)
    ru1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (ru1.ru_utime + ru1.ru_stime) - (ru0.ru_utime + ru0.ru_stime)
    print(f"[{label}: {len(rows)} missions, {time.perf_counter() - t0:.0f} s wall, {cpu:.0f} s CPU of the "
          f"workers, load {os.getloadavg()[0]:.1f}; failures {sum(not r['success'] for r in rows)}]")
    return rows


#: flock rows of the 2026-11-30 sweep (bench/RESULTS-explore.md): (case, "flock", size) ↦ (mean, std)
FLOCK_PREVIOUS = {(1, "flock", 2): (60.7, 35.7), (1, "flock", 3): (90.7, 41.9), (1, "flock", 5): (111.3, 47.5),
                  (1, "flock", 8): (348.9, 473.8), (1, "flock", "all"): (152.9, 149.7),
                  (2, "flock", 2): (171.2, 12.2), (2, "flock", 3): (220.2, 17.0), (2, "flock", 5): (224.4, 23.2),
                  (2, "flock", 8): (247.6, 19.7), (2, "flock", "all"): (215.8, 18.0)}


def _figures(rows: list[dict]) -> dict[tuple, float]:
    out = {}
    for k, v in summarise(rows).items():
        out[k] = v["mean"]
        out[k + ("std",)] = v["std"]
    return out


def diagnose(maps: int, workers: int, out_dir: Path, methods: tuple[str, ...] = ("epistemic", "ideal", "flock")) -> int:
    """Per-mission diagnosis of the slow epistemic missions and the paper-implied sweep."""
    from dataclasses import replace as dc_replace

    from sim.diagnosis import attribute, timeline
    from sim.experiments import run_one_diagnosed

    # flock and ideal do not gossip: gossip_target and exclude_rule change the epistemic team only, so the
    # paper-implied sweep runs the epistemic team alone and flock is taken from a default sweep when asked
    base = SweepSpec(cases=(1, 2), robots=(2, 3, 5, 8), maps=maps, diagnose=True, methods=methods)
    out_dir.mkdir(parents=True, exist_ok=True)
    n = len(base.cases) * maps * 4 * len(methods)
    print(f"\n== diagnosis sweep (defaults): {n} missions, {workers} workers ==")
    rows = _sweep(base, workers, "defaults")
    (out_dir / "defaults.json").write_text(json.dumps(rows, default=str))
    def key(r: dict) -> tuple:
        return r["case"], r["n_robots"], r["seed"]

    ideal = {key(r): r for r in rows if r["method"] == "ideal"}
    slow = [(r, ideal[key(r)]) for r in rows if r["method"] == "epistemic"
            and r["mission_time"] > 2.0 * ideal[key(r)]["mission_time"]]
    print(f"\n{len(slow)} of {len(ideal)} epistemic missions take more than 2× their ideal twin:")
    attributions = []
    for e, i in slow:
        a = attribute(e, i)
        attributions.append(a)
        print(f"\n-- Case {a['case']}, {a['n_robots']} robots, map {a['seed']}: epistemic {a['epistemic']:.1f} s, "
              f"ideal {a['ideal']:.1f} s (excess {a['excess']:.1f} s = discovery {a['discovery']:+.1f} + "
              f"allocation→completion {a['completion']:+.1f} + after the last completion {a['home']:+.1f})")
        for line in timeline(e):
            print("   " + line)
        for c in a["causes"]:
            print("   cause: " + c)
    counts = {"target_mismatch": sum(a["target_mismatch"] > 0 for a in attributions),
              "false_exclusions": sum(a["false_exclusions"] > 0 for a in attributions),
              "timeouts": sum(a["timeouts"] > 0 for a in attributions)}
    print(f"\nslow missions with: a ruleset-1 exclusion of a robot not busy {counts['false_exclusions']}, of "
          f"them sought at the wrong particle {counts['target_mismatch']}; a wait ended by the time-out "
          f"{counts['timeouts']}")

    # each rule changed alone, on the slow missions
    if slow:
        from concurrent.futures import ProcessPoolExecutor

        jobs = []
        for _, changes in SINGLE_CHANGES:
            for e, _ in slow:
                jobs.append(MissionConfig(case=e["case"], n_robots=e["n_robots"], method="epistemic", seed=e["seed"],
                                          record=False, **dict(changes)))
        with ProcessPoolExecutor(workers) as ex:
            res = list(ex.map(run_one_diagnosed, jobs))
        print("\n== the slow missions with each rule changed alone (epistemic mission time [s]) ==")
        head = "".join(f" {name[:22]:>23}" for name, _ in SINGLE_CHANGES)
        print(f"{'case/robots/map':>16} {'ideal':>7} {'default':>8}{head}")
        for m, (e, i) in enumerate(slow):
            vals = [res[c * len(slow) + m]["mission_time"] for c in range(len(SINGLE_CHANGES))]
            print(f"{e['case']:>6}/{e['n_robots']}/{e['seed']:<7} {i['mission_time']:>7.1f} {e['mission_time']:>8.1f}"
                  + "".join(f" {v:>23.1f}" for v in vals))

    print(f"\n== the sweep with the paper-implied parameters {dict(PAPER_IMPLIED)} ==")
    implied = _sweep(dc_replace(base, overrides=PAPER_IMPLIED, methods=("epistemic",)), workers, "paper-implied")
    implied += [r for r in rows if r["method"] != "epistemic"]  # unchanged by these parameters (see above)
    write_csv(rows, out_dir / "runs-defaults.csv")
    write_csv(implied, out_dir / "runs-paper-implied.csv")
    (out_dir / "diagnosis.json").write_text(json.dumps(
        {"slow": attributions, "defaults": rows, "paper_implied": implied}, default=str))
    from sim.plots import box_plot

    for c in (1, 2):
        box_plot(implied, out_dir / f"case{c}_boxplot_paper_implied.png", case=c)
    fd, fi = _figures(rows), _figures(implied)
    if "flock" not in methods:
        for k, v in FLOCK_PREVIOUS.items():  # the 2026-11-30 sweep's flock rows (same code, deterministic)
            for f in (fd, fi):
                f[k], f[k + ("std",)] = v
        print("(flock: the 2026-11-30 sweep's figures, bench/RESULTS-explore.md; the flock code is unchanged)")
    for c in (1, 2):
        print(f"\nFig. {6 if c == 1 else 8} (Case {'I' if c == 1 else 'II'}): mission time mean ± std [s] per team "
              "size — defaults | paper-implied")
        print(f"{'method':>10}" + "".join(f" {n:>24}" for n in (2, 3, 5, 8, "all")))
        for m in ("epistemic", "flock", "ideal"):
            if (c, m, 2) not in fd:
                continue
            cells = [f"{fd[(c, m, n)]:.1f}±{fd[(c, m, n, 'std')]:.0f} | {fi[(c, m, n)]:.1f}±{fi[(c, m, n, 'std')]:.0f}"
                     for n in (2, 3, 5, 8, "all")]
            print(f"{m:>10}" + "".join(f" {x:>24}" for x in cells))
    from sim.experiments import PAPER

    print(f"\n{'quantity':<40} {'defaults':>9} {'implied':>9} {'paper':>7}")
    for c in (1, 2):
        paper = PAPER[f"case{c}"]
        for q, a, b in ((f"case {c}: flock − epistemic mean [s]", "flock", "epistemic"),
                        (f"case {c}: epistemic − ideal mean [s]", "epistemic", "ideal")):
            vals = [f[(c, a, "all")] - f[(c, b, "all")] if (c, a, "all") in f and (c, b, "all") in f else None
                    for f in (fd, fi)]
            print(f"{q:<40} " + " ".join("     –   " if v is None else f"{v:>9.1f}" for v in vals)
                  + f" {paper['flock_minus_epistemic' if a == 'flock' else 'epistemic_minus_ideal']:>7.1f}")
        for m in ("epistemic", "ideal", "flock"):
            if (c, m, "all") in fd:
                print(f"{f'case {c}: std of {m} [s]':<40} {fd[(c, m, 'all', 'std')]:>9.1f} "
                      f"{fi[(c, m, 'all', 'std')]:>9.1f} {paper.get(f'std_{m}', float('nan')):>7.1f}")
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
