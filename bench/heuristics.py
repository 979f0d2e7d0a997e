"""A*'s admissible heuristics side by side: h_epi, h_chain (A*'s default) and h_pdb, on every shared mA*
instance (``mastar/expected.csv``) and the project's CC tasks (``specs/cc_*``).

In-process; per instance and heuristic a fresh state space; timed region: building the heuristic (h_pdb's
pattern tables) and the A* search, ``time.process_time``; the task is read before. Prints a Markdown table
(length, expanded nodes, CPU seconds per heuristic) and totals, with the load average.

    .venv/bin/python bench/heuristics.py [--timeout 300] [--only SUBSTRING] [--heuristics epi,chain,pdb]
"""

from __future__ import annotations

import argparse
import csv
import os
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))


def instances() -> list[tuple[Path, str, int | None]]:
    from planners.lang import shared_benchmarks

    out: list[tuple[Path, str, int | None]] = []
    bench = shared_benchmarks()
    if bench is not None:
        out += [(bench / "mastar" / r["file"], r["file"].rsplit("/", 1)[-1].removesuffix(".txt"),
                 int(r["expected_length"])) for r in csv.DictReader((bench / "mastar" / "expected.csv").open())]
    for f in sorted(ROOT.glob("specs/cc_*/*.txt")):
        n = f.stem.rsplit("__pl_", 1)
        out.append((f, f.stem, int(n[1]) if len(n) == 2 and n[1].isdigit() else None))
    return out


def run(path: Path, names: list[str], timeout: float) -> dict:
    from planners.epistemic import Limits, best_first, make_space
    from planners.heuristics import make_heuristic
    from planners.lang import load_task

    task = load_task(path)
    row = {}
    for name in names:
        space = make_space(task)
        c0 = time.process_time()
        res = best_first(space, Limits(timeout=timeout), kind="astar", h=make_heuristic(name, space))
        row[name] = {"length": res.length, "expanded": res.expanded, "cpu": time.process_time() - c0,
                     "status": res.status}
    return row


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--timeout", type=float, default=300.0, help="wall seconds per search")
    ap.add_argument("--only", default="", help="instances whose name contains this")
    ap.add_argument("--heuristics", default="epi,chain,pdb")
    a = ap.parse_args()
    names = a.heuristics.split(",")
    head = " | ".join(f"{n} len | {n} expanded | {n} CPU s" for n in names)
    print(f"| instance | optimum | {head} |")
    print("|---|--:|" + "--:|" * (3 * len(names)))
    rows = []
    for path, label, opt in instances():
        if a.only not in label:
            continue
        row = run(path, names, a.timeout)
        rows.append((label, opt, row))
        cells = " | ".join(f"{row[n]['length'] if row[n]['status'] == 'solved' else row[n]['status']} | "
                           f"{row[n]['expanded']} | {row[n]['cpu']:.3f}" for n in names)
        print(f"| {label} | {opt if opt is not None else '?'} | {cells} |", flush=True)
    tot = "; ".join(f"{n}: {sum(r[n]['expanded'] for _, _, r in rows)} expanded, "
                    f"{sum(r[n]['cpu'] for _, _, r in rows):.2f} s CPU, "
                    f"{sum(r[n]['length'] == o for _, o, r in rows)}/{len(rows)} optimal" for n in names)
    print(f"\ntotals over {len(rows)} instances — {tot}; load average {os.getloadavg()[0]:.2f} on {os.cpu_count()} "
          "cores")


if __name__ == "__main__":
    main()
