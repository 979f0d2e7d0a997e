"""The states along a plan: ``delkit check --trace`` (text) and ``--trace-json FILE`` (for scripts), and the
frames of ``delkit view TASK PLAN`` / ``delkit model draw TASK --plan PLAN --step K``.

:func:`trace_plan` replays the plan with the transitions :func:`planners.validate.check_plan` uses — the
action's event model in the state (``Task.event_model``), delkit's product update, and the checker's
contraction rule (contract a state above ``_CONTRACT_ABOVE`` worlds, never for EPDDL tasks or tasks with
distributed knowledge of a group) — and records for every step: the action, its event model, which worlds
satisfy its executability condition, the product M ⊗ E before contraction, the contracted model, the state
carried on (the one the checker carries), what changed (worlds, facts and knowledge at the designated
worlds) and the goal's truth. The verdict is the checker's own (:func:`check_plan` is called), so the trace
never disagrees with ``delkit check``; it stops at the step where the checker stops.
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from typing import Any

from delkit.logic.formula import Formula, Kw, Prop, show
from delkit.models.kripke import KripkeModel

__all__ = ["Step", "Trace", "trace_plan", "state_json", "trace_text", "emit_trace"]


@dataclass
class Step:
    """One step of the trace (step 0: the initial state, no action)."""

    index: int
    action: str | None
    before: KripkeModel | None
    state: KripkeModel
    carried: str = "product"            # which model is the state: "initial", "product" or "contracted"
    events: list[Any] = field(default_factory=list)        # event model(s): one per macro part
    parts: list[str] = field(default_factory=list)
    precondition: Formula | None = None
    pre_worlds: list[int] = field(default_factory=list)    # worlds of ``before`` where exe(A) holds
    product: KripkeModel | None = None
    contracted: KripkeModel | None = None
    goal: bool = False
    failed: str = ""

    def to_json(self, prev: KripkeModel | None) -> dict:
        from delkit.io.formats import to_dict

        out: dict[str, Any] = {"step": self.index, "action": self.action, "state": state_json(self.state),
                               "carried": self.carried, "goal": self.goal}
        if self.action is not None:
            out["parts"] = self.parts
            out["precondition"] = {"formula": show(self.precondition) if self.precondition is not None else "⊤",
                                   "worlds": [_name(self.before, w) for w in self.pre_worlds]}
            out["event_models"] = [to_dict(e) for e in self.events]
            out["product_worlds"] = None if self.product is None else self.product.n_worlds
            out["contracted_worlds"] = None if self.contracted is None else self.contracted.n_worlds
        if prev is not None:
            out["changed"] = changes(prev, self.state)
        if self.failed:
            out["failed"] = self.failed
        return out


@dataclass
class Trace:
    steps: list[Step]
    verdict: dict
    goal: str

    def to_json(self) -> dict:
        out = []
        for i, s in enumerate(self.steps):
            out.append(s.to_json(self.steps[i - 1].state if i else None))
        return {"goal": self.goal, "verdict": self.verdict, "steps": out}


def _name(m: KripkeModel | None, w: int) -> str:
    return m.world_name(w) if m is not None else str(w)


def state_json(m: KripkeModel) -> dict:
    """A state for scripts: worlds (name, true propositions, designated) and each agent's pairs (indices)."""
    des = {int(d) for d in m.designated}
    return {"n_worlds": m.n_worlds,
            "worlds": [{"name": m.world_name(w), "true": sorted(m.true_props(w)), "designated": w in des}
                       for w in range(m.n_worlds)],
            "relations": {a: sorted([int(x), int(y)] for x, y in m.relations[a].pairs()) for a in m.agents}}


def changes(prev: KripkeModel, cur: KripkeModel) -> dict:
    """What changed at the designated worlds: facts (a proposition's truth) and who knows whether what."""
    facts = {}
    for p in cur.props:
        if p in prev.props:
            a, b = _truth(prev, Prop(p)), _truth(cur, Prop(p))
            if a != b:
                facts[p] = [a, b]
    learned, forgot = [], []
    for ag in cur.agents:
        for p in cur.props:
            f = Kw(ag, Prop(p))
            before, after = prev.holds(f), cur.holds(f)
            if after and not before:
                learned.append(f"{ag} now knows whether {p}")
            elif before and not after:
                forgot.append(f"{ag} no longer knows whether {p}")
    return {"worlds": [prev.n_worlds, cur.n_worlds], "facts": facts, "learned": learned, "forgot": forgot}


def _truth(m: KripkeModel, f: Formula) -> str:
    vec = m.check(f)
    vals = {bool(vec[int(d)]) for d in m.designated}
    return "true" if vals == {True} else ("false" if vals == {False} else "mixed")


def trace_plan(task: Any, plan: list[str], *, allow_inconsistent: bool = False, plan_source: str = "plan") -> Trace:
    """The states along ``plan`` (see the module docstring); the verdict is :func:`check_plan`'s."""
    import numpy as np

    from delkit.models.bisimulation import contract
    from delkit.models.update import product_update
    from planners import validate
    from planners.spaces import task_groups
    from planners.task import MacroSpec, has_event_actions

    verdict = validate.check_plan(task, plan, allow_inconsistent=allow_inconsistent, plan_source=plan_source)
    epddl = has_event_actions(task)
    keep = epddl or bool(task_groups(task))
    above = getattr(validate, "_CONTRACT_ABOVE", 64)
    model = task.initial
    steps = [Step(0, None, None, model, "initial", goal=model.holds(task.goal))]
    last = verdict.step if not verdict.valid else len(plan)
    for i, name in enumerate(plan, 1):
        if last is not None and i > last:
            break
        act = task.action(name)
        parts = list(act.steps) if isinstance(act, MacroSpec) else [act]
        step = Step(i, name, model, model, parts=[p.name for p in parts])
        step.precondition = parts[0].executable
        step.pre_worlds = [int(w) for w in np.flatnonzero(model.check(parts[0].executable))]
        cur = model
        for part in parts:
            if not cur.holds(part.executable):
                step.failed = f"precondition of {part.name} fails"
                break
            em = task.event_model(part, cur)
            step.events.append(em)
            new = product_update(cur, em)
            if not new.designated:
                step.failed = f"no event of {part.name} can happen at the actual world"
                break
            cur = new
        if step.failed:
            step.failed = verdict.reason or step.failed
            steps.append(step)
            break
        step.product = cur
        step.contracted = contract(cur) if cur.n_worlds <= 5000 else None
        if keep or cur.n_worlds <= above:
            step.state, step.carried = cur, "product"
        else:
            step.state, step.carried = (step.contracted if step.contracted is not None else contract(cur)), \
                "contracted"
        step.goal = step.state.holds(task.goal)
        model = step.state
        steps.append(step)
        if not verdict.valid and i == verdict.step:
            step.failed = verdict.reason
    return Trace(steps, verdict.to_json(), show(task.goal))


# ------------------------------------------------------------------------------------------ text


def _relation_text(m: KripkeModel, a: str) -> str:
    rel = m.relations[a]
    if rel.labels is not None or (rel.is_reflexive() and rel.is_symmetric() and rel.is_transitive()):
        classes: dict[frozenset, None] = {}
        for w in range(m.n_worlds):
            classes.setdefault(frozenset(int(v) for v in rel.successors(w)), None)
        return " ".join("{" + ", ".join(m.world_name(w) for w in sorted(c)) + "}" for c in classes)
    pairs = [f"{m.world_name(int(x))}→{m.world_name(int(y))}" for x, y in rel.pairs()]
    return ", ".join(pairs) or "(none)"


def state_text(m: KripkeModel, indent: str = "  ", max_worlds: int = 32) -> list[str]:
    des = {int(d) for d in m.designated}
    lines = [f"{indent}{m.n_worlds} world(s), designated: {', '.join(m.world_name(d) for d in sorted(des))}"]
    if m.n_worlds > max_worlds:
        return lines + [f"{indent}(worlds not listed above {max_worlds}; use --trace-json)"]
    for w in range(m.n_worlds):
        mark = "*" if w in des else " "
        lines.append(f"{indent}{mark} {m.world_name(w)}: {{{', '.join(sorted(m.true_props(w)))}}}")
    for a in m.agents:
        lines.append(f"{indent}  {a}: {_relation_text(m, a)}")
    return lines


def trace_text(tr: Trace) -> str:
    out = []
    for s in tr.steps:
        if s.action is None:
            out.append("step 0 (initial state)")
        else:
            out.append(f"step {s.index}: {s.action}" + (f" (macro: {', '.join(s.parts)})" if len(s.parts) > 1 else ""))
            pre = show(s.precondition) if s.precondition is not None else "⊤"
            where = ", ".join(_name(s.before, w) for w in s.pre_worlds)
            out.append(f"  executable if {pre}: holds at {where or 'no world'}")
            if s.failed:
                out.append(f"  FAILS: {s.failed}")
                continue
            sizes = [f"{len(e.events)} event(s)" for e in s.events]
            out.append(f"  event model: {'; '.join(sizes)}; M ⊗ E: {s.product.n_worlds} world(s)"
                       + (f", contracted: {s.contracted.n_worlds}" if s.contracted is not None else "")
                       + f"; carried on: {s.carried}")
        out += state_text(s.state)
        if s.index:
            ch = changes(tr.steps[s.index - 1].state, s.state)
            what = [f"{p}: {a} → {b}" for p, (a, b) in ch["facts"].items()] + ch["learned"] + ch["forgot"]
            out.append(f"  changed: {'; '.join(what) if what else 'nothing at the designated world(s)'}")
        out.append(f"  goal {tr.goal}: {'holds' if s.goal else 'does not hold'}")
    return "\n".join(out)


def emit_trace(task: Any, steps: list[str], *, text: bool, json_path: Any, allow_inconsistent: bool = False,
               plan_source: str = "plan", echo: Any = print) -> None:
    """``delkit check --trace`` / ``--trace-json FILE`` ('-': stdout): print and/or write the trace."""
    tr = trace_plan(task, steps, allow_inconsistent=allow_inconsistent, plan_source=plan_source)
    if text:
        echo(trace_text(tr))
    if json_path is not None:
        data = json.dumps(tr.to_json(), indent=1)
        if str(json_path) == "-":
            echo(data)
            return
        from pathlib import Path

        from delkit.errors import DelkitError

        try:
            Path(json_path).write_text(data + "\n", encoding="utf-8")
        except OSError as exc:
            raise DelkitError(f"{json_path}: cannot write the trace ({exc.strerror}); check the directory") from None
