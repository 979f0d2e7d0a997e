"""How far past ``--timeout T`` each command exits, measured from before its process starts.

    python bench/limits.py [--timeout 1.5] [--only SUBSTRING] [--markdown FILE]

Timed: wall seconds from just before ``subprocess.run`` starts the ``delkit`` process until it has exited
(interpreter start-up, imports, the work up to the deadline, output and exit are all inside), with the
child's CPU time (user + system, ``RUSAGE_CHILDREN``) and the load average beside it. The target is
``wall <= T + 0.5 s``. Tasks: an initial state slow to build (2^21 worlds), a single expansion of about
1-2 s (40 actions on a 2^11-world state), ≥ 1 GB held at the deadline, and every other command with a
``--timeout`` on a task that cannot finish in time. Every command is run with ``--json``: the ``answer``
column says whether stdout was one JSON limit answer (``status`` limit) and which counters it carried.
"""

from __future__ import annotations

import argparse
import os
import platform
import sys
import tempfile
import time
from pathlib import Path

from _timing import timed_run

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests" / "fuzz"))


#: a delkit process that holds 1.2 GB in 4 million Python objects (freeing them at interpreter shutdown is
#: what made exits slow) before it runs the command given on its command line
#: (its --timeout is set to the seconds the allocation took since process start + 1.5, printed on stderr)
HOLD = ("import sys, time\nfrom delkit.cli import run\nfrom delkit.resources import process_start\n"
        "big = [bytes(256) for _ in range(4_000_000)]  # ≈ 1.2 GB (4M objects of 289 bytes)\n"
        "t = time.monotonic() - process_start() + 1.5\nprint(f'TIMEOUT {t:.3f}', file=sys.stderr, flush=True)\n"
        "sys.argv = ['delkit', *sys.argv[1:], '--timeout', f'{t:.3f}']\nrun()\n")


def cases(tmp: Path, t: str) -> list[tuple[str, list[str]]]:
    from test_limits import many_free_fluents, slow_expansion

    (tmp / "a").mkdir()
    (tmp / "b").mkdir()
    slow = many_free_fluents(tmp / "a")
    exp = slow_expansion(tmp / "b")
    (tmp / "x.plan").write_text("flip\n")
    hold = tmp / "hold.py"
    hold.write_text(HOLD)
    return [
        ("plan: initial state slow to build", ["plan", *slow, "--timeout", t]),
        ("plan: one expansion ≈ 1-2 s", ["plan", *exp, "--timeout", t, "--engine", "fast"]),
        ("plan holding 1.2 GB (4M objects)", ["@hold", str(hold), "plan", *slow]),
        ("check: replay of a slow initial state", ["check", *slow, str(tmp / "x.plan"), "--timeout", t]),
        ("check (typer path: --timeout=T)", ["check", *slow, str(tmp / "x.plan"), f"--timeout={t}"]),
        ("prove --worlds 12", ["prove", "C{a,b} p -> K_a K_b K_a p", "--worlds", "12", "--timeout", t]),
        ("puzzle sum-product --limit 6000", ["puzzle", "sum-product", "--limit", "6000", "--timeout", t]),
        ("puzzle muddy -n 2000 --symbolic", ["puzzle", "muddy", "-n", "2000", "-m", "1000", "--symbolic",
                                             "--timeout", t]),
        ("epico table --repeat 5 --total-timeout", ["epico", "table", "--repeat", "5", "--total-timeout", t]),
        ("explore sweep --maps 40", ["explore", "sweep", "--maps", "40", "--workers", "1", "--timeout", t,
                                     "--out", str(tmp / "sweep")]),
        ("arms run demo_plan --no-video", ["arms", "run", str(ROOT / "arms" / "demo_plan.json"), "--no-video",
                                           "--timeout", t]),
        ("epico run alpha 2", ["epico", "run", "--goal", "alpha", "--colors", "2", "--timeout", t]),
        ("smcdel: 3000 queries on 26 variables", ["smcdel", str(_big_smcdel(tmp)), "--timeout", t]),
        ("plan: a search that cannot finish", ["plan", str(ROOT / "specs" / "cc_2_4_4" / "CC_2_4_4_s3__pl_7.txt"),
                                               "--timeout", t]),
    ]


def _big_smcdel(tmp: Path) -> Path:
    p = tmp / "big.smcdel.txt"
    p.write_text("VARS " + ",".join(str(i) for i in range(1, 27)) + "\nLAW Top\nOBS alice: 1\nbob: 2\n"
                 + "VALID? alice knows whether 1\n" * 3000)
    return p


def _answer(stdout: str) -> str:
    """What the --json limit answer was: 'JSON (counters)', or what was wrong with it."""
    import json

    lines = [ln for ln in stdout.splitlines() if ln.strip()]
    if len(lines) != 1:
        return f"{len(lines)} lines"
    try:
        rec = json.loads(lines[0])
    except ValueError:
        return "not JSON"
    if rec.get("status") != "limit":
        return f"status {rec.get('status')}"
    keys = [f"{k}={rec[k]}" for k in ("expanded", "generated", "worlds", "steps_replayed", "queries_answered")
            if k in rec]
    return "JSON" + (f" ({', '.join(keys)})" if keys else "")


def _batch_rows(delkit: str, env: dict, t: float) -> str:
    """A batch of 6 searches that cannot finish, 2 workers, ``--timeout T`` per task: every task's record is a
    limit answer; its ``wall`` (from the task's start in its worker) against T, and the batch's wall."""
    import json

    task = str(ROOT / "specs" / "cc_2_4_4" / "CC_2_4_4_s3__pl_7.txt")
    load = os.getloadavg()[0]
    p = timed_run([delkit, "plan", *[task] * 6, "--jobs", "2", "--timeout", f"{t:g}", "--json"], env=env,
                  clock=time.monotonic)
    recs = [json.loads(ln) for ln in p.stdout.splitlines() if ln.startswith("{")]
    tasks = [r for r in recs if not r.get("summary")]
    walls = [float(r.get("wall") or 0) for r in tasks]
    counted = sum(1 for r in tasks if r.get("status") == "limit" and r.get("expanded"))
    return ("| batch: 6 such searches, --jobs 2, per task | exit | tasks reported | limit answers with expanded > 0 "
            "| max task wall − T | batch wall s | load |\n|---|---:|---:|---:|---:|---:|---:|\n"
            f"| T = {t:g} s | {p.returncode} | {len(tasks)}/6 + {len(recs) - len(tasks)} summary | {counted} | "
            f"{max(walls) - t:+.2f} | {p.wall:.2f} | {load:.1f} |")


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--timeout", default="1.5")
    ap.add_argument("--only", default="")
    ap.add_argument("--markdown", type=Path)
    args = ap.parse_args()
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    delkit = str(Path(sys.executable).parent / "delkit")
    t = float(args.timeout)
    head = (f"{platform.node()} ({platform.machine()}, Python {platform.python_version()}), "
            f"{time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}")
    rows = ["| task | exit | wall s (from process start) | wall − T | CPU s | load | --json answer |",
            "|---|---:|---:|---:|---:|---:|---|"]
    print(head)
    print("\n".join(rows), flush=True)
    with tempfile.TemporaryDirectory() as d:
        for label, argv in cases(Path(d), args.timeout):
            if args.only not in label:
                continue
            cmd = [sys.executable, *argv[1:], "--json"] if argv[0] == "@hold" else [delkit, *argv, "--json"]
            load = os.getloadavg()[0]
            p = timed_run(cmd, env=env, clock=time.monotonic)
            wall, cpu = p.wall, p.cpu
            limit = next((float(a.split("=")[-1] if "=" in a else argv[k + 1]) for k, a in enumerate(argv)
                          if a.startswith(("--timeout", "--total-timeout"))), t)
            if argv[0] == "@hold":  # the script chose its limit after allocating
                limit = float(next(ln.split()[1] for ln in p.stderr.splitlines() if ln.startswith("TIMEOUT")))
            row = (f"| {label} (T = {limit:g} s) | {p.returncode} | {wall:.2f} | {wall - limit:+.2f} | {cpu:.2f} "
                   f"| {load:.1f} | {_answer(p.stdout)} |")
            rows.append(row)
            print(row, flush=True)
        if not args.only or args.only in "batch":
            rows += ["", _batch_rows(delkit, env, t)]
            print(rows[-1], flush=True)
    if args.markdown:
        args.markdown.write_text(head + "\n\n" + "\n".join(rows) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
