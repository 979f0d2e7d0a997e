"""Benchmark: the whole muddy-children puzzle (all N children muddy) for growing N.

Explicit engine (``delkit.puzzles.solve_muddy``: build the 2^N-world S5 model, the father's
announcement, N−1 "nobody knows" announcements, the final round) and the symbolic BDD engine
(``delkit.backends.symbolic.muddy_symbolic``). Each time is the median of ``--repeat`` runs, in seconds (explicit:
wall clock; symbolic: CPU time, imports excluded — see bench/symbolic.py for the comparison with SMCDEL).

    .venv/bin/python bench/muddy.py                 # explicit N = 2..16, symbolic N = 10..80
    .venv/bin/python bench/muddy.py --explicit 18 --symbolic 10,20,40,60,80,100

Reference: DEMO-S5 is reported to need 212 s for N = 12; target here: N = 14 in under 1 s.
"""

from __future__ import annotations

import argparse
import statistics
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from rich.console import Console  # noqa: E402
from rich.table import Table  # noqa: E402

from delkit.backends.symbolic import muddy_symbolic  # noqa: E402
from delkit.puzzles.muddy import solve_muddy  # noqa: E402


def _median_seconds(run, repeat: int) -> tuple[float, object]:
    results = [run() for _ in range(repeat)]
    return statistics.median(r.seconds for r in results), results[-1]


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--explicit", type=int, default=16, help="largest N for the explicit engine")
    ap.add_argument("--symbolic", default="10,14,20,30,40,60,80", help="comma-separated N for the BDD engine")
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args(argv)
    solve_muddy(3, 3)  # warm up imports and caches
    muddy_symbolic(3, 3)

    table = Table(title="muddy children, all N muddy (whole puzzle, median seconds)")
    for col in ("engine", "N", "worlds / peak BDD nodes of θ", "nobody-knows rounds", "seconds"):
        table.add_column(col, justify="right")
    for n in range(2, args.explicit + 1):
        sec, r = _median_seconds(lambda n=n: solve_muddy(n, n), args.repeat)
        assert r.nobody_knows_rounds == n - 1
        table.add_row("explicit", str(n), str(2 ** n), str(r.nobody_knows_rounds), f"{sec:.4f}")
    for n in (int(x) for x in args.symbolic.split(",") if x):
        sec, r = _median_seconds(lambda n=n: muddy_symbolic(n, n), args.repeat)
        assert r.nobody_knows_rounds == n - 1
        table.add_row("symbolic", str(n), str(r.law_nodes), str(r.nobody_knows_rounds), f"{sec:.4f}")
    Console().print(table)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
