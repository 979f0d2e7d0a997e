"""CLI commands on model files and formulas: ``delkit model check|dot|contract|show|diff|draw|macro``, ``delkit prove``.

Model files are JSON in the schema of :mod:`delkit.io.formats` (or DOT written by ``delkit model dot``).
Exit status: 0 = yes (holds / valid), 1 = no (fails / counter-model found), 2 = bad input.
Heavy imports (z3, lark, scipy) stay inside the commands so that ``delkit --help`` is fast.
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import typer

__all__ = ["register"]


def _events_option(specs: list[str], model=None, model_file: str = "") -> dict:
    """``NAME=FILE`` pairs → {NAME: EventModel} for formulas with [NAME,e] (checked against ``model``)."""
    from delkit.errors import DelkitError
    from delkit.io.formats import load_event_model

    out = {}
    for spec in specs:
        name, sep, path = spec.partition("=")
        if not sep or not name or not path:
            raise DelkitError(f"--event {spec!r}: write NAME=FILE.json, e.g. --event Ann=announce.json")
        out[name] = load_event_model(path)
        if model is not None:
            _fits(out[name], model, f"--event {spec}", model_file)
    return out


def _fits(events, model, where: str, model_file: str) -> None:
    """The event model can update ``model``: its formulas use the model's propositions, and it has a relation
    for every agent of the model (so that a formula [NAME,e]φ is about this model)."""
    from delkit.errors import UnknownSymbolError
    from delkit.logic.formula import props_of

    used: set[str] = set()
    for pre, post in zip(events.pre, events.post, strict=True):
        used |= props_of(pre) | set(post)
        for value in post.values():
            used |= props_of(value)
    unknown = sorted(used - set(model.props))
    if unknown:
        raise UnknownSymbolError(f"{where}: the event model uses proposition(s) {unknown} that {model_file} does "
                                 f"not have (it has {list(model.props)})")
    missing = sorted(set(model.agents) - set(events.agents))
    if missing:
        raise UnknownSymbolError(f"{where}: the event model has no relation for agent(s) {missing} of "
                                 f"{model_file}; give every agent of the model a relation")


def _load_pointed(path: str):
    """The Kripke model in ``path``; bad input if it has no designated world (every formula would hold)."""
    from delkit.errors import ModelError
    from delkit.io.formats import load_model

    m = load_model(path)
    if not m.designated:
        raise ModelError(f"{path}: the model has no designated world, so every formula would vacuously hold "
                         f"there; list the actual world(s) in \"designated\"")
    return m


def _write_or_print(text: str, output: Path | None, what: str, inputs: tuple[str, ...] = ()) -> None:
    if output is not None:
        from delkit.resources import check_outputs

        check_outputs([output], inputs, option="-o")  # never over the input file
    if output is None:
        sys.stdout.write(text if text.endswith("\n") else text + "\n")
        return
    from delkit.errors import DelkitError

    try:
        output.write_text(text if text.endswith("\n") else text + "\n", encoding="utf-8")
    except OSError as exc:
        raise DelkitError(f"{output}: cannot write the {what} ({exc.strerror}); check the directory") from None
    print(f"wrote {what} to {output}", file=sys.stderr)


def register(app: typer.Typer) -> None:
    """Attach ``delkit model …`` and ``delkit prove`` to the top-level app."""
    model = typer.Typer(help="Kripke and event model files (delkit's JSON or DOT; draw and diff also read SMCDEL's "
                             "language): check formulas, draw pictures (SVG, PNG, TikZ), export DOT, contract, "
                             "compare, check macros.",
                        no_args_is_help=True)
    app.add_typer(model, name="model")

    @model.command("check")
    def check(
        model_file: str = typer.Argument(..., metavar="MODEL", help="Kripke model (JSON schema of delkit.io.formats, "
                                                                    "or DOT)."),
        formula: str = typer.Argument(..., help="Formula, e.g. 'K_a p & ~K_b p' or 'C{a,b} p'."),
        event: list[str] = typer.Option([], "--event", "-e", metavar="NAME=FILE",
                                        help="Event model file for [NAME,e] in the formula (repeatable)."),
        as_json: bool = typer.Option(False, "--json", help="Print one JSON object."),
    ) -> None:
        """Truth of FORMULA at the designated worlds of MODEL, and the worlds where it holds."""
        from delkit.logic.formula import parse, show

        m = _load_pointed(model_file)
        f = parse(formula, events=_events_option(event, m, model_file))
        m.validate_symbols(f)
        vec = m.check(f)
        where = [m.world_name(w) for w in range(m.n_worlds) if vec[w]]
        ok = m.holds(f)
        blind = m.inconsistent_agents()
        if as_json:
            print(json.dumps({"formula": show(f), "holds": ok,
                              "designated": [m.world_name(d) for d in m.designated],
                              "true_at": where, "n_worlds": m.n_worlds,
                              "inconsistent_beliefs": [[a, m.world_name(w)] for a, w in blind]}))
        else:
            print(f"{show(f)}: {'holds' if ok else 'does NOT hold'} at the designated world(s) "
                  f"{', '.join(m.world_name(d) for d in m.designated) or '(none)'}")
            print(f"true at {len(where)} of {m.n_worlds} world(s): {', '.join(where) or '(none)'}")
            for a, w in blind:
                print(f"note: agent {a} has no accessible world at {m.world_name(w)} (believes everything there)")
        raise typer.Exit(0 if ok else 1)

    @model.command("dot")
    def dot(
        model_file: str = typer.Argument(..., metavar="MODEL", help="Kripke or event model (JSON)."),
        output: Path | None = typer.Option(None, "--output", "-o", help="Write the DOT here (default: stdout)."),
    ) -> None:
        """Graphviz DOT of a Kripke or event model (designated: double border; S5 edges undirected)."""
        from delkit.io.formats import load, to_dot

        _write_or_print(to_dot(load(model_file)), output, "DOT", (model_file,))

    @model.command("contract")
    def contract_cmd(
        model_file: str = typer.Argument(..., metavar="MODEL", help="Kripke model (JSON or DOT)."),
        output: Path | None = typer.Option(None, "--output", "-o", help="Write the JSON here (default: stdout)."),
    ) -> None:
        """Bisimulation contraction (quotient of the part generated by the designated worlds)."""
        from delkit.io.formats import dumps
        from delkit.models.bisimulation import contract

        m = _load_pointed(model_file)  # the contraction keeps the part generated by the designated worlds
        c = contract(m)
        _write_or_print(dumps(c), output, "contracted model", (model_file,))
        print(f"contracted {m.n_worlds} world(s) to {c.n_worlds}", file=sys.stderr)  # after: an error is one line

    @model.command("show")
    def show_cmd(
        model_file: str = typer.Argument(..., metavar="MODEL", help="Kripke or event model (JSON or DOT)."),
        as_json: bool = typer.Option(False, "--json", help="Print one JSON object."),
    ) -> None:
        """Check a model file and print a one-line summary (and its frame class)."""
        from delkit.io.formats import load
        from delkit.models.kripke import KripkeModel

        obj = load(model_file)
        frames = ([lg for lg in ("S5", "KD45") if not obj.frame_violations(lg)] or ["K"]
                  if isinstance(obj, KripkeModel) else None)
        if as_json:
            if isinstance(obj, KripkeModel):
                info = {"kind": "kripke-model", "worlds": obj.n_worlds, "props": list(obj.props),
                        "designated": [obj.world_name(d) for d in obj.designated], "frames": frames}
            else:
                info = {"kind": "event-model", "name": obj.name, "events": list(obj.events),
                        "designated": [obj.events[d] for d in obj.designated]}
            print(json.dumps({"file": model_file, **info, "agents": list(obj.agents)}))
            return
        print(repr(obj))
        if frames is not None:
            print(f"frame: {', '.join(frames)}")

    @model.command("diff")
    def diff_cmd(
        a: str = typer.Argument(..., metavar="A", help="Kripke model (JSON/DOT) or structure (.smcdel.txt)."),
        b: str = typer.Argument(..., metavar="B", help="Kripke model (JSON/DOT) or structure (.smcdel.txt)."),
        world_a: str | None = typer.Option(None, "--world-a", help="Point A at this world (a state such as "
                                           "'1,3' for .smcdel.txt); default: its designated worlds."),
        world_b: str | None = typer.Option(None, "--world-b", help="Point B at this world (as --world-a)."),
        props: str | None = typer.Option(None, "--props", help="Compare on these propositions only (p,q)."),
        max_worlds: int = typer.Option(4096, "--max-worlds", min=1,
                                       help="Largest explicit model of a symbolic structure."),
        engine: str = typer.Option("auto", "--engine", help="auto (symbolic for two .smcdel.txt files), symbolic "
                                   "(BDD partition refinement) or explicit (Kripke models)."),
        as_json: bool = typer.Option(False, "--json", help="Print one JSON object."),
    ) -> None:
        """Bisimilar (with the bisimulation) or a formula true in one and false in the other. Exit 0 = bisimilar,
        1 = told apart, 2 = bad input."""
        from delkit.cli.model_tools import run_diff

        raise typer.Exit(run_diff(a, b, world_a, world_b, props, max_worlds, as_json, engine))

    @model.command("draw")
    def draw_cmd(
        model_file: list[str] = typer.Argument(..., metavar="MODEL",
                                               help="Kripke/event model (JSON/DOT), structure (.smcdel.txt), or a "
                                                    "planning task (SPEC, or DOMAIN PROBLEM) with --plan."),
        output: Path = typer.Option(..., "--output", "-o", help="out.svg, out.png or out.tex (TikZ)."),
        max_worlds: int = typer.Option(64, "--max-worlds", min=0,
                                       help="Draw a structure's Kripke model only up to this many states."),
        layout: str = typer.Option("auto", "--layout", help="auto, layered, circle, spring or kamada-kawai."),
        seed: int = typer.Option(0, "--layout-seed", min=0, max=2**63 - 1, help="Seed of the spring layout."),
        plan: Path | None = typer.Option(None, "--plan", help="A plan file for the task: draw a state along it."),
        step: int = typer.Option(0, "--step", min=0, help="With a task: draw the state after this step (0: the "
                                                         "initial state)."),
    ) -> None:
        """Picture of a model or structure (no Graphviz needed): SVG, PNG or LaTeX/TikZ by the output's suffix.
        For a planning task, the initial state or (--plan, --step K) the state after step K."""
        from delkit.cli.model_tools import run_draw

        run_draw(model_file, output, max_worlds, layout, seed, plan=plan, step=step)

    @model.command("macro")
    def macro_cmd(
        macro_file: str = typer.Argument(..., metavar="MACRO", help="Event model of the macro (JSON)."),
        steps: list[str] = typer.Argument(..., metavar="STEP...", help="Event models it replaces, in order."),
        logic: str = typer.Option("S5", "--logic", "-l", help="Frame class for modal preconditions."),
        worlds: int = typer.Option(3, "--worlds", "-k", min=1, max=8, help="Bound for modal preconditions."),
        as_json: bool = typer.Option(False, "--json", help="Print one JSON object."),
    ) -> None:
        """Check (z3) that MACRO is the composition STEP1;STEP2;… (events matched by name)."""
        from delkit.errors import DelkitError
        from delkit.io.formats import load_event_model
        from delkit.verify import LOGICS, check_macro

        if logic.upper() not in LOGICS:  # an unknown frame class was silently accepted
            raise DelkitError(f"--logic {logic!r}: use one of {', '.join(LOGICS)}")

        res = check_macro(load_event_model(macro_file), [load_event_model(p) for p in steps], logic=logic,
                          worlds=worlds)
        if as_json:
            print(json.dumps({"equivalent": res.equivalent, "problems": list(res.problems),
                              "events_compared": res.events_compared, "bounded": res.bounded}))
        else:
            verdict = "equals" if res.equivalent else "does NOT equal"
            print(f"{macro_file} {verdict} the composition of {len(steps)} step(s) "
                  f"({res.events_compared} event(s) compared{', modal parts bounded' if res.bounded else ''})")
            for prob in res.problems:
                print(f"  - {prob}")
        raise typer.Exit(0 if res.equivalent else 1)

    @app.command("prove")
    def prove_cmd(
        formula: str = typer.Argument(..., help="Formula to prove, e.g. 'K_a p -> K_a K_a p'."),
        logic: str = typer.Option("S5", "--logic", "-l", help="Frame class: S5, KD45 or K."),
        worlds: int = typer.Option(4, "--worlds", "-k", min=1, max=12,
                                   help="Largest counter-model searched (number of worlds)."),
        timeout: float = typer.Option(60.0, "--timeout", min=0.0, help="Wall-clock limit in seconds from the start "
                                      "of the process (default 60; 0 or inf: none); reaching it is exit status 3."),
        as_json: bool = typer.Option(False, "--json", help="Print one JSON object."),
    ) -> None:
        """Is FORMULA valid? Searches (z3) a counter-model with at most --worlds worlds; prints it as JSON."""
        from delkit.errors import DelkitError
        from delkit.io.formats import dumps
        from delkit.logic.formula import parse, show
        from delkit.verify import LOGICS, prove

        if logic.upper() not in LOGICS:
            raise DelkitError(f"--logic {logic!r}: use one of {', '.join(LOGICS)}")
        from delkit.progress import progress
        from delkit.resources import counters, deadline

        counters()["worlds"] = worlds  # the size searched, for a limit answer
        with deadline(timeout, f"prove --worlds {worlds}", alarm=False), progress(quiet=as_json) as bar:
            # z3 runs in C (its own timeout, no SIGALRM): the bar shows the elapsed time while it searches
            bar.add_task(f"counter-models with ≤ {worlds} world(s) ({logic.upper()})", total=None)
            v = prove(parse(formula), logic=logic, worlds=worlds)
        if as_json:
            print(json.dumps(v.to_dict()))
        elif v.valid:
            kind = "valid" if v.exact else f"no counter-model with at most {v.worlds} world(s) ({v.logic})"
            print(f"{show(v.formula)}: {kind}")
        else:
            print(f"{show(v.formula)}: NOT valid in {v.logic}; counter-model (the formula is false at "
                  f"{v.counter_model.world_name(0)}):")
            print(dumps(v.counter_model))
        raise typer.Exit(0 if v.valid else 1)
