"""Event (action) models and the standard constructors.

An event model has events with a precondition (any formula) and postconditions (proposition ↦
formula, evaluated in the model *before* the update; propositions not mentioned keep their value), one
relation per agent over the events, and designated events.

The constructors follow the mA* semantics that EFP uses. Agents are split into *fully observant*
(see the action and its outcome), *partially observant* (see that the action happens, not its
outcome) and *oblivious* (believe nothing happened: they relate every event to the skip event ε,
whose precondition is ⊤ and which changes nothing). With oblivious agents the result is a KD45
(belief) model, no longer S5.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from delkit.errors import ModelError
from delkit.logic.formula import TOP, Formula, Not, Or, Prop, conj, is_propositional, parse, show
from delkit.models.relation import Relation

__all__ = [
    "EventModel", "public_announcement", "private_announcement", "semi_private_announcement",
    "announcement", "sensing", "ontic", "skip", "action",
]


def _f(x: Formula | str) -> Formula:
    return parse(x) if isinstance(x, str) else x


@dataclass(frozen=True, eq=False)
class EventModel:
    """An event model ``(Ev, Q, pre, post, Ev_d)``; hashable by identity (it is immutable)."""

    events: tuple[str, ...]
    agents: tuple[str, ...]
    pre: tuple[Formula, ...]
    post: tuple[Mapping[str, Formula], ...]
    relations: Mapping[str, Relation]
    designated: tuple[int, ...]
    name: str = "E"

    def __post_init__(self) -> None:
        k = len(self.events)
        if len(set(self.events)) != k:
            raise ModelError(f"event model {self.name!r}: duplicate event names {self.events}")
        if len(set(self.agents)) != len(self.agents):
            raise ModelError(f"event model {self.name!r}: duplicate agent names {list(self.agents)}")
        if len(self.pre) != k or len(self.post) != k:
            raise ModelError(f"event model {self.name!r}: {k} events but {len(self.pre)} preconditions and "
                             f"{len(self.post)} postcondition maps")
        object.__setattr__(self, "pre", tuple(_f(p) for p in self.pre))
        object.__setattr__(self, "post", tuple({p: _f(v) for p, v in m.items()} for m in self.post))
        for e, m in zip(self.events, self.post, strict=True):
            for p, v in m.items():
                if not is_propositional(v):
                    raise ModelError(f"event {e!r} of {self.name!r}: postcondition of {p!r} must be propositional, "
                                     f"got {show(v)}")
        missing = [a for a in self.agents if a not in self.relations]
        if missing:
            raise ModelError(f"event model {self.name!r}: no relation for agent(s) {missing}")
        for a, r in self.relations.items():
            if r.n != k:
                raise ModelError(f"event model {self.name!r}: relation of {a!r} on {r.n} events, expected {k}")
        des = tuple(sorted(set(int(d) for d in self.designated)))
        if not des:
            raise ModelError(f"event model {self.name!r} has no designated event")
        if any(d < 0 or d >= k for d in des):
            raise ModelError(f"event model {self.name!r}: designated event out of range 0..{k - 1}")
        object.__setattr__(self, "designated", des)
        object.__setattr__(self, "relations", dict(self.relations))

    # ------------------------------------------------------------------ building
    @staticmethod
    def build(events: Mapping[str, Mapping[str, Any]], relations: Mapping[str, Any],
              designated: Iterable[str], *, agents: Iterable[str] | None = None, name: str = "E") -> EventModel:
        """Readable constructor.

        ``events`` maps each event name to ``{"pre": φ, "post": {p: ψ}}`` (strings or formulas);
        ``relations[a]`` is a list of blocks of event names (a partition) or ``{"pairs": [(e, f), ...]}``.
        """
        names = tuple(events)
        idx = {e: i for i, e in enumerate(names)}

        def ev(x: str) -> int:
            if x not in idx:
                raise ModelError(f"event model {name!r}: unknown event {x!r}; events are {list(names)}")
            return idx[x]

        pre = tuple(_f(events[e].get("pre", TOP)) for e in names)
        post = tuple({p: _f(v) for p, v in events[e].get("post", {}).items()} for e in names)
        rels: dict[str, Relation] = {}
        for a, spec in relations.items():
            if isinstance(spec, Relation):
                rels[a] = spec
            elif isinstance(spec, Mapping):
                rels[a] = Relation.from_pairs(len(names), [(ev(x), ev(y)) for x, y in spec["pairs"]])
            else:
                rels[a] = Relation.from_blocks(len(names), [[ev(x) for x in blk] for blk in spec])
        return EventModel(names, tuple(agents) if agents is not None else tuple(relations), pre, post, rels,
                          tuple(ev(d) for d in designated), name)

    @property
    def n_events(self) -> int:
        return len(self.events)

    def event_index(self, e: str | int) -> int:
        if isinstance(e, int):
            return e
        try:
            return self.events.index(e)
        except ValueError:
            raise ModelError(f"event model {self.name!r} has no event {e!r}; events: {list(self.events)}") from None

    def relation(self, agent: str) -> Relation:
        try:
            return self.relations[agent]
        except KeyError:
            raise ModelError(f"event model {self.name!r} has no relation for agent {agent!r} "
                             f"(its agents: {list(self.agents)})") from None

    def renamed(self, name: str) -> EventModel:
        return EventModel(self.events, self.agents, self.pre, self.post, self.relations, self.designated, name)

    def changed_props(self) -> set[str]:
        """Propositions some event may change."""
        return {p for m in self.post for p, v in m.items() if v != Prop(p)}

    def _repr_svg_(self) -> str:
        """Inline picture in Jupyter (see :mod:`delkit.drawing.draw`)."""
        from delkit.drawing.draw import picture

        return picture(self).svg()

    def __repr__(self) -> str:
        return (f"EventModel({self.name!r}, events={list(self.events)}, agents={list(self.agents)}, "
                f"designated={[self.events[d] for d in self.designated]})")


# ----------------------------------------------------------------------------- constructors

def _agent_names(names: Iterable[str], what: str, name: str) -> tuple[str, ...]:
    """Agent names as a tuple; a bare string is an error (tuple("robot1") would be its letters)."""
    if isinstance(names, str):
        raise ModelError(f"{name}: {what} must be a list of agent names, e.g. [{names!r}], not the string "
                         f"{names!r}")
    return tuple(names)


def action(agents: Sequence[str], outcomes: Sequence[tuple[str, Formula | str, Mapping[str, Formula | str]]],
           *, full: Iterable[str], partial: Iterable[str] = (), designated: Iterable[str] | None = None,
           name: str = "action") -> EventModel:
    """The general mA* frame.

    ``outcomes`` are the "real" events ``(name, pre, post)``. Fully observant agents distinguish all
    outcomes; partially observant ones confuse all of them with each other; every other agent is
    oblivious and maps every event to the skip event ``ε`` (added automatically when someone is
    oblivious). ``designated`` defaults to all outcomes (the one whose precondition holds is actual).
    """
    agents = _agent_names(agents, "agents", name)
    full_s, partial_s = set(_agent_names(full, "full", name)), set(_agent_names(partial, "partial", name))
    unknown = (full_s | partial_s) - set(agents)
    if unknown:
        raise ModelError(f"{name}: observer(s) {sorted(unknown)} are not agents ({list(agents)})")
    if full_s & partial_s:
        raise ModelError(f"{name}: agent(s) {sorted(full_s & partial_s)} both fully and partially observant")
    oblivious = [a for a in agents if a not in full_s | partial_s]
    names = [o[0] for o in outcomes]
    pres = [_f(o[1]) for o in outcomes]
    posts = [{p: _f(v) for p, v in o[2].items()} for o in outcomes]
    k = len(outcomes)
    if oblivious:
        names.append("eps")
        pres.append(TOP)
        posts.append({})
    n = len(names)
    rels: dict[str, Relation] = {}
    for a in agents:
        if a in full_s:
            rels[a] = Relation.identity(n)
        elif a in partial_s:
            lab = np.zeros(n, dtype=np.int64)
            if oblivious:
                lab[k] = 1
            rels[a] = Relation.from_labels(lab)
        else:
            rels[a] = Relation.from_pairs(n, [(i, k) for i in range(n)])
    des = [names.index(d) for d in designated] if designated is not None else list(range(k))
    return EventModel(tuple(names), agents, tuple(pres), tuple(posts), rels, tuple(des), name)


def skip(agents: Sequence[str], name: str = "skip") -> EventModel:
    """The trivial update (one event, precondition ⊤, no change)."""
    return action(agents, [("skip", TOP, {})], full=agents, name=name)


def public_announcement(phi: Formula | str, agents: Sequence[str], name: str = "announce") -> EventModel:
    """[!φ]: one event with precondition φ that everyone sees. M ⊗ E ≅ M|φ."""
    return action(agents, [("e", phi, {})], full=agents, name=name)


def private_announcement(phi: Formula | str, group: Iterable[str], agents: Sequence[str],
                         name: str = "private") -> EventModel:
    """φ is announced to ``group`` only; everyone else believes nothing happened (oblivious)."""
    return action(agents, [("e", phi, {})], full=group, name=name)


def semi_private_announcement(phi: Formula | str, group: Iterable[str], agents: Sequence[str],
                              name: str = "semi_private") -> EventModel:
    """``group`` learns whether φ; every other agent sees that it does, but not the answer."""
    group = list(_agent_names(group, "group", name))
    phi = _f(phi)
    others = [a for a in agents if a not in group]
    return action(agents, [("yes", phi, {}), ("no", Not(phi), {})], full=group, partial=others, name=name)


def announcement(phi: Formula | str, agents: Sequence[str], *, full: Iterable[str], partial: Iterable[str] = (),
                 name: str = "announcement") -> EventModel:
    """mA* announcement of φ (true): full observers learn φ, partial observers learn that the full
    observers learned whether φ, the rest are oblivious. Designated: the event where φ holds."""
    phi = _f(phi)
    return action(agents, [("yes", phi, {}), ("no", Not(phi), {})], full=full, partial=partial,
                  designated=["yes"], name=name)


def sensing(phi: Formula | str, agents: Sequence[str], *, full: Iterable[str], partial: Iterable[str] = (),
            pre: Formula | str = TOP, name: str = "sense") -> EventModel:
    """mA* sensing ("determines φ"): full observers learn the actual truth value of φ, partial observers
    learn that they did, the rest are oblivious. Both outcomes are designated; the actual one survives."""
    phi, pre = _f(phi), _f(pre)
    return action(agents, [("yes", conj([pre, phi]), {}), ("no", conj([pre, Not(phi)]), {})], full=full,
                  partial=partial, name=name)


def ontic(effects: Mapping[str, Formula | str | bool] | Iterable[tuple[str, Formula | str | bool, Formula | str]],
          agents: Sequence[str], *, full: Iterable[str], partial: Iterable[str] = (), pre: Formula | str = TOP,
          name: str = "ontic") -> EventModel:
    """Ontic action: sets propositions. ``effects`` maps p to its new value (a bool or a formula), or is a
    list of conditional effects ``(p, value, condition)``: p becomes value where condition holds, else
    keeps its value. Full (and partial) observers see the change; the rest are oblivious."""
    post: dict[str, Formula] = {}
    items = effects.items() if isinstance(effects, Mapping) else None
    if items is not None:
        for p, v in items:
            post[p] = _val(v)
    else:
        for p, v, cond in effects:  # type: ignore[misc]
            value, c = _val(v), _f(cond)
            old = post.get(p, Prop(p))
            post[p] = Or((conj([c, value]), conj([Not(c), old])))
    full_all = list(full) + list(partial)
    return action(agents, [("e", pre, post)], full=full_all, name=name)


def _val(v: Formula | str | bool) -> Formula:
    if isinstance(v, bool):
        from delkit.logic.formula import BOT

        return TOP if v else BOT
    return _f(v)
