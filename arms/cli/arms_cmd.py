"""``delkit arms``: two simulated Franka Pandas (MuJoCo) that execute primitive plans.

Commands: ``run PLAN.json`` (execute, verify against the symbolic state, render), ``demo`` (the built-in
two-robot plan), ``bench-ik`` (IK success rate and times, TRAC-IK protocol), ``scene`` (save the MJCF).
Heavy imports (mujoco, mink, pinocchio) happen inside the commands.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import typer


def _progress_cb(total: int, label: str):
    """A rich progress bar on stderr; returns (callback(i, item), stop())."""
    from delkit.progress import progress

    prog = progress()
    prog.start()
    task = prog.add_task(label, total=total)

    def cb(i: int, item) -> None:
        prog.update(task, completed=i, description=f"{label}: {item}")

    return cb, prog.stop


def _report(result, note: str, as_json: bool) -> int:
    if as_json:
        obj = result.to_json()
        obj["render"] = note
        print(json.dumps(obj))
    else:
        from rich.console import Console
        from rich.table import Table

        con = Console()
        table = Table(title="arms run", show_lines=False)
        for col in ("#", "robot", "action", "ok", "worst block", "error (mm)", "t_sim (s)"):
            table.add_column(col)
        for a in result.actions:
            err = "-" if a.max_block_error != a.max_block_error else f"{a.max_block_error * 1000:.2f}"
            table.add_row(str(a.index), a.robot,
                          a.text.split(": ", 1)[-1] + (f" → {dict(a.observed)}" if a.observed else ""),
                          "yes" if a.success else "[red]NO[/red]", a.worst_block or "-", err,
                          f"{a.sim_time:.1f}")
        con.print(table)
        con.print(f"success: {result.success}   simulated {result.sim_seconds:.1f} s in "
                  f"{result.wall_seconds:.1f} s wall ({result.realtime_factor:.1f}× real time), "
                  f"grasp={result.grasp}, max slip in hand {result.max_slip * 1000:.2f} mm, "
                  f"arm–arm contacts: {result.arm_contacts}")
        if result.failure:
            con.print(f"[red]failure:[/red] {result.failure}")
        con.print(note)
    return 0 if result.success else 1


#: the files ``arms run --out DIR`` may write in DIR (each checked against the input plan first)
_OUTPUT_NAMES = ("scene.xml", "result.json", "final.png", "run.mp4", "run.gif")


def register(app: typer.Typer) -> None:
    """Attach ``delkit arms ...`` to the top-level app."""
    sub = typer.Typer(help="Two simulated Franka Pandas (MuJoCo + mink/pinocchio IK) executing plans.",
                      no_args_is_help=True)

    @sub.callback()
    def _needs_arms_extra() -> None:
        """Two simulated Franka Pandas (MuJoCo + mink/pinocchio IK) executing plans."""
        from arms.cli.extra import EXTRA, REQUIRES
        from delkit.errors import require_extra

        require_extra(EXTRA, *REQUIRES, what="delkit arms")

    @sub.command("run")
    def run(plan: Path = typer.Argument(..., help="primitive-plan JSON (format: arms/README.md)"),
            out: Path | None = typer.Option(None, "--out", help="directory for scene.xml, result.json, "
                                                                  "final.png and the video"),
            grasp: str = typer.Option("friction", "--grasp", help="friction (default) or weld (debugging only)"),
            as_json: bool = typer.Option(False, "--json", help="print one JSON object"),
            video: bool = typer.Option(True, "--video/--no-video", help="also write run.mp4 / run.gif"),
            frames: bool = typer.Option(False, "--frames", help="also write every frame as PNG"),
            tolerance: float = typer.Option(0.01, "--tolerance", help="max block error (m)"),
            timeout: float = typer.Option(0.0, "--timeout", min=0.0,
                                          help="wall-clock limit in seconds for the whole run (0: none)")) -> None:
        """Execute a primitive plan in physics, check every block after every action, render."""
        from arms.demo import execute_and_render
        from arms.plan import load_plan, symbolic_trace
        from arms.world import ArmsError
        from delkit.resources import deadline

        if grasp not in ("weld", "friction"):
            raise ArmsError(f"--grasp must be weld or friction, not {grasp!r}")
        if not tolerance > 0:
            raise ArmsError(f"--tolerance must be a positive distance in metres (e.g. 0.01), not {tolerance!r}")
        if out is not None:  # nothing written inside --out may replace the plan
            from delkit.paths import refuse_overwrite_input

            refuse_overwrite_input([out / n for n in _OUTPUT_NAMES] + [out], [plan], option="--out")
        p = load_plan(plan)
        symbolic_trace(p)  # reject a plan that is wrong on paper before simulating it
        cb, stop = _progress_cb(len(p.actions), "executing")
        try:
            with deadline(timeout, f"arms run {plan}"):  # physics, IK and rendering: the limit holds throughout
                result, note = _execute(execute_and_render, p, out, grasp, video, tolerance, cb, frames)
        finally:
            stop()
        raise typer.Exit(_report(result, note, as_json))

    @sub.command("demo")
    def demo(out: Path = typer.Option(Path("arms-demo"), "--out", help="output directory"),
             as_json: bool = typer.Option(False, "--json", help="print one JSON object"),
             video: bool = typer.Option(False, "--video/--no-video", help="also write a video")) -> None:
        """robot1 senses its stack, moves the block under another one to the shared table, robot2 takes it."""
        from arms.demo import demo_plan, execute_and_render

        p = demo_plan()
        cb, stop = _progress_cb(len(p.actions), "demo")
        try:
            result, note = _execute(execute_and_render, p, out, "friction", video, 0.01, cb)
        finally:
            stop()
        raise typer.Exit(_report(result, note, as_json))

    @sub.command("bench-ik")
    def bench_ik(targets: int = typer.Option(1000, "--targets", min=1, help="number of random poses"),
                 budget_ms: float = typer.Option(5.0, "--budget-ms", help="time budget per target"),
                 seed: int = typer.Option(0, "--seed", min=0, max=2**63 - 1, help="seed of the random target poses"),
                 clock: str = typer.Option("wall", "--clock", help="wall (default) or cpu: what the "
                                                                   "budget and the times measure"),
                 protocol: str = typer.Option("trac-ik", "--protocol",
                                              help="trac-ik (default: midpoint seed + random restarts, as "
                                                   "TRAC-IK measures) or seed-table (nearest precomputed "
                                                   "configurations first; not comparable with TRAC-IK)"),
                 as_json: bool = typer.Option(False, "--json", help="print one JSON object")) -> None:
        """IK on N random reachable TCP poses: success rate, mean / median / p95 time (analytic, mink, CLIK)."""
        from arms.benchmark import PROTOCOLS, TRAC_IK_PANDA, benchmark_ik
        from arms.world import ArmsError

        if clock not in ("wall", "cpu"):
            raise ArmsError(f"--clock must be wall or cpu, not {clock!r}")
        if protocol not in PROTOCOLS:
            raise ArmsError(f"--protocol must be one of {', '.join(PROTOCOLS)}, not {protocol!r}")
        if not budget_ms > 0 or budget_ms == float("inf"):
            raise ArmsError(f"--budget-ms must be a positive time in milliseconds (e.g. 5), not {budget_ms!r}")
        from delkit.resources import require

        require(1024.0 * targets, f"--targets {targets} (the random poses and per-solve records)",
                "use fewer --targets")

        cb, stop = _progress_cb(3 * targets, "IK")
        try:
            stats = benchmark_ik(targets, seed=seed, budget=budget_ms / 1000.0, clock=clock, protocol=protocol,
                                 progress=cb)
        finally:
            stop()
        if as_json:
            print(json.dumps({"targets": targets, "budget_ms": budget_ms, "seed": seed, "clock": clock,
                              "protocol": protocol,
                              "solvers": [s.to_json() for s in stats],
                              "published": [{"solver": n, "success_rate": r / 100, "mean_ms": t}
                                            for n, r, t in TRAC_IK_PANDA]}))
            return
        from rich.console import Console
        from rich.table import Table

        table = Table(title=f"IK, {targets} random reachable Panda poses, {budget_ms:g} ms budget ({clock} clock, "
                            f"{protocol} protocol)")
        for col in ("solver", "success %", "mean ms", "median ms", "p95 ms"):
            table.add_column(col)
        for s in stats:
            table.add_row(s.solver, f"{100 * s.rate:.2f}", f"{s.mean_s * 1e3:.3f}", f"{s.median_s * 1e3:.3f}",
                          f"{s.p95_s * 1e3:.3f}")
        for n, r, t in TRAC_IK_PANDA:
            table.add_row(f"{n} (published, its protocol)", f"{r:.2f}", f"{t:.2f}", "-", "-")
        con = Console()
        con.print(table)
        for s in stats:  # which poses failed, and why (the analytic solver says why; the others time out)
            if s.failures:
                shown = "; ".join(f"#{i}: {r}" for i, r in s.failures[:5])
                more = f" (+{len(s.failures) - 5} more)" if len(s.failures) > 5 else ""
                con.print(f"{s.solver}: {len(s.failures)} failed — {shown}{more}", highlight=False)

    @sub.command("scene")
    def scene(out: Path = typer.Argument(..., help="MJCF file to write"),
              plan: Path | None = typer.Option(None, "--plan", help="take the world from this plan "
                                                                  "(default: the demo's world)")) -> None:
        """Save the MuJoCo scene (two arms, tables, blocks) as MJCF."""
        from arms.demo import demo_plan
        from arms.plan import load_plan
        from arms.scene import build_scene, save_mjcf

        world = (load_plan(plan) if plan else demo_plan()).world
        path = save_mjcf(build_scene(world), out)
        print(f"wrote {path}", file=sys.stderr)

    app.add_typer(sub, name="arms")


def _execute(execute_and_render, plan, out, grasp, video, tolerance, cb, frames=False):
    return execute_and_render(plan, out, grasp=grasp, render=out is not None, video=video,
                              progress=cb, tolerance=tolerance, save_frames=frames)
