"""Closed-loop e-PICO missions in physics: success rate without and with injected faults, replans used.

    .venv/bin/python bench/arms_mission.py [--goal alpha] [--colors 1 2 3 4] [--layouts 20]
        [--faults none drop@0 misplace@0 swap-colours] [--workers 1] [--json FILE] [--results FILE]
        [--default-layout [--repeat K]] [--ik analytic|mink]

For every colour count and layout seed 0 … N−1 (``planners.epico.generate(goal, colors, seed)``: a random
layout), one mission per fault setting: the e-PICO plan (epistemic + classical) executed on the two
simulated Pandas with friction grasps, line-of-sight sensing, DEL belief updates, the per-action monitor
and replanning (``arms.mission``). Success = the goal holds in the simulated world and in the robots'
beliefs, every block within 1 cm of its symbolic place, no arm–arm contact. Per row: successes, replans
used (mean / max), planning seconds per plan (mean / max, wall), simulated seconds, CPU seconds of the
whole mission (scene build, planning, physics, control, sensing) and the real-time factor on the CPU
clock (simulated s / CPU s) and on the wall clock (the machine is shared: the wall clock includes time
given to other processes). Inside the timed region: everything from instance generation to the final
goal check.
"""

from __future__ import annotations

import argparse
import datetime
import json
import os
import platform
import sys
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))


def one(goal: str, colors: int, seed: int | None, fault: str, ik: str = "analytic") -> dict:
    import arms.executor
    from arms.cli.epico_run import run_mission
    from arms.mission import parse_fault

    arms.executor.DEFAULT_IK = ik  # the executor's per-tick IK (--ik)

    faults = () if fault == "none" else (parse_fault(fault),)
    t0, c0 = time.perf_counter(), time.process_time()
    try:
        _inst, res, _m = run_mission(goal, colors, seed, faults=faults)
    except Exception as exc:  # a crash is a failed mission, reported with its message
        return {"goal": goal, "colors": colors, "seed": seed, "fault": fault, "success": False,
                "reason": f"{type(exc).__name__}: {exc}", "replans": 0, "planning_s": [], "sim_s": 0.0,
                "cpu_s": time.process_time() - c0, "wall_s": time.perf_counter() - t0, "max_err_m": None,
                "fault_log": [], "contacts": 0}
    return {"goal": goal, "colors": colors, "seed": seed, "fault": fault, "success": res.success,
            "reason": res.reason, "replans": res.replans, "planning_s": res.planning_seconds,
            "sim_s": res.sim_seconds, "cpu_s": time.process_time() - c0, "wall_s": time.perf_counter() - t0,
            "max_err_m": res.max_block_error, "fault_log": res.faults, "contacts": res.arm_contacts}


def _star(args):
    return one(*args)


def table(rows: list[dict]) -> str:
    head = ("| colours | fault | missions | fault fired | success | replans mean / max | planning s per plan "
            "mean / max | sim s mean | CPU s mean | RTF (sim/CPU) | RTF (sim/wall) |")
    out = [head, "|---|---|---|---|---|---|---|---|---|---|---|"]
    keys = sorted({(r["colors"], r["fault"]) for r in rows}, key=lambda k: (k[0], k[1] != "none", k[1]))
    for c, f in keys:
        rs = [r for r in rows if r["colors"] == c and r["fault"] == f]
        ok = sum(r["success"] for r in rs)
        fired = sum(bool(r["fault_log"]) and not any("nothing swapped" in x or "not fired" in x
                                                     for x in r["fault_log"]) for r in rs)
        rep = [r["replans"] for r in rs]
        plan = [p for r in rs for p in r["planning_s"]]
        sim = sum(r["sim_s"] for r in rs)
        cpu = sum(r["cpu_s"] for r in rs)
        wall = sum(r["wall_s"] for r in rs)
        out.append(f"| {c} | {f} | {len(rs)} | {fired if f != 'none' else '-'} | {ok}/{len(rs)} "
                   f"({100 * ok / len(rs):.0f} %) | "
                   f"{sum(rep) / len(rep):.2f} / {max(rep)} | "
                   f"{(sum(plan) / len(plan)) if plan else float('nan'):.3f} / {max(plan, default=float('nan')):.3f} | "
                   f"{sim / len(rs):.1f} | {cpu / len(rs):.1f} | {sim / cpu if cpu else 0:.1f} | "
                   f"{sim / wall if wall else 0:.1f} |")
    return "\n".join(out)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--goal", default="alpha")
    ap.add_argument("--colors", type=int, nargs="+", default=[1, 2, 3, 4])
    ap.add_argument("--layouts", type=int, default=20)
    ap.add_argument("--first-seed", type=int, default=0)
    ap.add_argument("--faults", nargs="+", default=["none", "drop@0", "misplace@0", "swap-colours"])
    ap.add_argument("--default-layout", action="store_true",
                    help="the seed's default layout (`delkit epico run` without --seed) instead of random ones")
    ap.add_argument("--repeat", type=int, default=1, help="with --default-layout: run it this many times")
    ap.add_argument("--ik", choices=("analytic", "mink"), default="analytic",
                    help="the executor's per-tick IK (default analytic; mink: the QP on every tick)")
    ap.add_argument("--workers", type=int, default=1)
    ap.add_argument("--json", type=Path, default=None, help="write every mission's row (JSON lines)")
    ap.add_argument("--results", type=Path, default=None, help="write the markdown table to this file")
    ap.add_argument("--summarise", type=Path, default=None, help="only print the table of a --json file")
    args = ap.parse_args(argv)
    if args.summarise is not None:
        rows = [json.loads(line) for line in args.summarise.read_text().splitlines() if line.strip()]
        fails = [f"- colours {r['colors']}, seed {r['seed']}, {r['fault']}: {r['reason']}"
                 for r in rows if not r["success"]]
        print(table(rows), "", "Failures:" if fails else "Failures: none", *fails, sep="\n")
        return 0

    from delkit.progress import progress

    # seed by seed (every colour count and fault for seed 0, then seed 1, ...): a partial run covers all cells
    seeds = [None] * args.repeat if args.default_layout else range(args.first_seed, args.first_seed + args.layouts)
    jobs = [(args.goal, c, s, f, args.ik) for s in seeds for c in args.colors for f in args.faults]
    rows: list[dict] = []
    load0 = os.getloadavg()[0]
    t0 = time.perf_counter()
    sink = args.json.open("a") if args.json else None
    with progress(transient=False) as prog:
        task = prog.add_task("missions", total=len(jobs))
        if args.workers > 1:
            with ProcessPoolExecutor(args.workers) as pool:
                results = pool.map(_star, jobs)
                for r in results:
                    rows.append(r)
                    if sink:
                        sink.write(json.dumps(r) + "\n")
                        sink.flush()
                    prog.advance(task)
        else:
            for j in jobs:
                r = one(*j)
                rows.append(r)
                if sink:
                    sink.write(json.dumps(r) + "\n")
                    sink.flush()
                prog.advance(task)
    if sink:
        sink.close()
    fails = [f"- colours {r['colors']}, seed {r['seed']}, {r['fault']}: {r['reason']}"
             for r in rows if not r["success"]]
    machine = (f"{platform.machine()}, {os.cpu_count()} cores shared with other jobs, Python "
               f"{platform.python_version()}, load average {load0:.1f} → {os.getloadavg()[0]:.1f}")
    text = "\n".join([
        f"Goal {args.goal}; layouts: "
        + (f"the default layout, {args.repeat} run(s)" if args.default_layout else
           f"seeds {args.first_seed}…{args.first_seed + args.layouts - 1}")
        + f" per colour count; faults: {', '.join(args.faults)}; friction grasps; per-tick IK: {args.ik}",
        table(rows), "", "Failures:" if fails else "Failures: none", *fails, "",
        f"machine: {machine}; {len(rows)} missions in {time.perf_counter() - t0:.0f} s wall",
        f"date: {datetime.datetime.now(datetime.UTC).strftime('%Y-%m-%d %H:%M UTC')}",
    ])
    print(text)
    if args.results is not None:
        args.results.write_text(text + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
