"""Benchmark: delkit's symbolic (BDD) backend beside SMCDEL's published-on-this-machine figures.

Every delkit figure is in-process CPU time (``time.process_time``, the minimum of ``--repeat`` runs; wall
time of the same run beside it), imports excluded, with the same timed region as SMCDEL's figures:

* muddy children, all N muddy, whole puzzle (build the structure, father's announcement, N−1 rounds of
  "nobody knows", the last round), :func:`delkit.symbolic.muddy_symbolic`;
* drinking logicians: SMCDEL's single nested formula ``thirstyF n`` at the state where all want
  (structure and formula built inside the timed region), :func:`delkit.puzzles.drinking.check_thirsty`;
* dining cryptographers: SMCDEL's benchmark formula on SMCDEL's encoding (complete graph of shared
  bits), validity, :func:`delkit.puzzles.dining.smcdel_dining_check`;
* Sum and Product: SMCDEL's ``sapSolutions`` formula on SMCDEL's encoding,
  :func:`delkit.puzzles.sum_product.smcdel_sum_product`, and delkit's own dialogue (Kw of the bits).

The SMCDEL column is the figure from issue 12 (SMCDEL with CacBDD, measured by the lead on this machine,
in-process CPU); ``ratio`` = delkit / SMCDEL (below 1: delkit is faster). ``load`` is the machine's
1-minute load average when the row finished (the box is shared; CPU times grow with the load too). The
growth lines fit t ∝ N^k by least squares on log-log: over the muddy rows both columns have (N = 40…100,
SMCDEL's exponent beside), and over all muddy rows measured.

    .venv/bin/python bench/symbolic.py                     # all rows, 3 repeats
    .venv/bin/python bench/symbolic.py --muddy 10,20,40,60,80,100,150,200 --repeat 5
"""

from __future__ import annotations

import argparse
import math
import os
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from rich.console import Console  # noqa: E402
from rich.table import Table  # noqa: E402

import delkit.symbolic  # noqa: E402,F401 - imports before any clock starts
from delkit.puzzles.dining import smcdel_dining_check  # noqa: E402
from delkit.puzzles.drinking import check_thirsty  # noqa: E402
from delkit.puzzles.sum_product import smcdel_sum_product, solve_sum_product  # noqa: E402
from delkit.symbolic import muddy_symbolic  # noqa: E402

SMCDEL = {  # issue 12: SMCDEL (CacBDD), in-process CPU seconds on this machine
    ("muddy", 40): 0.031, ("muddy", 60): 0.073, ("muddy", 80): 0.16, ("muddy", 100): 0.48,
    ("drinking", 100): 0.066, ("drinking", 200): 0.26, ("drinking", 400): 1.52,
    ("dining", 10): 0.012, ("dining", 40): 0.040, ("dining", 80): 0.26,
    ("sum-product (SMCDEL formula)", 100): 0.9,
}


def _best(run, repeat: int) -> tuple[float, float, object]:
    """min CPU seconds, wall seconds of that run, the run's answer."""
    best = (math.inf, math.inf, None)
    for _ in range(repeat):
        w0 = time.perf_counter()
        cpu, answer = run()
        wall = time.perf_counter() - w0
        if cpu < best[0]:
            best = (cpu, wall, answer)
    return best


def _fit(points: list[tuple[int, float]]) -> float:
    xs = [math.log(n) for n, _ in points]
    ys = [math.log(t) for _, t in points]
    mx, my = sum(xs) / len(xs), sum(ys) / len(ys)
    return sum((x - mx) * (y - my) for x, y in zip(xs, ys, strict=True)) / sum((x - mx) ** 2 for x in xs)


def rows(muddy: list[int], drinking: list[int], dining: list[int], repeat: int):
    def muddy_run(n: int):
        r = muddy_symbolic(n, n)
        return r.seconds, r.nobody_knows_rounds == n - 1 and r.muddy_know_round == n

    def sap_own():
        r = solve_sum_product(100, symbolic=True)
        return r.seconds, r.solutions == ((4, 13),)

    def sap_smcdel():
        pairs, sec = smcdel_sum_product(100)
        return sec, pairs == [(4, 13)]

    jobs = [("muddy", n, lambda n=n: muddy_run(n)) for n in muddy]
    jobs += [("drinking", n, lambda n=n: check_thirsty(n)[::-1]) for n in drinking]
    jobs += [("dining", n, lambda n=n: smcdel_dining_check(n)[::-1]) for n in dining]
    jobs += [("sum-product (SMCDEL formula)", 100, sap_smcdel), ("sum-product (delkit dialogue)", 100, sap_own)]
    for name, n, run in jobs:
        cpu, wall, ok = _best(run, repeat)
        yield name, n, cpu, wall, bool(ok), SMCDEL.get((name, n))


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--muddy", default="10,20,40,60,80,100", help="comma-separated N (all muddy)")
    ap.add_argument("--drinking", default="100,200,400")
    ap.add_argument("--dining", default="10,40,80")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--markdown", action="store_true", help="print a Markdown table instead")
    args = ap.parse_args(argv)

    def ints(text: str) -> list[int]:
        return [int(x) for x in text.split(",") if x]

    muddy_symbolic(3, 3)  # warm up
    table = Table(title="delkit symbolic vs SMCDEL (in-process CPU seconds; min of repeats)")
    cols = ("puzzle", "N", "right answer", "delkit CPU s", "delkit wall s", "SMCDEL CPU s", "ratio", "load")
    for col in cols:
        table.add_column(col, justify="right")
    md = ["| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)]
    mine: list[tuple[int, float]] = []
    every: list[tuple[int, float]] = []
    for name, n, cpu, wall, ok, ref in rows(ints(args.muddy), ints(args.drinking), ints(args.dining), args.repeat):
        ratio = f"{cpu / ref:.2f}" if ref else "—"
        cells = (name, str(n), "yes" if ok else "NO", f"{cpu:.4f}", f"{wall:.4f}",
                 f"{ref:.3f}" if ref else "—", ratio, f"{os.getloadavg()[0]:.1f}")
        table.add_row(*cells)
        md.append("| " + " | ".join(cells) + " |")
        if name == "muddy":
            every.append((n, cpu))
            if ref:
                mine.append((n, cpu))
    console = Console()
    if args.markdown:
        print("\n".join(md))
    else:
        console.print(table)
    if len(mine) >= 2:
        ref_pts = [(n, SMCDEL[("muddy", n)]) for n, _ in mine]
        print(f"muddy growth on N = {', '.join(str(n) for n, _ in mine)}: delkit N^{_fit(mine):.2f}, "
              f"SMCDEL N^{_fit(ref_pts):.2f}")
    if len(every) > len(mine) and len(every) >= 2:
        print(f"muddy growth on N = {', '.join(str(n) for n, _ in every)}: delkit N^{_fit(every):.2f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
