"""Checking a plan against finding it: for every problem of the shared mA* and EPDDL suites,
``delkit plan --json`` then ``delkit check`` of the plan it found, each as its own process.

    python bench/check_cost.py [--timeout 120] [--only SUBSTRING] [--markdown FILE]

Timed: the whole process of each command (start-up, reading, grounding, search or replay, output), as CPU
time (user + system of the child, from ``resource.getrusage(RUSAGE_CHILDREN)``), with the wall time beside
it. A plan is within the target when check CPU <= plan CPU + 0.1 s. Problems the planner does not solve
within ``--timeout`` are listed with no check.
"""

from __future__ import annotations

import argparse
import csv
import json
import os
import platform
import sys
import tempfile
import time
from pathlib import Path

from _timing import timed_run

ROOT = Path(__file__).resolve().parents[1]
BENCH = ROOT.parent / "shared" / "benchmarks"
if not BENCH.exists():
    BENCH = Path("/work/shared/benchmarks")


def _run(argv: list[str]) -> tuple[int, str, str, float, float]:
    """(exit status, stdout, stderr, CPU seconds, wall seconds) of one delkit process."""
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    r = timed_run([str(Path(sys.executable).parent / "delkit"), *argv], env=env)
    return r.returncode, r.stdout, r.stderr, r.cpu, r.wall


def problems(only: str) -> list[tuple[str, list[str], list[str]]]:
    """(label, spec files, --library args) of every problem in the two suites' expected.csv."""
    out = []
    with open(BENCH / "mastar" / "expected.csv") as fh:
        for row in csv.DictReader(fh):
            out.append((f"mA* {row['file']}", [str(BENCH / "mastar" / row["file"])], []))
    with open(BENCH / "epddl2026" / "expected.csv") as fh:
        for row in csv.DictReader(fh):
            libs = [x for lib in row["libraries"].split() for x in ("--library", str(BENCH / "epddl2026" / lib))]
            out.append((f"EPDDL {row['problem'].split('domains/')[-1]}",
                        [str(BENCH / "epddl2026" / row["domain"]), str(BENCH / "epddl2026" / row["problem"])], libs))
    cb = BENCH / "epddl" / "coin_in_the_box"
    out.append(("E-PDDL coin_in_the_box/pb1", [str(cb / "coininthebox.epddl"), str(cb / "pb1.epddl")], []))
    return [p for p in out if only in p[0]]


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--timeout", type=float, default=120.0, help="plan --timeout per problem")
    ap.add_argument("--only", default="", help="only problems whose label contains this")
    ap.add_argument("--markdown", type=Path)
    args = ap.parse_args()
    rows, tmp = [], Path(tempfile.mkdtemp(prefix="delkit-checkcost-"))
    head = (f"{platform.node()} ({platform.machine()}, Python {platform.python_version()}), "
            f"{time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, load at start {os.getloadavg()[0]:.1f}")
    print(head, flush=True)
    print("| problem | plan len | plan CPU s | plan wall s | check CPU s | check wall s | check − plan CPU | ok |")
    print("|---|---:|---:|---:|---:|---:|---:|---|")
    for label, files, libs in problems(args.only):
        rc, out, err, pcpu, pwall = _run(["plan", *files, *libs, "--timeout", str(args.timeout), "--json"])
        try:
            res = json.loads(out)
        except json.JSONDecodeError:
            res = {"status": f"exit {rc}: {err.strip()[:80]}"}
        if res.get("status") != "solved":
            line = f"| {label} | – | {pcpu:.3f} | {pwall:.2f} | – | – | – | {res.get('status')} |"
            print(line, flush=True)
            rows.append(line)
            continue
        plan_file = tmp / "found.plan"
        plan_file.write_text("\n".join(res["plan"]) + "\n")
        crc, cout, cerr, ccpu, cwall = _run(["check", *files, str(plan_file), *libs])
        verdict = "valid" if crc == 0 else f"exit {crc}: {(cout or cerr).strip()[:60]}"
        within = "yes" if crc == 0 and ccpu <= pcpu + 0.1 else "NO"
        line = (f"| {label} | {len(res['plan'])} | {pcpu:.3f} | {pwall:.2f} | {ccpu:.3f} | {cwall:.2f} | "
                f"{ccpu - pcpu:+.3f} | {within} ({verdict}) |")
        print(line, flush=True)
        rows.append(line)
    tail = f"load at end {os.getloadavg()[0]:.1f}"
    print(tail)
    if args.markdown:
        args.markdown.write_text(head + "\n\n" + "\n".join(rows) + "\n\n" + tail + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
