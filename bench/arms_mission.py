"""Closed-loop e-PICO missions on the planner's own DEL belief state: faults caught, --no-shield, speed.

    .venv/bin/python bench/arms_mission.py [--goal alpha] [--colors 1 2 3 4] [--layouts 20]
        [--faults none drop-msg@0 repaint@0 occlusion] [--no-shield-too] [--reading symmetric|owner]
        [--workers 1] [--json FILE] [--results FILE] [--summarise FILE]
    .venv/bin/python bench/arms_mission.py --perf [--repeat 3]
    .venv/bin/python bench/arms_mission.py --cells

Missions: for every colour count and layout seed 0 … N−1 (``planners.epico.generate(goal, colors, seed,
symmetric=True)``: a random both-robot layout), one mission per fault: the e-PICO plan executed on the two
simulated Pandas (friction grasps, side cameras) with the shield before every primitive action and the
checks after every task, on the planner's DEL state (compact backend), replanning from the belief state.
Per row: missions, faults fired / caught, successes (goal in the belief state, world = the belief state's
actual world, blocks within 1 cm, no arm contact), missions in which a step ran with a false precondition
("unsafe"), missions with a divergence nobody acted on ("audit", only --no-shield), replans, simulated s,
CPU s of the whole mission and of the task execution (physics, control, sensing, shield, checks, belief
updates; not the planning or the scene build), the real-time factor sim s / execution CPU s, and the CPU
share of the shield + checks and of the belief updates in the execution CPU. With ``--no-shield-too`` every
faulty mission runs again with ``--no-shield``.

``--perf``: the default α/4 mission (the seed's layout generalised), repeated: the same figures, per run.
All times are CPU (``time.process_time``) of this process; the machine is shared (load average printed).
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


def one(goal: str, colors: int, seed: int | None, fault: str, shield: bool = True, symmetric: bool = True,
        ik: str = "analytic") -> dict:
    """One mission. ``fault``: ``none``, one fault, several joined by ``+`` (``repaint@0+drop-msg@0``), and
    ``duplicates`` among them for a layout with several blocks of one colour per robot
    (``arms.mission.duplicate_layout(colors, seed)``)."""
    import arms.executor
    from arms.cli.epico_run import run_mission
    from arms.mission import duplicate_layout, parse_fault

    arms.executor.DEFAULT_IK = ik  # the executor's per-tick IK (--ik)

    parts = [] if fault == "none" else fault.split("+")
    layout = duplicate_layout(colors, seed or 0) if "duplicates" in parts else None
    faults = tuple(parse_fault(f) for f in parts if f != "duplicates")
    base = {"goal": goal, "colors": colors, "seed": seed, "fault": fault, "shield": shield}
    c0 = time.process_time()
    try:
        _inst, res, _m = run_mission(goal, colors, seed, faults=faults, shield=shield,
                                     symmetric=None if symmetric else False, layout=layout)
    except Exception as exc:  # a crash is a failed mission, reported with its message
        return {**base, "success": False, "reason": f"{type(exc).__name__}: {exc}", "replans": 0, "sim_s": 0.0,
                "cpu_s": time.process_time() - c0, "exec_s": 0.0, "guard_s": 0.0, "belief_s": 0.0, "fired": 0,
                "caught": 0, "caught_by": [], "unsafe": 0, "unheeded": 0, "audit_agrees": False, "fault_log": [],
                "unfired": [], "discarded": 0, "revisions": 0}
    log = res.faults
    fired = _fired(log)
    caught = len(res.caught_by)
    return {**base, "success": res.success, "reason": res.reason, "replans": res.replans, "sim_s": res.sim_seconds,
            "cpu_s": time.process_time() - c0, "exec_s": res.exec_cpu_seconds, "guard_s": res.guard_cpu_seconds,
            "belief_s": res.belief_cpu_seconds, "fired": fired, "caught": caught,
            "caught_by": sorted({c["by"] for c in res.caught_by}), "unsafe": len(res.unsafe_steps),
            "unheeded": len(res.unheeded), "audit_agrees": bool(res.audit["final"]["agrees"]),
            "revisions": sum(e["kind"] == "revision" for e in res.belief_log),
            "goal_in_beliefs": res.goal_in_beliefs, "goal_in_world": res.goal_in_world,
            "fault_log": log, "unfired": res.unfired, "planning_s": res.planning_seconds}


def _fired(log: list[str]) -> int:
    """Fault events in a mission's fault log (a swap that swapped something counts as one)."""
    return sum(1 for x in log if " fired at" in x or x.startswith("occlusion fired")
               or (x.startswith("swap-colours: ") and " is " in x and "caught" not in x))


def _star(args):
    return one(*args)


def table(rows: list[dict]) -> str:
    head = ("| colours | fault | shield | missions | faults fired | caught | caught by | success | audit agrees at end "
            "| unsafe step | unheeded divergence | wrong step shown | revisions | replans mean | sim s mean "
            "| CPU s mean (mission) | CPU s mean (execution) | shield+checks % of execution "
            "| belief updates CPU s mean |")
    out = [head, "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    keys = sorted({(r["colors"], r["fault"], r["shield"]) for r in rows},
                  key=lambda k: (k[0], k[1] != "none", k[1], not k[2]))
    for c, f, sh in keys:
        rs = [r for r in rows if r["colors"] == c and r["fault"] == f and r["shield"] == sh]
        n = len(rs)
        ok = sum(r["success"] for r in rs)
        ex = sum(r["exec_s"] for r in rs)
        by = sorted({b for r in rs for b in r.get("caught_by", [])})
        wrong = sum(bool(r["unsafe"] or r["unheeded"] or not r["audit_agrees"]) for r in rs)
        out.append(
            f"| {c} | {f} | {'on' if sh else 'OFF'} | {n} | {sum(_fired(r['fault_log']) for r in rs)} | "
            f"{sum(min(r['caught'], _fired(r['fault_log'])) for r in rs)} | {', '.join(by) or '-'} | {ok}/{n} | "
            f"{sum(r['audit_agrees'] for r in rs if r['success'])}/{ok} | {sum(r['unsafe'] > 0 for r in rs)} | "
            f"{sum(r['unheeded'] > 0 for r in rs)} | {wrong if not sh else '-'} | {sum(r['revisions'] for r in rs)} | "
            f"{sum(r['replans'] for r in rs) / n:.2f} | {sum(r['sim_s'] for r in rs) / n:.1f} | "
            f"{sum(r['cpu_s'] for r in rs) / n:.2f} | {ex / n:.2f} | "
            f"{100 * sum(r['guard_s'] for r in rs) / ex if ex else 0:.2f} | "
            f"{sum(r['belief_s'] for r in rs) / n:.3f} |")
    return "\n".join(out)


def perf(repeat: int, ik: str = "analytic") -> str:
    import arms.executor
    from arms.cli.epico_run import run_mission

    arms.executor.DEFAULT_IK = ik

    run_mission("alpha", 1, None, symmetric=True)  # imports, caches
    lines = ["| run | sim s | CPU s (mission) | CPU s (execution) | RTF sim/mission CPU | RTF sim/exec CPU | "
             "shield+checks CPU s (% of execution) | belief updates CPU s (%) | planning CPU s |",
             "|---|---|---|---|---|---|---|---|---|"]
    for i in range(repeat):
        c0 = time.process_time()
        _inst, res, _m = run_mission("alpha", 4, None, symmetric=True)
        cpu = time.process_time() - c0
        ex = res.exec_cpu_seconds
        assert res.success, res.reason
        lines.append(f"| {i} | {res.sim_seconds:.2f} | {cpu:.3f} | {ex:.3f} | {res.sim_seconds / cpu:.1f} | "
                     f"{res.sim_seconds / ex:.1f} | "
                     f"{res.guard_cpu_seconds:.4f} ({100 * res.guard_cpu_seconds / ex:.2f} %)"
                     f" | {res.belief_cpu_seconds:.4f} ({100 * res.belief_cpu_seconds / ex:.2f} %) | "
                     f"{sum(res.planning_cpu_seconds):.3f} |")
    return "\n".join(lines)


def cells() -> str:
    """Every defined Table-1 cell (N ≤ 4) on the seed's layout, one mission each (no fault)."""
    from arms.cli.epico_run import run_mission

    lines = ["| goal | colours | success | audit agrees at end | executed steps | every executed precondition true "
             "| looks | sim s | mission CPU s | execution CPU s | planning CPU s | shield+checks CPU s | "
             "belief updates CPU s |", "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for g in ("alpha", "beta", "gamma", "delta"):
        for n in (1, 2, 3, 4):
            if g in ("gamma", "delta") and n == 1:
                continue
            c0 = time.process_time()
            _inst, res, _m = run_mission(g, n, None)
            cpu = time.process_time() - c0
            ex = [s for s in res.steps if s.executed and s.task not in ("final look", "recovery")]
            looks = sum(1 for s in res.steps if "look" in s.checks)
            lines.append(f"| {g} | {n} | {res.success} | {res.audit['final']['agrees']} | {len(ex)} | "
                         f"{all(s.precondition_holds for s in ex)} | {looks} | {res.sim_seconds:.1f} | {cpu:.2f} | "
                         f"{res.exec_cpu_seconds:.2f} | {sum(res.planning_cpu_seconds):.3f} | "
                         f"{res.guard_cpu_seconds:.3f} | {res.belief_cpu_seconds:.3f} |")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--goal", default="alpha")
    ap.add_argument("--colors", type=int, nargs="+", default=[1, 2, 3, 4])
    ap.add_argument("--layouts", type=int, default=20)
    ap.add_argument("--first-seed", type=int, default=0)
    ap.add_argument("--faults", nargs="+", default=["none", "repaint@0", "drop-msg@0", "occlusion",
                                                    "repaint@0+drop-msg@0", "duplicates+repaint@0"],
                    help="faults per mission; several joined by + ; 'duplicates' = a layout with several blocks of "
                         "one colour per robot")
    ap.add_argument("--no-shield-too", action="store_true", help="run every faulty mission again with --no-shield")
    ap.add_argument("--no-shield-only", action="store_true", help="run the faulty missions with --no-shield only")
    ap.add_argument("--reading", choices=["symmetric", "owner"], default="symmetric")
    ap.add_argument("--perf", action="store_true", help="the α/4 default mission, --repeat times")
    ap.add_argument("--cells", action="store_true", help="every defined Table-1 cell (N ≤ 4), seed's layout")
    ap.add_argument("--repeat", type=int, default=3)
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
                 for r in rows if not r["success"] and r["shield"]]
        print(table(rows), "", "Failures:" if fails else "Failures: none", *fails, sep="\n")
        return 0

    if args.cells:
        load0 = os.getloadavg()[0]
        print(cells())
        print(f"load average {load0:.1f} → {os.getloadavg()[0]:.1f}; {platform.machine()}, {os.cpu_count()} cores")
        return 0
    if args.perf:
        load0 = os.getloadavg()[0]
        text = perf(args.repeat, args.ik)
        print(text)
        print(f"load average {load0:.1f} → {os.getloadavg()[0]:.1f}; {platform.machine()}, {os.cpu_count()} cores")
        return 0
    from delkit.progress import progress

    # seed by seed (every colour count and fault for seed 0, then seed 1, ...): a partial run covers all cells
    sym = args.reading == "symmetric"
    jobs = [(args.goal, c, s, f, sh, sym) for s in range(args.first_seed, args.first_seed + args.layouts)
            for c in args.colors for f in args.faults
            for sh in ((False,) if args.no_shield_only else (True, False) if args.no_shield_too else (True,))
            if sh or f != "none"]
    jobs = [(*j, args.ik) for j in jobs]
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
             for r in rows if not r["success"] and r["shield"]]
    machine = (f"{platform.machine()}, {os.cpu_count()} cores shared with other jobs, Python "
               f"{platform.python_version()}, load average {load0:.1f} → {os.getloadavg()[0]:.1f}")
    text = "\n".join([
        f"Goal {args.goal}; layouts: seeds {args.first_seed}…{args.first_seed + args.layouts - 1} per colour count; "
        f"faults: {', '.join(args.faults)}; reading: {args.reading}; friction grasps",
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
