"""Frontier benchmark: coverage, plan lengths and CPU of BFS, A*, novelty (BFWS-style) and the ``--search auto``
portfolio in the same run, on the generated frontier families (:mod:`planners.generators.frontier`: spy-linear,
spy-sensing, hotel-distributed, ugv-coordination at :data:`SIZES`) and the shared suites (EPDDL 2026:
../shared/benchmarks/epddl2026/expected.csv; mA*: ../shared/benchmarks/mastar/expected.csv), read in place.

Timed region, per (instance, search): one fresh ``delkit plan FILES --search S --timeout T --json`` process —
start-up, reading, grounding, search, output; CPU = the child's user + system time (``RUSAGE_CHILDREN``), wall
beside it. The searches of one instance run one after the other (same load). ``--timeout`` is delkit's own
limit (wall, counted from the start of the process, every phase); the process is killed 15 s after it.

Every plan found is replayed by the project's validator (:func:`planners.validate.check_plan`, in this process,
outside the clock) in the semantics ``delkit plan`` used; a row with an invalid plan is marked ``INVALID``.
Plans that reach the goal only vacuously (``"vacuous"`` in the JSON) are marked ``v``.

    .venv/bin/python bench/frontier.py [--timeout 60] [--suites generated,epddl2026,mastar] [--only SUBSTR]
                                       [--searches bfs,astar,novelty,auto] [--json out.json] [--markdown]
"""

from __future__ import annotations

import argparse
import csv
import json
import os
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from _timing import timed_run  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
SHARED = Path(os.environ.get("DELKIT_BENCHMARKS", ROOT.parent / "shared" / "benchmarks"))
if not SHARED.exists():
    SHARED = Path("/work/shared/benchmarks")


def generated(folder: Path) -> list[dict]:
    from planners.generators.frontier import SIZES, generate

    rows = []
    for family, sizes in SIZES.items():
        for size in sizes:
            inst = generate(family, *size)
            d, p, lib = inst.write(folder / inst.name)
            rows.append({"suite": "generated", "family": family, "name": inst.name, "files": [str(d), str(p)],
                         "library": [str(lib)], "known": inst.optimum})
    return rows


def _expected(suite: str, row: Callable[[Path, dict], dict]) -> list[dict]:
    """The rows of a shared suite's expected.csv, each made by ``row(suite folder, CSV record)``."""
    base = SHARED / suite
    with open(base / "expected.csv") as f:
        return [{"suite": suite, **row(base, r)} for r in csv.DictReader(f)]


def epddl2026() -> list[dict]:
    return _expected("epddl2026", lambda base, r: {
        "family": r["problem"].split("/")[2], "name": r["problem"].split("/")[2] + "/" + Path(r["problem"]).stem,
        "files": [str(base / r["domain"]), str(base / r["problem"])],
        "library": [str(base / x) for x in r["libraries"].split(";") if x], "known": r["shortest_known"]})


def mastar() -> list[dict]:
    return _expected("mastar", lambda base, r: {
        "family": r["file"].split("/")[0], "name": Path(r["file"]).stem, "files": [str(base / r["file"])],
        "library": [], "known": r["expected_length"]})


def run_one(row: dict, search: str, timeout: float) -> dict:
    cmd = [sys.executable, "-c", "import sys; from delkit.cli import main; sys.exit(main())", "plan", *row["files"],
           "--search", search, "--timeout", f"{timeout:g}", "--json"]
    for lib in row["library"]:
        cmd += ["-l", lib]
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    t = timed_run(cmd, timeout=timeout + 15, env=env)
    out: dict = {"search": search, "cpu": round(t.cpu, 3), "wall": round(t.wall, 3)}
    if t.timed_out:
        out.update(status="killed")
        return out
    try:
        js = json.loads(t.stdout.strip().splitlines()[-1])
    except (ValueError, IndexError):
        out.update(status="error", error=(t.stderr or t.stdout)[-300:])
        return out
    out.update(status=js["status"], length=js.get("length"), plan=js.get("plan"), vacuous=js.get("vacuous", []),
               semantics=js.get("semantics"), optimal=js.get("optimal"), phase=js.get("search"),
               phases=js.get("phases"))
    return out


def validate(row: dict, res: dict, cache: dict) -> None:
    if res.get("status") != "solved":
        return
    from planners.lang import load_task
    from planners.validate import check_plan

    key = tuple(row["files"])
    if key not in cache:
        files = [Path(f) for f in row["files"]]
        cache[key] = load_task(files[0], files[1] if len(files) > 1 else None, [Path(x) for x in row["library"]])
    res["valid"] = check_plan(cache[key], list(res["plan"])).valid


def cell(r: dict) -> str:
    st = r["status"]
    if st == "solved":
        mark = ("" if r.get("valid") else " INVALID") + (" v" if r.get("vacuous") else "")
        opt = "*" if r.get("optimal") else ""
        return f"{r['length']}{opt} {r['cpu']:.2f}s{mark}"
    return {"limit": "—", "unsolvable": "none", "killed": "killed", "error": "ERR"}.get(st, st) + f" {r['cpu']:.1f}s"


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--timeout", type=float, default=60.0)
    ap.add_argument("--suites", default="generated,epddl2026,mastar")
    ap.add_argument("--searches", default="bfs,astar,novelty,auto")
    ap.add_argument("--only", default="")
    ap.add_argument("--json", type=Path)
    ap.add_argument("--markdown", action="store_true", help="print the table as Markdown")
    args = ap.parse_args()
    searches = args.searches.split(",")
    tmp = Path(tempfile.mkdtemp(prefix="frontier-"))
    rows: list[dict] = []
    for suite in args.suites.split(","):
        rows += {"generated": lambda: generated(tmp), "epddl2026": epddl2026, "mastar": mastar}[suite]()
    rows = [r for r in rows if args.only in r["name"]]
    cache: dict = {}
    sep = " | " if args.markdown else "  "
    head = ["suite", "instance", "known"] + searches
    print(("| " if args.markdown else "") + sep.join(head) + (" |" if args.markdown else ""))
    if args.markdown:
        print("|" + "|".join("---" for _ in head) + "|")
    t0 = time.time()
    for row in rows:
        row["results"] = []
        for s in searches:
            res = run_one(row, s, args.timeout)
            validate(row, res, cache)
            row["results"].append(res)
        line = [row["suite"], row["name"], str(row["known"])] + [cell(r) for r in row["results"]]
        print(("| " if args.markdown else "") + sep.join(line) + (" |" if args.markdown else ""), flush=True)
        if args.json:
            args.json.write_text(json.dumps(rows, indent=1))
    print()
    print("coverage (solved / tried) and CPU summed over the instances every search solved, per family:")
    fams: dict = {}
    for row in rows:
        fams.setdefault((row["suite"], row["family"]), []).append(row)
    for (suite, fam), rs in fams.items():
        cov = [sum(1 for r in rs if r["results"][i]["status"] == "solved") for i in range(len(searches))]
        common = [r for r in rs if all(x["status"] == "solved" for x in r["results"])]
        cpu = [sum(r["results"][i]["cpu"] for r in common) for i in range(len(searches))]
        bad = sum(1 for r in rs for x in r["results"] if x["status"] == "solved" and not x.get("valid"))
        print(f"  {suite}/{fam}: " + ", ".join(f"{s} {c}/{len(rs)}" for s, c in zip(searches, cov, strict=True))
              + f"; CPU on the {len(common)} solved by all: "
              + ", ".join(f"{s} {c:.2f}s" for s, c in zip(searches, cpu, strict=True))
              + (f"; {bad} INVALID plans" if bad else ""))
    print(f"\n{len(rows)} instances, {time.time() - t0:.0f} s wall; load at the end: "
          f"{open('/proc/loadavg').read().split()[:3] if Path('/proc/loadavg').exists() else '?'}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
