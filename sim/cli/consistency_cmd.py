"""``delkit consistency``: action consistency with inconsistent beliefs (seed 002, VERIFYAC/ENFORCEAC).

* ``delkit consistency table`` — every row of Table I (search and rescue, E = 200) beside the paper's;
* ``delkit consistency run --robots N`` — one episode of one or all algorithms.

Heavy imports (numpy, planners, sim) stay inside the commands so that ``delkit --help`` stays fast.
"""

from __future__ import annotations

import json

import typer

ALGORITHM_CHOICES = ("enforce", "baseline1", "baseline2", "all")


def _config(**kw):
    from delkit.errors import SimulationError
    from sim.sar import SARConfig

    if kw["epochs"] < 1:  # an episode without a planning step has no Not-AC rate and no mean J
        raise SimulationError(f"--epochs must be at least 1 (the paper uses 200), got {kw['epochs']}")
    robots, cells = kw.get("robots", 2), kw["width"] * kw["height"]
    if kw["width"] >= 2 and kw["height"] >= 2 and robots > cells:
        raise SimulationError(f"--robots {robots} do not fit on a {kw['width']}×{kw['height']} grid "
                              f"({cells} cells, one robot per cell); use a bigger grid or fewer robots")
    cfg = SARConfig(**kw)  # checks the ranges first
    from delkit.resources import require, sar_bytes

    require(sar_bytes(cfg.width, cfg.height, cfg.robots, cfg.epochs),
            f"a {cfg.width}×{cfg.height} grid with {cfg.robots} robots over {cfg.epochs} epochs",
            "use a smaller --width/--height or fewer --epochs")
    return cfg


def _progress(quiet: bool = False):
    from delkit.progress import progress

    return progress(quiet=quiet)


def _wide_console():
    """A stdout console at least 132 columns wide, so that tables are not squeezed when piped."""
    from rich.console import Console

    return Console(width=max(Console().width, 132))


def _fmt_paper(paper: tuple[int, int, float] | None) -> tuple[str, str, str]:
    if paper is None:
        return "–", "–", "–"
    return str(paper[0]), str(paper[1]), f"{paper[2]:.1f}"


def register(app: typer.Typer) -> None:
    """Attach ``delkit consistency {table, run}``."""
    sub = typer.Typer(help="Action consistency with inconsistent beliefs (VERIFYAC / ENFORCEAC of Kundu, Rafaeli "
                           "and Indelman).",
                      no_args_is_help=True)
    app.add_typer(sub, name="consistency")

    @sub.command("table")
    def table(
        epochs: int = typer.Option(200, "--epochs", help="Planning steps per episode (E)."),
        seed: int = typer.Option(0, "--seed", min=0, max=2**63 - 1,
                                    help="Seed of the world, the sensor noise and the comm failures."),
        width: int = typer.Option(10, "--width", help="Grid width (cells)."),
        height: int = typer.Option(10, "--height", help="Grid height (cells)."),
        policy: str = typer.Option("all", "--policy", help="What a triggered robot sends: all|greedy|oldest."),
        trigger: str = typer.Option("paper", "--trigger", help="T1/T2 rules: paper|useful."),
        tie_break: str = typer.Option("random", "--tie-break", help="Ties in J: random (common seed)|index."),
        resend: bool = typer.Option(False, "--resend/--no-resend",
                                    help="Baseline-I re-sends a backlog lost on a restricted step (ours, not the "
                                         "paper's; off by default)."),
        as_json: bool = typer.Option(False, "--json", help="Print one JSON object."),
    ) -> None:
        """Reproduce every row of Table I (Input, Algorithm, Not-AC, COMM, Time) beside the paper's."""
        from sim.sar import ALGORITHM_NAMES, INIT_NAMES, PAPER_TABLE_I, table_i

        base = _config(epochs=epochs, seed=seed, width=width, height=height, policy=policy, trigger=trigger,
                       tie_break=tie_break, resend=resend)
        total = len(PAPER_TABLE_I) * 3
        with _progress(as_json) as bar:
            task = bar.add_task("Table I episodes", total=total)
            rows = table_i(base, on_run=lambda row: bar.advance(task))
        if as_json:
            print(json.dumps({"epochs": epochs, "seed": seed, "grid": [width, height], "policy": policy,
                              "trigger": trigger, "tie_break": tie_break,
                              "rows": [r.as_dict() for r in rows]}))
            return
        from rich.table import Table

        t = Table(title=f"Table I — E = {epochs}, seed {seed}, {width}×{height} grid (ours | paper)",
                  caption="restr: steps with the channel down; prim: motion primitives per robot; init: prior; "
                          "Not-AC: steps whose joint action was not action-consistent; COMM: one-way messages; "
                          "obs: observations they carried; Time s: wall seconds; paper: Kundu, Rafaeli, Indelman, "
                          "Table I", caption_justify="left")
        for col in ("restr", "prim", "init", "Algorithm", "Not-AC", "COMM", "obs", "Time s",
                    "paper Not-AC", "paper COMM", "paper Time s"):
            t.add_column(col, justify="left" if col in ("init", "Algorithm") else "right")
        for i, r in enumerate(rows):
            first = i % 3 == 0
            t.add_row(str(r.comm_restr) if first else "", str(r.primitives) if first else "",
                      INIT_NAMES[r.init].removesuffix("-Init") if first else "", ALGORITHM_NAMES[r.algorithm],
                      str(r.ours.not_ac), str(r.ours.comms), str(r.ours.observations_sent), f"{r.ours.time_s:.2f}",
                      *_fmt_paper(r.paper), end_section=i % 3 == 2)
        _wide_console().print(t)

    @sub.command("run")
    def run(
        robots: int = typer.Option(2, "--robots", help="Number of robots N (2–6)."),
        algorithm: str = typer.Option("all", "--algorithm", help="enforce|baseline1|baseline2|all."),
        primitives: int = typer.Option(4, "--primitives", help="Motion primitives per robot: 4 or 8."),
        init: str = typer.Option("max-entropy", "--init", help="Prior: max-entropy|entropy."),
        comm_restr: int = typer.Option(0, "--comm-restr", help="Random steps on which the channel is down."),
        epochs: int = typer.Option(200, "--epochs", help="Planning steps (E)."),
        seed: int = typer.Option(0, "--seed", min=0, max=2**63 - 1, help="Seed."),
        width: int = typer.Option(10, "--width", help="Grid width (cells)."),
        height: int = typer.Option(10, "--height", help="Grid height (cells)."),
        policy: str = typer.Option("all", "--policy", help="What a triggered robot sends: all|greedy|oldest."),
        trigger: str = typer.Option("paper", "--trigger", help="T1/T2 rules: paper|useful."),
        tie_break: str = typer.Option("random", "--tie-break", help="Ties in J: random|index."),
        resend: bool = typer.Option(False, "--resend/--no-resend",
                                    help="Baseline-I re-sends a backlog lost on a restricted step (ours, not the "
                                         "paper's; off by default)."),
        as_json: bool = typer.Option(False, "--json", help="Print one JSON object."),
    ) -> None:
        """Run one search-and-rescue episode and report Not-AC, COMMs and time."""
        from delkit.errors import SimulationError
        from sim.sar import ALGORITHM_NAMES, ALGORITHMS, run_episode

        if algorithm not in ALGORITHM_CHOICES:
            raise SimulationError(f"--algorithm {algorithm!r} is not one of {', '.join(ALGORITHM_CHOICES)}")
        cfg = _config(robots=robots, primitives=primitives, init=init, comm_restr=comm_restr, epochs=epochs,
                      seed=seed, width=width, height=height, policy=policy, trigger=trigger,
                      tie_break=tie_break, resend=resend)
        algs = ALGORITHMS if algorithm == "all" else (algorithm,)
        results = []
        with _progress(as_json) as bar:
            task = bar.add_task("episodes", total=len(algs))
            for alg in algs:
                results.append(run_episode(cfg, alg))
                bar.advance(task)
        if as_json:
            print(json.dumps({"results": [
                {k: v for k, v in r.as_dict().items() if k not in ("team_j", "since_comm")} for r in results]}))
            return
        from rich.table import Table

        t = Table(title=f"{robots} robots, {primitives} primitives, {init}, comm-restr={comm_restr}, "
                        f"E={epochs}, seed {seed}",
                  caption="Not-AC: steps whose joint action was not action-consistent; COMM: one-way messages; "
                          "obs sent: observations they carried; failed: messages lost while the channel was "
                          "down; max p: most observations of one robot its partner lacked when planning; mean J: "
                          "mean team objective of the executed actions", caption_justify="left")
        for col in ("Algorithm", "Not-AC", "COMM", "obs sent", "failed", "max p", "mean J", "Time (s)"):
            t.add_column(col, justify="left" if col == "Algorithm" else "right")
        for r in results:
            t.add_row(ALGORITHM_NAMES[r.algorithm], str(r.not_ac), str(r.comms), str(r.observations_sent),
                      str(r.failed_comms), str(r.max_unshared), f"{sum(r.team_j) / len(r.team_j):.2f}",
                      f"{r.time_s:.2f}")
        _wide_console().print(t)
