"""EPDDL (2026) benchmark: every problem of ../shared/benchmarks/epddl2026/expected.csv, delkit beside plank.

Timed regions (CPU seconds are the figures to compare: the machine is shared; wall seconds are printed too):

* *parse*: reading the run's files (domain, problem, action-type libraries) into s-expressions
  (``planners.lang.sexpr.read``), in-process; median of ``--repeat`` runs;
* *ground*: the whole reader — read + parse + type + ground every action + build the initial state
  (``load_epddl2026``), in-process with warm imports (one untimed load first); median of ``--repeat``. Nothing is
  cached from one load to the next;
* *search*: set-up of the state space (``planners.lang.epddl_run.space_for``, as ``delkit plan --engine auto``:
  goal and actions compiled) + BFS, limit ``--timeout``; each run on a new state space (nothing cached from an
  earlier run but delkit's process-wide tables of bit positions and frame numbers); median of ``--repeat``
  runs when the first takes < 1 s CPU, else that one run;
* *process*: a fresh ``python -c "...delkit.cli.main()" plan DOMAIN PROBLEM [--library L] --json`` — interpreter
  start-up, imports, reading, grounding, search, output, exit; CPU = the child's user + system time
  (``RUSAGE_CHILDREN``); median of ``--repeat`` after one untimed warm-up run. ``PYTHONDONTWRITEBYTECODE`` is
  removed from the child's environment, so (as for an installed package) the warm-up leaves ``.pyc`` files and
  the timed runs do not recompile delkit's sources.

plank's figures come from the same CSV row: ``plank_bfs_s`` is what plank's ``bfs_planner`` prints as
"Runtime": wall time (``std::chrono``, millisecond resolution) of ``search::planner::solve`` only — the goal
check of the initial state, its bisimulation contraction and the BFS. It excludes process start-up, parsing,
type checking and grounding (``grounder_helper::build_ground_task``, run before ``solve``) and writing the plan.
``plank_ground_s`` is plank's grounding time as recorded in the CSV (plank prints none; measured outside plank).
Target (issue 14): delkit's parse + ground + search ≤ ``plank_bfs_s`` on every problem plank solves, compared
as whole processes where plank needs ≥ 0.3 s; every grounding ≤ 0.1 s. The last column is delkit's search
CPU alone over ``plank_bfs_s`` (the same region as plank's: ≤ 1 means delkit's search is faster).

    .venv/bin/python bench/epddl.py [--repeat 5] [--timeout 60] [--only NAME] [--json out.json] [--no-process]
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
# as the CLI (delkit/cli/__init__.py): numpy's BLAS on one thread — its idle pool's CPU would otherwise be counted
# in this process's CPU seconds (process_time counts every thread)
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

from planners.epistemic import Limits, bfs  # noqa: E402
from planners.lang import shared_benchmarks  # noqa: E402
from planners.lang.epddl2026 import load_epddl2026  # noqa: E402
from planners.lang.epddl_run import space_for  # noqa: E402
from planners.lang.sexpr import read  # noqa: E402


def _num(x: str) -> float | None:
    try:
        return float(x)
    except ValueError:
        return None


def _whole(args: list[str], timeout: float) -> tuple[float, float, dict]:
    """Wall and CPU (the child's user + system) seconds of one ``delkit plan`` process and its JSON answer."""
    env = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
    env["PYTHONPATH"] = str(ROOT)
    p = timed_run([sys.executable, "-c", "import sys; from delkit.cli import main; sys.exit(main())",
                   "plan", *args, "--json", "--timeout", str(timeout)], env=env, timeout=timeout + 60)
    if p.timed_out:
        raise subprocess.TimeoutExpired(p.stdout, timeout + 60)
    try:
        data = json.loads(p.stdout)
    except json.JSONDecodeError:
        data = {"status": f"error rc={p.returncode}", "reason": p.stderr.strip()[-200:]}
    return p.wall, p.cpu, data


def _median(runs: list[tuple[float, float]]) -> tuple[float, float]:
    return statistics.median(r[0] for r in runs), statistics.median(r[1] for r in runs)


def _timed(fn) -> tuple[float, float]:
    t0, c0 = time.perf_counter(), time.process_time()
    fn()
    return time.perf_counter() - t0, time.process_time() - c0


def run(repeat: int, timeout: float, only: str | None, process: bool = True) -> list[dict]:
    bench = shared_benchmarks()
    if bench is None:
        raise SystemExit("../shared/benchmarks is not available")
    base = bench / "epddl2026"
    rows = [r for r in csv.DictReader((base / "expected.csv").open()) if not only or only in r["problem"]]
    out = []
    load_epddl2026(base / rows[0]["domain"], base / rows[0]["problem"],
                   [base / rows[0]["libraries"]] if rows[0]["libraries"] else [])  # warm imports
    for r in rows:
        files = [base / r["domain"], base / r["problem"]]
        libs = [base / r["libraries"]] if r["libraries"] else []
        texts = [(str(f), f) for f in [*files, *libs]]
        parse = _median([_timed(lambda t=texts: [read(f.read_text(), s) for s, f in t]) for _ in range(repeat)])
        task = load_epddl2026(*files, libs)
        ground = _median([_timed(lambda f=files, li=libs: load_epddl2026(*f, li)) for _ in range(repeat)])
        engine = type(space_for(task)).__name__   # as `delkit plan` (--engine auto)
        found: list = []

        def search(t=task, found=found) -> None:  # the state space is set up inside the timed region
            found.append(bfs(space_for(t), Limits(timeout=timeout)))

        s = _timed(search)
        if s[1] < 1.0:  # short searches: median of `repeat` cold runs (each on a new state space)
            s = _median([s] + [_timed(search) for _ in range(repeat - 1)])
        res = found[0]
        args = [str(f) for f in files] + [x for lib in libs for x in ("--library", str(lib))]
        w, status = (float("nan"), float("nan")), None
        if process:
            _whole(args, timeout)  # warm-up: writes the .pyc files
            runs = [_whole(args, timeout) for _ in range(repeat if res.status != "limit" else 1)]
            w, status = _median([(x[0], x[1]) for x in runs]), runs[-1][2].get("status")
        out.append({"problem": r["problem"].split("domains/")[1], "worlds": task.initial.n_worlds,
                    "actions": len(task.actions), "parse_s": parse[0], "parse_cpu": parse[1],
                    "ground_s": ground[0], "ground_cpu": ground[1],
                    "search_s": s[0], "search_cpu": s[1], "status": res.status, "length": res.length,
                    "expanded": res.expanded, "process_s": w[0], "process_cpu": w[1],
                    "process_status": status, "engine": engine,
                    "plank_ground_s": _num(r["plank_ground_s"]), "plank_bfs": r["plank_bfs"],
                    "plank_bfs_s": _num(r["plank_bfs_s"]), "plank_len": r["plank_bfs_len"],
                    "shortest_known": r["shortest_known"]})
    return out


def _ratio(ours: float, plank: float | None) -> str:
    """delkit's search CPU seconds over plank's whole bfs_planner seconds (≤ 1: the search alone is faster)."""
    return "—" if not plank else f"{ours / plank:.2f}"


def table(rows: list[dict]) -> str:
    head = ("| problem | worlds | actions | parse s (cpu) | ground s (cpu) | search s (cpu) | ground+search cpu | "
            "process s (cpu) | delkit | plank ground s | plank bfs s | plank | shortest known | target | "
            "search cpu / plank bfs |")
    lines = [head, "|" + "---|" * 15]
    for r in rows:
        gs = r["ground_cpu"] + r["search_cpu"]
        ours = f"{r['status']}" + (f" {r['length']}" if r["length"] is not None else "")
        pb = r["plank_bfs_s"]
        plank = r["plank_bfs"] + (f" {r['plank_len']}" if r["plank_len"] else "")
        if r["plank_bfs"] not in ("solved", "no-plan") or pb is None:
            target = "— (plank does not solve)"
        elif r["status"] == "limit":
            target = "missed (no answer within the limit)"
        else:   # CPU seconds: the machine is shared, wall time is inflated by other load
            ours_t = r["process_cpu"] if pb >= 0.3 else gs
            if ours_t != ours_t:  # --no-process: the whole process was not measured
                target = "not measured (--no-process)"
            else:
                target = ("met" if ours_t <= pb else "missed") + (" (process)" if pb >= 0.3 else "")
        if r["ground_cpu"] > 0.1:
            target += "; ground > 0.1 s"
        lines.append(f"| {r['problem']} | {r['worlds']} | {r['actions']} | {r['parse_s']:.4f} ({r['parse_cpu']:.4f}) | "
                     f"{r['ground_s']:.4f} ({r['ground_cpu']:.4f}) | {r['search_s']:.3f} ({r['search_cpu']:.3f}) | "
                     f"{gs:.3f} | {r['process_s']:.3f} ({r['process_cpu']:.3f}) | {ours} | "
                     f"{r['plank_ground_s'] if r['plank_ground_s'] is not None else '300+'} | "
                     f"{pb if pb is not None else '—'} | {plank} | {r['shortest_known'] or '?'} | {target} | "
                     f"{_ratio(r['search_cpu'], pb) if r['plank_bfs'] in ('solved', 'no-plan') else '—'} |")
    return "\n".join(lines)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--timeout", type=float, default=60.0)
    ap.add_argument("--only", default=None, help="substring of the problem path")
    ap.add_argument("--json", type=Path, default=None)
    ap.add_argument("--no-process", action="store_true", help="skip the whole-process runs")
    ap.add_argument("--table-from", type=Path, default=None, help="print the table of a saved --json run")
    a = ap.parse_args()
    if a.table_from:
        print(table(json.loads(a.table_from.read_text())))
        return
    rows = run(a.repeat, a.timeout, a.only, process=not a.no_process)
    print(table(rows))
    if a.json:
        a.json.write_text(json.dumps(rows, indent=1))


if __name__ == "__main__":
    main()
