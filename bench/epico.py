"""Benchmark: e-PICO Tables 1 and 2 (seed 004) — delkit beside the seed and the peer (echosys).

Timed region per run (wall and CPU, mean of --repeat runs): building the grounded task and its initial state
from the E-PDDL texts, the epistemic search (BFS, optimal), flattening and the classical breakdown of every
ontic task, and the plan/1 check. The seed's Table 1 times the search from a given initial state (its
initial states are reported apart, and here in the 'init s' column). Run:

    PYTHONPATH=. python bench/epico.py [--repeat 5] [--colors 1,2,3,4,5,6] [--json]
"""

from __future__ import annotations

import argparse
import json
import platform
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))


def classical_engines(repeat: int = 20) -> list[dict]:
    """One classical call (put_on_shared_robot1_red from the seed's layout: red under black, Listing 5) per
    engine: our BFS, clingo (ASP twin, multi-shot incremental), pyperplan BFS on specs/epico/classical.pddl
    (parse + ground + search). Median wall and CPU milliseconds of ``repeat`` calls."""
    import logging
    import statistics
    import tempfile
    import time

    from planners.classical import goal_for, solve_bfs, solve_classical, to_pddl
    from planners.epico import generate

    logging.disable(logging.CRITICAL)
    dom = Path(__file__).resolve().parents[1] / "specs" / "epico" / "classical.pddl"

    def pyper(state, goal):
        from pyperplan import grounding
        from pyperplan.pddl.parser import Parser
        from pyperplan.search.breadth_first_search import breadth_first_search

        with tempfile.TemporaryDirectory() as d:
            pf = Path(d) / "p.pddl"
            pf.write_text(to_pddl(state, goal))
            parser = Parser(str(dom), str(pf))
            return breadth_first_search(grounding.ground(parser.parse_problem(parser.parse_domain())))

    rows = []
    for n in (2, 4, 6):
        st = generate("alpha", n).classical_init
        goal = goal_for("put_on_shared_robot1_red", st)
        for name, fn in (("delkit bfs", solve_bfs), ("clingo", solve_classical), ("pyperplan bfs", pyper)):
            walls, cpus, length = [], [], None
            for _ in range(repeat):
                c0, w0 = time.process_time(), time.perf_counter()
                r = fn(st, goal)
                walls.append(time.perf_counter() - w0)
                cpus.append(time.process_time() - c0)
                length = len(r) if isinstance(r, list) else len(r.actions)
            rows.append({"colors": n, "engine": name, "length": length, "wall_ms": 1000 * statistics.median(walls),
                         "cpu_ms": 1000 * statistics.median(cpus)})
    return rows


def main(argv: list[str] | None = None) -> int:
    from planners.cli.epico_cmd import format_tables
    from planners.epico import GOALS, generate
    from planners.hierarchy import solve, table_cell

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--colors", default="1,2,3,4")
    ap.add_argument("--timeout", type=float, default=110.0)
    ap.add_argument("--symmetric", action="store_true", help="model both robots' colours (4^n worlds)")
    ap.add_argument("--json", action="store_true")
    ap.add_argument("--classical-engines", action="store_true", help="only compare the classical engines")
    args = ap.parse_args(argv)
    if args.classical_engines:
        rows = classical_engines()
        if args.json:
            print(json.dumps(rows))
        else:
            print(f"{'colours':>7} {'engine':14} {'actions':>7} {'wall ms':>8} {'cpu ms':>8}")
            for r in rows:
                print(f"{r['colors']:>7} {r['engine']:14} {r['length']:>7} {r['wall_ms']:8.2f} {r['cpu_ms']:8.2f}")
        return 0
    solve(generate("alpha", 1))  # warm-up
    cells = []
    for g in GOALS:
        for n in (int(c) for c in args.colors.split(",")):
            cells.append(table_cell(g, n, repeat=args.repeat, timeout=args.timeout,
                                    symmetric=args.symmetric))
            print(f"# {g} {n}: done", file=sys.stderr, flush=True)
    if args.json:
        print(json.dumps({"machine": platform.processor() or platform.machine(), "cells": cells}))
    else:
        print(format_tables(cells))
    return 0


if __name__ == "__main__":
    sys.exit(main())
