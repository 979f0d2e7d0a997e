"""Parallel BFS of one task against serial BFS: ``delkit plan TASK --json`` vs ``delkit plan TASK --jobs N --json``.

Each run is a fresh process (``python -c "from delkit.cli import run; run()"``: the ``delkit`` console script);
the timed region is the whole process — interpreter start, imports, reading the task, the search (and in
the parallel run its worker processes' start-up and the whole search), exit. Wall seconds by the clock
around the process; CPU seconds are user + system of the process *and its children* (``RUSAGE_CHILDREN``: the
parallel run's workers are joined before it exits). Serial and parallel runs alternate (serial first on
odd repeats, parallel first on even ones) so that a change of the machine's load hits both alike; the load
average (1 min) is read before and after every run and printed. Speed-up = median serial wall / median
parallel wall; the plans of both are compared (lengths and actions). On a loaded machine wall times say little
(the parallel run's processes wait for cores); the *critical-path CPU* of a parallel run (:func:`critical`)
estimates its wall time on idle cores from CPU times, and serial CPU / critical-path CPU the speed-up there.

The instances (serial BFS ≥ 5 s CPU on this machine): the project's 5-agent Grapevine pl6
(``specs/grapevine5``), plank's EPDDL (2026) Selective-Communication problem_1 (shared benchmarks), and a
generated Collaboration-and-Communication task (``bench/cc_tasks.py``: 2 agents, 3 rooms, 4 boxes, 4 goal
conjuncts, seed 2; plan length 6).

    .venv/bin/python bench/parallel.py             # the record: 3 alternating repeats, medians (≈ 5 min idle)
    .venv/bin/python bench/parallel.py [--repeats 3] [--jobs 2] [--quick] [--only grapevine5,sc]
    .venv/bin/python bench/parallel.py --quick     # one repeat of each: about 2 min on an idle machine
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

_MAIN = "from delkit.cli import run; run()"  # the console script (it leaves by os._exit, as `delkit` does)


def instances(tmp: Path) -> dict[str, list[str]]:
    """name -> the files of ``delkit plan`` (those whose inputs are missing are left out)."""
    out: dict[str, list[str]] = {"grapevine5": [str(ROOT / "specs" / "grapevine5" / "Grapevine_5__pl_6.txt")]}
    bench = ROOT.parent / "shared" / "benchmarks"
    if not bench.is_dir():
        from planners.lang import shared_benchmarks

        bench = shared_benchmarks() or bench
    plank = bench / "epddl2026" / "plank"
    sc = plank / "domains" / "Selective-Communication"
    if sc.is_dir():
        out["sc"] = [str(sc / "sc.epddl"), str(sc / "instances" / "problem_1.epddl"),
                     "--library", str(plank / "libraries" / "intermediate.epddl")]
    from bench.cc_tasks import draw

    cc = tmp / "CC_2_3_4_g4_s2.txt"  # 2 agents, 3 rooms, 4 boxes, 4 goal conjuncts, seed 2: BFS finds length 6
    cc.write_text(draw(2, 3, 4, 4, 2))
    out["cc_2_3_4"] = [str(cc)]
    return out


def run(files: list[str], jobs: int | None, timeout: float) -> dict:
    """One fresh ``delkit plan`` process: its JSON line, wall and CPU (children included), load before/after."""
    cmd = [sys.executable, "-c", _MAIN, "plan", *files, "--json", "--timeout", f"{timeout:g}"]
    if jobs:
        cmd += ["--jobs", str(jobs)]
    env = {**os.environ, "PYTHONPATH": str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", "")}
    load0 = os.getloadavg()[0]
    t0 = time.perf_counter()
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, env=env, text=True)
    out, err = proc.communicate()
    wall = time.perf_counter() - t0
    # communicate() reaped the child; its rusage (and its reaped children's) is in RUSAGE_CHILDREN's delta
    return {"wall": wall, "out": out, "err": err, "code": proc.returncode, "load": (load0, os.getloadavg()[0])}


def measured(files: list[str], jobs: int | None, timeout: float) -> dict:
    import resource

    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    r = run(files, jobs, timeout)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    r["cpu"] = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    try:
        r["json"] = json.loads(r["out"].strip().splitlines()[-1])
    except (ValueError, IndexError):
        r["json"] = {"status": "error", "reason": r["err"].strip()[-200:]}
    return r


def critical(r: dict) -> float:
    """A parallel run's CPU on its critical path: its whole CPU (all processes) less what ran alongside —
    the search's CPU beside the slowest part of each phase (``parallel.parts_cpu``, ``critical_cpu`` of its
    JSON) and each worker's start-up beside the caller's (``start_cpu``: the shorter of the two) — what its
    wall time would be on idle cores."""
    st = r["json"].get("parallel") or {}
    if not st:
        return float("nan")
    start = st.get("start_cpu") or [0.0]
    return r["cpu"] - (sum(st["parts_cpu"]) - st["critical_cpu"]) - sum(min(start[0], h) for h in start[1:])


def _verdict(serial_wall: float, speedup: float) -> str:
    """The target: a wall speed-up ≥ 1.6× where serial BFS takes ≥ 5 s — valid on an otherwise idle
    machine only (the runs' own processes raise the load average to ≈ 1–2 there)."""
    if serial_wall < 5.0:
        return "n/a (serial < 5 s)"
    return "met" if speedup >= 1.6 else "missed"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--timeout", type=float, default=600.0)
    ap.add_argument("--quick", action="store_true", help="one repeat of each instance (≈ 2-3 min idle)")
    ap.add_argument("--only", default="", help="comma-separated instance names (grapevine5, sc, cc_2_3_4)")
    ap.add_argument("--json", type=Path, default=None, help="write every run's figures here")
    a = ap.parse_args()
    repeats = 1 if a.quick else a.repeats
    with tempfile.TemporaryDirectory() as tmp:
        todo = instances(Path(tmp))
        if a.only:
            todo = {k: v for k, v in todo.items() if k in a.only.split(",")}
        print(f"# {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, {os.cpu_count()} cores, --jobs {a.jobs}, "
              f"{repeats} repeat(s); load average (1 min) at start {os.getloadavg()[0]:.2f}", flush=True)
        runs: dict[str, dict[str, list]] = {k: {"serial": [], "parallel": []} for k in todo}
        for rep in range(repeats):
            for name, files in todo.items():
                order = [("serial", None), ("parallel", a.jobs)]
                if rep % 2:
                    order.reverse()
                for kind, jobs in order:
                    r = measured(files, jobs, a.timeout)
                    runs[name][kind].append(r)
                    js = r["json"]
                    print(f"{name:10} {kind:8} wall {r['wall']:7.2f} s  CPU {r['cpu']:7.2f} s  load "
                          f"{r['load'][0]:5.2f} → {r['load'][1]:5.2f}  {js.get('status')} length {js.get('length')} "
                          f"expanded {js.get('expanded')}", flush=True)
        print()
        print(f"| instance | serial wall s | serial CPU s | --jobs {a.jobs} wall s | --jobs {a.jobs} CPU s | "
              "speed-up (wall) | CPU ratio | parts' CPU s | phases | critical-path CPU s | "
              "speed-up on idle cores (est.) | same plan | load (min–max) | target |")
        print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
        for name, kinds in runs.items():
            s, p = kinds["serial"], kinds["parallel"]
            sw, sc_ = statistics.median(r["wall"] for r in s), statistics.median(r["cpu"] for r in s)
            pw, pc = statistics.median(r["wall"] for r in p), statistics.median(r["cpu"] for r in p)
            plans = {tuple(r["json"].get("plan") or ()) for r in s + p}
            lengths = {r["json"].get("length") for r in s + p}
            same = "yes" if len(plans) == 1 and None not in lengths else f"NO ({sorted(map(str, lengths))})"
            loads = [x for r in s + p for x in r["load"]]
            crit = statistics.median(critical(r) for r in p)
            mid = sorted(p, key=lambda r: r["wall"])[len(p) // 2]["json"].get("parallel") or {}  # the median run's
            parts = " + ".join(f"{c:.2f}" for c in mid.get("parts_cpu", ()))
            print(f"| {name} | {sw:.2f} | {sc_:.2f} | {pw:.2f} | {pc:.2f} | {sw / pw:.2f}× | {pc / sc_:.2f} | "
                  f"{parts} | {mid.get('phases', '')} | {crit:.2f} | {sc_ / crit:.2f}× | {same} | "
                  f"{min(loads):.1f}–{max(loads):.1f} | {_verdict(sw, sw / pw)} |")
        print(f"\n(medians of {repeats} run(s) each; the target: wall speed-up ≥ 1.6× where serial BFS takes ≥ 5 s, "
              "measured on an otherwise idle machine — any other job on it makes the wall columns meaningless; the "
              "runs' own processes raise the load average to ≈ 1–2)")
        if a.json:
            a.json.write_text(json.dumps({k: {kind: [{x: r[x] for x in ("wall", "cpu", "load", "json")} for r in v]
                                              for kind, v in d.items()} for k, d in runs.items()}, indent=1))


if __name__ == "__main__":
    main()
