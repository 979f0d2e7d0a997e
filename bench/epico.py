"""Benchmark: e-PICO Tables 1 and 2 (seed 004) for three readings side by side — the paper's (both robots
ignorant of their own colours), owner robot1 (robot1's colours only) and per-colour sensing — and the
hand-over reading for the §5 prose macro; delkit beside the seed and the peer (echosys).

Timed region per run (CPU, mean of --repeat runs): building the grounded task and its initial state from
the E-PDDL texts (also reported alone), the epistemic search (BFS, optimal), flattening and the classical
breakdown of every ontic task, and the plan/1 check. The seed's Table 1 times the search from a given
initial state (its initial states are reported apart, and here beside ours). Run:

    PYTHONPATH=. python bench/epico.py [--repeat 5] [--colors 1,2,3,4] [--reading paper ...] [--json]
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


READINGS = (("paper", {}), ("owner robot1", {"owners": ("robot1",)}), ("per-colour sensing", {"sensing": "color"}))


def _fmt(x) -> str:
    return "TO" if x is None else x if isinstance(x, str) else f"{x:.3f}"


def side_by_side(by_reading: dict[str, list[dict]]) -> str:
    """Table 1 for the readings side by side: per reading and macro side CPU seconds and states expanded;
    the paper's initial-state time and Table 1 beside."""
    from planners.hierarchy import SEED_INITIAL, SEED_TABLE1

    names = list(by_reading)
    cells = {name: {(c["goal"], c["colors"]): c for c in cs} for name, cs in by_reading.items()}
    keys = [(c["goal"], c["colors"]) for c in by_reading[names[0]]]
    w = 23
    head1 = f"{'':10} | " + " | ".join(f"{n:^{w}}" for n in names) + f" | {'paper (seed 004)':^27}"
    head2 = (f"{'goal col':10} | " + " | ".join(f"{'off s':>6} {'exp':>4} {'on s':>6} {'exp':>4}" for _ in names)
             + f" | {'no':>7} {'yes':>7} {'init s':>7}")
    init_row = []
    lines = [head1, head2]
    for g, n in keys:
        parts = []
        for name in names:
            c = cells[name].get((g, n), {})
            if c.get("status") == "ND":
                parts.append(f"{'ND':>{w}}")
                continue
            sub = []
            for side in ("off", "on"):
                d = c.get(side, {})
                sub.append(f"{d['cpu']:6.3f} {d['expanded']:>4}" if d.get("status") == "ok" else f"{'TO':>6} {'':>4}")
            parts.append(" ".join(sub))
        sn, sy = SEED_TABLE1.get(g, {}).get(n, ("ND", "ND") if g in ("gamma", "delta") and n < 2 else ("-", "-"))
        lines.append(f"{g:6} {n:>3} | " + " | ".join(parts) +
                     f" | {_fmt(sn):>7} {_fmt(sy):>7} {SEED_INITIAL.get(n, '-'):>7}")
        init_row.append(n)
    lines.append("")
    lines.append("initial state alone, CPU s (grounding + Kripke model + compact form; macros on), per reading:")
    for name in names:
        per = {}
        for c in by_reading[name]:
            on = c.get("on", {})
            if on.get("status") == "ok":
                per[c["colors"]] = max(per.get(c["colors"], 0.0), on["initial_cpu"])
        lines.append(f"  {name:20} " + ", ".join(f"{k} col {v:.4f}" for k, v in sorted(per.items()))
                     + "   (paper: " + ", ".join(f"{k} col {v}" for k, v in SEED_INITIAL.items()) + ")")
    return "\n".join(lines)


def handover_table(cells: list[dict]) -> str:
    """The hand-over reading: no macro, Listing 4's pspb_and_announce, the §5 prose take_and_announce, both."""
    sides = ["off", "pspb", "take", "on"]
    lines = ["hand-over reading (the other robot takes; the owner only partially observes the take): CPU s / "
             "states expanded / branching / epistemic plan length",
             f"{'goal col':10} | " + " | ".join(f"{s:^22}" for s in sides)]
    for c in cells:
        if c["status"] == "ND":
            lines.append(f"{c['goal']:6} {c['colors']:>3} | ND")
            continue
        parts = []
        for s in sides:
            d = c.get(s, {})
            parts.append(f"{d['cpu']:6.3f} {d['expanded']:>4} {d['branching']:4.1f} {len(d['plan']):>3}"
                         if d.get("status") == "ok" else f"{'TO':>22}")
        lines.append(f"{c['goal']:6} {c['colors']:>3} | " + " | ".join(parts))
    lines.append("sides: off = no macro; pspb = pspb_and_announce (Table 1's caption, Listing 4 as Definition 4.1 "
                 "builds it); take = take_and_announce (§5 prose); on = both")
    return "\n".join(lines)


STUDY_READINGS = (("paper", {}), ("hand-over", {"takes": "handover"}))


def macro_study(colors: list[int], tree_colors: list[int], repeat: int, timeout: float, tree_timeout: float,
                readings: list[str]) -> list[dict]:
    """Macros off / on in the same run, per reading (paper's, hand-over), goal and colour count, for two
    searches over the same states and successors: delkit's BFS (duplicate detection) and a tree BFS (none: the
    e-PICO paper's planner, EFP, checks visited states only on request). Per side: CPU s of a whole solve,
    states expanded, generated, branching, epistemic plan length. One row per cell on stderr as it finishes."""
    from planners.epico import GOALS, reading_of
    from planners.hierarchy import table_cell

    rows = []
    for name, kw in STUDY_READINGS:
        if name not in readings:
            continue
        rd = reading_of(**kw)
        for n in colors:
            for g in GOALS:
                row = {"reading": name, "goal": g, "colors": n}
                row["bfs"] = table_cell(g, n, repeat=repeat if n <= 4 else 1, timeout=timeout, reading=rd)
                if n in tree_colors:
                    row["tree"] = table_cell(g, n, repeat=repeat, timeout=tree_timeout, reading=rd, search="tree")
                rows.append(row)
                print(json.dumps(row), file=sys.stderr, flush=True)
    return rows


def _side(d: dict) -> str:
    if d.get("status") != "ok":
        return f"{'TO':>8} {'':>6} {'':>7} {'':>5} {'':>3}"
    return f"{d['cpu']:8.3f} {d['expanded']:>6} {d['generated']:>7} {d['branching']:5.1f} {len(d['plan']):>3}"


def study_table(rows: list[dict]) -> str:
    """The macro study as text: per search, off and on sides, the CPU ratio and the generated-states ratio."""
    lines = []
    for search in ("bfs", "tree"):
        sel = [r for r in rows if search in r]
        if not sel:
            continue
        what = ("duplicate detection, delkit default" if search == "bfs"
                else "no duplicate detection, as EFP by default")
        side_h = f"{'CPU s':>8} {'exp':>6} {'gen':>7} {'br':>5} {'len':>3}"
        lines += ["", f"search: {search} ({what}); sides off | on: CPU s, expanded, generated, branching, length",
                  f"{'reading':9} {'goal':6} {'col':>3} | {side_h} | {side_h} | {'CPU off/on':>10} {'gen off/on':>10}"]
        for r in sel:
            c = r[search]
            if c["status"] == "ND":
                lines.append(f"{r['reading']:9} {r['goal']:6} {r['colors']:>3} | ND")
                continue
            off, on = c.get("off", {}), c.get("on", {})
            both = off.get("status") == on.get("status") == "ok"
            ratio = f"{off['cpu'] / on['cpu']:10.2f}" if both else f"{'-':>10}"
            gen = f"{off['generated'] / max(on['generated'], 1):10.2f}" if both else f"{'-':>10}"
            lines.append(f"{r['reading']:9} {r['goal']:6} {r['colors']:>3} | {_side(off)} | {_side(on)} | "
                         f"{ratio} {gen}")
    return "\n".join(lines)


PERSPECTIVE_CASES = (("alpha", 1, {}), ("alpha", 2, {}), ("beta", 2, {}),
                     ("alpha", 2, {"robot1": ("red", "black")}), ("beta", 2, {"robot1": ("red", "black")}),
                     ("alpha", 2, {"robot2": ("red", "black")}), ("gamma", 2, {"robot1": ("red", "black")}))


def perspectives() -> list[dict]:
    """Per instance (paper's reading, default layout, ``known`` = what a robot already knows, e.g. after
    sensing; macros off): the external planner's plan, whether it is valid from each robot's perspective
    (the first failing step), and the shortest plan from each robot's perspective with its CPU seconds."""
    import time

    from planners.epico import ROBOTS, generate
    from planners.hierarchy import epistemic_task, perspective_check, plan_from_perspective, solve

    rows = []
    for goal, n, known in PERSPECTIVE_CASES:
        inst = generate(goal, n).with_known(known)
        task, _, _ = epistemic_task(inst, macros=False)
        ext = solve(inst, macros=False)
        row = {"goal": goal, "colors": n, "known": {r: list(v) for r, v in known.items()},
               "external_plan": list(ext.epistemic_plan), "from": {}}
        for r in ROBOTS:
            chk = perspective_check(task, ext.epistemic_plan, r)
            c0 = time.process_time()
            res = plan_from_perspective(task, r, max_depth=8)
            row["from"][r] = {"external_plan_valid": chk.valid, "fails_at": None if chk.valid else chk.step + 1,
                              "plan": list(res.plan) if res.solved else None, "status": res.status,
                              "cpu": time.process_time() - c0, "expanded": res.expanded}
        rows.append(row)
    return rows


def perspective_table(rows: list[dict]) -> str:
    short = {"sense_table": "sense", "put_on_shared": "put", "announce_block_on_barrier": "ann",
             "take_from_shared": "take"}

    def sh(plan):
        if plan is None:
            return "none"
        out = []
        for a in plan:
            for k, v in short.items():
                if a.startswith(k + "_"):
                    a = v + "(" + a[len(k) + 1:].replace("robot", "r").replace("_", " ") + ")"
            out.append(a)
        return "; ".join(out) or "(empty)"

    lines = [f"{'goal':6} {'col':>3} {'known':22} | {'external plan':48} | "
             f"{'valid from r1':>13} {'r2':>6} | {'plan from robot1 (CPU s)':44} | plan from robot2 (CPU s)"]
    for r in rows:
        kn = ", ".join(f"{k}: {'+'.join(v)}" for k, v in r["known"].items()) or "nothing"
        f1, f2 = r["from"]["robot1"], r["from"]["robot2"]

        def v(f):
            return "yes" if f["external_plan_valid"] else f"no@{f['fails_at']}"

        def p(f):
            return f"{sh(f['plan']) if f['plan'] else f['status']} ({f['cpu']:.2f})"

        lines.append(f"{r['goal']:6} {r['colors']:>3} {kn:22} | {sh(r['external_plan']):48} | {v(f1):>13} "
                     f"{v(f2):>6} | {p(f1):44} | {p(f2)}")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    from planners.cli.epico_cmd import LEGEND, format_tables
    from planners.epico import GOALS, generate, reading_of
    from planners.hierarchy import HANDOVER_SIDES, solve, table_cell

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--colors", default="1,2,3,4")
    ap.add_argument("--timeout", type=float, default=110.0)
    ap.add_argument("--reading", action="append", choices=[n for n, _ in READINGS] + ["hand-over"],
                    help="only these readings (repeatable; default: all three side by side, and hand-over)")
    ap.add_argument("--symmetric", action="store_true", help=argparse.SUPPRESS)  # the default now
    ap.add_argument("--json", action="store_true")
    ap.add_argument("--classical-engines", action="store_true", help="only compare the classical engines")
    ap.add_argument("--macro-study", action="store_true", help="only the macro study: paper's and hand-over "
                    "readings, macros off/on, BFS and tree search (--colors, --tree-colors, --study-reading)")
    ap.add_argument("--tree-colors", default="1,2,3,4", help="colour counts for the tree search (macro study)")
    ap.add_argument("--tree-timeout", type=float, default=60.0, help="limit per tree-search run, seconds")
    ap.add_argument("--study-reading", action="append", choices=[n for n, _ in STUDY_READINGS],
                    help="macro study: only these readings (repeatable; default both)")
    ap.add_argument("--perspectives", action="store_true", help="only the plans from each robot's perspective "
                    "beside the external planner's")
    args = ap.parse_args(argv)
    if args.perspectives:
        rows = perspectives()
        print(json.dumps(rows) if args.json else perspective_table(rows))
        return 0
    if args.macro_study:
        solve(generate("alpha", 1))  # warm-up
        rows = macro_study([int(c) for c in args.colors.split(",")],
                           [int(c) for c in args.tree_colors.split(",") if c], args.repeat, args.timeout,
                           args.tree_timeout, args.study_reading or [n for n, _ in STUDY_READINGS])
        if args.json:
            print(json.dumps(rows))
        else:
            print(study_table(rows))
        return 0
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
    cols = [int(c) for c in args.colors.split(",")]
    wanted = args.reading or [n for n, _ in READINGS] + ["hand-over"]
    by_reading: dict[str, list[dict]] = {}
    for name, kw in READINGS:
        if name not in wanted:
            continue
        rd = reading_of(**kw)
        by_reading[name] = [table_cell(g, n, repeat=args.repeat, timeout=args.timeout, reading=rd)
                            for g in GOALS for n in cols]
        print(f"# {name}: done", file=sys.stderr, flush=True)
    hand = []
    if "hand-over" in wanted:
        hand = [table_cell(g, n, repeat=args.repeat, timeout=args.timeout, reading=reading_of(takes="handover"),
                           sides=HANDOVER_SIDES) for g in GOALS for n in cols]
        print("# hand-over: done", file=sys.stderr, flush=True)
    if args.json:
        print(json.dumps({"machine": platform.processor() or platform.machine(), "readings": by_reading,
                          "hand-over": hand}))
        return 0
    if by_reading:
        print(side_by_side(by_reading))
        for name in by_reading:
            print()
            print(format_tables(by_reading[name], reading_of(**dict(READINGS)[name])).replace("\n\n" + LEGEND, ""))
    if hand:
        print()
        print(handover_table(hand))
    print()
    print(LEGEND)
    return 0


if __name__ == "__main__":
    sys.exit(main())
