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

``--plank-bin PATH`` (or ``$PLANK_BIN``; bench/peers/plank builds it) also runs plank's ``bfs_planner`` in the
same run: one fresh plank process right before each timed delkit process (same round), its whole-process CPU
(parsing, type checking, grounding, search, output; ``RUSAGE_CHILDREN``) beside delkit's whole process, with the
search-only "Runtime" plank prints itself.

Without it, plank's figures come from the same CSV row: ``plank_bfs_s`` is what plank's ``bfs_planner`` prints as
"Runtime": wall time (``std::chrono``, millisecond resolution) of ``search::planner::solve`` only — the goal
check of the initial state, its bisimulation contraction and the BFS. It excludes process start-up, parsing,
type checking and grounding (``grounder_helper::build_ground_task``, run before ``solve``) and writing the plan.
``plank_ground_s`` is plank's grounding time as recorded in the CSV (plank prints none; measured outside plank).
Target: delkit's parse + ground + search ≤ ``plank_bfs_s`` on every problem plank solves, compared
as whole processes where plank needs ≥ 0.3 s; every grounding ≤ 0.1 s. The last column is delkit's search
CPU alone over ``plank_bfs_s`` (the same region as plank's: ≤ 1 means delkit's search is faster).

    .venv/bin/python bench/epddl.py [--repeat 5] [--timeout 60] [--only NAME] [--json out.json] [--no-process]
"""

from __future__ import annotations

import argparse
import csv
import json
import os
import resource
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


PLANK_MEMORY = 8 << 30  # address-space cap of a plank process (bytes)


def _plank_once(binary: Path, files: list[Path], libs: list[Path], timeout: float) -> tuple[float, float, dict]:
    """One process of plank's ``bfs_planner -d DOMAIN -p PROBLEM [-l LIBRARY...]``: wall and CPU seconds of the whole
    process (parsing, type checking, grounding, search, output), its answer (``status``, ``length``) and the
    "Runtime" it prints itself (search only, the CSV's ``plank_bfs_s``). Run in a scratch directory."""
    import tempfile

    cmd = [str(binary), "-d", str(files[0]), "-p", str(files[1])] + ([ "-l", *map(str, libs)] if libs else [])
    def cap() -> None:  # plank's grounder enumerates every valuation on some problems (2^33): cap its memory
        resource.setrlimit(resource.RLIMIT_AS, (PLANK_MEMORY, PLANK_MEMORY))

    with tempfile.TemporaryDirectory(prefix="plank-") as cwd:
        r = timed_run(cmd, cwd=cwd, timeout=timeout, preexec_fn=cap)
    if r.timed_out:
        return r.wall, r.cpu, {"status": "timeout", "length": None, "runtime": None}
    lines = r.stdout.splitlines()
    runtime = next((_num(ln.split(":", 1)[1].strip().rstrip(".")) for ln in lines if ln.startswith("Runtime:")), None)
    if "Plan found:" in lines:
        steps = [ln for ln in lines[lines.index("Plan found:") + 1:] if ln.split(".", 1)[0].strip().isdigit()]
        return r.wall, r.cpu, {"status": "solved", "length": len(steps), "runtime": runtime}
    oom = "bad_alloc" in r.stderr or "bad_alloc" in r.stdout
    status = ("no-plan" if r.returncode == 0 else f"out of memory ({PLANK_MEMORY >> 30} GiB cap)" if oom
              else f"error (exit {r.returncode})")
    return r.wall, r.cpu, {"status": status, "length": None, "runtime": runtime}


def _median(runs: list[tuple[float, float]]) -> tuple[float, float]:
    return statistics.median(r[0] for r in runs), statistics.median(r[1] for r in runs)


def _timed(fn) -> tuple[float, float]:
    t0, c0 = time.perf_counter(), time.process_time()
    fn()
    return time.perf_counter() - t0, time.process_time() - c0


def run(repeat: int, timeout: float, only: str | None, process: bool = True, plank: Path | None = None) -> list[dict]:
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
        same: list[tuple[float, float, dict]] = []
        if process:
            _whole(args, timeout)  # warm-up: writes the .pyc files
            runs = []
            for i in range(repeat if res.status != "limit" else 1):
                if plank is not None and (i == 0 or r["plank_bfs"] in ("solved", "no-plan")):
                    # plank's process right before delkit's, in the same round (once where plank is known to run
                    # out of time or memory: its limit is the whole run)
                    same.append(_plank_once(plank, files, libs, timeout))
                runs.append(_whole(args, timeout))
            w, status = _median([(x[0], x[1]) for x in runs]), runs[-1][2].get("status")
        elif plank is not None:
            same = [_plank_once(plank, files, libs, timeout) for _ in range(repeat)]
        out.append({"problem": r["problem"].split("domains/")[1], "worlds": task.initial.n_worlds,
                    "actions": len(task.actions), "parse_s": parse[0], "parse_cpu": parse[1],
                    "ground_s": ground[0], "ground_cpu": ground[1],
                    "search_s": s[0], "search_cpu": s[1], "status": res.status, "length": res.length,
                    "expanded": res.expanded, "process_s": w[0], "process_cpu": w[1],
                    "process_status": status, "engine": engine,
                    "plank_ground_s": _num(r["plank_ground_s"]), "plank_bfs": r["plank_bfs"],
                    "plank_bfs_s": _num(r["plank_bfs_s"]), "plank_len": r["plank_bfs_len"],
                    "shortest_known": r["shortest_known"],
                    **({"plank_same_cpu": statistics.median(x[1] for x in same),
                        "plank_same_wall": statistics.median(x[0] for x in same),
                        "plank_same_status": same[-1][2]["status"], "plank_same_len": same[-1][2]["length"],
                        "plank_same_runtime": same[-1][2]["runtime"]} if same else {})})
    return out


def _ratio(ours: float, plank: float | None) -> str:
    """delkit's search CPU seconds over plank's whole bfs_planner seconds (≤ 1: the search alone is faster)."""
    return "—" if not plank else f"{ours / plank:.2f}"


def table(rows: list[dict]) -> str:
    head = ("| problem | worlds | actions | parse s (cpu) | ground s (cpu) | search s (cpu) | ground+search cpu | "
            "process s (cpu) | delkit | plank ground s | plank bfs s | plank | shortest known | target | "
            "search cpu / plank bfs |")
    same = any("plank_same_cpu" in r for r in rows)
    if same:
        head += " plank same run | plank process cpu s (its Runtime) | delkit process cpu / plank's |"
    lines = [head, "|" + "---|" * (18 if same else 15)]
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
                     f"{_ratio(r['search_cpu'], pb) if r['plank_bfs'] in ('solved', 'no-plan') else '—'} |"
                     + (_same_cols(r) if same else ""))
    if same:
        both = [r for r in rows if r.get("plank_same_status") == "solved" and r["status"] == "solved"]
        if both:
            ratios = [r["process_cpu"] / r["plank_same_cpu"] for r in both if r["plank_same_cpu"]]
            lines.append(f"\nplank in the same run: solved {sum(r.get('plank_same_status') == 'solved' for r in rows)}"
                         f"/{len(rows)}; where both solve ({len(both)}), lengths equal on "
                         f"{sum(r['plank_same_len'] == r['length'] for r in both)}; delkit's whole process / plank's: "
                         f"median {statistics.median(ratios):.2f}, summed CPU delkit "
                         f"{sum(r['process_cpu'] for r in both):.3f} s, "
                         f"plank {sum(r['plank_same_cpu'] for r in both):.3f} s")
    return "\n".join(lines)


def _same_cols(r: dict) -> str:
    if "plank_same_cpu" not in r:
        return " — | — | — |"
    st = r["plank_same_status"] + (f" {r['plank_same_len']}" if r["plank_same_len"] is not None else "")
    rt = f" ({r['plank_same_runtime']:g})" if r["plank_same_runtime"] is not None else ""
    ok = r["plank_same_status"] == "solved" and r["status"] == "solved" and r["plank_same_cpu"]
    ratio = f"{r['process_cpu'] / r['plank_same_cpu']:.2f}" if ok and r["process_cpu"] == r["process_cpu"] else "—"
    return f" {st} | {r['plank_same_cpu']:.3f}{rt} | {ratio} |"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--timeout", type=float, default=60.0)
    ap.add_argument("--only", default=None, help="substring of the problem path")
    ap.add_argument("--json", type=Path, default=None)
    ap.add_argument("--no-process", action="store_true", help="skip the whole-process runs")
    ap.add_argument("--table-from", type=Path, default=None, help="print the table of a saved --json run")
    ap.add_argument("--plank-bin", type=Path, default=None, help="plank's bfs_planner: measure plank in the same run "
                    "(default $PLANK_BIN; bench/peers/plank/build.sh builds it)")
    a = ap.parse_args()
    plank = a.plank_bin or (Path(os.environ["PLANK_BIN"]) if os.environ.get("PLANK_BIN") else None)
    if plank is not None and not (plank.is_file() and os.access(plank, os.X_OK)):
        raise SystemExit(f"--plank-bin {plank}: not an executable file (build it: sh bench/peers/plank/build.sh)")
    if a.table_from:
        print(table(json.loads(a.table_from.read_text())))
        return
    rows = run(a.repeat, a.timeout, a.only, process=not a.no_process, plank=plank)
    print(table(rows))
    if a.json:
        a.json.write_text(json.dumps(rows, indent=1))


if __name__ == "__main__":
    main()
