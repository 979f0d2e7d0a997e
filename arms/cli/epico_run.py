"""``delkit epico run``: generate an e-PICO instance, plan it (epistemic + classical), execute the primitive
plan on the two simulated Pandas in closed loop (``arms.mission``) and report per task.

``register(epico_app)`` adds the ``run`` command to the ``epico`` sub-app. :func:`epico_replanner` is the
bridge between the e-PICO pipeline (``planners.epico`` / ``planners.hierarchy``) and ``arms.mission``'s
``replan(world_json, known) -> plan/1`` callable; the benchmark ``bench/arms_mission.py`` and the tests
use it too. Heavy imports happen inside the functions.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import typer


def epico_replanner(goal: str, colors: int, origin: dict[str, str], *, macros: bool = True,
                    symmetric: bool = False):
    """``replan(world_json, known)`` for :class:`arms.mission.Mission` backed by e-PICO's ``solve``.

    The observed world becomes an e-PICO ``Layout`` (blocks on the shared table keep their original owner),
    ``known`` (robot ↦ {block: colour}) becomes ``solve(..., known=)``'s (owner, colour) pairs, and every
    primitive action is tagged with the e-PICO task it comes from. A planner failure is
    :class:`arms.mission.GoalUnreachable`."""
    from arms.mission import GoalUnreachable
    from planners.epico import EpicoError, Layout, generate
    from planners.hierarchy import solve

    def replan(world_json: dict, known: dict) -> dict:
        try:
            layout = Layout.from_world(world_json, {b: origin[b] for b in world_json.get("barrier", [])})
            inst = generate(goal, colors, layout=layout, symmetric=symmetric)
            # what each robot knows of the modelled owners' colours (e-PICO's hold(owner, colour) fluents)
            kn = {r: sorted({(origin[b], c) for b, c in bel.items() if origin.get(b) in inst.owners})
                  for r, bel in known.items()}
            sol = solve(inst, known={r: v for r, v in kn.items() if v} or None, macros=macros)
        except EpicoError as exc:
            raise GoalUnreachable(str(exc)) from None
        actions = []
        for rec in sol.tasks:
            for a in rec.actions:
                actions.append({**a, "task": rec.task})
        plan = dict(sol.primitive_plan)
        plan["actions"] = actions
        plan["world"] = {**plan["world"], "layout": world_json.get("layout", {})}
        return plan

    return replan


def run_mission(goal: str, colors: int, seed: int | None, *, faults=(), grasp: str = "friction",
                max_replans: int = 4, macros: bool = True, symmetric: bool = False, record_fps: float = 0.0,
                progress=None):
    """Generate, plan, execute; returns (instance, MissionResult, Mission)."""
    from arms.mission import Mission
    from arms.world import World
    from planners.epico import generate

    inst = generate(goal, colors, seed, symmetric=symmetric)
    world = World.from_json(inst.layout.to_world())
    origin = {b: r for r in world.robots for st in world.stacks[r] for b in st}
    replan = epico_replanner(inst.goal, colors, origin, macros=macros, symmetric=symmetric)
    m = Mission(world, inst.goal, replan, faults=tuple(faults), grasp=grasp, max_replans=max_replans,
                record_fps=record_fps, progress=progress)
    return inst, m.run(), m


def _render(m, res, out: Path) -> str:
    from arms.render import RenderSkipped, render_frames
    from arms.scene import save_mjcf

    ex = m.executor
    files = {"scene": str(save_mjcf(ex.scene, out / "scene.xml"))}
    frames = [*ex.frames, ex.data.qpos.copy()]
    try:
        files.update(render_frames(ex.scene.spec.to_xml(), frames, out, video=True, fps=10.0, width=480,
                                   height=360))
        note = f"wrote {files.get('png')}" + (f" and {files['video']}" if "video" in files else "")
    except RenderSkipped as exc:
        note = f"video and picture skipped: {exc}"
    res.files.update(files)
    return note


def _print_report(inst, res, note: str) -> None:
    from rich.console import Console
    from rich.table import Table

    con = Console()
    table = Table(title=f"e-PICO {inst.goal}, {inst.colors} colour(s): closed-loop execution", show_lines=True)
    for col in ("plan", "task", "planned", "done", "observed", "world & beliefs"):
        table.add_column(col, overflow="fold")
    for t in res.tasks():
        obs = "; ".join(f"{k}: {v}" for k, v in t["observed"].items())
        table.add_row(str(t["plan"]), t["task"], "\n".join(t["planned"]) or "-", "\n".join(t["done"]) or "-", obs,
                      "match" if t["ok"] else f"[red]DIVERGED[/red] {t['message']}" if t["done"] else t["status"])
    con.print(table)
    for e in res.belief_log:
        to = f" → {', '.join(e['to'])}" if e["to"] else ""
        con.print(f"  t={e['t_sim_s']:6.2f} s  {e['kind']:8s} {e['robot']}{to}: {e['block']} is {e['colour']}")
    verdict = "[green]SUCCESS[/green]" if res.success else "[red]FAILURE[/red]"
    con.print(f"{verdict}: {res.reason}")
    con.print(f"replans: {res.replans}; planning s per plan: {[round(x, 3) for x in res.planning_seconds]}; "
              f"faults: {res.faults or 'none'}; lost blocks: {res.lost or 'none'}")
    con.print(f"simulated {res.sim_seconds:.1f} s in {res.wall_seconds:.1f} s wall / {res.cpu_seconds:.1f} s CPU "
              f"({res.realtime_factor:.1f}× real time on the wall clock); grasp={res.grasp}; max block error "
              f"{res.max_block_error * 1000:.1f} mm; arm–arm contacts: {res.arm_contacts}")
    con.print(note)


def register(epico_app: typer.Typer) -> None:
    """Add ``run`` to the ``delkit epico`` sub-app."""

    @epico_app.command("run")
    def run(goal: str = typer.Option(..., "--goal", help="alpha, beta, gamma or delta (α β γ δ)"),
            colors: int = typer.Option(..., "--colors", help="number of colours, 1–4 (Table 1)"),
            seed: int | None = typer.Option(None, "--seed", help="random layout (default: the seed's layout)"),
            out: Path | None = typer.Option(None, "--out", help="directory for result.json, scene.xml, the video "
                                                                 "and final.png"),
            fault: list[str] = typer.Option([], "--fault", help="drop@K, misplace@K or swap-colours (repeatable)"),
            grasp: str = typer.Option("friction", "--grasp", help="friction (default) or weld (debugging only)"),
            max_replans: int = typer.Option(4, "--max-replans", min=0, help="give up after this many replans"),
            macros: bool = typer.Option(True, "--macros/--no-macros", help="plan with e-PICO's macros"),
            symmetric: bool = typer.Option(False, "--symmetric", help="model both robots' colours (e-PICO "
                                                                     "default: robot2 learns robot1's)"),
            timeout: float = typer.Option(0.0, "--timeout", min=0.0, help="wall-clock limit in seconds for "
                                          "planning, replanning, physics and rendering (0: none)"),
            as_json: bool = typer.Option(False, "--json", help="print one JSON object")) -> None:
        """Plan an e-PICO goal and execute it on the two simulated arms, re-sensing and replanning on
        divergences; report per task what was planned, done and observed."""
        from arms.cli import EXTRA, REQUIRES
        from delkit.cli.plugins import require_extra

        require_extra(EXTRA, *REQUIRES, what="delkit epico run")
        from arms.mission import parse_fault
        from arms.world import ArmsError
        from delkit.resources import deadline

        if grasp not in ("weld", "friction"):
            raise ArmsError(f"--grasp must be friction or weld, not {grasp!r}")
        faults = [parse_fault(f) for f in fault]
        if out is not None:
            try:
                out.mkdir(parents=True, exist_ok=True)
            except OSError as exc:
                raise ArmsError(f"{out}: cannot create the output directory: {exc.strerror}") from None
        from arms.cli.arms_cmd import _progress_cb

        cb, stop = _progress_cb(0, "mission")
        with deadline(timeout, f"epico run --goal {goal} --colors {colors}"):
            try:
                inst, res, m = run_mission(goal, colors, seed, faults=faults, grasp=grasp, max_replans=max_replans,
                                           macros=macros, symmetric=symmetric,
                                           record_fps=10.0 if out is not None else 0.0,
                                           progress=lambda msg: cb(0, msg))
            finally:
                stop()
            note = "rendering not requested (--out DIR)"
            if out is not None:
                note = _render(m, res, out)
                (out / "result.json").write_text(json.dumps(res.to_json(), indent=2))
                res.files["result"] = str(out / "result.json")
        for f in res.faults:  # e.g. drop@K with K beyond the last primitive action: the run never tested it
            if "not fired" in f:
                print(f"delkit: warning: --fault {f}", file=sys.stderr)
        if as_json:
            obj = res.to_json()
            obj["instance"] = {"goal": inst.goal, "colors": inst.colors, "seed": seed,
                               "layout": inst.layout.to_json()}
            obj["render"] = note
            print(json.dumps(obj))
        else:
            _print_report(inst, res, note)
        sys.stdout.flush()
        raise typer.Exit(0 if res.success else 1)
