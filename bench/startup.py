"""Start-up benchmark: whole-process time of each ``delkit`` command on a tiny input.

Each row runs ``python -c "from delkit.cli import main; ..." ARGS`` as a fresh process ``--runs`` times
(after one untimed warm-up run that also fills the parser cache) and reports the median wall seconds and the
median CPU seconds (user + system of the child, from ``RUSAGE_CHILDREN``) — the timed region is the whole
process: interpreter start, imports, parsing, the command itself, exit. Children may write bytecode
(``PYTHONDONTWRITEBYTECODE`` is removed from their environment) so that, as for an installed package, the
warm-up run leaves ``.pyc`` files and the timed runs do not recompile delkit's sources. Two baselines are the bare
interpreter and ``import numpy``. The plan/check inputs are ``CB_simple__pl_2`` from
``../shared/benchmarks/mastar`` (skipped if absent) and ``specs/coin_in_the_box``; ``Coin_in_the_Box__pl_3`` (mA*)
and plank's EPDDL (2026) Coin-in-the-Box ``problem_2`` are planned too. ``--runs 11`` for the figures in
``bench/RESULTS-planner.md``. ``--ab DIR`` times a second checkout (e.g. ``git worktree add --detach /tmp/old
COMMIT``) in the same run, its runs alternating with this tree's (same inputs, same load): an A/B column.
With ``--ab`` every round of a row also runs the bare interpreter (a per-row baseline column, same load).
``--entry run`` runs the console script's entry point instead (``delkit.cli.run``: what ``delkit`` and ``python -m
delkit`` run; it leaves with ``os._exit``, so the interpreter's teardown — ≈ 10 ms — is not in the process).

    .venv/bin/python bench/startup.py [--runs 7] [--json out.json] [--only plan,check] [--ab DIR] [--entry run]
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

_MAIN = "import sys; from delkit.cli import main; sys.exit(main())"
# ``--entry run``: what the ``delkit`` console script (and ``python -m delkit``) runs — delkit.cli.run, which
# leaves with os._exit after flushing (no interpreter teardown) and arms the --timeout watchdog thread
_RUN = "from delkit.cli import run; run()"
_ENTRY = {"main": _MAIN, "run": _RUN}
ENTRY = _MAIN

_MODEL = {
    "delkit": "kripke-model", "version": 1, "props": ["m1", "m2"], "agents": ["c1", "c2"],
    "worlds": [{"name": "mm", "true": ["m1", "m2"]}, {"name": "mc", "true": ["m1"]},
               {"name": "cm", "true": ["m2"]}, {"name": "cc", "true": []}],
    "relations": {"c1": {"blocks": [["mm", "cm"], ["mc", "cc"]]}, "c2": {"blocks": [["mm", "mc"], ["cm", "cc"]]}},
    "designated": ["mm"],
}


def cases(tmp: Path) -> list[tuple[str, list[str]]]:
    """(label, argv) of every command, on tiny inputs written into ``tmp``."""
    from planners.lang import shared_benchmarks

    model = tmp / "muddy2.json"
    model.write_text(json.dumps(_MODEL))
    coin = ROOT / "specs" / "coin_in_the_box"
    out: list[tuple[str, list[str]]] = [
        ("python -c pass (baseline)", ["<python>", "pass"]),
        ("python -c 'import numpy' (baseline)", ["<python>", "import numpy"]),
        ("delkit --help", ["--help"]),
        ("delkit version", ["version"]),
        ("delkit plan --help", ["plan", "--help"]),
    ]
    bench = shared_benchmarks()
    if bench is not None:
        cb = bench / "mastar" / "CB_simple" / "CB_simple__pl_2.txt"
        plan_file = tmp / "cb2.plan"
        plan_file.write_text("peek_up_key_a\nopen_a\n")
        coin3 = bench / "mastar" / "Coin_In_The_Box" / "Coin_in_the_Box__pl_3.txt"
        plank = bench / "epddl2026" / "plank"
        out += [("delkit plan Coin_in_the_Box__pl_3 (mA*)", ["plan", str(coin3)]),
                ("delkit plan Coin-in-the-Box problem_2 (EPDDL 2026)",
                 ["plan", str(plank / "domains" / "Coin-in-the-Box" / "cb.epddl"),
                  str(plank / "domains" / "Coin-in-the-Box" / "instances" / "problem_2.epddl"),
                  "-l", str(plank / "libraries" / "intermediate.epddl")])]
        out += [("delkit plan CB_simple__pl_2", ["plan", str(cb)]),
                ("delkit plan CB_simple__pl_2 --json", ["plan", str(cb), "--json"]),
                ("delkit plan CB_simple__pl_2 --search astar", ["plan", str(cb), "--search", "astar"]),
                ("delkit check CB_simple__pl_2 PLAN", ["check", str(cb), str(plan_file)]),
                ("delkit check CB_simple__pl_2 PLAN -p 'at end opened'",
                 ["check", str(cb), str(plan_file), "-p", "at end opened"])]
    out += [("delkit plan coin (E-PDDL)", ["plan", str(coin / "domain.epddl"), str(coin / "problem.epddl")]),
            ("delkit check coin (E-PDDL) --properties",
             ["check", str(coin / "domain.epddl"), str(coin / "problem.epddl"), str(coin / "problem.plan"),
              "--properties", str(coin / "problem.props")]),
            ("delkit model show", ["model", "show", str(model)]),
            ("delkit model check", ["model", "check", str(model), "K_c1 m2"]),
            ("delkit model dot", ["model", "dot", str(model)]),
            ("delkit model contract", ["model", "contract", str(model)]),
            ("delkit prove 'K_a p -> p' -k 2", ["prove", "K_a p -> p", "-k", "2"]),
            ("delkit puzzle drinking", ["puzzle", "drinking"]),
            ("delkit puzzle muddy", ["puzzle", "muddy"]),
            ("delkit arms scene", ["arms", "scene", str(tmp / "scene.xml")])]
    return out


def _once(argv: list[str], env: dict[str, str]) -> tuple[float, float, int]:
    """One run of ``argv`` in a fresh process (``python -c`` puts the working directory first on ``sys.path``: it
    is the checkout on ``PYTHONPATH``, so that checkout's code runs): (wall s, CPU s, exit status)."""
    cmd = [sys.executable, "-c", argv[1]] if argv and argv[0] == "<python>" else [sys.executable, "-c", ENTRY, *argv]
    r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    proc = subprocess.run(cmd, env=env, cwd=env["PYTHONPATH"].split(os.pathsep)[0], stdout=subprocess.DEVNULL,
                          stderr=subprocess.DEVNULL, check=False)
    wall = time.perf_counter() - t0
    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime)
    return wall, cpu, proc.returncode


def _env(root: Path) -> dict[str, str]:
    env = dict(os.environ, PYTHONPATH=str(root) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    env.pop("PYTHONDONTWRITEBYTECODE", None)  # as an installed package: the warm-up run leaves .pyc files
    return env


def run(runs: int, only: list[str] | None = None, ab: Path | None = None) -> list[dict]:
    """One row per command; with ``ab`` each round also runs the other checkout and the bare interpreter, in
    alternation, so that every row has its own same-load A/B and baseline (``pass_cpu_median``)."""
    envs = [_env(ROOT)] + ([_env(ab)] if ab is not None else [])
    rows = []
    with tempfile.TemporaryDirectory() as d:
        for label, argv in cases(Path(d)):
            if only and not any(o in label for o in only):
                continue
            jobs = [(argv, env) for env in envs] + ([(["<python>", "pass"], envs[0])] if ab is not None else [])
            for a, env in jobs:
                _once(a, env)  # warm-up: page cache, parser cache, .pyc files
            walls: list[list[float]] = [[] for _ in jobs]
            cpus: list[list[float]] = [[] for _ in jobs]
            codes: list[set[int]] = [set() for _ in jobs]
            for _ in range(runs):
                for k, (a, env) in enumerate(jobs):  # alternating: every column sees the same load
                    w, c, rc = _once(a, env)
                    walls[k].append(w)
                    cpus[k].append(c)
                    codes[k].add(rc)
            row = {"command": label, "argv": argv, "runs": runs, "wall_median": statistics.median(walls[0]),
                   "wall_min": min(walls[0]), "cpu_median": statistics.median(cpus[0]), "exit": sorted(codes[0])}
            if ab is not None:
                row.update(ab_wall_median=statistics.median(walls[1]), ab_cpu_median=statistics.median(cpus[1]),
                           ab_exit=sorted(codes[1]), pass_cpu_median=statistics.median(cpus[2]))
            rows.append(row)
    return rows


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--runs", type=int, default=7)
    ap.add_argument("--only", default="", help="comma-separated substrings of the command labels to run")
    ap.add_argument("--json", type=Path, default=None)
    ap.add_argument("--ab", type=Path, default=None, help="a second checkout, timed in alternation (A/B)")
    ap.add_argument("--entry", choices=sorted(_ENTRY), default="main",
                    help="main: python -c 'sys.exit(delkit.cli.main())' (the interpreter's teardown included, the "
                         "protocol of the earlier figures); run: the console script's delkit.cli.run")
    args = ap.parse_args()
    global ENTRY
    ENTRY = _ENTRY[args.entry]
    load0 = os.getloadavg()[0]
    rows = run(args.runs, [s for s in args.only.split(",") if s] or None, args.ab)
    w = max(len(r["command"]) for r in rows)
    print(f"whole-process time, median of {args.runs} runs, entry {args.entry} (python {sys.version.split()[0]}, "
          f"{os.cpu_count()} cores, load average {load0:.1f} before, {os.getloadavg()[0]:.1f} after)")
    extra = f" {args.ab} CPU s | {args.ab} wall s | `pass` CPU s, same rounds |" if args.ab else ""
    print(f"| {'command':<{w}} | wall s (median) | wall s (min) | CPU s (median) | exit |{extra}")
    print(f"|{'-' * (w + 2)}|----------------:|-------------:|---------------:|-----:|"
          + ("---:|---:|---:|" if args.ab else ""))
    for r in rows:
        tail = (f" {r['ab_cpu_median']:.3f} | {r['ab_wall_median']:.3f} | {r['pass_cpu_median']:.3f} |"
                if args.ab else "")
        print(f"| {r['command']:<{w}} | {r['wall_median']:15.3f} | {r['wall_min']:12.3f} | {r['cpu_median']:14.3f} | "
              f"{','.join(map(str, r['exit'])):>4} |{tail}")
    if args.json:
        args.json.write_text(json.dumps(rows, indent=2))


if __name__ == "__main__":
    main()
