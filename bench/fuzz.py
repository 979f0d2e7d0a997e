"""Fuzz every delkit command and print the outcome counts per command.

    python bench/fuzz.py -n 5000 --seed 2026 [--families plan,model] [--markdown bench/RESULTS-fuzz.md]

Inputs come from the hypothesis generators in ``tests/fuzz/fuzzgen.py`` (mutated shared benchmarks and
``specs/``, random JSON models and arms plans, boundary numbers, deep nesting); each runs in-process in a
forked, memory-limited worker with a per-input time budget (``tests/fuzz/fuzzkit.py``). Columns: ``error``
= exit 2 with one ``delkit: error:`` line; ``ok`` = an answer its oracle accepts; ``crash`` = traceback;
``limit`` = MemoryError under the worker's address-space limit; ``hang`` = over the time budget;
``wrong`` = an answer the oracle rejects. Timed region: everything, generation included.
"""

from __future__ import annotations

import argparse
import platform
import resource
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT), str(ROOT / "tests" / "fuzz")]


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("-n", type=int, default=5000, help="number of inputs")
    ap.add_argument("--seed", type=int, default=2026)
    ap.add_argument("--families", default="", help="comma-separated subset of tests/fuzz/fuzzgen.FAMILIES, e.g. "
                                                     "plan,check,model,epddl2026,convert,smcdel,epico")
    ap.add_argument("--mem-mb", type=int, default=3072, help="address-space limit of the worker (MiB)")
    ap.add_argument("--markdown", type=Path, help="also write the table (and every bad case) here")
    args = ap.parse_args()

    import fuzzgen
    from fuzzkit import Runner

    from delkit.progress import progress

    fams = [f for f in args.families.split(",") if f] or None
    t0, c0 = time.perf_counter(), time.process_time()
    with progress() as bar:
        task = bar.add_task("fuzz", total=args.n)

        def seen(outcome, tally):
            bad = len(tally.bad)
            bar.update(task, completed=tally.total, description=f"fuzz: {bad} bad" if bad else "fuzz")
            if outcome.kind in tally.BAD:
                bar.console.print(f"[red]{outcome.kind}[/red] {outcome.case.describe()[:200]} -> "
                                  f"{outcome.detail[:200]}")

        with Runner(mem_mb=args.mem_mb) as runner:
            tally = fuzzgen.run_fuzz(args.n, seed=args.seed, families=fams, runner=runner, on_outcome=seen)
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    cpu_workers = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu_all = cpu + cpu_workers.ru_utime + cpu_workers.ru_stime
    head = (f"{tally.total} inputs, seed {args.seed}, worker limit {args.mem_mb} MiB; {wall:.0f} s wall, "
            f"{cpu_all:.0f} s CPU (driver + workers); {platform.node()} "
            f"({platform.machine()}, Python {platform.python_version()}), "
            f"{time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}")
    print(head)
    print(tally.table())
    if tally.bad:
        print("\nbad outcomes:")
        print(tally.report_bad(200))
    if args.markdown:
        args.markdown.write_text(
            f"# Fuzz run\n\n`python bench/fuzz.py -n {args.n} --seed {args.seed}"
            f"{' --families ' + args.families if args.families else ''}`\n\n{head}\n\n{tally.table()}\n\n"
            + ("## Bad outcomes\n\n" + tally.report_bad(500) + "\n" if tally.bad else "No bad outcomes.\n"))
    return 1 if tally.bad else 0


if __name__ == "__main__":
    sys.exit(main())
