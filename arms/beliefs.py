"""The robots' belief state during execution: the planner's own DEL state, updated by the tasks' event models.

There is no second belief model. A :class:`BeliefState` holds one state of the planner's state space (the
``space`` the planner searched: ``planners.spaces.CompactSpace`` — compact bit-set backend — or ``DelSpace``
— numpy ``KripkeModel`` + product update), starting from the task's initial state. After every executed
task the executor applies *that task's* event model (``task.event_model(action, state)``, the mA* model
the planner itself applies), with the event chosen by what the simulation observed:

* a **sensing** task (``sense_table ?ag``): the observation (fluent ↦ truth value read by the camera)
  selects the one event of the sensing model whose precondition it satisfies — only that event is
  designated. If no designated world satisfies it, the observation contradicts the belief state: the
  contradicted fluents are revised (:meth:`revise`) and the sensing applied after the revision; an
  observation that does not decide every sensed fluent (occlusion) is refused;
* an **announcement**: heard → the task's event model; not heard (lost message; messages are acknowledged,
  so the speaker knows) → the same announcement with the listeners oblivious (their state is unchanged);
* an **ontic** task: its event model as the planner applies it.

:meth:`holds` evaluates any formula (the shield evaluates the task's precondition, epistemic parts
included), :meth:`valuation` is the actual world (the check compares it with the world read from physics),
:meth:`key` is the canonical bisimulation key (the check compares it with the plan's prediction),
:meth:`knowledge` lists the knowledge formulas ``K_a p`` / ``K_a ¬p`` that hold (the belief log).
:meth:`forget` is the public event "these fluents may have changed unnoticed" (every assignment one event,
nobody distinguishes them, all designated). **Evidence is never discarded**: an observation that contradicts
every actual world of the state is a named *belief revision* (:meth:`revise`): the public "may have
changed" event on exactly the fluents the observation contradicts (logged as ``kind: revision`` with what
was revised and why), after which the observation is applied as the sensing event it is. (DEL's product
update cannot remove a belief; this is the standard substitute — the forget-then-sense reading of
revision, not Baltag–Smets plausibility models.) :meth:`look` is a robot's own look at some fluents (it
fully observes, the other robots see it looking): what the mission's checks apply when a look disagrees
with the state.

This module uses delkit only; the planner's task and space are passed in (``arms`` does not need
``planners`` to import it).
"""

from __future__ import annotations

import itertools
import re
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, replace
from typing import Any

from delkit.logic.formula import BOT, TOP, And, Formula, K, Not, Prop, conj, show
from delkit.models.events import EventModel, action
from delkit.models.kripke import KripkeModel

__all__ = ["BeliefState", "BeliefError", "pretty", "BeliefEvent"]


def _literals(f: Formula) -> list[tuple[str, bool]] | None:
    """A conjunction of fluent literals as (fluent, value) pairs; None for any other formula."""
    parts = f.args if isinstance(f, And) else [] if f == TOP else [f]
    out = []
    for x in parts:
        if isinstance(x, Prop):
            out.append((x.name, True))
        elif isinstance(x, Not) and isinstance(x.arg, Prop):
            out.append((x.arg.name, False))
        else:
            return None
    return out


class BeliefError(Exception):
    """An event that cannot be applied to the belief state (message says which and why)."""


_FLUENT = re.compile(r"\b(hold|occup_by)_(robot\d+)_([A-Za-z]+)\b")


def pretty(text_or_formula: str | Formula) -> str:
    """A formula as people read it: ``K{robot2} hold_robot1_red`` → ``K_robot2 hold(robot1, red)``."""
    s = text_or_formula if isinstance(text_or_formula, str) else show(text_or_formula)
    s = _FLUENT.sub(lambda m: f"{m.group(1)}({m.group(2)}, {m.group(3)})", s)
    return re.sub(r"K\{([^},]+)\}", r"K_\1", s)


@dataclass(frozen=True)
class BeliefEvent:
    """One applied event: when, which task, how it was chosen, and the knowledge it added."""

    time: float
    task: str
    kind: str           # sensing / announcement / ontic / forget / revision / look / observation
    robot: str
    chosen: str         # e.g. "observed hold(robot1, red), ¬hold(robot1, black)" or "heard by robot2"
    learnt: tuple[str, ...] = ()
    observed: dict | None = None     # sensing: fluent ↦ value the camera read
    heard: bool = True               # announcement received
    forgot: tuple[str, ...] = ()     # forget: the fluents
    forced: bool = False             # applied with a false precondition (--no-shield only)
    public: str = ""                 # observe: the formula everybody observed (delkit syntax)
    revised: tuple[str, ...] = ()    # revision: what was believed of each revised fluent and what was seen

    def to_json(self) -> dict:
        return {"t_sim_s": round(self.time, 3), "task": self.task, "kind": self.kind, "robot": self.robot,
                "chosen": self.chosen, "learnt": list(self.learnt), "observed": self.observed, "heard": self.heard,
                "forgot": list(self.forgot), "forced": self.forced, "public": self.public,
                "revised": list(self.revised)}


class BeliefState:
    """The planner's DEL state as the robots' beliefs (see module docstring)."""

    def __init__(self, task: Any, space: Any, state: Any | None = None) -> None:
        self.task = task
        self.space = space
        self.compact = hasattr(space, "engine")
        self.backend = "compact" if self.compact else "numpy"
        self.state = space.initial()[0] if state is None else state
        self.log: list[BeliefEvent] = []

    # -- reading ------------------------------------------------------------------------------------
    def copy(self, state: Any | None = None) -> BeliefState:
        out = BeliefState(self.task, self.space, self.state if state is None else state)
        return out

    def holds(self, f: Formula) -> bool:
        """f holds in the state (at every designated world)."""
        return bool(self.space.holds(self.state, f))

    def kripke(self) -> KripkeModel:
        return self.space.to_kripke(self.state) if self.compact else self.state

    def key(self) -> Any:
        """Canonical key: equal iff the two (multi-)pointed states are bisimilar."""
        if self.compact:
            return self.state.key
        return self.space._key(self.state)[1]

    def valuation(self) -> dict[str, bool | None]:
        """Truth of every fluent at the actual world(s); None where designated worlds disagree."""
        props = self.task.props
        if self.compact:
            eng, s = self.space.engine, self.state
            vals = [s.val[p] for p in s.points]
            out = {}
            for p in props:
                bits = {(v >> eng.pidx[p]) & 1 for v in vals}
                out[p] = bool(bits.pop()) if len(bits) == 1 else None
            return out
        m = self.state
        out = {}
        for j, p in enumerate(m.props):
            bits = {bool(m.valuation[d, j]) for d in m.designated}
            out[p] = bits.pop() if len(bits) == 1 else None
        return {p: out.get(p) for p in props}

    def knowledge(self, agents: Iterable[str] | None = None) -> list[str]:
        """Every ``K_a p`` / ``K_a ¬p`` that holds (a ∈ agents, p a fluent), in readable form."""
        out = []
        for a in (agents or self.task.agents):
            for p in self.task.props:
                if self.holds(K(a, Prop(p))):
                    out.append(pretty(f"K{{{a}}} {p}"))
                elif self.holds(K(a, Not(Prop(p)))):
                    out.append(pretty(f"K{{{a}}} ¬{p}"))
        return out

    def differences(self, other: BeliefState) -> list[str]:
        """Readable formulas (fluents, K_a p, K_a ¬p) true in one state and not in the other."""
        out = []
        fs: list[Formula] = [Prop(p) for p in self.task.props]
        fs += [K(a, lit) for a in self.task.agents for p in self.task.props for lit in (Prop(p), Not(Prop(p)))]
        for f in fs:
            mine, theirs = self.holds(f), other.holds(f)
            if mine != theirs:
                out.append(f"{pretty(f)} is {'true' if mine else 'false'} in the belief state, "
                           f"{'true' if theirs else 'false'} in the plan's prediction")
        return out

    # -- updating -----------------------------------------------------------------------------------
    def _apply_em(self, em: EventModel, what: str) -> None:
        if self.compact:
            new = self.space.engine.apply(self.state, em)
            if new is not None and self.space.engine.believes_bottom(new):
                raise BeliefError(f"{what}: after it {', '.join(self.space.inconsistent(new))} would believe ⊥")
        else:
            from delkit.models.update import preconditions, product_update

            m = self.state
            pre = preconditions(m, em)
            des = list(em.designated)
            ok = all(bool(pre[w, des].any()) for w in m.designated)
            new = product_update(m, em) if ok else None
            if new is not None:
                bad = new.inconsistent_agents()
                if bad:
                    raise BeliefError(f"{what}: after it {', '.join(bad)} would believe ⊥")
                new = self.space._key(new)[0]
        if new is None:
            raise BeliefError(f"{what}: no actual world of the belief state satisfies the chosen event")
        self.state = new

    def _restrict(self, lit: Formula, what: str, *, force: bool = False) -> None:
        """Keep as actual only the designated worlds where ``lit`` holds (the observed outcome). ``force``
        (``--no-shield`` only): an observation that contradicts every actual world is believed anyway — the
        actual worlds become those where it holds (what an unguarded executor does)."""
        if self.compact and self._designated_bits(lit):
            # the same restriction on the compact state: an event per outcome of lit, nobody tells them apart,
            # only lit's designated — each world is kept once, the actual ones are those where lit holds
            em = action(self.task.agents, [("yes", lit, {}), ("no", Not(lit), {})], full=[],
                        partial=list(self.task.agents), designated=["yes"], name="restrict")
            new = self.space.engine.apply(self.state, em)
            if new is not None:
                self.state = new
                return
        m = self.kripke()
        truth = m.check(lit)
        des = tuple(int(w) for w in m.designated if truth[w])
        if not des and force:
            des = tuple(int(w) for w in range(m.n_worlds) if truth[w])
        if not des:
            raise BeliefError(f"{what}: the observation ({pretty(lit)}) contradicts every actual world of the "
                              "belief state")
        m = replace(m, designated=des, _cache={}) if "_cache" in m.__dataclass_fields__ else replace(m, designated=des)
        self.state = self.space.engine.from_kripke(m) if self.compact else self.space._key(m)[0]

    def event_model(self, name: str) -> EventModel | None:
        """The task's event model in the current state as the planner builds it (None: not executable)."""
        act = self.task.action(name)
        if self.compact and hasattr(self.space, "event_model_named"):
            return self.space.event_model_named(self.state, name)
        if not self.holds(act.executable):
            return None
        return self.task.event_model(act, self.kripke())

    def apply(self, name: str, *, robot: str = "", time: float = 0.0, observed: Mapping[str, bool] | None = None,
              heard: bool = True, force: bool = False) -> BeliefEvent:
        """Apply the event model of task ``name``; for sensing the event ``observed`` selects, for an
        announcement the listeners' model (``heard``). ``force`` (``--no-shield`` only) applies the event
        model even if the task's precondition does not hold in the belief state."""
        act = self.task.action(name)
        before = set(self.knowledge())
        em = self.event_model(name)
        forced = em is None
        if em is None:
            if not force:
                raise BeliefError(f"{name}: its precondition {pretty(act.executable)} does not hold in the "
                                  "belief state")
            em = self.task.event_model(replace(act, executable=TOP), self.kripke())
        chosen = "as planned"
        if act.kind == "sensing":
            if observed is None:
                raise BeliefError(f"{name}: a sensing task needs the sensor's observation")
            sensed = [f for f, _c in act.sensed]
            missing = [show(f) for f in sensed if f.name not in observed]  # type: ignore[attr-defined]
            if missing:
                raise BeliefError(f"{name}: the observation does not decide {', '.join(map(pretty, missing))}")
            # the sensing model as the planner applies it (all outcomes designated), then the actual worlds
            # are those where the observed outcome happened (single-pointed: the same as designating only the
            # observed event; multi-pointed after a forget: the observation removes the worlds it excludes)
            lit = conj([f if observed[f.name] else Not(f) for f in sensed])  # type: ignore[attr-defined]
            contra = self.contradicted({f.name: bool(observed[f.name]) for f in sensed})  # type: ignore
            if contra is not None and not force:
                # evidence is never discarded: the contradicted fluents are revised, then the task's sensing
                self.revise(contra, {p: bool(observed[p]) for p in contra}, time=time,
                            why=f"{robot}'s {name} contradicts every actual world")
                em = self.event_model(name)
                if em is None:
                    raise BeliefError(f"{name}: its precondition {pretty(act.executable)} does not hold after "
                                      "the revision")
            self._apply_em(em, name)
            self._restrict(lit, name, force=force)
            chosen = "observed " + ", ".join(pretty(("" if observed[f.name] else "¬") + f.name)  # type: ignore
                                             for f in sensed)
            em = None
        elif act.kind == "announcement" and not heard:
            phi = conj([f for f, _c in act.sensed]) if act.sensed else TOP
            em = action(self.task.agents, [("yes", phi, {}), ("no", Not(phi), {})], full=[robot], partial=[],
                        designated=["yes"], name=f"{name} (lost)")
            chosen = "lost: the listeners did not receive it (their state is unchanged)"
        elif act.kind == "announcement":
            chosen = "received by " + ", ".join(a for a in self.task.agents if a != robot)
        if em is not None:
            self._apply_em(em, name)
        learnt = tuple(k for k in self.knowledge() if k not in before)
        ev = BeliefEvent(time, name, act.kind, robot, chosen, learnt, dict(observed) if observed else None, heard,
                         forced=forced)
        self.log.append(ev)
        return ev

    def observe_public(self, phi: Formula, *, time: float = 0.0, what: str = "") -> BeliefEvent:
        """Everybody observes that ``phi`` holds (public announcement; e.g. "the shared table is empty")."""
        from delkit.models.events import sensing

        before = set(self.knowledge())
        # everybody senses phi (both outcomes designated), then the actual worlds are those where it holds
        self._apply_em(sensing(phi, self.task.agents, full=list(self.task.agents), name="observe"),
                       what or pretty(phi))
        self._restrict(phi, what or pretty(phi))
        ev = BeliefEvent(time, "observe", "observation", "", what or f"everybody sees {pretty(phi)}",
                         tuple(k for k in self.knowledge() if k not in before), public=show(phi))
        self.log.append(ev)
        return ev

    def forget(self, props: Iterable[str], *, time: float = 0.0, why: str = "") -> BeliefEvent:
        """The public event "``props`` may have changed unnoticed" (see module docstring)."""
        props = sorted(set(props))
        before = set(self.knowledge())
        outcomes = []
        for bits in itertools.product((True, False), repeat=len(props)):
            label = "".join("1" if b else "0" for b in bits)
            outcomes.append((f"f{label}", TOP, {p: (TOP if b else BOT) for p, b in zip(props, bits, strict=True)}))
        em = action(self.task.agents, outcomes, full=[], partial=list(self.task.agents), name="forget")
        self._apply_em(em, "forget " + ", ".join(map(pretty, props)))
        gone = tuple(k for k in before if k not in set(self.knowledge()))
        ev = BeliefEvent(time, "forget", "forget", "", why or ("may have changed: " + ", ".join(map(pretty, props))),
                         tuple(f"no longer: {g}" for g in gone), forgot=tuple(props))
        self.log.append(ev)
        return ev

    # -- revision and looks ---------------------------------------------------------------------------
    def _designated_bits(self, lit: Formula) -> bool:
        """Some designated world satisfies ``lit`` (compact backend and a conjunction of literals: read from
        the designated worlds' valuation bits, without building the Kripke model)."""
        lits = _literals(lit) if self.compact else None
        if lits is None:
            m = self.kripke()
            truth = m.check(lit)
            return any(bool(truth[w]) for w in m.designated)
        eng, st = self.space.engine, self.state
        return any(all(bool((st.val[w] >> eng.pidx[p]) & 1) == v for p, v in lits) for w in st.points)

    def contradicted(self, observed: Mapping[str, bool]) -> list[str] | None:
        """None if some actual world agrees with every observed fluent; else the fluents to revise: those
        whose observed value differs from the actual worlds' (all of them if the worlds disagree)."""
        lit = conj([Prop(p) if v else Not(Prop(p)) for p, v in observed.items()])
        if self._designated_bits(lit):
            return None
        val = self.valuation()
        out = [p for p, v in observed.items() if val.get(p) is not None and val[p] != v]
        return out or sorted(observed)

    def revise(self, props: Iterable[str], seen: Mapping[str, bool], *, time: float = 0.0,
               why: str = "") -> BeliefEvent:
        """Named belief revision: the public "may have changed" event on ``props`` (the fluents an
        observation contradicts; ``seen`` their observed values), logged as ``kind: revision``."""
        props = sorted(set(props))
        val = self.valuation()
        revised = tuple(f"{pretty(p)}: believed {str(val.get(p)).lower() if val.get(p) is not None else 'unknown'}"
                        f" at the actual world, seen {str(seen[p]).lower() if p in seen else 'undecided'}"
                        for p in props)
        ev = self.forget(props, time=time, why=why or "revision")
        ev = replace(ev, kind="revision", chosen=f"revision ({why or 'an observation contradicts the state'}): "
                     + ", ".join(map(pretty, props)) + " may have changed", revised=revised)
        self.log[-1] = ev
        return ev

    def look(self, robot: str, observed: Mapping[str, bool], *, time: float = 0.0, what: str = "",
             public: bool = False) -> BeliefEvent:
        """``robot`` looks and sees ``observed`` (fluent ↦ value): a sensing event per fluent in which it is
        the full observer and the other agents partial (they see it look), the observed outcome actual;
        ``public``: every robot looks at it (e.g. both side cameras at the shared table) and all see all. An
        observation that contradicts every actual world revises the contradicted fluents first."""
        from delkit.models.events import sensing

        observed = {p: bool(v) for p, v in observed.items()}
        contra = self.contradicted(observed)
        if contra is not None:
            self.revise(contra, {p: observed[p] for p in contra}, time=time,
                        why=f"{robot}'s look contradicts every actual world")
        before = set(self.knowledge())
        others = [] if public else [a for a in self.task.agents if a != robot]
        full = list(self.task.agents) if public else [robot]
        for p in sorted(observed):
            self._apply_em(sensing(Prop(p), self.task.agents, full=full, partial=others, name=f"look {p}"),
                           what or f"{robot} looks")
        self._restrict(conj([Prop(p) if v else Not(Prop(p)) for p, v in sorted(observed.items())]),
                       what or f"{robot} looks")
        kind = "observation" if public else "look"
        ev = BeliefEvent(time, "look", kind, robot, what or f"{robot} looks: " + ", ".join(
            pretty(("" if v else "¬") + p) for p, v in sorted(observed.items())),
            tuple(k for k in self.knowledge() if k not in before), observed=dict(observed),
            public="public" if public else "")
        self.log.append(ev)
        return ev
