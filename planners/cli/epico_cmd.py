"""``delkit epico``: the e-PICO pipeline (Soldà, Fabiano, Dovier) — generate an instance, solve it to a primitive plan,
print Tables 1 and 2. Heavy imports stay inside the commands."""

from __future__ import annotations

import json
from pathlib import Path

import typer

_OWNER_HELP = ("ROBOT: a robot whose colours are unknown fluents (repeatable). Default: both robots — the "
               "paper's reading (§4.4), 4^n worlds for n colours; --owner robot1 is the reduced reading "
               "(robot1's colours only, 2^n worlds)")
_SENSING_HELP = "table: one sense_table per robot (default); color: one sense_color per robot and colour"
_TAKES_HELP = ("seen: any robot takes from the shared table, both see it (default); handover: the other robot "
               "takes, the owner only partially observes it (the §5 prose macro take_and_announce)")
_SYMMETRIC_HELP = "accepted for old scripts: both robots' colours, which is the default now"


def _reading(owner: list[str], sensing: str, takes: str, symmetric: bool = False):
    """The Reading of the CLI options; ``--owner`` values with ``=`` (BLOCK=ROBOT) are not robots (solve
    --world) and are left out here."""
    from planners.epico import ROBOTS, EpicoError, reading_of

    robots = [o for o in owner if "=" not in o]
    bad = [o for o in robots if o not in ROBOTS]
    if bad:
        raise EpicoError(f"--owner {bad[0]!r}: a robot ({', '.join(ROBOTS)}), or BLOCK=ROBOT with --world")
    if symmetric and robots and tuple(sorted(robots)) != ROBOTS:
        raise EpicoError("--symmetric (both robots' colours) contradicts --owner " + " ".join(robots))
    return reading_of(tuple(robots) or None, sensing=sensing, takes=takes)


def register(app: typer.Typer) -> None:
    """Attach the ``epico`` sub-app."""
    from delkit.cli.plugins import group

    sub = group(app, "epico", help="e-PICO (Soldà, Fabiano, Dovier): epistemic plan → macros flattened → "
                                   "classical breakdown → primitive plan for the arms.")

    @sub.command("generate")
    def generate_cmd(goal: str = typer.Option("alpha", "--goal", help="alpha, beta, gamma or delta"),
                     colors: int = typer.Option(2, "--colors", help="number of colours, 1..8"),
                     seed: int | None = typer.Option(None, "--seed",
                                                     help="random layout (default: the layout of the e-PICO paper)"),
                     owner: list[str] = typer.Option([], "--owner", help=_OWNER_HELP),
                     sensing: str = typer.Option("table", "--sensing", help=_SENSING_HELP),
                     takes: str = typer.Option("seen", "--takes", help=_TAKES_HELP),
                     symmetric: bool = typer.Option(False, "--symmetric", help=_SYMMETRIC_HELP),
                     out: Path | None = typer.Option(None, "--out", help="output directory (default: print "
                                                     "the problem, or everything with --json)"),
                     as_json: bool = typer.Option(False, "--json", help="print one JSON object")) -> None:
        """Write domain.epddl, problem.epddl (epistemic level), classical.json and world.json (same layout)."""
        from planners.epico import generate

        inst = generate(goal, colors, seed, reading=_reading(owner, sensing, takes, symmetric))
        if out is None:
            if as_json:
                typer.echo(json.dumps({**inst.to_json(), "problem": inst.problem_text}))
            else:
                typer.echo(inst.problem_text, nl=False)
            return
        out.mkdir(parents=True, exist_ok=True)
        (out / "domain.epddl").write_text(inst.domain_text)
        (out / "problem.epddl").write_text(inst.problem_text)
        (out / "classical.json").write_text(json.dumps(inst.classical_init.to_json(), indent=2) + "\n")
        (out / "world.json").write_text(json.dumps(inst.layout.to_world(), indent=2) + "\n")
        files = [str(out / f) for f in ("domain.epddl", "problem.epddl", "classical.json", "world.json")]
        if as_json:
            typer.echo(json.dumps({"files": files, **inst.to_json()}))
        else:
            typer.echo(f"{inst.goal} with {colors} colour(s), {inst.reading.describe()}: " + ", ".join(files))

    @sub.command("solve")
    def solve_cmd(goal: str = typer.Option("alpha", "--goal", help="alpha, beta, gamma or delta"),
                  colors: int = typer.Option(2, "--colors", help="number of colours, 1..8"),
                  owner: list[str] = typer.Option([], "--owner", help=_OWNER_HELP + "; with --world also "
                                                  "BLOCK=ROBOT: whose block lies on the shared table"),
                  sensing: str = typer.Option("table", "--sensing", help=_SENSING_HELP),
                  takes: str = typer.Option("seen", "--takes", help=_TAKES_HELP),
                  symmetric: bool = typer.Option(False, "--symmetric", help=_SYMMETRIC_HELP),
                  macros: bool = typer.Option(True, "--macros/--no-macros", help="offer the macros to the planner"),
                  timeout: float = typer.Option(110.0, "--timeout", help="wall-clock limit in seconds from the "
                                                "start of the process (0 or inf: none); reaching it is exit 3"),
                  classical: str = typer.Option("bfs", "--classical", help="classical engine: bfs or clingo"),
                  world: Path | None = typer.Option(None, "--world", help="start from this layout: a world JSON "
                                                    "or a plan/1 JSON (its world), e.g. observed after a fault, "
                                                    "or `epico generate --seed S --out DIR`'s DIR/world.json"),
                  block_owner: list[str] = typer.Option([], "--block-owner", help="BLOCK=ROBOT: whose block "
                                                        "lies on the shared table of --world (repeatable)"),
                  known: list[str] = typer.Option([], "--known", help="ROBOT:COLOUR,COLOUR — colours whose "
                                                  "presence the robot already knows (repeatable)"),
                  perspective: str = typer.Option("external", "--perspective", help="external: an external "
                                                  "planner that knows the actual world (the e-PICO paper's "
                                                  "reading, default); ROBOT: a plan that works in every world "
                                                  "ROBOT considers possible, each step known applicable by the "
                                                  "robot doing it (implicit coordination, Engesser et al. 2017)"),
                  out: Path | None = typer.Option(None, "--out", help="write the primitive plan (plan/1 JSON)"),
                  as_json: bool = typer.Option(False, "--json", help="print one JSON object")) -> None:
        """Solve one instance: epistemic plan, flattened plan, primitive plan, times, classical calls."""
        from planners.epico import EpicoError, Layout, generate
        from planners.hierarchy import EpicoLimits, solve

        if classical not in ("bfs", "clingo"):
            raise EpicoError(f"--classical {classical!r}: use bfs or clingo")
        from planners.epico import ROBOTS

        if perspective not in ("external", *ROBOTS):
            raise EpicoError(f"--perspective {perspective!r}: use external (the e-PICO paper's reading) or a "
                             f"robot ({', '.join(ROBOTS)})")
        if classical == "clingo":  # say so before the epistemic search, not after it
            from delkit.errors import require_extra

            require_extra("asp", "clingo", what="--classical clingo")
        from delkit.paths import read_input, refuse_overwrite_input

        refuse_overwrite_input([out], [world], option="--out")  # before the search: the plan never replaces --world
        layout = None
        if world is not None:
            try:
                obj = json.loads(read_input(world, "world JSON"))
            except (OSError, UnicodeDecodeError, json.JSONDecodeError) as exc:
                raise EpicoError(f"{world}: cannot read a world JSON ({exc})") from None
            obj = obj.get("world", obj) if isinstance(obj, dict) else obj
            pairs = [*block_owner, *(o for o in owner if "=" in o)]
            owners = dict(o.split("=", 1) for o in pairs if "=" in o)
            if len(owners) != len(pairs) or any(not k.strip() or not v.strip() for k, v in owners.items()):
                raise EpicoError(f"--block-owner takes BLOCK=ROBOT, e.g. --block-owner red_2=robot2; got {pairs}")
            try:
                layout = Layout.from_world(obj, owners)
            except EpicoError as exc:
                raise EpicoError(f"{world}: {exc}") from None
        elif block_owner or any("=" in o for o in owner):
            raise EpicoError("--block-owner BLOCK=ROBOT (or --owner BLOCK=ROBOT) says whose block lies on the "
                             "shared table of --world; give --world too")
        knows: dict[str, list[str]] = {}
        for k in known:
            robot, sep, cols = k.partition(":")
            if not sep or not cols:
                raise EpicoError(f"--known takes ROBOT:COLOUR,COLOUR, got {k!r}")
            knows.setdefault(robot, []).extend(c for c in cols.split(",") if c)
        from delkit.resources import deadline, parse_timeout, time_left, time_limit

        limit = parse_timeout(timeout)
        with deadline(limit, f"epico solve --goal {goal} --colors {colors}"):
            try:
                sol = solve(generate(goal, colors, layout=layout, reading=_reading(owner, sensing, takes, symmetric)),
                            macros=macros, known=knows or None,
                            limits=EpicoLimits(timeout=time_left(), classical=classical), perspective=perspective)
            except EpicoError as exc:
                if limit is not None and "time limit" in str(exc):
                    raise time_limit() from None  # the search stopped at the deadline: exit 3 like every limit
                raise
        if out is not None:
            sol.write(out)
        if as_json:
            typer.echo(json.dumps(sol.to_json()))
            return
        t = sol.times
        typer.echo(sol.instance.reading.describe())
        typer.echo("plan reading: " + sol.search["perspective_meaning"])
        typer.echo(f"{sol.instance.goal}, {colors} colour(s), macros {'on' if macros else 'off'}: initial state "
                   f"{t['initial']:.3f} s, epistemic search {t['epistemic']:.3f} s, classical {t['classical']:.4f} s "
                   f"({sol.classical_calls} call(s))")
        typer.echo("epistemic plan:  " + ", ".join(sol.epistemic_plan))
        typer.echo("flattened plan:  " + ", ".join(sol.flat_plan))
        typer.echo("primitive plan:")
        for rec in sol.tasks:
            typer.echo(f"  {rec.task}")
            for a in rec.actions:
                args = ", ".join(map(str, a.get("args", [])))
                typer.echo(f"    {a['robot']}: {a['action']}({args})")
        if out is not None:
            typer.echo(f"wrote {out}")

    @sub.command("macros")
    def macros_cmd(colors: int = typer.Option(2, "--colors", help="number of colours, 1..8"),
                   handwritten: Path | None = typer.Option(None, "--handwritten", help="a hand-written macro "
                                                           "(:action ...) to check (default: Listing 4 of the e-PICO "
                                                           "paper)"),
                   as_json: bool = typer.Option(False, "--json", help="print one JSON object")) -> None:
        """Prove every macro equal to its sequence (z3) and check a hand-written macro against the composition."""
        from planners.hierarchy import macro_report

        rep = macro_report(colors, str(handwritten) if handwritten else None)
        if as_json:
            typer.echo(json.dumps(rep))
        else:
            for p in rep["proofs"]:
                verdict = "= its sequence (z3)" if p["equal"] else "DIFFERS: " + "; ".join(p["problems"])
                typer.echo(f"{p['macro']}: {verdict}; {p['obligations']} obligations, {p['events']} events, "
                           f"{p['state']}")
            hw = rep["handwritten_check"]
            if hw["consistent"]:
                typer.echo(f"{rep['handwritten']}: no difference found in {hw['states_checked']} states")
            else:
                cex = hw["counterexample"]
                typer.echo(f"{rep['handwritten']}: INCONSISTENT with the composition — after "
                           f"{cex['plan'] or 'nothing'}: {cex['difference']}")
                for line in hw["symbolic"]:
                    typer.echo(f"  symbolic: {line}")
        # exit 1 when a macro differs from its sequence, or the user's --handwritten macro is inconsistent (the
        # default, the seed's Listing 4, is inconsistent on purpose: its counterexample is the seed's point)
        ok = rep["all_equal"] and (handwritten is None or rep["handwritten_check"]["consistent"])
        raise typer.Exit(0 if ok else 1)

    @sub.command("table")
    def table_cmd(repeat: int = typer.Option(1, "--repeat", min=1, help="runs per cell (mean)"),
                  colors: str = typer.Option("1,2,3,4", "--colors", help="comma-separated colour counts"),
                  timeout: float = typer.Option(110.0, "--timeout", help="limit per run, seconds (0 or inf: "
                                                "none); a run over it is a TO cell"),
                  total: float = typer.Option(0.0, "--total-timeout", help="wall-clock limit of the whole table "
                                              "from the start of the process (0 or inf: none); reaching it is "
                                              "exit 3"),
                  owner: list[str] = typer.Option([], "--owner", help=_OWNER_HELP),
                  sensing: str = typer.Option("table", "--sensing", help=_SENSING_HELP),
                  takes: str = typer.Option("seen", "--takes", help=_TAKES_HELP),
                  symmetric: bool = typer.Option(False, "--symmetric", help=_SYMMETRIC_HELP),
                  search: str = typer.Option("bfs", "--search", help="bfs: breadth-first with duplicate "
                                             "detection (default); tree: without it, as the e-PICO paper's "
                                             "planner (EFP) searches by default"),
                  as_json: bool = typer.Option(False, "--json", help="print one JSON object")) -> None:
        """Tables 1 and 2: every (goal, colours) cell, macros off and on, beside the paper's numbers. Default:
        the paper's reading (both robots ignorant of their own colours); the reading is printed."""
        from planners.epico import GOALS, EpicoError
        from planners.hierarchy import HANDOVER_SIDES, TABLE_SIDES, table_cell

        if search not in ("bfs", "tree"):
            raise EpicoError(f"--search {search!r}: use bfs or tree")
        rd = _reading(owner, sensing, takes, symmetric)
        sides = HANDOVER_SIDES if rd.takes == "handover" else TABLE_SIDES

        try:
            cols = [int(c) for c in colors.split(",") if c.strip()]
        except ValueError:
            raise EpicoError(f"--colors {colors!r}: a comma-separated list of numbers, e.g. 1,2,3,4") from None
        if not cols:
            raise EpicoError(f"--colors {colors!r} names no colour count; e.g. --colors 1,2,3,4")
        from delkit.resources import deadline, parse_timeout

        per_run, limit = parse_timeout(timeout), parse_timeout(total, "--total-timeout")
        worst = 2.0 * repeat * len(GOALS) * len(cols) * (per_run if per_run is not None else float("inf"))
        if limit is None and worst > 86400.0:
            raise EpicoError(f"epico table: {2 * repeat * len(GOALS) * len(cols)} runs of up to "
                             f"{'no limit' if per_run is None else f'{per_run:g} s'} each could take more than a "
                             f"day; bound the whole table with --total-timeout SECONDS, or use a smaller --repeat")
        from delkit.progress import progress
        from planners.epico import generate
        from planners.hierarchy import solve

        cells = []
        with deadline(limit, "epico table", "--total-timeout"):
            solve(generate("alpha", 1, reading=rd))  # warm-up: imports and caches are not part of any cell's time
            with progress(quiet=as_json) as prog:
                job = prog.add_task("e-PICO table", total=len(GOALS) * len(cols))
                for g in GOALS:
                    for n in cols:
                        cells.append(table_cell(g, n, repeat=repeat, timeout=per_run, reading=rd, sides=sides,
                                                search=search))
                        prog.advance(job)
        if as_json:
            typer.echo(json.dumps({"reading": rd.to_json(), "description": rd.describe(), "cells": cells,
                                   "repeat": repeat, "search": search}))
            return
        if search == "tree":
            typer.echo("search: tree (breadth-first without duplicate detection, as the e-PICO paper's planner EFP "
                       "by default); exp = tree nodes expanded")
        typer.echo(format_tables(cells, rd))


LEGEND = """Legend: reading = which model (paper: both robots ignorant of their own colours, as §4.4 states;
  owner robot1: only robot1's colours are fluents; per-colour sensing: one sense_color per colour).
  off / on = macros offered to the planner: none / the domain's macros (pspb_and_announce, Listing 4 as
  Definition 4.1 builds it; with hand-over takes also take_and_announce, the §5 prose macro).
  CPU s = CPU seconds of one solve (initial state + epistemic search + breakdown into primitive actions +
  plan check), mean of the repeats. init = CPU seconds of the initial state alone (grounding, Kripke model,
  compact form). exp = states expanded by the breadth-first search; br = successors generated per expanded
  state (branching factor). off/on = CPU ratio (> 1: macros help). paper = the e-PICO paper's Table 1, seconds
  (Intel i7-8565U, EFP; search from a given initial state); paper init = the paper's initial-state seconds
  (§5). echosys = the peer implementation (PyPI echosys) on a machine like ours, seconds.
  Table 2: cpu ms = CPU milliseconds of all classical-planner calls of a solve; calls = their number;
  max ms = the slowest call; paper s / paper calls = the paper's Table 2.
  ND = not defined (γ, δ need two colours); TO = no plan within the time limit (110 s, as the paper)."""


def format_tables(cells: list[dict], reading=None) -> str:
    """Tables 1 and 2 as text for one reading, delkit beside the paper (and the peer where measured)."""
    from planners.hierarchy import PEER_TABLE1, SEED_INITIAL, SEED_TABLE1, SEED_TABLE2

    def f(x):
        return "TO" if x is None else f"{x:.3f}"

    sides = cells[0].get("sides", ["off", "on"]) if cells else ["off", "on"]
    head = [reading.describe() if reading is not None else f"reading: {cells[0].get('reading', 'paper')}"
            if cells else "", "",
            "Table 1: CPU seconds to a plan, per macro side; states expanded (exp), branching (br)"]
    side_h = " ".join(f"{s + ' CPU s':>10} {'exp':>5} {'br':>5}" for s in sides)
    lines = head + [f"{'goal':6} {'col':>3} | {side_h} {sides[0] + '/' + sides[-1]:>7} | {'init':>7} "
                    f"{'paper init':>10} | {'paper no':>8} {'paper yes':>9} | {'echosys no':>10} {'yes':>7}"]
    for c in cells:
        g, n = c["goal"], c["colors"]
        if c["status"] == "ND":
            lines.append(f"{g:6} {n:>3} | " + " ".join(f"{'ND':>10} {'':>5} {'':>5}" for _ in sides))
            continue
        parts = []
        for s in sides:
            d = c.get(s, {})
            parts.append(f"{f(d['cpu']):>10} {d['expanded']:>5} {d['branching']:>5.1f}" if d.get("status") == "ok"
                         else f"{'TO':>10} {'':>5} {'':>5}")
        sn, sy = SEED_TABLE1.get(g, {}).get(n, ("-", "-"))
        pn, py = PEER_TABLE1.get(g, {}).get(n, ("-", "-"))
        ratio = f"{c['ratio']:.2f}" if c.get("ratio") else "-"
        last = c.get(sides[-1], {})
        init = f"{last['initial_cpu']:.4f}" if last.get("status") == "ok" else "-"
        lines.append(f"{g:6} {n:>3} | {' '.join(parts)} {ratio:>7} | {init:>7} {SEED_INITIAL.get(n, '-'):>10} | "
                     f"{sn if isinstance(sn, str) else f(sn):>8} {sy if isinstance(sy, str) else f(sy):>9} | "
                     f"{pn if isinstance(pn, str) else f(pn):>10} {py if isinstance(py, str) else f(py):>7}")
    last_side = sides[-1]
    lines += ["", f"Table 2: classical breakdown (macros {last_side}): cumulative CPU ms, calls, slowest call (CPU "
              "ms); paper beside (seconds, calls)",
              f"{'goal':6} {'col':>3} | {'cpu ms':>8} {'calls':>5} {'max ms':>7} | {'paper s':>7} {'paper calls':>11}"]
    for c in cells:
        g, n = c["goal"], c["colors"]
        on = c.get(last_side, {})
        seed = SEED_TABLE2.get(g, {}).get(n, "ND" if c["status"] == "ND" else "-")
        ss = seed if isinstance(seed, str) else ("TO", "TO") if seed is None else (f"{seed[0]:.3f}", seed[1])
        if on.get("status") != "ok":
            first = ss[0] if isinstance(ss, tuple) else ss
            lines.append(f"{g:6} {n:>3} | {c['status']:>8} {'':>5} {'':>7} | {first:>7}")
            continue
        lines.append(f"{g:6} {n:>3} | {on.get('classical_cpu', on['classical']) * 1000:8.2f} {on['calls']:>5} "
                     f"{on.get('max_call_cpu', 0.0) * 1000:7.2f} | "
                     f"{ss[0] if isinstance(ss, tuple) else ss:>7} {ss[1] if isinstance(ss, tuple) else '':>11}")
    return "\n".join(lines + ["", LEGEND])
