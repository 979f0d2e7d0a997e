"""Fuzz every delkit command and print the outcome counts per command.

    python bench/fuzz.py -n 5000 --seed 2026 [--families plan,model] [--markdown bench/RESULTS-fuzz.md]
    python bench/fuzz.py --list                      # the families, with the module that registers each

Families come from ``tests/fuzz/fuzzgen.py`` (which also registers those of ``tests/fuzz/fuzzsafety.py``) and
from every ``bench/fuzz_*.py`` module (or ``--modules a,b``) that defines ``FAMILIES = {name: (strategy,
weight)}``: each is registered with ``fuzzgen.register_families`` before the run, so ``--families NAME``
selects it like the built-in ones. A family whose cases are not command lines gives them
``mode="call"`` (``argv[0]`` = ``"module:function"``, called with the case and a scratch directory in the
worker, returning a ``fuzzkit.Outcome``).

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
# not bench/ itself (Python puts a script's folder first): bench/packaging.py would shadow the 'packaging'
# distribution that matplotlib imports, and the commands that draw would crash inside the harness
sys.path[:] = [str(ROOT), str(ROOT / "tests" / "fuzz")] + [
    p for p in sys.path if Path(p or ".").resolve() != Path(__file__).resolve().parent]


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("-n", type=int, default=5000, help="number of inputs")
    ap.add_argument("--seed", type=int, default=2026)
    ap.add_argument("--families", default="", help="comma-separated subset of tests/fuzz/fuzzgen.FAMILIES, e.g. "
                                                     "plan,check,model,epddl2026,convert,smcdel,epico")
    ap.add_argument("--mem-mb", type=int, default=3072, help="address-space limit of the worker (MiB)")
    ap.add_argument("--markdown", type=Path, help="also write the table (and every bad case) here")
    ap.add_argument("--modules", default=None, help="comma-separated modules whose FAMILIES to add (default: every "
                                                    "bench/fuzz_*.py)")
    ap.add_argument("--list", action="store_true", help="list the families and exit")
    args = ap.parse_args()

    import fuzzgen
    from fuzzkit import Runner

    origin = _register(fuzzgen, args.modules)
    if args.list:
        for name, (_strategy, weight) in sorted(fuzzgen.FAMILIES.items()):
            print(f"{name:16} weight {weight:3}  {origin.get(name, 'tests/fuzz/fuzzgen.py')}")
        return 0
    unknown = [f for f in args.families.split(",") if f and f not in fuzzgen.FAMILIES]
    if unknown:
        print(f"fuzz.py: unknown famil{'y' if len(unknown) == 1 else 'ies'} {', '.join(unknown)}; see --list",
              file=sys.stderr)
        return 2

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


def _register(fuzzgen, modules: str | None) -> dict[str, str]:
    """Import the modules with more families (default: every bench/fuzz_*.py) and register their FAMILIES;
    returns family -> the module that registered it."""
    import importlib
    import importlib.util

    origin = {name: "tests/fuzz/fuzzsafety.py" for name in getattr(sys.modules.get("fuzzsafety"), "FAMILIES", {})}
    if modules is None:
        # by file path: bench/ itself must not go on sys.path (bench/packaging.py would shadow the 'packaging'
        # distribution that matplotlib imports)
        names = [str(p) for p in sorted(Path(__file__).resolve().parent.glob("fuzz_*.py"))]
    else:
        names = [m for m in modules.split(",") if m]
    for name in names:
        if name.endswith(".py"):
            spec = importlib.util.spec_from_file_location(Path(name).stem, name)
            module = importlib.util.module_from_spec(spec)
            sys.modules[Path(name).stem] = module  # the worker finds "module:function" calls by this name
            spec.loader.exec_module(module)
        else:
            module = importlib.import_module(name)
        fams = getattr(module, "FAMILIES", None)
        if not isinstance(fams, dict):
            continue
        fuzzgen.register_families(fams)
        origin.update({fam: getattr(module, "__file__", name) for fam in fams})
    return origin


if __name__ == "__main__":
    sys.exit(main())
