"""Benchmark: delkit's symbolic (BDD) backend beside SMCDEL, in the same run when SMCDEL is built here.

Every delkit figure is in-process CPU time (``time.process_time``), imports and
:func:`delkit.backends.symbolic.prepare` excluded, BDD manager creation included — the same timed region as
SMCDEL's (structure + formula + evaluation):

* muddy children, all N muddy, whole puzzle (build the structure, father's announcement, N−1 rounds of
  "nobody knows", the last round), :func:`delkit.backends.symbolic.muddy_symbolic`;
* drinking logicians: SMCDEL's single nested formula ``thirstyF n`` at the state where all want
  (structure and formula built inside the timed region), :func:`delkit.puzzles.drinking.check_thirsty`;
* dining cryptographers: SMCDEL's benchmark formula on SMCDEL's encoding (complete graph of shared
  bits), validity, :func:`delkit.puzzles.dining.smcdel_dining_check`;
* Sum and Product: SMCDEL's ``sapSolutions`` formula on SMCDEL's encoding,
  :func:`delkit.puzzles.sum_product.smcdel_sum_product` (in-process mode: also delkit's own dialogue).

Protocols: ``--fresh-process`` (the headline; SMCDEL's): one row per process, ``--repeat`` processes per
row, rows interleaved, min and median; each process stopped after 4 x ``--timeout`` wall seconds (no
CPU-time limit: it coarsens the CPU clock, see ``_WALL_FACTOR``). With ``--cli`` the
process is the ``delkit puzzle … --symbolic --json`` command line and the figure is the ``seconds`` it
reports itself. Without ``--fresh-process``: every row ``--repeat`` times in this process after the rows
before it (warm), minimum.

With ``--smcdel-bin PATH`` (``--fresh-process`` only) SMCDEL runs in the same sitting: for every row and
round one delkit process and one SMCDEL process (bench/peers/smcdel/SmcdelBench.hs: SMCDEL's own example
modules, ``getCPUTime`` around structure + formula + evaluation), the order alternating from round to
round, and the SMCDEL columns are that run's min and median. ``--managers inside`` (default): both BDD
managers are created inside the clock (delkit's ``new_manager``, CacBDD's set-up by the first BDD
operation); ``outside``: both before it (delkit: the puzzle's manager made before the call and passed in;
SMCDEL: ``--warm``); ``both``: both protocols interleaved in the same rounds, one table each. Without
``--smcdel-bin`` the SMCDEL column holds figures recorded earlier on this machine (SMCDEL v1.3.0, CacBDD,
in-process CPU), labelled "not this run".
``ratio`` = delkit / SMCDEL (below 1: delkit is faster).
``load`` is the machine's 1-minute load average when the row finished. The growth lines fit t ∝ N^k by
least squares on log-log over N = 100…200 (SMCDEL's exponent beside) and over all muddy rows measured.

    .venv/bin/python bench/symbolic.py --fresh-process --repeat 7 --muddy 10,20,40,60,80,100,150,200
    .venv/bin/python bench/symbolic.py --fresh-process --cli --repeat 7
    .venv/bin/python bench/symbolic.py --fresh-process --repeat 1 --muddy 300,400 --drinking "" --dining ""
    .venv/bin/python bench/symbolic.py --fresh-process --repeat 7 --muddy 10,20,40,60,80,100,150,200 \
        --smcdel-bin /work/peers/smcdel/out/bin/smcdel-bench --managers both   # SMCDEL in the same run
    .venv/bin/python bench/symbolic.py --repeat 5                  # in-process repeats
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

import delkit.backends.symbolic  # noqa: E402,F401 - imports before any clock starts
from delkit.backends.symbolic import muddy_manager, muddy_symbolic  # noqa: E402
from delkit.puzzles.dining import smcdel_dining_check, smcdel_dining_manager  # noqa: E402
from delkit.puzzles.drinking import check_thirsty, drinking_manager  # noqa: E402
from delkit.puzzles.sum_product import smcdel_sum_product, solve_sum_product  # noqa: E402

SMCDEL = {  # SMCDEL v1.3.0 (CacBDD) built on this machine, recorded earlier (not this run): alternating fresh
    # processes, CPU time in-process (getCPUTime around structure + formula + evaluation), manager inside
    ("muddy", 10): 0.0012, ("muddy", 20): 0.0044, ("muddy", 40): 0.029, ("muddy", 60): 0.113,
    ("muddy", 80): 0.295, ("muddy", 100): 0.627, ("muddy", 150): 2.56, ("muddy", 200): 6.21,
    ("drinking", 100): 0.034, ("drinking", 200): 0.169, ("drinking", 400): 0.980,
    ("dining", 10): 0.0012, ("dining", 40): 0.0236, ("dining", 80): 0.199,
    ("sum-product (SMCDEL formula)", 100): 0.688,
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
    points = [(n, max(t, 1e-9)) for n, t in points]
    xs = [math.log(n) for n, _ in points]
    ys = [math.log(t) for _, t in points]
    mx, my = sum(xs) / len(xs), sum(ys) / len(ys)
    return sum((x - mx) * (y - my) for x, y in zip(xs, ys, strict=True)) / sum((x - mx) ** 2 for x in xs)


def rows(muddy: list[int], drinking: list[int], dining: list[int], repeat: int):
    """In-process rows: every row ``repeat`` times in this process, after the rows before it."""
    jobs = [("muddy", n) for n in muddy] + [("drinking", n) for n in drinking] + [("dining", n) for n in dining]
    jobs += [("sum-product (SMCDEL formula)", 100), ("sum-product (delkit dialogue)", 100)]
    for name, n in jobs:
        cpu, wall, ok = _best(lambda name=name, n=n: _job(name, n), repeat)
        yield name, n, cpu, wall, bool(ok), SMCDEL.get((name, n))


_MANAGERS = {  # the manager each row's call creates inside its clock unless given one made before it
    "muddy": muddy_manager, "drinking": drinking_manager, "dining": smcdel_dining_manager,
    "sum-product (SMCDEL formula)": lambda n: delkit.backends.symbolic.new_manager(),
}


def _job(name: str, n: int, *, outside: bool = False):
    """The timed call of one row: returns (CPU seconds, right answer). ``outside``: the row's BDD manager is
    created (and the BDD library loaded) before the call, so outside its clock."""
    bdd = None
    if outside:
        delkit.backends.symbolic.prepare()
        bdd = _MANAGERS[name](n)
    if name == "muddy":
        r = muddy_symbolic(n, n, bdd=bdd)
        return r.seconds, r.nobody_knows_rounds == n - 1 and r.muddy_know_round == n
    if name == "drinking":
        ok, sec = check_thirsty(n, bdd=bdd)
        return sec, ok
    if name == "dining":
        ok, sec = smcdel_dining_check(n, bdd=bdd)
        return sec, ok
    if name == "sum-product (SMCDEL formula)":
        pairs, sec = smcdel_sum_product(n, bdd=bdd)
        return sec, pairs == [(4, 13)]
    r = solve_sum_product(n, symbolic=True)
    return r.seconds, r.solutions == ((4, 13),)


_CLI = {  # the command line whose own reported "seconds" is read (puzzle_cmd.py)
    "muddy": lambda n: ["puzzle", "muddy", "-n", str(n), "-m", str(n), "--symbolic", "--json"],
    "drinking": lambda n: ["puzzle", "drinking", "--n", str(n), "--symbolic", "--formula", "--json"],
    "dining": lambda n: ["puzzle", "dining", "--n", str(n), "--symbolic", "--smcdel", "--json"],
    "sum-product (SMCDEL formula)": lambda n: ["puzzle", "sum-product", "--limit", str(n), "--symbolic",
                                               "--smcdel", "--json"],
}


# Fresh processes are stopped on the wall clock (at _WALL_FACTOR x --timeout), not by RLIMIT_CPU: while a
# process has a CPU-time limit, Linux reads its CPU clock (CLOCK_PROCESS_CPUTIME_ID, behind both
# time.process_time and GHC's getCPUTime) from the thread group's CPU timer, which advances only when the
# scheduler accounts the running time (ticks, context switches); a region of a few milliseconds then reads
# whole ticks too much or too little (dining 10, ~2 ms: 3.0-5.4 ms with the limit, 1.7-3.3 ms without;
# muddy 10 with the manager made before the clock read 0.0 s).
_WALL_FACTOR = 4


def _spawn(name: str, n: int, cli: bool, timeout: float, outside: bool = False) -> tuple[float, bool] | None:
    """One fresh process: this script's ``--one`` (the API call) or the ``delkit`` command line; its own
    reported CPU seconds and whether the answer was right; None when it ran out of ``timeout`` CPU seconds."""
    import json
    import subprocess

    root = Path(__file__).resolve().parents[1]
    env = dict(os.environ, PYTHONPATH=str(root) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    if cli:
        cmd = [str(Path(sys.executable).with_name("delkit")), *_CLI[name](n)]
    else:
        cmd = [sys.executable, str(Path(__file__).resolve()), "--one", name, str(n),
               *(["--manager-outside"] if outside else [])]
    try:  # a wall-clock limit (_WALL_FACTOR x timeout), no RLIMIT_CPU: see _WALL_FACTOR
        proc = subprocess.run(cmd, capture_output=True, text=True, env=env, timeout=_WALL_FACTOR * timeout)
    except subprocess.TimeoutExpired:
        return None
    if proc.returncode != 0:
        if proc.returncode < 0:
            return None
        raise RuntimeError(f"{' '.join(cmd)} failed: {proc.stderr.strip()[-400:]}")
    out = proc.stdout
    data = json.loads(out.strip().splitlines()[-1])
    if cli:
        ok = {"muddy": lambda d: d["nobody_knows_rounds"] == n - 1 and d["muddy_know_round"] == n,
              "drinking": lambda d: d["holds"], "dining": lambda d: d["valid"],
              "sum-product (SMCDEL formula)": lambda d: d["solutions"] == [[4, 13]]}[name](data)
        return data["seconds"], bool(ok)
    return data["cpu"], data["ok"]


def fresh_rows(jobs: list[tuple[str, int]], repeat: int, cli: bool, timeout: float):
    """Every row in ``repeat`` fresh processes, the rows interleaved (round r runs every row once), so
    that a change in the machine's load touches all rows alike. Yields name, N, min, median, ok, load."""
    import statistics

    times: dict[tuple[str, int], list[float]] = {j: [] for j in jobs}
    oks: dict[tuple[str, int], bool] = dict.fromkeys(jobs, True)
    dead: set[tuple[str, int]] = set()
    loads: dict[tuple[str, int], float] = {}
    for _ in range(repeat):
        for job in jobs:
            if job in dead:
                continue
            got = _spawn(*job, cli=cli, timeout=timeout)
            loads[job] = os.getloadavg()[0]
            if got is None:
                dead.add(job)
                continue
            times[job].append(got[0])
            oks[job] = oks[job] and got[1]
    for job in jobs:
        ts = times[job]
        yield (*job, min(ts) if ts else None, statistics.median(ts) if ts else None, oks[job] and bool(ts),
               len(ts), loads.get(job, 0.0))


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--muddy", default="10,20,40,60,80,100", help="comma-separated N (all muddy)")
    ap.add_argument("--drinking", default="100,200,400")
    ap.add_argument("--dining", default="10,40,80")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--markdown", action="store_true", help="print a Markdown table instead")
    ap.add_argument("--fresh-process", action="store_true",
                    help="one row per process (SMCDEL's protocol): min and median over --repeat processes")
    ap.add_argument("--cli", action="store_true", help="with --fresh-process: run the `delkit puzzle` command "
                    "line and read its own reported seconds")
    ap.add_argument("--timeout", type=float, default=60.0, help="a fresh process is stopped after "
                    f"{_WALL_FACTOR} x TIMEOUT wall seconds (then the row says '> T s')")
    ap.add_argument("--smcdel-bin", metavar="PATH", help="with --fresh-process: SMCDEL's side "
                    "(bench/peers/smcdel/SmcdelBench.hs, built as its README says) run alternately with delkit, "
                    "fresh process each, same repeats; the SMCDEL column is then this run's min and median")
    ap.add_argument("--managers", choices=("inside", "outside", "both"), default="inside",
                    help="with --smcdel-bin: both BDD managers created inside the clock, both before it, or both "
                    "protocols in the same rounds (two tables)")
    ap.add_argument("--manager-outside", action="store_true", help=argparse.SUPPRESS)
    ap.add_argument("--one", nargs=2, metavar=("PUZZLE", "N"), help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.smcdel_bin and not args.fresh_process:
        ap.error("--smcdel-bin runs with --fresh-process only")
    if args.managers != "inside" and not args.smcdel_bin:
        ap.error("--managers outside/both needs --smcdel-bin (the protocols compare delkit with SMCDEL)")

    if args.one:
        import json

        cpu, ok = _job(args.one[0], int(args.one[1]), outside=args.manager_outside)
        print(json.dumps({"cpu": cpu, "ok": bool(ok)}))
        return 0

    def ints(text: str) -> list[int]:
        return [int(x) for x in text.split(",") if x]

    if args.fresh_process:
        return _main_fresh(args, ints)
    return _main_inprocess(args, ints)


def _main_fresh(args, ints) -> int:
    jobs = [("muddy", n) for n in ints(args.muddy)] + [("drinking", n) for n in ints(args.drinking)]
    jobs += [("dining", n) for n in ints(args.dining)] + [("sum-product (SMCDEL formula)", 100)]
    if args.smcdel_bin:
        return _main_fresh_peer(args, jobs)
    where = "the CLI's own reported seconds" if args.cli else "the API call"
    cols = ("puzzle", "N", "right answer", "delkit CPU s (min)", "delkit CPU s (median)",
            "SMCDEL CPU s (recorded earlier, not this run)", "ratio (min)", "ratio (median)", "processes", "load")
    md = ["| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)]
    table = Table(title=f"delkit symbolic vs SMCDEL: fresh process per run, {where} (CPU seconds)")
    for col in cols:
        table.add_column(col, justify="right")
    mine: list[tuple[int, float]] = []
    for name, n, lo, med, ok, count, load in fresh_rows(jobs, args.repeat, args.cli, args.timeout):
        ref = SMCDEL.get((name, n))
        if lo is None:
            cells = (name, str(n), "—", f"> {args.timeout:.0f} s", "—", f"{ref:.4g}" if ref else "—", "—", "—",
                     "0", f"{load:.1f}")
        else:
            cells = (name, str(n), "yes" if ok else "NO", f"{lo:.4f}", f"{med:.4f}", f"{ref:.4g}" if ref else "—",
                     f"{lo / ref:.2f}" if ref else "—", f"{med / ref:.2f}" if ref else "—", str(count),
                     f"{load:.1f}")
            if name == "muddy":
                mine.append((n, lo))
        table.add_row(*cells)
        md.append("| " + " | ".join(cells) + " |")
    if args.markdown:
        print("\n".join(md))
    else:
        Console().print(table)
    _growth(mine)
    return 0


_SMCDEL_ARGS = {"muddy": lambda n: ["muddy", str(n)], "drinking": lambda n: ["drinking", str(n)],
                "dining": lambda n: ["dining", str(n)], "sum-product (SMCDEL formula)": lambda n: ["sap"]}


def _spawn_smcdel(binary: str, name: str, n: int, timeout: float, warm: bool) -> tuple[float, bool] | None:
    """One fresh SMCDEL process (bench/peers/smcdel/SmcdelBench.hs): its getCPUTime seconds around structure +
    formula + evaluation and whether its answer was right; None when it ran out of ``timeout`` CPU seconds."""
    import json
    import subprocess

    cmd = [binary, *(["--warm"] if warm else []), *_SMCDEL_ARGS[name](n)]
    try:
        proc = subprocess.run(cmd, capture_output=True, text=True, timeout=_WALL_FACTOR * timeout)
    except subprocess.TimeoutExpired:
        return None
    if proc.returncode < 0:  # killed
        return None
    try:
        if proc.returncode != 0:
            raise ValueError(f"exit status {proc.returncode}: {proc.stderr.strip()[-300:]}")
        data = json.loads(proc.stdout.strip().splitlines()[-1])
        return float(data["cpu"]), bool(data["ok"])
    except (ValueError, KeyError, IndexError, TypeError) as e:
        print(f"bench/symbolic.py: --smcdel-bin {binary}: `{' '.join(cmd)}` did not print SMCDEL's JSON line "
              f"({e}); build bench/peers/smcdel/SmcdelBench.hs as its README says", file=sys.stderr)
        raise SystemExit(2) from None


def fresh_rows_peer(jobs: list[tuple[str, int]], repeat: int, cli: bool, timeout: float, binary: str,
                    protocols: tuple[bool, ...]):
    """Like :func:`fresh_rows`, with SMCDEL beside delkit: round r runs, for every row and every protocol
    (False: managers inside the clock, True: outside), one delkit process and one SMCDEL process; which goes
    first alternates from round to round. Yields name, N, {(side, outside): (min, median, runs)}, ok, load range."""
    import statistics

    sides = [(side, outside) for outside in protocols for side in ("delkit", "smcdel")]
    times = {(j, side): [] for j in jobs for side in sides}
    oks = dict.fromkeys(jobs, True)
    dead: set = set()
    loads: dict[tuple[str, int], list[float]] = {j: [] for j in jobs}
    for rnd in range(repeat):
        for job in jobs:
            for side in sides if rnd % 2 == 0 else sides[::-1]:
                if (job, side) in dead:
                    continue
                who, outside = side
                got = (_spawn(*job, cli=cli, timeout=timeout, outside=outside) if who == "delkit" else
                       _spawn_smcdel(binary, *job, timeout=timeout, warm=outside))
                loads[job].append(os.getloadavg()[0])
                if got is None:
                    dead.add((job, side))
                    continue
                times[job, side].append(got[0])
                oks[job] = oks[job] and bool(got[1])
    for job in jobs:
        stats = {side: (min(ts), statistics.median(ts), len(ts)) if (ts := times[job, side]) else None
                 for side in sides}
        yield (*job, stats, oks[job] and all(stats.values()), (min(loads[job]), max(loads[job])))


def _main_fresh_peer(args, jobs: list[tuple[str, int]]) -> int:
    """The --fresh-process tables with a same-run SMCDEL column (--smcdel-bin): one per manager protocol."""
    if not (os.path.isfile(args.smcdel_bin) and os.access(args.smcdel_bin, os.X_OK)):
        print(f"bench/symbolic.py: --smcdel-bin {args.smcdel_bin}: no such executable; build it with "
              "bench/peers/smcdel/build.sh (see bench/peers/smcdel/README.md)", file=sys.stderr)
        return 2
    if args.cli and args.managers != "inside":
        print("bench/symbolic.py: --cli creates the manager inside the command's clock; use --managers inside",
              file=sys.stderr)
        return 2
    protocols = {"inside": (False,), "outside": (True,), "both": (False, True)}[args.managers]
    where = "the CLI's own reported seconds" if args.cli else "the API call"
    cols = ["puzzle", "N", "right answer (both)", "delkit s (min)", "delkit s (median)", "SMCDEL s (min)",
            "SMCDEL s (median)", "ratio (min)", "ratio (median)", "processes each", "load (1-min, range)"]
    over = f"> {args.timeout:.0f} s"
    tables: dict[bool, list[list[str]]] = {p: [] for p in protocols}
    curves = {p: {"delkit": [], "SMCDEL": []} for p in protocols}
    for name, n, stats, ok, (lo_load, hi_load) in fresh_rows_peer(jobs, args.repeat, args.cli, args.timeout,
                                                                   args.smcdel_bin, protocols):
        for outside in protocols:
            mine, peer = stats["delkit", outside], stats["smcdel", outside]
            tables[outside].append([
                name, str(n), "yes" if ok else "NO",
                f"{mine[0]:.4f}" if mine else over, f"{mine[1]:.4f}" if mine else "—",
                f"{peer[0]:.4f}" if peer else over, f"{peer[1]:.4f}" if peer else "—",
                f"{mine[0] / peer[0]:.2f}" if mine and peer else "—",
                f"{mine[1] / peer[1]:.2f}" if mine and peer else "—",
                f"{mine[2] if mine else 0}/{peer[2] if peer else 0}", f"{lo_load:.1f}–{hi_load:.1f}"])
            if name == "muddy":
                for side, got in (("delkit", mine), ("SMCDEL", peer)):
                    if got:
                        curves[outside][side].append((n, got[0]))
    for outside in protocols:
        title = (f"delkit symbolic vs SMCDEL, same run, BDD managers created {'before' if outside else 'inside'} "
                 f"the clock: fresh process each, alternating, {where} (CPU seconds)")
        out = tables[outside]
        if args.markdown:
            print(f"\n{title}\n")
            print("\n".join("| " + " | ".join(row) + " |" for row in [cols, ["---"] * len(cols), *out]))
        else:
            table = Table(*cols, title=title)
            for row in out:
                table.add_row(*row)
            Console().print(table)
        curve = curves[outside]
        both = {n for n, _ in curve["delkit"]} & {n for n, _ in curve["SMCDEL"]}
        for lo, hi in ((100, 200), (0, math.inf)):
            fits = {side: [(n, t) for n, t in pts if lo <= n <= hi and n in both] for side, pts in curve.items()}
            if len(fits["delkit"]) >= 2:
                print(f"\nmuddy growth (min) on N = {', '.join(str(n) for n, _ in fits['delkit'])}: "
                      + ", ".join(f"{side} N^{_fit(pts):.2f}" for side, pts in fits.items()))
    return 0


def _growth(mine: list[tuple[int, float]]) -> None:
    """Least-squares exponents of t ∝ N^k on log-log: over N = 100…200 (delkit beside SMCDEL's) and over all
    muddy rows measured."""
    big = [(n, t) for n, t in mine if 100 <= n <= 200 and ("muddy", n) in SMCDEL]
    if len(big) >= 2:
        ref = [(n, SMCDEL[("muddy", n)]) for n, _ in big]
        print(f"muddy growth on N = {', '.join(str(n) for n, _ in big)}: delkit N^{_fit(big):.2f}, "
              f"SMCDEL N^{_fit(ref):.2f}")
    if len(mine) >= 2:
        print(f"muddy growth on N = {', '.join(str(n) for n, _ in mine)}: delkit N^{_fit(mine):.2f}")


def _main_inprocess(args, ints) -> int:
    muddy_symbolic(3, 3)  # warm up
    table = Table(title="delkit symbolic vs SMCDEL (in-process CPU seconds; min of repeats)")
    cols = ("puzzle", "N", "right answer", "delkit CPU s", "delkit wall s", "SMCDEL CPU s", "ratio", "load")
    for col in cols:
        table.add_column(col, justify="right")
    md = ["| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)]
    every: list[tuple[int, float]] = []
    for name, n, cpu, wall, ok, ref in rows(ints(args.muddy), ints(args.drinking), ints(args.dining), args.repeat):
        ratio = f"{cpu / ref:.2f}" if ref else "—"
        cells = (name, str(n), "yes" if ok else "NO", f"{cpu:.4f}", f"{wall:.4f}",
                 f"{ref:.4g}" if ref else "—", ratio, f"{os.getloadavg()[0]:.1f}")
        table.add_row(*cells)
        md.append("| " + " | ".join(cells) + " |")
        if name == "muddy":
            every.append((n, cpu))
    if args.markdown:
        print("\n".join(md))
    else:
        Console().print(table)
    _growth(every)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
