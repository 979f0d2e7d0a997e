"""Benchmark of the arms layer: IK success rate / time (TRAC-IK protocol) and physics speed.

    .venv/bin/python bench/ik.py [--targets 1000] [--seed 0] [--protocol trac-ik|seed-table|both]
                                 [--clock wall|cpu|both] [--results FILE]

IK: the analytic solver (``arms.ik_analytic``: He & Liu's closed form over a q7 sweep, batch-CLIK
fallback), mink and the pinocchio CLIK, one after another on the same targets.
N random joint vectors within the Panda's limits → FK → solve IK for that TCP pose; success =
position error < 1e-5 m and orientation error < 1e-4 rad within the 5 ms budget. Protocol ``trac-ik``
(default, TRAC-IK's own): every query starts from the middle of the joint ranges, random restarts
inside the budget, mean (TRAC-IK's statistic) and median of every query's time. ``seed-table``: the
variant that starts from the nearest of 16,384 precomputed configurations (table built outside the
timed region) — not comparable with TRAC-IK's figures. Clocks: wall (as TRAC-IK measures) and the
thread CPU clock (insensitive to other processes on a loaded machine). Inside the timed region: the
solve call only (target pose given as a 4×4 matrix; the FK check of the answer is outside).
Physics: the built-in two-robot plan with friction grasps, simulated seconds per wall second.
"""

from __future__ import annotations

import argparse
import datetime
import os
import platform
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from arms.benchmark import TRAC_IK_PANDA, benchmark_ik  # noqa: E402
from arms.demo import demo_plan  # noqa: E402
from arms.executor import run_plan  # noqa: E402


def _fmt(x: float) -> str:
    return "-" if x != x else f"{x:.3f}"


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--targets", type=int, default=1000)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--budget-ms", type=float, default=5.0)
    ap.add_argument("--protocol", choices=("trac-ik", "seed-table", "both"), default="both")
    ap.add_argument("--clock", choices=("wall", "cpu", "both"), default="both")
    ap.add_argument("--results", type=Path, default=None, help="write the markdown table to this file")
    args = ap.parse_args(argv)

    rows = []
    load_before = os.getloadavg()[0]
    protocols = ("trac-ik", "seed-table") if args.protocol == "both" else (args.protocol,)
    clocks = ("wall", "cpu") if args.clock == "both" else (args.clock,)
    for protocol in protocols:
        for clock in clocks:
            for s in benchmark_ik(args.targets, seed=args.seed, budget=args.budget_ms / 1000, clock=clock,
                                  protocol=protocol):
                rows.append((f"{s.solver} [{protocol}, {clock} clock]", 100 * s.rate, s.mean_s * 1e3,
                             s.median_s * 1e3, s.p95_s * 1e3, s.us_per_iteration))
    rows += [(f"{n} (published, Panda, TRAC-IK protocol)", r, t, float("nan"), float("nan"), float("nan"))
             for n, r, t in TRAC_IK_PANDA]

    t0, c0 = time.perf_counter(), time.process_time()
    result, _ = run_plan(demo_plan(), grasp="friction")
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    load_after = os.getloadavg()[0]

    head = (f"| solver [protocol, clock] | success % (≤ {args.budget_ms:g} ms) | mean ms | median ms | p95 ms "
            "| µs / iteration |")
    lines = [head, "|---|---|---|---|---|---|"]
    for name, rate, mean, med, p95, per_it in rows:
        lines.append(f"| {name} | {rate:.2f} | {_fmt(mean)} | {_fmt(med)} | {_fmt(p95)} | {_fmt(per_it)} |")
    errs = [a.max_block_error for a in result.actions]
    phys = [
        "| plan | success | simulated s | wall s (incl. scene build) | sim s / wall s | CPU s | sim s / CPU s | "
        "max block error mm | max slip in hand mm |",
        "|---|---|---|---|---|---|---|---|---|",
        f"| built-in two-robot plan ({len(result.actions)} actions, friction grasp) | {result.success} | "
        f"{result.sim_seconds:.1f} | {wall:.1f} | {result.sim_seconds / wall:.2f} | {cpu:.1f} | "
        f"{result.sim_seconds / cpu:.1f} | {1000 * max(errs):.2f} | "
        f"{1000 * result.max_slip:.3f} |",
    ]
    machine = (f"{platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}, "
               f"load average {load_before:.1f} → {load_after:.1f}")
    text = "\n".join([
        f"IK: {args.targets} random reachable poses of robot1's TCP, seed {args.seed}",
        *lines, "", "Physics:", *phys, "", f"machine: {machine}",
        f"date: {datetime.datetime.now(datetime.UTC).strftime('%Y-%m-%d %H:%M UTC')}",
    ])
    print(text)
    if args.results is not None:
        args.results.write_text(text + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
