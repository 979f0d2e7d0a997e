"""Plan and property checker: replay a plan in DEL semantics and say why it fails.

The replay uses the numpy backend (``delkit.models.update.product_update`` and ``delkit.models.bisimulation.contract``,
which
keeps every formula's truth and keeps the replay small; no contraction at all when the task mentions
distributed knowledge of a group), not the planner's compact backend, so a plan found by the planner is
checked independently of the planner's own state code. A small task (an initial state the reader built
without numpy, every replayed state small enough to stay uncontracted) is replayed with the same product
update written with plain lists (:mod:`planners.replay`: no numpy, which is most of a small check's start-up),
falling back to the numpy replay for anything else. A macro is replayed as its steps.
For each step A_i the checker verifies, in order:

1. the action exists;
2. M_{i-1}, s ⊨ exe(A_i) at the pointed world — if not, it names the failing conjunct and, for a belief
   B_a φ, the world that agent a considers possible where φ fails (recursively);
3. the update has a pointed world (a truthful announcement of a false φ has none);
4. no agent has an empty belief set at the pointed world of M_i (no vacuous success: B_a ⊥);
5. the properties: ``always φ`` on every M_0..M_n, ``eventually φ`` on some M_i, ``at end φ`` on M_n;

and finally the goal on M_n. The first failure is reported with its step (0 = initial state).
"""

from __future__ import annotations

import re
from pathlib import Path

from delkit._records import DataclassFields, Factory, Record
from delkit.errors import DelkitError, ParseError, io_reason
from delkit.logic.formula import And, C, D, E, Formula, K, Kw, Not, Or, Prop, agents_of, props_of, show, subformulas
from delkit.resources import TimeLimit, check_time, counters
from planners.replay import NeedNumpy, PlainState
from planners.replay import event_model as plain_events
from planners.replay import initial_state as plain_initial
from planners.replay import usable as plain_usable
from planners.task import ActionSpec, EventAction, MacroSpec, Task, apply_action, uncovered_worlds

TYPE_CHECKING = False  # typing.TYPE_CHECKING without importing typing (start-up: delkit._records)
if TYPE_CHECKING:
    from typing import Any, Literal

    from delkit.models.kripke import KripkeModel

    PropertyKind = Literal["always", "eventually", "at end"]
else:
    PropertyKind = str

__all__ = ["Property", "CheckResult", "check_plan", "parse_property", "read_plan", "parse_plan_text", "explain"]


class Property(Record):
    """A temporal property over the states M_0..M_n of a plan's execution (this module's records are frozen
    dataclass-compatible records written by hand for start-up time: :mod:`delkit._records`)."""

    __dataclass_fields__ = DataclassFields("kind", "formula", ("text", ""))
    kind: PropertyKind
    formula: Formula
    text: str

    def __init__(self, kind: PropertyKind, formula: Formula, text: str = "") -> None:
        self.__dict__.update(kind=kind, formula=formula, text=text)

    def __str__(self) -> str:
        return self.text or f"{self.kind} {show(self.formula)}"


class CheckResult(Record):
    """``valid`` or the first failure: its step (0 = initial state), action, kind and reason."""

    __dataclass_fields__ = DataclassFields("valid", "steps", ("step", None), ("action", None), ("kind", None),
                                           ("reason", ""), ("agent", None), ("world", None),
                                           ("details", Factory(dict)), ("inconsistent_beliefs", ()))
    valid: bool
    steps: int
    step: int | None
    action: str | None
    kind: str | None
    reason: str
    agent: str | None
    world: str | None
    details: dict
    #: EPDDL semantics keeps states where an agent believes ⊥: each such (step, action, agent, world)
    inconsistent_beliefs: tuple[dict, ...]

    def __init__(self, valid: bool, steps: int, step: int | None = None, action: str | None = None,
                 kind: str | None = None, reason: str = "", agent: str | None = None, world: str | None = None,
                 details: dict | None = None, inconsistent_beliefs: tuple[dict, ...] = ()) -> None:
        self.__dict__.update(valid=valid, steps=steps, step=step, action=action, kind=kind, reason=reason, agent=agent,
                             world=world, details={} if details is None else details,
                             inconsistent_beliefs=inconsistent_beliefs)

    def warnings(self) -> list[str]:
        """One line per state where EPDDL semantics kept an agent believing ⊥ (empty: none)."""
        return [f"step {b['step']} ({b['action']}) leaves agent {b['agent']} believing ⊥ at {b['world']}; EPDDL "
                f"keeps such states, so the plan is checked on (with --allow-inconsistent: no warning)"
                for b in self.inconsistent_beliefs]

    def to_json(self) -> dict[str, Any]:
        extra = {"inconsistent_beliefs": list(self.inconsistent_beliefs)} if self.inconsistent_beliefs else {}
        if self.valid:
            return {"valid": True, "steps": self.steps, **extra}
        out: dict[str, Any] = {"valid": False, "step": self.step, "action": self.action, "kind": self.kind,
                               "reason": self.reason}
        if self.agent is not None:
            out["agent"] = self.agent
        if self.world is not None:
            out["world"] = self.world
        out.update(self.details)
        out.update(extra)
        return out


# ----------------------------------------------------------------------------- inputs

_PDDL_STEP = re.compile(r"\(\s*([^()]+?)\s*\)")


def parse_plan_text(text: str) -> list[str]:
    """Action names from plan text: one per line, or separated by commas/whitespace; ``#``/``;``/``%``
    start comments except EFP's ``%%% Executed actions: ... %%%`` header; ``(open a)`` means ``open_a``."""
    names: list[str] = []
    for raw in text.splitlines():
        line = raw.strip()
        m = re.match(r"%%%\s*Executed actions:(.*?)%%%", line)
        if m:
            line = m.group(1)
        else:
            line = re.split(r"[#;%]", line, maxsplit=1)[0]
        line = _PDDL_STEP.sub(lambda mm: "_".join(mm.group(1).split()), line)
        names.extend(t for t in re.split(r"[\s,]+", line) if t)
    return names


def read_plan(path: str | Path) -> list[str]:
    """Read a plan file: plan text (see :func:`parse_plan_text`) or a JSON plan file (``delkit plan
    --plan-out``, :mod:`planners.plan_file`)."""
    from planners.plan_file import looks_like_json, parse_plan_json

    p = Path(path)
    try:
        from delkit.paths import read_input

        text = read_input(p, "plan file")
    except (OSError, UnicodeDecodeError) as exc:
        raise ParseError(f"cannot read the plan file: {io_reason(exc)}", source=str(p)) from None
    return parse_plan_json(text, str(p)) if looks_like_json(text) else parse_plan_text(text)


_PROP_RE = re.compile(r"^\s*(always|eventually|at\s+end)\s+(.+)$", re.S)


def parse_property(text: str, task: Task, *, source: str = "--property", line: int = 1) -> Property:
    """``always φ`` / ``eventually φ`` / ``at end φ``; φ in delkit syntax (``K_a p``, ``C{a,b} p``) or mA*
    syntax (``B(a, p)``, ``C([a,b], p)``, ``-p``). ``source``/``line`` say where the text came from (a
    properties file and its line), for the error messages."""
    m = _PROP_RE.match(text)
    bare = re.fullmatch(r"\s*(always|eventually|at\s+end)\s*", text)
    if bare:
        raise ParseError(f"property {text.strip()!r} has no formula after {bare.group(1)!r}; write e.g. "
                         f"'{bare.group(1)} K_a p'", source=source, line=line, column=len(text.rstrip()) + 1)
    if not m:
        raise ParseError(f"property {text!r} must start with 'always', 'eventually' or 'at end'",
                         source=source, line=line, column=1, expected=["always φ", "eventually φ", "at end φ"])
    kind = "at end" if m.group(1).startswith("at") else m.group(1)
    body = m.group(2).strip()
    try:
        f = parse_formula(body, task, source=source)
    except ParseError as exc:  # positions inside φ → positions in the property's line
        if exc.line != 1 or exc.column is None:
            raise
        raise ParseError(exc.bare_message, source=source, line=line, column=exc.column + m.start(2),
                         expected=exc.expected) from None
    except DelkitError as exc:
        raise type(exc)(f"{source}:{line}: {exc}") from None
    return Property(kind, f, text.strip())  # type: ignore[arg-type]


def parse_formula(body: str, task: Task, *, source: str = "<formula>") -> Formula:
    """A formula over the task's fluents/agents, in delkit or mA* syntax; unknown symbols are errors."""
    from delkit.logic.formula import parse
    from planners.lang.mastar import parse_mastar_formula

    clash = sorted({"T", "F", "true", "false"} & set(task.props))
    if clash:  # 'always T' would silently mean the constant, not the fluent
        raise ParseError(f"the task has a fluent named {clash[0]!r}, which formulas read as a constant; rename "
                         f"the fluent to check properties about it", source=source)
    try:
        f = parse(body, source=source)
        _validate_symbols(task, f)
        return f
    except DelkitError as first:
        try:
            return parse_mastar_formula(body, task, source=source)
        except ParseError as second:
            if isinstance(first, ParseError):
                # report the reading that got further into the text (mA* ``B(zz, p)``: its unknown agent)
                def pos(e: ParseError) -> tuple[int, int]:
                    return (e.line or 0, e.column or 0)

                raise (second if pos(second) > pos(first) else first) from None
            # e.g. an unknown agent or fluent: say which formula
            raise type(first)(f"{body!r}: {first}") from None


def _validate_symbols(task: Task, f: Formula) -> None:
    """``task.initial.validate_symbols(f)`` (the same errors), without building a numpy initial state."""
    m = task.plain_initial
    if m is None:
        task.initial.validate_symbols(f)
        return
    from delkit.errors import UnknownSymbolError

    bad_p = sorted(props_of(f) - set(m.props))
    if bad_p:
        raise UnknownSymbolError(f"formula mentions unknown proposition(s) {bad_p}; the model has {list(m.props)}")
    bad_a = sorted(agents_of(f) - set(m.agents))
    if bad_a:
        raise UnknownSymbolError(f"formula mentions unknown agent(s) {bad_a}; the model has {list(m.agents)}")


# ----------------------------------------------------------------------------- explanations

def _world_text(m: KripkeModel | PlainState, w: int) -> str:
    """A world by its name (the user's, for an explicit EPDDL initial state; ``w3`` otherwise) and its
    true fluents — the same name :meth:`KripkeModel.world_name` gives everywhere else in a message."""
    true = sorted(m.true_props(w))
    return f"{m.world_name(w)}{{{', '.join(true)}}}"


def explain(m: KripkeModel | PlainState, f: Formula, w: int, depth: int = 0) -> tuple[str, str | None, str | None]:
    """Why ``f`` is false at world ``w`` of ``m``: (text, agent, world) naming whose belief and which world
    (``m`` a KripkeModel, or the plain replay's :class:`~planners.replay.PlainState`)."""
    if depth > 6:
        return f"{show(f)} is false at {_world_text(m, w)}", None, _world_text(m, w)
    if isinstance(f, And):
        for g in f.args:
            if not m.check(g)[w]:
                return explain(m, g, w, depth + 1)
    if isinstance(f, Prop):
        return f"fluent {f.name} is false at {_world_text(m, w)}", None, _world_text(m, w)
    if isinstance(f, Not) and isinstance(f.arg, Prop):
        return f"fluent {f.arg.name} is true at {_world_text(m, w)}", None, _world_text(m, w)
    if isinstance(f, K):
        bad = [int(v) for v in m.relation(f.agent).successors(w) if not m.check(f.arg)[v]]
        if bad:
            inner, _, _ = explain(m, f.arg, bad[0], depth + 1)
            return (f"agent {f.agent} does not believe {show(f.arg)}: at {_world_text(m, w)} it considers "
                    f"possible {_world_text(m, bad[0])}, where {inner}", f.agent, _world_text(m, bad[0]))
    if isinstance(f, Kw):
        return f"agent {f.agent} does not know whether {show(f.arg)} at {_world_text(m, w)}", f.agent, \
            _world_text(m, w)
    if isinstance(f, Not) and isinstance(f.arg, K):
        return (f"agent {f.arg.agent} believes {show(f.arg.arg)} at {_world_text(m, w)} (the formula requires it "
                f"not to)", f.arg.agent, _world_text(m, w))
    if isinstance(f, (C, E)):
        reach = m.reachable([w], f.group) if isinstance(f, C) else None
        for a in f.group:
            for v in m.relation(a).successors(w):
                if not m.check(f.arg)[int(v)]:
                    inner, _, _ = explain(m, f.arg, int(v), depth + 1)
                    return (f"{show(f)} fails: agent {a} considers possible {_world_text(m, int(v))}, where "
                            f"{inner}", a, _world_text(m, int(v)))
        if reach is not None:
            good = m.check(f.arg)
            bad = [v for v in range(m.n_worlds) if reach[v] and not good[v] and v != w]
            if bad:
                return (f"{show(f)} fails: {_world_text(m, bad[0])} is reachable through the beliefs of "
                        f"{', '.join(f.group)} and there {show(f.arg)} is false", None, _world_text(m, bad[0]))
    if isinstance(f, Or):
        return f"none of the alternatives of {show(f)} holds at {_world_text(m, w)}", None, _world_text(m, w)
    return f"{show(f)} is false at {_world_text(m, w)}", None, _world_text(m, w)


# ----------------------------------------------------------------------------- replay

def _failing_world(m: KripkeModel | PlainState, f: Formula) -> int:
    """The first designated world where ``f`` fails (a multi-pointed state fails where one of them fails)."""
    vec = m.check(f)
    return next((int(w) for w in m.designated if not vec[int(w)]), int(m.designated[0]))


#: replayed models with more worlds than this are contracted after each step
_CONTRACT_ABOVE = 64


def _replay_one(task: Task, i: int, n: int, name: str, label: str, act: Any, model: KripkeModel | PlainState,
                allow_inconsistent: bool, kept: list | None = None) -> CheckResult | KripkeModel | PlainState:
    """One (non-macro) action at step ``i``: the new model, or the CheckResult saying why it fails.
    ``kept`` (EPDDL semantics): a state where an agent believes ⊥ is kept and recorded there instead. A
    :class:`~planners.replay.PlainState` is updated by the plain replay (no numpy)."""
    check_time()
    point = model.designated[0]
    if not model.holds(act.executable):
        bad_w = next((int(w) for w in model.designated if not model.check(act.executable)[int(w)]), point)
        why, ag, wd = explain(model, act.executable, bad_w)
        return CheckResult(False, n, i, name, "precondition",
                           f"step {i} ({label}) is not executable: precondition {show(act.executable)} fails — "
                           f"{why}", ag, wd, {"precondition": show(act.executable)})
    plain = isinstance(model, PlainState)
    if plain:
        from delkit.resources import memory_budget

        em = plain_events(task, act, model)
        if model.product_bytes_bound(em) > memory_budget()[0]:
            raise NeedNumpy("the numpy replay's memory estimate decides")  # it refuses with its own figure
    else:
        from delkit.resources import product_update_bytes, require

        em = task.event_model(act, model)
        # estimate before allocating (the replayed states are contracted, so this only trips on huge actions)
        require(product_update_bytes(model, em), f"replaying step {i} ({label})",
                "check a shorter plan or a smaller task")
    uncovered = uncovered_worlds(em, model) if isinstance(act, EventAction) else []
    if uncovered:
        # plank's updater: every designated world needs a designated event whose precondition holds there;
        # explained at the first designated world where none does, with each designated event's reason
        w = uncovered[0]
        labels = getattr(act, "event_labels", None) or em.events  # the user's events, not the type's slots
        whys = [f"event {labels[d]}: {explain(model, em.pre[d], w)[0]}" for d in em.designated]
        wname = model.world_name(w)
        return CheckResult(False, n, i, name, "not-applicable",
                           f"step {i} ({label}) is not applicable: at designated world {wname} no designated "
                           f"event's precondition holds ({'; '.join(whys)})", None, wname)
    if plain:
        new = model.product(em)
    else:
        from delkit.models.update import product_update

        new = product_update(model, em)
    if not new.designated:
        sensed = ", ".join(show(f) for f in act.active_sensed(model)) if isinstance(act, ActionSpec) else ""
        return CheckResult(False, n, i, name, "not-applicable",
                           f"step {i} ({label}): no event of the action can happen at the actual world"
                           + (f" (announced {sensed} is false there)" if sensed else ""), None,
                           _world_text(model, point))
    if not allow_inconsistent:
        inc = new.inconsistent_agents()
        if inc and kept is not None:
            kept.extend({"step": i, "action": label, "agent": ag, "world": _world_text(new, w)} for ag, w in inc)
        elif inc:
            ag, w = inc[0]
            return CheckResult(False, n, i, name, "inconsistent-belief",
                               f"step {i} ({label}) leaves agent {ag} with no accessible world at the actual "
                               f"world: {ag} believes ⊥ (everything), so no belief goal may count as reached",
                               ag, _world_text(new, w))
    return new


def check_plan(task: Task, plan: list[str] | tuple[str, ...], properties: list[Property] | tuple = (), *,
               allow_inconsistent: bool = False, require_goal: bool = True,
               plan_source: str = "plan", epddl: bool | None = None) -> CheckResult:
    """Replay ``plan`` from the task's initial state with delkit's product update (see module docstring).

    ``plan_source`` names the plan (e.g. its file) in the error for an action the task does not have.
    ``epddl`` (default: whether the task has :class:`EventAction` s, as the tasks read from EPDDL (2026) files
    do — the planner's ``space_for`` decides the same way) replays with EPDDL's semantics: a state where an
    agent believes ⊥ is never refused (K and KD45 states are legitimate there, and plank does not prune them),
    and recorded in ``CheckResult.inconsistent_beliefs`` (unless ``allow_inconsistent``), as a warning.

    Every replayed state is contracted (bisimulation; with the groups whose distributed knowledge the task or
    a property mentions refined like agents — collective bisimulation — and kept uncontracted only where
    that quotient would change a group's intersection relation), so checking costs about what planning does;
    a contracted world keeps the name of the first world it stands for."""
    if epddl is None:  # the planner's default semantics of inconsistent beliefs (planners.beliefs)
        from planners.beliefs import keeps_inconsistent

        epddl = keeps_inconsistent(task)
    kept: list[dict] = []
    res = None
    if plain_usable(task, [p.formula for p in properties], _CONTRACT_ABOVE):
        try:
            res = _check(task, plan, properties, allow_inconsistent, require_goal, plan_source, epddl, kept, True)
        except TimeLimit:
            raise
        except DelkitError:  # NeedNumpy, or an error the numpy replay reports in its own words
            kept.clear()
    if res is None:
        res = _check(task, plan, properties, allow_inconsistent, require_goal, plan_source, epddl, kept, False)
    if not kept:
        return res
    return CheckResult(res.valid, res.steps, res.step, res.action, res.kind, res.reason, res.agent, res.world,
                       res.details, tuple(kept))


def _contract(m: KripkeModel, groups: tuple[tuple[str, ...], ...]) -> KripkeModel:
    """The bisimulation contraction of ``m`` keeping its world names; for ``groups``, the collective one."""
    from delkit.models.bisimulation import quotient, refine
    from planners.spaces import with_group_relations

    g = m.generated()
    blocks = refine(with_group_relations(g, groups) if groups else g)
    if blocks.size and int(blocks.max()) + 1 == g.n_worlds:
        return g  # nothing to merge
    q = quotient(g, blocks, keep_names=True)
    for grp in groups:  # D_G is read on ⋂ R_a: the quotient must not add pairs to it
        inter = g.relations[grp[0]]
        qinter = q.relations[grp[0]]
        for a in grp[1:]:
            inter, qinter = inter.intersect(g.relations[a]), qinter.intersect(q.relations[a])
        coo = inter.to_matrix().tocoo()
        want = {(int(x), int(y)) for x, y in zip(blocks[coo.row], blocks[coo.col], strict=True)}
        qc = qinter.to_matrix().tocoo()
        if want != set(zip(qc.row.tolist(), qc.col.tolist(), strict=True)):
            return g
    return q


def _check(task: Task, plan, properties, allow_inconsistent: bool, require_goal: bool, plan_source: str,
           epddl: bool, kept: list[dict], plain: bool = False) -> CheckResult:
    """The replay; ``plain``: on :class:`~planners.replay.PlainState` s, raising NeedNumpy (the caller then
    replays on numpy) as soon as a state grows past ``_CONTRACT_ABOVE`` worlds."""
    names = {a.name for a in task.actions}
    for i, name in enumerate(plan, 1):
        if name not in names:
            from delkit.errors import PlanningError

            try:
                task.action(name)  # raises with suggestions
            except PlanningError as exc:
                raise PlanningError(f"{plan_source}: step {i}: {exc}") from None
            raise PlanningError(f"{plan_source}: step {i}: unknown action {name!r}")
    from planners.spaces import task_groups

    groups = tuple(sorted(set(task_groups(task)) | {tuple(sorted(set(g.group))) for pr in properties
                                                     for g in subformulas(pr.formula)
                                                     if isinstance(g, D) and len(set(g.group)) > 1}))
    if plain:
        model = plain_initial(task, groups)
    else:
        model = task.initial
        if model.n_worlds > _CONTRACT_ABOVE:
            model = _contract(model, groups)
    n = len(plan)
    seen_eventually = [False] * len(properties)

    def props_at(step: int, m: KripkeModel | PlainState, act: str | None) -> CheckResult | None:
        for j, pr in enumerate(properties):
            ok = m.holds(pr.formula)
            if pr.kind == "always" and not ok:
                why, ag, wd = explain(m, pr.formula, _failing_world(m, pr.formula))
                when = "in the initial state" if step == 0 else f"after step {step}"
                return CheckResult(False, n, step, act, "property", f"'{pr}' is violated {when}: {why}",
                                   ag, wd, {"property": str(pr)})
            if pr.kind == "eventually" and ok:
                seen_eventually[j] = True
        return None

    bad = props_at(0, model, None)
    if bad:
        return bad
    live = counters()  # steps replayed so far, for a limit answer
    for i, name in enumerate(plan, 1):
        live["steps_replayed"] = i - 1
        act = task.action(name)
        # a macro is replayed as its steps (Definition 4.1: Φ(j, Φ(i, s))); a failure names the step
        parts = [(f"{name} [macro part {j}/{len(act.steps)}: {st.name}]", st) for j, st in
                 enumerate(act.steps, 1)] if isinstance(act, MacroSpec) else [(name, act)]
        new = model
        for label, part in parts:
            bad = _replay_one(task, i, n, name, label, part, new, allow_inconsistent,
                              kept if epddl else None)
            if isinstance(bad, CheckResult):
                return bad
            new = bad
        # bisimulation contraction keeps every formula's truth at the actual world (properties, goal,
        # preconditions) and keeps the replay small: without it a 15-step plan doubled to 2^15 worlds; for
        # distributed knowledge the collective one (see _contract). Not for small models (contraction needs
        # scipy, whose import costs more than such a replay)
        if new.n_worlds <= _CONTRACT_ABOVE:
            model = new
        elif plain:
            raise NeedNumpy(f"step {i}: {new.n_worlds} worlds")
        else:
            model = _contract(new, groups)
        bad = props_at(i, model, name)
        if bad:
            return bad
    for j, pr in enumerate(properties):
        if pr.kind == "eventually" and not seen_eventually[j]:
            return CheckResult(False, n, n, plan[-1] if plan else None, "property",
                               f"'{pr}' never holds along the plan", details={"property": str(pr)})
        if pr.kind == "at end" and not model.holds(pr.formula):
            why, ag, wd = explain(model, pr.formula, _failing_world(model, pr.formula))
            return CheckResult(False, n, n, plan[-1] if plan else None, "property",
                               f"'{pr}' fails in the final state: {why}", ag, wd, {"property": str(pr)})
    if require_goal and not model.holds(task.goal):
        why, ag, wd = explain(model, task.goal, _failing_world(model, task.goal))
        return CheckResult(False, n, n, plan[-1] if plan else None, "goal",
                           f"the goal {show(task.goal)} does not hold after the plan"
                           f"{'' if n else ' (empty plan: in the initial state)'}: {why}", ag, wd)
    return CheckResult(True, n)


def final_state(task: Task, plan: list[str]) -> KripkeModel:
    """The state after executing ``plan`` (raises if a step is not executable)."""
    from delkit.errors import PlanningError

    model = task.initial
    for i, name in enumerate(plan, 1):
        new = apply_action(task, task.action(name), model)
        if new is None:
            raise PlanningError(f"step {i} ({name}) is not applicable (executability fails or no event can "
                                f"happen at the actual world)")
        model = new
    return model
