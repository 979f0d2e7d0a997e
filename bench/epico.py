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


def main(argv: list[str] | None = None) -> int:
    from delkit.cli.epico_cmd import format_tables
    from planners.epico import GOALS, generate
    from planners.hierarchy import solve, table_cell

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--colors", default="1,2,3,4")
    ap.add_argument("--timeout", type=float, default=110.0)
    ap.add_argument("--symmetric", action="store_true", help="model both robots' colours (4^n worlds)")
    ap.add_argument("--json", action="store_true")
    args = ap.parse_args(argv)
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
