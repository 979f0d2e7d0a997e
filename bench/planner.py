"""Epistemic planner benchmark: every instance of ../shared/benchmarks/mastar/expected.csv (and the
project's own specs/grapevine5), whole process beside EFP.

For each instance the script runs ``delkit plan FILE --json`` as a fresh process (``python -c "from
delkit.cli import main ..."``) ``--runs`` times after one untimed warm-up and reports:

* the **whole-process** median wall seconds and median CPU seconds (user + system of the child, from
  ``RUSAGE_CHILDREN``) — interpreter start, imports, parsing, initial state, search, output, exit: the
  same region as EFP's recorded times, which are whole runs of the EFP binary (children may write
  bytecode, as an installed package has: the warm-up leaves ``.pyc`` files);
* the **search** seconds the planner reports (``seconds`` in its JSON: initial state + search, no parsing),
  median over the runs;
* EFP's recorded seconds from the same CSV row (C++ -O2, 2-core machine, BFS, 60 s limit; "poss" is EFP's
  faster possibilities representation, "Kripke" its Kripke one) and the difference ours − EFP-poss.

Targets: whole-process faster than EFP wherever EFP needs ≥ 0.3 s, never more than 0.2 s slower.

``--expansions`` instead prints, in-process, BFS's and A*'s (default heuristic ``h_epi``) plan lengths and
expanded nodes on every instance (and A*'s search seconds), with the ratio A*/BFS; ``--bfs-timeout`` caps
BFS (a capped BFS is shown as a lower bound on its expansions).

    .venv/bin/python bench/planner.py [--runs 5] [--search bfs] [--engine fast] [--no-own] [--json out.json]
    .venv/bin/python bench/planner.py --expansions [--bfs-timeout 1200]
    .venv/bin/python bench/planner.py --suite [--jobs 2]
    .venv/bin/python bench/planner.py --heuristics        # A*: h_epi vs h_chain, expansions and CPU
    .venv/bin/python bench/planner.py [--suite] --efp-bin /work/peers/efp/build/bin/efp.out   # EFP in the same run

``--efp-bin PATH`` (or ``$EFP_BIN``) measures EFP in the same run (bench/peers/efp: how to build it): before
each timed ``delkit plan`` process, one ``efp.out FILE -st POSS`` process (EFP's possibilities representation,
BFS, its default search), timed the same way (whole process, CPU from ``RUSAGE_CHILDREN``); the table gains
EFP's same-run median CPU and its plan length, and the recorded CSV column stays beside it. With ``--suite`` it
adds EFP's totals over the suite: one EFP process per instance (EFP has no batch mode), summed, and the wall
of the same processes run two at a time (the 2 cores delkit's ``--jobs 2`` uses).

``--suite`` runs the whole suite as ONE ``delkit plan FILE... --jobs N --json`` command and prints
each task's length beside EFP's, and the command's total CPU and wall seconds beside the sum of EFP's.
"""

from __future__ import annotations

import argparse
import csv
import json
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

from _timing import timed_run

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from delkit.progress import track  # noqa: E402
from planners.lang import shared_benchmarks  # noqa: E402

_MAIN = "import sys; from delkit.cli import main; sys.exit(main())"
OWN = [("specs/grapevine5/Grapevine_5__pl_6.txt", 6)]


def _efp(x: str) -> float | None:
    try:
        return float(x)
    except ValueError:
        return None  # ">60 (timeout)"


def _efp_once(binary: Path, path: Path, timeout: float) -> tuple[float, float, dict]:
    """One EFP process on ``path`` (possibilities, BFS): (wall s, CPU s, {"length", "status"}). EFP runs in a
    scratch directory (it may write result files into its working directory); a run past ``timeout`` is
    killed and reported as ``timeout`` (its CPU until then is counted)."""
    import tempfile

    with tempfile.TemporaryDirectory(prefix="efp-") as cwd:
        r = timed_run([str(binary), str(path), "-st", "POSS"], cwd=cwd, timeout=timeout)
    wall, cpu, text, code = r.wall, r.cpu, r.stdout, r.returncode
    if r.timed_out:
        return wall, cpu, {"length": None, "status": "timeout"}
    for line in text.splitlines():
        if line.strip().startswith("Plan Length:"):
            return wall, cpu, {"length": int(line.split(":")[1]), "status": "solved"}
    if "Initial was Goal" in text:
        return wall, cpu, {"length": 0, "status": "solved"}
    status = "unsolvable" if "No plan found" in text or "does not exists any Plan" in text else f"error (exit {code})"
    return wall, cpu, {"length": None, "status": status}


def _efp_binary(arg: Path | None) -> Path | None:
    path = arg or (Path(os.environ["EFP_BIN"]) if os.environ.get("EFP_BIN") else None)
    if path is not None and not (path.is_file() and os.access(path, os.X_OK)):
        raise SystemExit(f"--efp-bin {path}: not an executable file (build it: sh bench/peers/efp/build.sh)")
    return path


def _once(path: Path, search: str, engine: str, timeout: float) -> tuple[float, float, dict]:
    env = dict(os.environ, PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    env.pop("PYTHONDONTWRITEBYTECODE", None)  # as an installed package: the warm-up run leaves .pyc files
    cmd = [sys.executable, "-c", _MAIN, "plan", str(path), "--json", "--search", search, "--engine", engine,
           "--timeout", f"{timeout:g}"]
    r = timed_run(cmd, env=env)
    try:
        out = json.loads(r.stdout)
    except json.JSONDecodeError:
        out = {"status": "error", "length": None, "expanded": None, "seconds": None,
               "reason": r.stderr.strip()[-200:]}
    return r.wall, r.cpu, out


def run(runs: int, search: str, engine: str, timeout: float, own: bool = True, efp: Path | None = None) -> list[dict]:
    bench = shared_benchmarks()
    if bench is None:
        raise SystemExit("../shared/benchmarks is not available")
    items = [(bench / "mastar" / r["file"], r["file"], int(r["expected_length"]), _efp(r["efp_possibilities_s"]),
              _efp(r["efp_kripke_s"]), r["efp_kripke_s"])
             for r in csv.DictReader((bench / "mastar" / "expected.csv").open())]
    if own:
        items += [(ROOT / f, f, n, None, None, "-") for f, n in OWN]
    out = []
    for path, name, expected, poss, kripke, kripke_text in track(items, f"plan ({search})"):
        _once(path, search, engine, timeout)  # warm-up (page cache, parser cache)
        walls, cpus, searches, res = [], [], [], {}
        e_cpus, e_walls, e_res = [], [], {}
        for _ in range(runs):
            if efp is not None:  # EFP's process right before ours, in the same run
                ew, ec, e_res = _efp_once(efp, path, timeout)
                e_walls.append(ew)
                e_cpus.append(ec)
            w, c, res = _once(path, search, engine, timeout)
            walls.append(w)
            cpus.append(c)
            if res.get("seconds") is not None:
                searches.append(res["seconds"])
        out.append({"file": name, "expected": expected, "length": res.get("length"), "status": res.get("status"),
                    "expanded": res.get("expanded"), "wall": statistics.median(walls), "wall_min": min(walls),
                    "cpu": statistics.median(cpus), "search": statistics.median(searches) if searches else None,
                    "efp_poss": poss, "efp_kripke": kripke, "efp_kripke_text": kripke_text,
                    "efp_same_cpu": statistics.median(e_cpus) if e_cpus else None,
                    "efp_same_wall": statistics.median(e_walls) if e_walls else None,
                    "efp_same_length": e_res.get("length"), "efp_same_status": e_res.get("status")})
    return out


def expansions(bfs_timeout: float) -> list[dict]:
    """BFS vs A* (h_epi) in-process on every instance: lengths, expanded nodes, A*'s seconds."""
    from planners.epistemic import Limits, plan
    from planners.lang import load_task

    bench = shared_benchmarks()
    if bench is None:
        raise SystemExit("../shared/benchmarks is not available")
    items = [(bench / "mastar" / r["file"], r["file"], int(r["expected_length"]))
             for r in csv.DictReader((bench / "mastar" / "expected.csv").open())]
    items += [(ROOT / f, f, n) for f, n in OWN]
    out = []
    for path, name, expected in track(items, "load + search"):
        task = load_task(path)
        c0 = time.process_time()
        a = plan(task, search="astar", limits=Limits(timeout=600))
        a_cpu = time.process_time() - c0
        b = plan(task, search="bfs", limits=Limits(timeout=bfs_timeout))
        out.append({"file": name, "expected": expected, "bfs_length": b.length, "bfs_status": b.status,
                    "bfs_expanded": b.expanded, "bfs_seconds": b.seconds, "astar_length": a.length,
                    "astar_expanded": a.expanded, "astar_seconds": a.seconds, "astar_cpu": a_cpu})
        print(f"| {name.rsplit('/', 1)[-1].removesuffix('.txt')} | {expected} | {b.length} | "
              f"{'>=' if b.status == 'limit' else ''}{b.expanded} | {b.seconds:.3f} | {a.length} | {a.expanded} | "
              f"{a.seconds:.3f} | {a.expanded / max(1, b.expanded):.3f} |", flush=True)
    return out


def suite(jobs: int, timeout: float, search: str, efp: Path | None = None) -> tuple[list[dict], dict]:
    """The whole shared mA* suite in ONE batch command (``delkit plan FILE... --jobs N --json``): per task its
    JSON line, and the whole command's CPU (user + system of the command and its workers, RUSAGE_CHILDREN)
    and wall seconds — the timed region is the whole batch process (start-up, spawning the workers, every
    task, the summary)."""
    bench = shared_benchmarks()
    if bench is None:
        raise SystemExit("../shared/benchmarks is not available")
    rows = list(csv.DictReader((bench / "mastar" / "expected.csv").open()))
    files = [str(bench / "mastar" / r["file"]) for r in rows]
    env = dict(os.environ, PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    cmd = [sys.executable, "-c", _MAIN, "plan", *files, "--jobs", str(jobs), "--json", "--timeout", str(timeout),
           "--search", search]
    subprocess.run(cmd, env=env, capture_output=True, check=False)  # warm-up: .pyc files, page cache
    proc = timed_run(cmd, env=env)
    wall, cpu = proc.wall, proc.cpu
    lines = [json.loads(ln) for ln in proc.stdout.splitlines() if ln.startswith("{")]
    by_file = {ln["file"]: ln for ln in lines if not ln.get("summary")}
    out = []
    for r, f in zip(rows, files, strict=True):
        got = by_file.get(f, {})
        out.append({"file": r["file"], "expected": int(r["expected_length"]), "length": got.get("length"),
                    "status": got.get("status"), "expanded": got.get("expanded"), "task_cpu": got.get("cpu"),
                    "efp_poss": _efp(r["efp_possibilities_s"])})
    total = {"cpu": cpu, "wall": wall, "exit": proc.returncode, "jobs": jobs,
             "efp_poss_total": sum(x["efp_poss"] or 0.0 for x in out),
             "efp_missing": sum(x["efp_poss"] is None for x in out)}
    if efp is not None:
        total.update(_efp_suite(efp, [Path(f) for f in files], out, timeout, jobs))
    return out, total


def _efp_suite(efp: Path, files: list[Path], out: list[dict], timeout: float, jobs: int) -> dict:
    """EFP over the suite in the same run: one process per instance, one at a time (summed CPU and wall), then
    the same processes ``jobs`` at a time (wall of the whole set, as delkit's --jobs uses that many cores)."""
    from concurrent.futures import ThreadPoolExecutor

    runs = [_efp_once(efp, f, timeout) for f in files]
    for row, (_, c, res) in zip(out, runs, strict=True):
        row.update(efp_same_cpu=c, efp_same_length=res["length"], efp_same_status=res["status"])
    t0 = time.perf_counter()
    with ThreadPoolExecutor(max_workers=jobs) as pool:
        list(pool.map(lambda f: _efp_once(efp, f, timeout), files))
    return {"efp_same_cpu": sum(c for _, c, _ in runs), "efp_same_wall_serial": sum(w for w, _, _ in runs),
            "efp_same_wall_parallel": time.perf_counter() - t0,
            "efp_same_solved": sum(r["status"] == "solved" for _, _, r in runs)}


def heuristics_table(timeout: float) -> list[dict]:
    """A* with h_epi and with h_chain (A*'s default) in-process on every instance: lengths, expanded nodes,
    CPU seconds of the search (time.process_time around it; the task is read before)."""
    from planners.epistemic import Limits, best_first, make_space
    from planners.heuristics import h_chain, h_epi
    from planners.lang import load_task

    bench = shared_benchmarks()
    if bench is None:
        raise SystemExit("../shared/benchmarks is not available")
    items = [(bench / "mastar" / r["file"], r["file"], int(r["expected_length"]))
             for r in csv.DictReader((bench / "mastar" / "expected.csv").open())]
    items += [(ROOT / f, f, n) for f, n in OWN]
    out = []
    for path, name, expected in items:
        task = load_task(path)
        row: dict = {"file": name, "expected": expected}
        for label, make in (("epi", h_epi), ("chain", h_chain)):
            space = make_space(task)
            c0 = time.process_time()
            res = best_first(space, Limits(timeout=timeout), kind="astar", h=make(space))
            row[label] = {"length": res.length, "expanded": res.expanded, "cpu": time.process_time() - c0,
                          "status": res.status}
        out.append(row)
        e, c = row["epi"], row["chain"]
        print(f"| {name.rsplit('/', 1)[-1].removesuffix('.txt')} | {expected} | {e['length']} | {e['expanded']} | "
              f"{e['cpu']:.3f} | {c['length']} | {c['expanded']} | {c['cpu']:.3f} | "
              f"{c['expanded'] / max(1, e['expanded']):.3f} |", flush=True)
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--runs", type=int, default=5)
    ap.add_argument("--search", default="bfs", choices=["bfs", "gbfs", "astar"])
    ap.add_argument("--engine", default="fast", choices=["fast", "del"])
    ap.add_argument("--timeout", type=float, default=60.0)
    ap.add_argument("--json", type=Path, default=None)
    ap.add_argument("--expansions", action="store_true", help="BFS vs A* expanded nodes (in-process)")
    ap.add_argument("--bfs-timeout", type=float, default=1200.0)
    ap.add_argument("--no-own", action="store_true", help="only the shared instances (not specs/grapevine5)")
    ap.add_argument("--suite", action="store_true", help="the whole suite as one batch command (--jobs)")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--heuristics", action="store_true", help="A* with h_epi vs h_chain (in-process)")
    ap.add_argument("--efp-bin", type=Path, default=None, help="EFP's efp.out: measure EFP in the same run "
                    "(default $EFP_BIN; bench/peers/efp/build.sh builds it)")
    args = ap.parse_args()
    efp = _efp_binary(args.efp_bin)
    if args.heuristics:
        print("| instance | optimum | h_epi len | h_epi expanded | h_epi CPU s | h_chain len | h_chain expanded "
              "| h_chain CPU s | chain/epi expanded |")
        print("|---|--:|--:|--:|--:|--:|--:|--:|--:|")
        rows = heuristics_table(args.timeout)
        fewer = sum(r["chain"]["expanded"] < r["epi"]["expanded"] for r in rows)
        more = sum(r["chain"]["expanded"] > r["epi"]["expanded"] for r in rows)
        print(f"\nlengths equal to the optimum: h_epi {sum(r['epi']['length'] == r['expected'] for r in rows)}/"
              f"{len(rows)}, h_chain {sum(r['chain']['length'] == r['expected'] for r in rows)}/{len(rows)}; "
              f"h_chain expands fewer nodes on {fewer}, more on {more}, as many on {len(rows) - fewer - more}; "
              f"total expanded h_epi {sum(r['epi']['expanded'] for r in rows)}, h_chain "
              f"{sum(r['chain']['expanded'] for r in rows)}; load average {os.getloadavg()[0]:.2f} on "
              f"{os.cpu_count()} cores")
        if args.json:
            args.json.write_text(json.dumps(rows, indent=1))
        return
    if args.suite:
        rows, total = suite(args.jobs, args.timeout, args.search, efp)
        print(f"delkit plan <{len(rows)} files> --jobs {args.jobs} --json --search {args.search}: one command, "
              f"python {sys.version.split()[0]}, {os.cpu_count()} cores")
        same = " EFP same-run len | EFP same-run CPU s |" if efp else ""
        print(f"| instance | EFP len | our len | status | expanded | task CPU s | EFP-poss s (CSV) |{same}")
        print("|---|--:|--:|---|--:|--:|--:|" + ("--:|--:|" if efp else ""))
        for r in rows:
            ok = "" if r["length"] == r["expected"] else " (!)"
            cpu = f"{r['task_cpu']:.3f}" if r["task_cpu"] is not None else "-"
            extra = (f" {r['efp_same_length'] if r['efp_same_length'] is not None else r['efp_same_status']} | "
                     f"{r['efp_same_cpu']:.3f} |") if efp else ""
            print(f"| {r['file'].rsplit('/', 1)[-1].removesuffix('.txt')} | {r['expected']} | {r['length']}{ok} | "
                  f"{r['status']} | {r['expanded']} | {cpu} | "
                  f"{r['efp_poss'] if r['efp_poss'] is not None else '-'} |{extra}")
        print(f"\nlengths equal to EFP's: {sum(r['length'] == r['expected'] for r in rows)}/{len(rows)}; "
              f"whole command: CPU {total['cpu']:.3f} s, wall {total['wall']:.3f} s (exit {total['exit']}); "
              f"EFP-poss total (sum of its whole-process seconds per instance"
              f"{', ' + str(total['efp_missing']) + ' missing' if total['efp_missing'] else ''}): "
              f"{total['efp_poss_total']:.3f} s; load average {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores")
        if efp:
            print(f"EFP in the same run ({efp}, -st POSS, one process per instance): solved "
                  f"{total['efp_same_solved']}/{len(rows)}, CPU {total['efp_same_cpu']:.3f} s, wall "
                  f"{total['efp_same_wall_serial']:.3f} s one at a time, {total['efp_same_wall_parallel']:.3f} s "
                  f"{args.jobs} at a time; delkit's whole command / EFP's CPU: "
                  f"{total['cpu'] / total['efp_same_cpu']:.2f}")
        if args.json:
            args.json.write_text(json.dumps({"rows": rows, "total": total}, indent=1))
        return
    if args.expansions:
        print("| instance | optimum | BFS len | BFS expanded | BFS search s | A* len | A* expanded | A* search s "
              "| A*/BFS expanded |")
        print("|---|--:|--:|--:|--:|--:|--:|--:|--:|")
        rows = expansions(args.bfs_timeout)
        big = [r for r in rows if r["bfs_expanded"] >= 1000]
        print(f"\nA* length = BFS length on {sum(r['astar_length'] == r['bfs_length'] for r in rows)}/{len(rows)}; "
              f"instances where BFS expands >= 1000 nodes: {len(big)}, A* <= 1/5 of BFS on "
              f"{sum(5 * r['astar_expanded'] <= r['bfs_expanded'] for r in big)}/{len(big)}; "
              f"load average {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores")
        if args.json:
            args.json.write_text(json.dumps(rows, indent=1))
        return
    rows = run(args.runs, args.search, args.engine, args.timeout, own=not args.no_own, efp=efp)
    print(f"delkit plan --search {args.search} --engine {args.engine}, whole process, median of {args.runs} runs; "
          f"python {sys.version.split()[0]}, {os.cpu_count()} cores")
    same = efp is not None
    print("| instance | EFP len | our len | expanded | whole wall s | whole CPU s | search s | EFP-poss s (CSV) "
          "| wall − EFP-poss s | CPU − EFP-poss s | EFP-Kripke s (CSV) |"
          + (" EFP same-run len | EFP same-run CPU s | CPU / EFP same-run |" if same else ""))
    print("|---|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|" + ("--:|--:|--:|" if same else ""))
    for r in rows:
        ok = "" if r["length"] == r["expected"] else " (!)"
        p = r["efp_poss"]
        cols = [r["file"].rsplit("/", 1)[-1].removesuffix(".txt"), str(r["expected"]), f"{r['length']}{ok}",
                str(r["expanded"]), f"{r['wall']:.3f}", f"{r['cpu']:.3f}",
                f"{r['search']:.3f}" if r["search"] is not None else "-",
                f"{p:.3f}" if p is not None else "-", f"{r['wall'] - p:+.3f}" if p is not None else "-",
                f"{r['cpu'] - p:+.3f}" if p is not None else "-", r["efp_kripke_text"]]
        if same:
            e = r["efp_same_cpu"]
            cols += [str(r["efp_same_length"]) if r["efp_same_length"] is not None else str(r["efp_same_status"]),
                     f"{e:.3f}", f"{r['cpu'] / e:.2f}" if e and r["efp_same_status"] == "solved" else "-"]
        print("| " + " | ".join(cols) + " |")
    efp_rows = [r for r in rows if r["efp_poss"] is not None]
    slow = [r for r in efp_rows if r["efp_poss"] >= 0.3]
    print()
    print(f"instances: {len(rows)}; lengths equal to the expected optimum: "
          f"{sum(r['length'] == r['expected'] for r in rows)}/{len(rows)}")
    for key in ("wall", "cpu"):
        faster = sum(r[key] < r["efp_poss"] for r in slow)
        worst = max(efp_rows, key=lambda r, k=key: r[k] - r["efp_poss"])
        print(f"{key}: faster than EFP-poss (CSV) on {faster}/{len(slow)} instances where EFP-poss needs >= 0.3 s; "
              f"largest excess over EFP-poss {worst[key] - worst['efp_poss']:+.3f} s "
              f"({worst['file'].rsplit('/', 1)[-1]}); faster on {sum(r[key] < r['efp_poss'] for r in efp_rows)}/"
              f"{len(efp_rows)} overall")
    if same:
        solved = [r for r in rows if r["efp_same_status"] == "solved"]
        slow = [r for r in solved if r["efp_same_cpu"] >= 0.3]
        print(f"EFP in the same run: solved {len(solved)}/{len(rows)}, lengths equal to ours on "
              f"{sum(r['efp_same_length'] == r['length'] for r in solved)}/{len(solved)}; delkit's whole-process CPU "
              f"below EFP's on {sum(r['cpu'] < r['efp_same_cpu'] for r in slow)}/{len(slow)} instances where EFP "
              f"needs >= 0.3 s (median ratio "
              f"{statistics.median(r['cpu'] / r['efp_same_cpu'] for r in slow) if slow else float('nan'):.2f}), "
              f"on {sum(r['cpu'] < r['efp_same_cpu'] for r in solved)}/{len(solved)} overall; summed CPU delkit "
              f"{sum(r['cpu'] for r in solved):.3f} s, EFP {sum(r['efp_same_cpu'] for r in solved):.3f} s")
    print(f"load average at the end: {os.getloadavg()[0]:.2f} on {os.cpu_count()} cores")
    if args.json:
        args.json.write_text(json.dumps(rows, indent=1))


if __name__ == "__main__":
    main()
