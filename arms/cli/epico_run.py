"""``delkit epico run``: generate an e-PICO instance, plan it (epistemic + classical), execute the primitive
plan on the two simulated Pandas in closed loop (``arms.mission``) on the planner's own DEL belief state,
and report per task and per step (precondition in the belief state, checks).

``register(epico_app)`` adds the ``run`` command to the ``epico`` sub-app. :class:`EpicoModel` is the
bridge between the e-PICO pipeline (``planners.epico`` / ``planners.hierarchy`` / ``planners.spaces``)
and :class:`arms.mission.Mission`; the benchmark ``bench/arms_mission.py`` and the tests use it too.
Heavy imports happen inside the functions.
"""

from __future__ import annotations

import json
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import typer


@dataclass
class TaskPlan:
    """One simple task of the flattened e-PICO plan and the primitive actions it became."""

    name: str
    kind: str
    robot: str
    actions: list

    def to_json(self) -> dict:
        return {"task": self.name, "kind": self.kind, "robot": self.robot, "actions": list(self.actions)}


class EpicoModel:
    """The planner's side of :class:`arms.mission.Mission`: the e-PICO task, the state space the planner
    searches (its backend: ``compact``, the default, or ``del`` — numpy; the search and the belief state use
    the same one), the initial belief state, and
    planning *from a belief state*: the epistemic search starts from the executor's current DEL state
    (the task with that state as its initial state; macros as in ``epico solve``), the hierarchy breaks the
    ontic tasks down from the classical state the robots observe (block positions measured, colours as
    last seen by the cameras, the planner's own assumption for blocks nobody has seen)."""

    def __init__(self, inst, *, macros: bool = True, engine: str = "compact", timeout: float = 110.0) -> None:
        from planners.epico import ROBOTS
        from planners.hierarchy import EpicoLimits, epistemic_task
        from planners.spaces import make_space

        self.inst, self.macros, self.engine = inst, macros, engine
        self.task, _ptask, self.ms = epistemic_task(inst, macros=macros)
        self.space = make_space(self.task, engine=engine)  # type: ignore[arg-type]
        self.limits = EpicoLimits(timeout=timeout)
        self.owner = {b: r for r in ROBOTS for st in inst.layout.stacks[r] for b in st} | dict(inst.layout.owners)
        self.owners = tuple(inst.owners)
        self.colours = tuple(dict.fromkeys(p.rsplit("_", 1)[1] for p in self.task.props))

    def initial_belief(self):
        from arms.beliefs import BeliefState

        return BeliefState(self.task, self.space)

    def plan(self, belief, world_json: dict) -> tuple[list[TaskPlan], dict]:
        """The epistemic plan from ``belief`` (a :class:`arms.beliefs.BeliefState`); each task's primitive
        actions are made when it is about to run (:meth:`breakdown`), from what the robots have seen by then.
        With takes seen by both robots, a robot takes back only its own block (a take by the other robot
        moves the block to the taker's table, after which ``hold(owner, c)`` may be false: the mission
        models that, the planner's domain does not)."""
        from dataclasses import replace

        from arms.mission import GoalUnreachable
        from planners.epistemic import Limits, bfs, make_space
        from planners.macros import with_macros

        t0, c0 = time.perf_counter(), time.process_time()
        task = replace(self.task, initial=belief.kripke(), _cache={})
        if self.inst.reading.takes != "handover":
            task = replace(task, actions=tuple(a for a in task.actions if not _foreign_take(a.name)), _cache={})
        ptask = with_macros(task, self.ms) if self.macros else task
        res = bfs(make_space(ptask, engine=self.engine), Limits(timeout=self.limits.timeout))  # type: ignore[arg-type]
        if not res.solved:
            raise GoalUnreachable(f"the epistemic planner finds no plan from the belief state: {res.reason}")
        by_name = {m.name: m for m in self.ms}
        out = []
        for name in res.plan or ():
            for simple in (by_name[name].step_names if name in by_name else (name,)):
                act = self.task.action(simple)
                robot = next((r for r in self.task.agents if r in simple.split("_")), "")
                out.append(TaskPlan(simple, act.kind, robot, []))
        return out, {"epistemic_plan": list(res.plan or ()), "expanded": res.expanded,
                     "wall_s": time.perf_counter() - t0, "cpu_s": time.process_time() - c0}

    def breakdown(self, name: str, world_json: dict) -> list[dict]:
        """The primitive actions of task ``name`` from the observed world (block positions measured, colours
        as the cameras saw them, ``unseen`` for the others; owners of blocks on the shared table from where
        they stood): the classical level for an ontic task (BFS, fewest arm actions), the arms' ``sense`` /
        ``announce`` for an epistemic one."""
        from planners.classical import CState, goal_for, solve_bfs
        from planners.hierarchy import _epistemic_primitive

        st = CState.make(world_json["stacks"], tuple(world_json.get("barrier", ())), world_json["colors"],
                         world_json.get("owners", {}))
        act = self.task.action(name)
        if act.kind != "ontic":
            return [_epistemic_primitive(name, st, self.task)]
        goal = goal_for(name, st, self.task.agents)
        r = solve_bfs(st, goal, max_steps=self.limits.classical_max_steps, timeout=self.limits.classical_timeout)
        return [a.to_json() for a in r.actions]


def _foreign_take(name: str) -> bool:
    """``take_from_shared_R_O_C`` with R ≠ O."""
    if not name.startswith("take_from_shared_"):
        return False
    taker, owner, _c = name[len("take_from_shared_"):].split("_")
    return taker != owner


def run_mission(goal: str, colors: int, seed: int | None, *, faults=(), grasp: str = "friction",
                max_replans: int = 4, macros: bool = True, symmetric: bool | None = None, record_fps: float = 0.0,
                shield: bool = True, engine: str = "compact", progress=None, sensing: str = "table",
                takes: str = "seen", layout=None):
    """Generate, plan, execute; returns (instance, MissionResult, Mission). ``symmetric=None``: the
    generator's default instance; ``layout``: a given :class:`planners.epico.Layout` (e.g. several blocks of
    one colour per robot, :func:`arms.mission.duplicate_layout`)."""
    from arms.mission import Mission
    from arms.world import World
    from planners.epico import generate

    # the paper's reading (both robots ignorant of their own colours) unless the reduced one is asked for
    inst = generate(goal, colors, seed, layout=layout, owners=("robot1",) if symmetric is False else None,
                    sensing=sensing, takes=takes)
    world = World.from_json(inst.layout.to_world())
    model = EpicoModel(inst, macros=macros, engine=engine)
    m = Mission(world, inst.goal, model, faults=tuple(faults), grasp=grasp, max_replans=max_replans,
                record_fps=record_fps, progress=progress, shield=shield)
    return inst, m.run(), m


def _process_times() -> dict:
    """CPU (user + system, this process and its finished children) and wall seconds since the process
    started: the whole command, start-up and imports included."""
    import os

    from delkit.resources import process_start

    t = os.times()
    return {"cpu_s": round(t.user + t.system + t.children_user + t.children_system, 3),
            "wall_s": round(time.monotonic() - process_start(), 3)}


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
    reading = ("both robots' colours (the paper's reading)" if len(inst.owners) > 1 else "robot1's colours only") + (
        f", sensing {inst.reading.sensing}, takes {inst.reading.takes}")
    table = Table(title=f"e-PICO {inst.goal}, {inst.colors} colour(s), {reading}: closed-loop execution on the "
                        f"planner's DEL belief state ({res.backend} backend, shield {'on' if res.shield else 'OFF'})",
                  show_lines=True)
    for col in ("plan", "task", "precondition (belief state)", "done", "observed", "checks"):
        table.add_column(col, overflow="fold")
    for t in res.tasks():
        obs = "; ".join(f"{k}: {v}" for k, v in t["observed"].items() if k not in ("learnt",))
        pre = next((s for s in res.steps if s.plan == t["plan"] and s.task == t["task"]), None)
        truth = "" if pre is None or pre.precondition_holds is None else (
            " [green]✓[/green]" if pre.precondition_holds else " [red]✗[/red]")
        table.add_row(str(t["plan"]), t["task"], (t["precondition"] or "-") + truth, "\n".join(t["done"]) or "-",
                      obs, "match" if t["ok"] else f"[red]DIVERGED[/red] {t['message']}" if t["done"] else t["status"])
    con.print(table)
    con.print("belief log (the planner's DEL state; formulas that became true):")
    for e in res.belief_log:
        learnt = ", ".join(e["learnt"]) or "nothing new"
        con.print(f"  t={e['t_sim_s']:6.2f} s  {e['task']} ({e['chosen']}): {learnt}")
    for s in res.unsafe_steps:
        con.print(f"[red]WRONG STEP[/red] {s.index} ({s.text}) [{s.task}]: executed although its precondition "
                  f"{s.precondition} is false in the belief state")
    for i, msg in res.unheeded:
        con.print(f"[red]UNHEEDED[/red] after step {i}: {msg}")
    audit = res.audit.get("final", {})
    if audit:
        bad = audit["actual_world_differs"] + [f"false belief {b}" for b in audit["false_beliefs"]]
        con.print("audit (ground truth, not used by the loop): "
                  + ("agrees with the belief state" if audit["agrees"] else "; ".join(bad)))
    verdict = "[green]SUCCESS[/green]" if res.success else "[red]FAILURE[/red]"
    if res.unfired:
        verdict += f" [red](fault(s) NEVER FIRED: {', '.join(res.unfired)})[/red]"
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
            seed: int | None = typer.Option(None, "--seed",
                                             help="random layout (default: the layout of the e-PICO paper)"),
            out: Path | None = typer.Option(None, "--out", help="directory for result.json, scene.xml, the video "
                                                                 "and final.png"),
            fault: list[str] = typer.Option([], "--fault", help="drop@K, misplace@K, drop-msg@K, repaint@K, "
                                            "swap-colours or occlusion (repeatable)"),
            grasp: str = typer.Option("friction", "--grasp", help="friction (default) or weld (debugging only)"),
            max_replans: int = typer.Option(4, "--max-replans", min=0, help="give up after this many replans"),
            macros: bool = typer.Option(True, "--macros/--no-macros", help="plan with e-PICO's macros"),
            symmetric: bool = typer.Option(False, "--symmetric", help="both robots ignorant of their own blocks "
                                           "(the paper's reading; default: the generator's default instance)"),
            owner: str = typer.Option("", "--owner", help="robot1: the reduced reading (only robot1's colours "
                                      "are fluents)"),
            shield: bool = typer.Option(True, "--shield/--no-shield", help="--no-shield: turn the belief-side "
                                        "guards off (only to show the run that goes wrong without them)"),
            engine: str = typer.Option("compact", "--engine", help="DEL backend of the belief state: compact "
                                       "(the planner's default) or del (numpy)"),
            sensing: str = typer.Option("table", "--sensing", help="table: one sense_table per robot (default); "
                                        "color: one sense_color per robot and colour"),
            takes: str = typer.Option("seen", "--takes", help="seen: a robot takes its own block back, both see it "
                                      "(default); handover: the other robot takes, the owner partially observes"),
            timeout: float = typer.Option(0.0, "--timeout", min=0.0, help="wall-clock limit in seconds for "
                                          "planning, replanning, physics and rendering (0: none)"),
            as_json: bool = typer.Option(False, "--json", help="print one JSON object")) -> None:
        """Plan an e-PICO goal and execute it on the two simulated arms, re-sensing and replanning on
        divergences; report per task what was planned, done and observed."""
        from arms.cli.extra import EXTRA, REQUIRES
        from delkit.errors import require_extra

        require_extra(EXTRA, *REQUIRES, what="delkit epico run")
        from arms.mission import parse_fault
        from arms.world import ArmsError
        from delkit.resources import deadline

        if owner not in ("", "robot1"):
            raise ArmsError(f"--owner takes robot1 (the reduced reading), not {owner!r}")
        reading = True if symmetric else False if owner == "robot1" else None
        if engine not in ("compact", "del"):
            raise ArmsError(f"--engine must be compact or del, not {engine!r}")
        if sensing not in ("table", "color"):
            raise ArmsError(f"--sensing must be table or color, not {sensing!r}")
        if takes not in ("seen", "handover"):
            raise ArmsError(f"--takes must be seen or handover, not {takes!r}")
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
                                           macros=macros, symmetric=reading, shield=shield, engine=engine,
                                           sensing=sensing, takes=takes,
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
        process = _process_times()
        if as_json:
            obj = res.to_json()
            obj["instance"] = {"goal": inst.goal, "colors": inst.colors, "seed": seed,
                               "layout": inst.layout.to_json(), "reading": inst.reading.to_json()}
            obj["render"] = note
            obj["process"] = process
            print(json.dumps(obj))
        else:
            _print_report(inst, res, note)
            print(f"whole process: {process['cpu_s']:.2f} s CPU, {process['wall_s']:.2f} s wall (start-up, imports, "
                  "planning, physics, rendering)")
        sys.stdout.flush()
        raise typer.Exit(0 if res.success and not res.unfired else 1)
