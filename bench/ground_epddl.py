"""EPDDL (2026) reading + grounding alone: CPU time of ``load_epddl2026`` per problem of
../shared/benchmarks/epddl2026/expected.csv (read + parse + type + ground + initial state, in-process, warm imports,
one untimed load first; nothing is cached from one load to the next).

Per problem: the median and the minimum of ``--repeat`` loads (``time.process_time``), and the tracked objects a
load leaves for the cyclic garbage collector. With ``--against DIR`` (another checkout, e.g. ``git archive`` of an
older commit) both checkouts are measured in fresh processes, alternately, ``--rounds`` times each, and the table
gives the median of the per-round medians (and the smallest minimum) of both and their ratio: the machine is
shared, and alternating spreads its load over both sides.

    OPENBLAS_NUM_THREADS=1 .venv/bin/python bench/ground_epddl.py [--repeat 40] [--only NAME]
        [--against /tmp/old-checkout --rounds 3] [--json out.json]
"""

from __future__ import annotations

import argparse
import csv
import gc
import json
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
BENCH = ROOT.parent / "shared" / "benchmarks" / "epddl2026"


def _rows(only: str | None) -> list[dict]:
    return [r for r in csv.DictReader((BENCH / "expected.csv").open()) if not only or only in r["problem"]]


def measure(root: Path, repeat: int, only: str | None) -> dict[str, dict]:
    """In this process, with ``root``'s planners: per problem, CPU seconds of each load and the cyclic garbage
    one load leaves (tracked objects freed only by the collector)."""
    sys.path.insert(0, str(root))
    from planners.lang.epddl2026 import load_epddl2026

    out = {}
    for r in _rows(only):
        files = [BENCH / r["domain"], BENCH / r["problem"]]
        libs = [BENCH / r["libraries"]] if r["libraries"] else []
        load_epddl2026(*files, libs)   # warm: imports, first-use caches of numpy etc.
        n = repeat if not any(k in r["problem"] for k in ("Selective", "Tiger", "ncn")) else max(3, repeat // 4)
        times = []
        for _ in range(n):
            c0 = time.process_time()
            load_epddl2026(*files, libs)
            times.append(time.process_time() - c0)
        gc.collect()
        gc.disable()
        task = load_epddl2026(*files, libs)
        del task
        garbage = gc.collect()
        gc.enable()
        out[r["problem"].split("domains/")[1]] = {"median": statistics.median(times), "min": min(times),
                                                 "garbage": garbage}
    return out


def _child(root: Path, repeat: int, only: str | None) -> dict[str, dict]:
    env = {**os.environ, "OPENBLAS_NUM_THREADS": "1", "PYTHONPATH": str(root)}
    p = subprocess.run([sys.executable, __file__, "--measure", str(root), "--repeat", str(repeat),
                        *(["--only", only] if only else [])], capture_output=True, text=True, env=env, check=True)
    return json.loads(p.stdout)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=40)
    ap.add_argument("--only", default=None, help="substring of the problem path")
    ap.add_argument("--against", type=Path, default=None, help="another checkout to compare with")
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--json", type=Path, default=None)
    ap.add_argument("--measure", type=Path, default=None, help=argparse.SUPPRESS)
    a = ap.parse_args()
    if a.measure:
        print(json.dumps(measure(a.measure, a.repeat, a.only)))
        return
    sides = [ROOT] + ([a.against.resolve()] if a.against else [])
    runs: dict[Path, list[dict]] = {s: [] for s in sides}
    for _ in range(a.rounds if a.against else 1):
        for s in sides:
            runs[s].append(_child(s, a.repeat, a.only))
    keys = list(runs[ROOT][0])
    summary = {}
    for k in keys:
        summary[k] = {str(s): {"median": statistics.median(r[k]["median"] for r in runs[s]),
                               "min": min(r[k]["min"] for r in runs[s]), "garbage": runs[s][0][k]["garbage"]}
                      for s in sides}
    if a.against:
        print(f"| problem | {a.against.name}: median ms (min) | garbage | this checkout: median ms (min) | garbage | "
              f"speed-up (median) |")
        print("|---|---|---|---|---|---|")
        for k, v in summary.items():
            old, new = v[str(sides[1])], v[str(ROOT)]
            print(f"| {k} | {old['median'] * 1e3:.2f} ({old['min'] * 1e3:.2f}) | {old['garbage']} | "
                  f"{new['median'] * 1e3:.2f} ({new['min'] * 1e3:.2f}) | {new['garbage']} | "
                  f"{old['median'] / new['median']:.2f}x |")
    else:
        print("| problem | load CPU median ms (min) | garbage objects per load |")
        print("|---|---|---|")
        for k, v in summary.items():
            x = v[str(ROOT)]
            print(f"| {k} | {x['median'] * 1e3:.2f} ({x['min'] * 1e3:.2f}) | {x['garbage']} |")
    if a.json:
        a.json.write_text(json.dumps(summary, indent=1))


if __name__ == "__main__":
    main()
