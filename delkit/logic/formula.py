"""Formulas of dynamic epistemic logic: an immutable, hashable AST.

Grammar of the text syntax (see :func:`parse`; :func:`show` prints it back so that
``parse(show(f)) == f``)::

    φ ::= p | T | F | ~φ | φ & φ | φ | φ | φ -> φ | φ <-> φ | (φ)
        | K_a φ | B_a φ | Kw_a φ          knowledge / belief (box) of agent a, knowing whether
        | M_a φ | <a> φ                   a considers φ possible (diamond: ~K_a ~φ)
        | E{a,b} φ | C{a,b} φ | D{a,b} φ  everybody / common / distributed knowledge of a group
        | Dkw{a,b} φ | Ckw{a,b} φ         distributed / common knowing whether (D_G φ ∨ D_G ¬φ, C_G φ ∨ C_G ¬φ)
        | [!φ] φ | <!φ> φ                public announcement  [!φ]ψ, and its diamond ~[!φ]~ψ
        | [E,e] φ | <E,e> φ               update with event e of the event model named E, and its diamond

Agent names after ``K_`` (``B_``, ``Kw_``, ``M_``, ``<…>``) are letters and digits; other names are written in
braces: ``K{robot_1} p``, ``M{robot_1} p``, ``<{robot_1}> p``. ``B_a`` is read as ``K_a`` (on KD45 models the
box is belief). ``~`` may also be written ``!`` or ``¬``. The diamonds are abbreviations: ``M_a φ`` is parsed
to ``~K_a ~φ`` (so every backend evaluates it), and :func:`show` prints that back as ``~K_a ~φ`` unless asked
for ``diamonds=True``. Binding: unary operators bind tightest, then ``&``, ``|``, ``->`` (right associative),
``<->``; ``&``, ``|`` and ``<->`` chains are flat (``<->`` groups to the left).
"""

from __future__ import annotations

import re
from collections.abc import Iterable, Mapping, Sequence
from functools import lru_cache

from delkit._records import DataclassFields, frozen_delattr, frozen_setattr
from delkit.errors import ParseError

TYPE_CHECKING = False  # typing.TYPE_CHECKING without importing typing (start-up: delkit._records)
if TYPE_CHECKING:
    from typing import Any, Protocol
else:
    Protocol = object  # EventModelLike is a typing.Protocol for the type checkers

__all__ = [
    "Dkw", "Ckw",
    "Formula", "Top", "Bot", "Prop", "Not", "And", "Or", "Implies", "Iff", "K", "Kw", "E", "C", "D",
    "Announce", "Update", "TOP", "BOT", "parse", "show", "conj", "disj", "props_of", "agents_of",
    "subformulas", "substitute", "is_propositional", "modal_depth",
]


class EventModelLike(Protocol):
    """What the formula language needs of the event model E of an update formula [E,e]ψ: its event names,
    preconditions and postconditions. :class:`delkit.models.events.EventModel` is one; formulas do not import
    it (event models are built from formulas, so the dependency points from events to formulas)."""

    @property
    def events(self) -> Sequence[str]: ...

    @property
    def pre(self) -> Sequence[Formula]: ...

    @property
    def post(self) -> Sequence[Mapping[str, Formula]]: ...


_init = object.__setattr__  # the records' own __init__ (their __setattr__ refuses)


def _cached_hash(self: Formula) -> int:
    """The hash of the fields' tuple, computed once per object; subformulas without a cached hash are hashed
    first, bottom-up without recursion, so that deeply nested formulas (a stack of 400 announcements)
    hash in linear time and without RecursionError."""
    h = getattr(self, "_hash", None)  # a missing slot is an AttributeError caught in C (a raise here costs ~1 µs)
    if h is not None:
        return h
    try:  # subformulas usually have their hash already: one step
        h = self._field_hash()
    except RecursionError:  # a deep chain of fresh subformulas: bottom-up below
        pass
    else:
        _init(self, "_hash", h)
        return h
    stack: list[tuple[Formula, bool]] = [(self, False)]
    while stack:
        f, ready = stack.pop()
        if ready:
            if not hasattr(f, "_hash"):
                _init(f, "_hash", f._field_hash())
            continue
        stack.append((f, True))
        stack.extend((c, False) for c in children(f) if not hasattr(c, "_hash"))
    return self._hash


class Formula:
    """Base class of all formulas. Supports ``~f``, ``f & g``, ``f | g``, ``f >> g`` (implication).

    Formulas are immutable (assigning raises ``dataclasses.FrozenInstanceError``), compared and hashed by
    their fields, printed by ``repr`` as ``K(agent='a', arg=Prop(name='p'))`` and pickled by their fields; the
    :mod:`dataclasses` functions (``fields``, ``replace``, ``is_dataclass``) work on them. The classes are
    written by hand rather than with ``@dataclass`` (start-up time: see :mod:`delkit._records`).

    Hashes are computed once per object and cached (slot ``_hash``): formulas are dictionary keys in the
    evaluators' caches, and without the cache hashing a deep formula is linear in its size each time. The
    value is that of the tuple of the fields (as a frozen dataclass's).
    """

    __slots__ = ("_hash",)
    __match_args__: tuple[str, ...] = ()
    __setattr__ = frozen_setattr
    __delattr__ = frozen_delattr

    def __invert__(self) -> Formula:
        return Not(self)

    def __and__(self, other: Formula) -> Formula:
        return And((self, other))

    def __or__(self, other: Formula) -> Formula:
        return Or((self, other))

    def __rshift__(self, other: Formula) -> Formula:
        return Implies(self, other)

    def __str__(self) -> str:
        return show(self)

    __hash__ = _cached_hash

    def __repr__(self) -> str:
        inner = ", ".join(f"{n}={getattr(self, n)!r}" for n in self.__match_args__)
        return f"{type(self).__name__}({inner})"

    def __reduce__(self) -> tuple:
        return (type(self), tuple(getattr(self, n) for n in self.__match_args__))


class _Nullary(Formula):
    __slots__ = ()
    __dataclass_fields__ = DataclassFields()

    def __init__(self) -> None:
        pass

    def __eq__(self, other: object) -> bool:
        return True if other.__class__ is self.__class__ else NotImplemented

    __hash__ = _cached_hash

    def _field_hash(self) -> int:
        return hash(())


class Top(_Nullary):
    """⊤, true everywhere."""

    __slots__ = ()


class Bot(_Nullary):
    """⊥, false everywhere."""

    __slots__ = ()


TOP = Top()
BOT = Bot()


class Prop(Formula):
    """An atomic proposition."""

    __slots__ = ("name",)
    __match_args__ = ("name",)
    __dataclass_fields__ = DataclassFields("name")
    name: str

    def __init__(self, name: str) -> None:
        _init(self, "name", name)

    def __eq__(self, other: object) -> bool:
        if other.__class__ is self.__class__:
            return self is other or self.name == other.name  # type: ignore[attr-defined]
        return NotImplemented

    __hash__ = _cached_hash

    def _field_hash(self) -> int:
        return hash((self.name,))


class Not(Formula):
    __slots__ = ("arg",)
    __match_args__ = ("arg",)
    __dataclass_fields__ = DataclassFields("arg")
    arg: Formula

    def __init__(self, arg: Formula) -> None:
        _init(self, "arg", arg)

    def __eq__(self, other: object) -> bool:
        if other.__class__ is self.__class__:
            a, b = self.arg, other.arg  # type: ignore[attr-defined]
            return a is b or a == b
        return NotImplemented

    __hash__ = _cached_hash

    def _field_hash(self) -> int:
        return hash((self.arg,))


class _Nary(Formula):
    __slots__ = ("args",)
    __match_args__ = ("args",)
    __dataclass_fields__ = DataclassFields("args")
    args: tuple[Formula, ...]

    def __init__(self, args: Iterable[Formula]) -> None:
        _init(self, "args", tuple(args))

    def __eq__(self, other: object) -> bool:
        if other.__class__ is self.__class__:
            return self is other or self.args == other.args  # type: ignore[attr-defined]
        return NotImplemented

    __hash__ = _cached_hash

    def _field_hash(self) -> int:
        return hash((self.args,))


class And(_Nary):
    """Conjunction of any number of formulas (the empty conjunction is ⊤)."""

    __slots__ = ()


class Or(_Nary):
    """Disjunction of any number of formulas (the empty disjunction is ⊥)."""

    __slots__ = ()


class _Binary(Formula):
    __slots__ = ("left", "right")
    __match_args__ = ("left", "right")
    __dataclass_fields__ = DataclassFields("left", "right")
    left: Formula
    right: Formula

    def __init__(self, left: Formula, right: Formula) -> None:
        _init(self, "left", left)
        _init(self, "right", right)

    def __eq__(self, other: object) -> bool:
        if other.__class__ is self.__class__:
            a, b = self.left, other.left  # type: ignore[attr-defined]
            if a is b or a == b:
                a, b = self.right, other.right  # type: ignore[attr-defined]
                return a is b or a == b
            return False
        return NotImplemented

    __hash__ = _cached_hash

    def _field_hash(self) -> int:
        return hash((self.left, self.right))


class Implies(_Binary):
    __slots__ = ()


class Iff(_Binary):
    __slots__ = ()


class _Agent(Formula):
    __slots__ = ("agent", "arg")
    __match_args__ = ("agent", "arg")
    __dataclass_fields__ = DataclassFields("agent", "arg")
    agent: str
    arg: Formula

    def __init__(self, agent: str, arg: Formula) -> None:
        _init(self, "agent", agent)
        _init(self, "arg", arg)

    def __eq__(self, other: object) -> bool:
        if other.__class__ is self.__class__:
            if self.agent != other.agent:  # type: ignore[attr-defined]
                return False
            a, b = self.arg, other.arg  # type: ignore[attr-defined]
            return a is b or a == b
        return NotImplemented

    __hash__ = _cached_hash

    def _field_hash(self) -> int:
        return hash((self.agent, self.arg))


class K(_Agent):
    """K_a φ: φ holds in every world agent a considers possible (belief on KD45 models)."""

    __slots__ = ()


class Kw(_Agent):
    """Kw_a φ = K_a φ ∨ K_a ¬φ: agent a knows whether φ."""

    __slots__ = ()


def _group(agents: Iterable[str]) -> tuple[str, ...]:
    return tuple(sorted(set(agents)))


class _Group(Formula):
    __slots__ = ("group", "arg")
    __match_args__ = ("group", "arg")
    __dataclass_fields__ = DataclassFields("group", "arg")
    group: tuple[str, ...]
    arg: Formula

    def __init__(self, group: Iterable[str], arg: Formula) -> None:
        _init(self, "group", _group(group))
        _init(self, "arg", arg)

    def __eq__(self, other: object) -> bool:
        if other.__class__ is self.__class__:
            if self.group != other.group:  # type: ignore[attr-defined]
                return False
            a, b = self.arg, other.arg  # type: ignore[attr-defined]
            return a is b or a == b
        return NotImplemented

    __hash__ = _cached_hash

    def _field_hash(self) -> int:
        return hash((self.group, self.arg))


class E(_Group):
    """E_G φ = ⋀_{a∈G} K_a φ: everybody in G knows φ."""

    __slots__ = ()


class C(_Group):
    """C_G φ: φ holds in every world reachable in one or more steps of ⋃_{a∈G} R_a."""

    __slots__ = ()


class D(_Group):
    """D_G φ: φ holds in every world reachable by ⋂_{a∈G} R_a (distributed knowledge)."""

    __slots__ = ()


class Announce(Formula):
    """[!φ]ψ: if φ is true, ψ holds after φ is publicly announced."""

    __slots__ = ("announced", "arg")
    __match_args__ = ("announced", "arg")
    __dataclass_fields__ = DataclassFields("announced", "arg")
    announced: Formula
    arg: Formula

    def __init__(self, announced: Formula, arg: Formula) -> None:
        _init(self, "announced", announced)
        _init(self, "arg", arg)

    def __eq__(self, other: object) -> bool:
        if other.__class__ is self.__class__:
            return (self.announced, self.arg) == (other.announced, other.arg)  # type: ignore[attr-defined]
        return NotImplemented

    __hash__ = _cached_hash

    def _field_hash(self) -> int:
        return hash((self.announced, self.arg))


class Update(Formula):
    """[E,e]ψ: if pre(e) holds, ψ holds after the update with event model E at event e.

    ``event`` is an event index or name of ``model``; ``name`` is how the model is written in text.
    """

    __slots__ = ("model", "event", "arg", "name")
    __match_args__ = ("model", "event", "arg", "name")
    __dataclass_fields__ = DataclassFields("model", "event", "arg", ("name", "E"))
    model: EventModelLike
    event: int
    arg: Formula
    name: str

    def __init__(self, model: EventModelLike, event: int, arg: Formula, name: str = "E") -> None:
        _init(self, "model", model)
        _init(self, "event", event)
        _init(self, "arg", arg)
        _init(self, "name", name)

    def __eq__(self, other: object) -> bool:
        if other.__class__ is self.__class__:
            return ((self.model, self.event, self.arg, self.name)
                    == (other.model, other.event, other.arg, other.name))  # type: ignore[attr-defined]
        return NotImplemented

    __hash__ = _cached_hash

    def _field_hash(self) -> int:
        return hash((self.model, self.event, self.arg, self.name))


# ----------------------------------------------------------------------------- helpers


def Dkw(group: Iterable[str], arg: Formula) -> Formula:  # noqa: N802 - named like the operator (SMCDEL's Dkw)
    """Distributed knowing whether, ``D_G φ ∨ D_G ¬φ`` (SMCDEL's ``Dkw``): the group's pooled information
    settles φ. A derived form, so every backend evaluates it; text syntax ``Dkw{a,b} φ``."""
    return Or((D(group, arg), D(group, Not(arg))))


def Ckw(group: Iterable[str], arg: Formula) -> Formula:  # noqa: N802 - named like the operator (SMCDEL's Ckw)
    """Common knowing whether, ``C_G φ ∨ C_G ¬φ`` (SMCDEL's ``Ckw``); text syntax ``Ckw{a,b} φ``."""
    return Or((C(group, arg), C(group, Not(arg))))


def conj(parts: Iterable[Formula]) -> Formula:
    """Conjunction, flattened; ⊤ for no parts and the part itself for one."""
    flat: list[Formula] = []
    for p in parts:
        if isinstance(p, And):
            flat.extend(p.args)
        elif not isinstance(p, Top):
            flat.append(p)
    if not flat:
        return TOP
    return flat[0] if len(flat) == 1 else And(flat)


def disj(parts: Iterable[Formula]) -> Formula:
    """Disjunction, flattened; ⊥ for no parts and the part itself for one."""
    flat: list[Formula] = []
    for p in parts:
        if isinstance(p, Or):
            flat.extend(p.args)
        elif not isinstance(p, Bot):
            flat.append(p)
    if not flat:
        return BOT
    return flat[0] if len(flat) == 1 else Or(flat)


def children(f: Formula) -> tuple[Formula, ...]:
    """Immediate subformulas."""
    if isinstance(f, (And, Or)):
        return f.args
    if isinstance(f, (Implies, Iff)):
        return (f.left, f.right)
    if isinstance(f, Announce):
        return (f.announced, f.arg)
    if isinstance(f, (Not, K, Kw, E, C, D, Update)):
        return (f.arg,)
    return ()


def subformulas(f: Formula) -> Iterable[Formula]:
    """All subformulas, each once, children before parents (does not enter event models)."""
    seen: set[Formula] = set()
    order: list[Formula] = []
    stack: list[tuple[Formula, bool]] = [(f, False)]
    while stack:
        g, done = stack.pop()
        if done:
            if g not in seen:
                seen.add(g)
                order.append(g)
            continue
        if g in seen:
            continue
        stack.append((g, True))
        for c in children(g):
            stack.append((c, False))
    return order


def props_of(f: Formula) -> set[str]:
    """Proposition names occurring in f (and in the pre- and postconditions of event models it mentions)."""
    out: set[str] = set()
    for g in subformulas(f):
        if isinstance(g, Prop):
            out.add(g.name)
        elif isinstance(g, Update):
            for pre in g.model.pre:
                out |= props_of(pre)
            for post in g.model.post:
                for p, val in post.items():
                    out.add(p)
                    out |= props_of(val)
    return out


def agents_of(f: Formula) -> set[str]:
    """Agent names occurring in f."""
    out: set[str] = set()
    for g in subformulas(f):
        if isinstance(g, (K, Kw)):
            out.add(g.agent)
        elif isinstance(g, (E, C, D)):
            out |= set(g.group)
    return out


def is_propositional(f: Formula) -> bool:
    """True if f has no modal or dynamic operator."""
    return all(isinstance(g, (Top, Bot, Prop, Not, And, Or, Implies, Iff)) for g in subformulas(f))


def modal_depth(f: Formula) -> int:
    """Nesting depth of K/Kw/E/C/D/dynamic operators."""
    if isinstance(f, (K, Kw, E, C, D)):
        return 1 + modal_depth(f.arg)
    if isinstance(f, Announce):
        return 1 + max(modal_depth(f.announced), modal_depth(f.arg))
    if isinstance(f, Update):
        return 1 + modal_depth(f.arg)
    cs = children(f)
    return max((modal_depth(c) for c in cs), default=0)


def substitute(f: Formula, mapping: Mapping[str, Formula]) -> Formula:
    """Replace propositions by formulas everywhere in f (used to compose postconditions)."""
    if isinstance(f, Prop):
        return mapping.get(f.name, f)
    if isinstance(f, (Top, Bot)):
        return f
    if isinstance(f, Not):
        return Not(substitute(f.arg, mapping))
    if isinstance(f, And):
        return And(substitute(a, mapping) for a in f.args)
    if isinstance(f, Or):
        return Or(substitute(a, mapping) for a in f.args)
    if isinstance(f, Implies):
        return Implies(substitute(f.left, mapping), substitute(f.right, mapping))
    if isinstance(f, Iff):
        return Iff(substitute(f.left, mapping), substitute(f.right, mapping))
    raise ValueError(f"substitute is only defined on propositional formulas, not on {show(f)}")


# ----------------------------------------------------------------------------- printing

_EVENT_NAME = r"^[A-Za-z_][A-Za-z0-9_.']*$"  # compiled on first use (re's cache): start-up
_PREC = {Iff: 1, Implies: 2, Or: 3, And: 4}
_ATOMIC = 9


def _agent(a: str) -> str:
    x = a[:-1] if a.endswith("\n") else a  # as re.match(r"^[A-Za-z0-9]+$", a), without compiling it at import
    return f"_{a}" if x.isascii() and x.isalnum() else "{" + a + "}"


def _group_text(g: tuple[str, ...]) -> str:
    return "{" + ",".join(g) + "}"


def _prec(f: Formula) -> int:
    return _PREC.get(type(f), _ATOMIC)


def show(f: Formula, *, diamonds: bool = False) -> str:
    """Print a formula in the text syntax; :func:`parse` reads it back to an equal formula.

    With ``diamonds=True`` the duals are printed as diamonds: ``~K_a ~φ`` as ``M_a φ``, ``~[!ψ]~φ`` as
    ``<!ψ> φ``, ``~[E,e]~φ`` as ``<E,e> φ`` (the default keeps the boxes, as delkit has always printed)."""
    return _show(f, diamonds)


def _event_text(f: Update) -> str:
    ev = f.model.events[f.event]
    if not re.match(_EVENT_NAME, ev):
        import json

        ev = json.dumps(ev)
    return ev


def _show(f: Formula, dia: bool) -> str:
    if dia and isinstance(f, Not) and isinstance(f.arg, (K, Announce, Update)) and isinstance(f.arg.arg, Not):
        box, inner = f.arg, f.arg.arg.arg
        if isinstance(box, K):
            return "M" + _agent(box.agent) + " " + _wrap(inner, _ATOMIC, dia)
        if isinstance(box, Announce):
            return "<!" + _show(box.announced, dia) + "> " + _wrap(inner, _ATOMIC, dia)
        return f"<{box.name},{_event_text(box)}> " + _wrap(inner, _ATOMIC, dia)
    if isinstance(f, Top):
        return "T"
    if isinstance(f, Bot):
        return "F"
    if isinstance(f, Prop):
        return f.name
    if isinstance(f, Not):
        return "~" + _wrap(f.arg, _ATOMIC, dia)
    if isinstance(f, And):
        if not f.args:
            return "T"
        if len(f.args) == 1:
            return "(" + _show(f.args[0], dia) + " & T)"
        return " & ".join(_wrap(a, _PREC[And] + 1, dia) for a in f.args)
    if isinstance(f, Or):
        if not f.args:
            return "F"
        if len(f.args) == 1:
            return "(" + _show(f.args[0], dia) + " | F)"
        return " | ".join(_wrap(a, _PREC[Or] + 1, dia) for a in f.args)
    if isinstance(f, Implies):
        return _wrap(f.left, _PREC[Implies] + 1, dia) + " -> " + _wrap(f.right, _PREC[Implies], dia)
    if isinstance(f, Iff):
        return _wrap(f.left, _PREC[Iff] + 1, dia) + " <-> " + _wrap(f.right, _PREC[Iff] + 1, dia)
    if isinstance(f, K):
        return "K" + _agent(f.agent) + " " + _wrap(f.arg, _ATOMIC, dia)
    if isinstance(f, Kw):
        return "Kw" + _agent(f.agent) + " " + _wrap(f.arg, _ATOMIC, dia)
    if isinstance(f, (E, C, D)):
        return type(f).__name__ + _group_text(f.group) + " " + _wrap(f.arg, _ATOMIC, dia)
    if isinstance(f, Announce):
        return "[!" + _show(f.announced, dia) + "] " + _wrap(f.arg, _ATOMIC, dia)
    if isinstance(f, Update):
        return f"[{f.name},{_event_text(f)}] " + _wrap(f.arg, _ATOMIC, dia)
    raise TypeError(f"not a formula: {f!r}")


def _wrap(f: Formula, min_prec: int, dia: bool) -> str:
    text = _show(f, dia)
    return text if _prec(f) >= min_prec else "(" + text + ")"


# ----------------------------------------------------------------------------- parsing

_GRAMMAR = r"""
?start: iff
?iff: imp ("<->" imp)*            -> iff_chain
?imp: disj ("->" imp)?            -> imp
?disj: conj ("|" conj)*           -> or_chain
?conj: unary ("&" unary)*         -> and_chain
?unary: NOT unary                 -> neg
      | KOP unary                 -> k
      | KWOP unary                -> kw
      | KBRACE agentname "}" unary  -> kbrace
      | KWBRACE agentname "}" unary -> kwbrace
      | GROUPOP agents "}" unary  -> grp
      | GROUPWOP agents "}" unary -> grpw
      | "[" "!" iff "]" unary     -> announce
      | "[" NAME "," (NAME | QUOTED) "]" unary -> update
      | MOP unary                 -> m
      | DIAOP unary               -> m_angle
      | MBRACE agentname "}" unary  -> mbrace
      | DIABRACE agentname "}" ">" unary -> mbrace
      | "<" "!" iff ">" unary     -> announce_dia
      | "<" NAME "," (NAME | QUOTED) ">" unary -> update_dia
      | atom
?atom: "T"                        -> top
     | "F"                        -> bot
     | "true"                     -> top
     | "false"                    -> bot
     | NAME                       -> prop
     | "(" iff ")"
agents: (agentname ("," agentname)*)?
agentname: NAME

NOT: "~" | "!" | "¬"
KOP.3: /(K|B)_[A-Za-z0-9]+/
KWOP.4: /Kw_[A-Za-z0-9]+/
KBRACE.3: /(K|B)\{/
KWBRACE.4: /Kw\{/
GROUPOP.3: /[ECD]\{/
MOP.3: /M_[A-Za-z0-9]+/
MBRACE.3: /M\{/
DIAOP.3: /<[A-Za-z0-9]+>/
DIABRACE.3: /<\{/
GROUPWOP.4: /(Dkw|Ckw)\{/
NAME: /[A-Za-z_][A-Za-z0-9_.']*/
QUOTED: /"([^"\\]|\\.)*"/
%ignore /[ \t\r\n]+/
%ignore /#[^\n]*/
"""


@lru_cache(maxsize=1)
def _parser() -> Any:
    from delkit.logic._larkcache import build_lark

    return build_lark("formula", _GRAMMAR, propagate_positions=False, maybe_placeholders=False)


_TOKEN_NAMES = {
    "NOT": "~", "KOP": "K_a", "KWOP": "Kw_a", "KBRACE": "K{agent}", "KWBRACE": "Kw{agent}",
    "GROUPOP": "C{a,b}/E{..}/D{..}", "MOP": "M_a", "MBRACE": "M{agent}", "DIAOP": "<a>", "DIABRACE": "<{agent}>",
    "LESSTHAN": "<", "MORETHAN": ">", "NAME": "a name", "LPAR": "(", "RPAR": ")", "LSQB": "[",
    "GROUPWOP": "Dkw{a,b}/Ckw{..}",
    "RSQB": "]", "AMPERSAND": "&", "VBAR": "|", "COMMA": ",", "RBRACE": "}", "BANG": "!",
    "$END": "end of formula", "T": "T", "F": "F", "TRUE": "true", "FALSE": "false",
}


def _token_name(name: str) -> str:
    """Readable name of a lark terminal (anonymous ones such as ``->`` are looked up in the grammar)."""
    if name in _TOKEN_NAMES:
        return _TOKEN_NAMES[name]
    try:
        return str(_parser().get_terminal(name).pattern.value)
    except Exception:  # noqa: BLE001 - unknown to the grammar: keep lark's name
        return name


def parse(text: str, *, events: Mapping[str, EventModelLike] | None = None, source: str = "<formula>",
          line_offset: int = 0, column_offset: int = 0) -> Formula:
    """Parse the text syntax into a :class:`Formula`.

    ``events`` maps names used in ``[E,e]`` to event models. Errors raise :class:`ParseError` with the
    line and column in ``source`` (offsets let callers report positions inside a larger file).
    """
    if not text.strip():
        raise ParseError("empty formula; write e.g. 'K_a p & ~K_b p'", source=source,
                         line=1 + line_offset, column=1 + column_offset)
    fast = _fast_parse(text)
    if fast is not None:
        return fast
    try:
        tree = _parser().parse(text)
    except _lark_errors()[0] as exc:
        tok = exc.token
        expected = sorted({_token_name(t) for t in exc.expected})
        if tok.type == "$END":
            lines = text.splitlines() or [""]
            line, column, shown = len(lines), len(lines[-1]) + 1, "end of formula"
        else:
            line, column, shown = exc.line, exc.column, repr(str(tok))
        raise ParseError(f"unexpected {shown}", source=source, line=line + line_offset,
                         column=column + (column_offset if line == 1 else 0),
                         expected=expected) from None
    except _lark_errors()[1] as exc:
        raise ParseError(f"unexpected character {text[exc.pos_in_stream]!r}", source=source,
                         line=exc.line + line_offset,
                         column=exc.column + (column_offset if exc.line == 1 else 0)) from None
    except _lark_errors()[2] as exc:
        lines = text.splitlines() or [""]
        raise ParseError("formula ends too early", source=source, line=len(lines) + line_offset,
                         column=len(lines[-1]) + 1,
                         expected=sorted({_token_name(t) for t in exc.expected})) from None
    except _lark_errors()[3] as exc:  # pragma: no cover - other lark errors
        raise ParseError(str(exc), source=source) from None
    return _Build(events or {}, source).build(tree)


def _lark_errors() -> tuple:
    from lark.exceptions import UnexpectedCharacters, UnexpectedEOF, UnexpectedInput, UnexpectedToken

    return UnexpectedToken, UnexpectedCharacters, UnexpectedEOF, UnexpectedInput


# ----------------------------------------------------------------------------- the fast reader
# Most formulas a user types (properties of `delkit check -p`, goals, formulas in specs) use the connectives,
# K/B/Kw/M with an agent, E/C/D/Dkw/Ckw with a group and <a>; for those text :func:`_fast_parse` builds the
# formula the grammar's parser would, by recursive descent over the same tokens, without importing lark
# (≈ 0.1 s of a small `delkit check -p` run). It reads the grammar's tokens as lark's contextual lexer does
# (terminals tried in lark's order: priority, then length; NAME where only an agent name may follow), and
# answers None — and the lark parser reads the text — for anything else: announcements, [E,e], <!φ>, <{…}>,
# quoted names, and every text with an error (so the error messages stay lark's). tests/cli/test_startup.py
# checks it against the lark parser on random formulas and random token strings.
_FAST_TOKEN = (r"[ \t\r\n]+|#[^\n]*|(?P<kw>Kw_[A-Za-z0-9]+)|(?P<brace>(?:Dkw|Ckw|Kw|[KBECDM])\{)"
               r"|(?P<k>[KB]_[A-Za-z0-9]+)|(?P<m>M_[A-Za-z0-9]+)|(?P<dia><[A-Za-z0-9]+>)|(?P<name>[A-Za-z_][A-Za-z0-9_.']*)|(?P<sym><->|->|[~!¬&|()])")
_FAST_NAME = r"(?:[ \t\r\n]+|#[^\n]*)*([A-Za-z_][A-Za-z0-9_.']*)(?:[ \t\r\n]+|#[^\n]*)*"
_KEYWORDS = {"T": TOP, "F": BOT, "true": TOP, "false": BOT}


class _NotFast(Exception):
    """The fast reader does not take this text: the lark parser reads it."""


def _fast_parse(text: str) -> Formula | None:
    """The formula of ``text`` as :func:`parse` builds it, or None (see the comment above)."""
    try:
        return _FastReader(text).read()
    except (_NotFast, RecursionError):
        return None


class _FastReader:
    """Recursive descent over the tokens, lexed on demand from ``pos`` (agent names in braces by NAME alone)."""

    __slots__ = ("text", "pos", "kind", "tok", "end", "_lex")

    def __init__(self, text: str) -> None:
        self.text = text
        self._lex = re.compile(_FAST_TOKEN).match
        self.pos = 0
        self.kind, self.tok, self.end = self._next(0)

    def _next(self, pos: int) -> tuple[str, str, int]:
        """The kind of the token at or after ``pos`` (its regex group; '' at the end), its text, its end."""
        text, n = self.text, len(self.text)
        while pos < n:
            m = self._lex(text, pos)
            if m is None:
                raise _NotFast
            if m.lastgroup is not None:
                return m.lastgroup, m.group(m.lastgroup), m.end()
            pos = m.end()
        return "", "", n

    def read(self) -> Formula:
        f = self.iff()
        if self.tok:
            raise _NotFast
        return f

    def peek(self) -> str:
        return self.tok

    def advance(self) -> None:
        self.pos = self.end
        self.kind, self.tok, self.end = self._next(self.end)

    def take(self) -> tuple[str, str]:
        kind, t = self.kind, self.tok
        if not t:
            raise _NotFast
        self.advance()
        return kind, t

    def iff(self) -> Formula:
        out = self.imp()
        while self.peek() == "<->":
            self.advance()
            out = Iff(out, self.imp())
        return out

    def imp(self) -> Formula:
        left = self.disj()
        if self.peek() == "->":
            self.advance()
            return Implies(left, self.imp())
        return left

    def disj(self) -> Formula:
        parts = [self.conj()]
        while self.peek() == "|":
            self.advance()
            parts.append(self.conj())
        return parts[0] if len(parts) == 1 else Or(parts)

    def conj(self) -> Formula:
        parts = [self.unary()]
        while self.peek() == "&":
            self.advance()
            parts.append(self.unary())
        return parts[0] if len(parts) == 1 else And(parts)

    def agents(self, several: bool) -> list[str]:
        """The agent names after a brace token (just taken), through the closing ``}``: NAME tokens, as the
        contextual lexer reads them there; ``several``: a comma-separated group (at least one)."""
        text, pos = self.text, self.pos
        name = re.compile(_FAST_NAME).match
        names = []
        while True:
            m = name(text, pos)
            if m is None or m.group(1) in _KEYWORDS:
                raise _NotFast
            names.append(m.group(1))
            pos = m.end()
            if several and text.startswith(",", pos):
                pos += 1
                continue
            if not text.startswith("}", pos):
                raise _NotFast
            break
        self.pos = pos + 1
        self.kind, self.tok, self.end = self._next(pos + 1)
        return names

    def unary(self) -> Formula:  # noqa: C901 - one clause per operator, as _Build
        kind, t = self.take()
        if kind == "name":
            return _KEYWORDS.get(t) or Prop(t)
        if t in ("~", "!", "¬"):
            return Not(self.unary())
        if kind == "k":
            return K(t[2:], self.unary())
        if kind == "kw":
            return Kw(t[3:], self.unary())
        if kind == "m":
            return Not(K(t[2:], Not(self.unary())))
        if kind == "dia":
            return Not(K(t[1:-1], Not(self.unary())))
        if kind == "brace":
            if t in ("K{", "B{", "Kw{", "M{"):
                (agent,) = self.agents(False)
                arg = self.unary()
                if t == "M{":
                    return Not(K(agent, Not(arg)))
                return Kw(agent, arg) if t == "Kw{" else K(agent, arg)
            group = self.agents(True)
            arg = self.unary()
            return {"E{": E, "C{": C, "D{": D, "Dkw{": Dkw, "Ckw{": Ckw}[t](group, arg)
        if t == "(":
            f = self.iff()
            if self.take()[1] != ")":
                raise _NotFast
            return f
        raise _NotFast


class _Build:
    def __init__(self, events: Mapping[str, EventModelLike], source: str) -> None:
        self.events = events
        self.source = source

    def build(self, t: Any) -> Formula:  # noqa: C901 - a flat dispatch
        from lark import Token

        if isinstance(t, Token):
            raise AssertionError(t)
        d = t.data
        ch = t.children
        if d in ("and_chain", "or_chain", "imp", "iff_chain") and len(ch) == 1:
            return self.build(ch[0])
        if d == "top":
            return TOP
        if d == "bot":
            return BOT
        if d == "prop":
            return Prop(str(ch[0]))
        if d == "neg":
            return Not(self.build(ch[1]))
        if d == "k":
            return K(str(ch[0])[2:], self.build(ch[1]))
        if d == "kw":
            return Kw(str(ch[0])[3:], self.build(ch[1]))
        if d == "kbrace":
            return K(self._agent(ch[1]), self.build(ch[2]))
        if d == "kwbrace":
            return Kw(self._agent(ch[1]), self.build(ch[2]))
        if d == "grp":
            op = str(ch[0])[0]
            group = [self._agent(a) for a in ch[1].children]
            if not group:
                raise ParseError(f"{op}{{}} needs at least one agent", source=self.source,
                                 line=ch[0].line, column=ch[0].column)
            return {"E": E, "C": C, "D": D}[op](group, self.build(ch[2]))
        if d == "m":
            return Not(K(str(ch[0])[2:], Not(self.build(ch[1]))))
        if d == "m_angle":
            return Not(K(str(ch[0])[1:-1], Not(self.build(ch[1]))))
        if d == "mbrace":
            return Not(K(self._agent(ch[1]), Not(self.build(ch[-1]))))
        if d == "grpw":
            op = str(ch[0])[:3]
            group = [self._agent(a) for a in ch[1].children]
            if not group:
                raise ParseError(f"{op}{{}} needs at least one agent", source=self.source,
                                 line=ch[0].line, column=ch[0].column)
            return {"Dkw": Dkw, "Ckw": Ckw}[op](group, self.build(ch[2]))
        if d == "announce":
            return Announce(self.build(ch[0]), self.build(ch[1]))
        if d == "announce_dia":
            return Not(Announce(self.build(ch[0]), Not(self.build(ch[1]))))
        if d in ("update", "update_dia"):
            dia = d == "update_dia"
            name, ev = str(ch[0]), str(ch[1])
            if ch[1].type == "QUOTED":
                import json

                try:
                    ev = json.loads(ev)
                except json.JSONDecodeError as exc:  # "e\q": an escape JSON does not know
                    raise ParseError(f"bad escape in the quoted event name {ev} ({exc.msg}); inside quotes "
                                     f"write \\\\ for a backslash and \\\" for a quote", source=self.source,
                                     line=ch[1].line, column=ch[1].column + exc.pos) from None
            if name not in self.events:
                known = ", ".join(sorted(self.events)) or "none given"
                raise ParseError(f"unknown event model {name!r} (known: {known})", source=self.source,
                                 line=ch[0].line, column=ch[0].column)
            model = self.events[name]
            if ev not in model.events:
                raise ParseError(f"event model {name!r} has no event {ev!r} (events: "
                                 f"{', '.join(model.events)})", source=self.source, line=ch[1].line,
                                 column=ch[1].column)
            if dia:
                return Not(Update(model, model.events.index(ev), Not(self.build(ch[2])), name))
            return Update(model, model.events.index(ev), self.build(ch[2]), name)
        if d == "and_chain":
            return And(self.build(c) for c in ch)
        if d == "or_chain":
            return Or(self.build(c) for c in ch)
        if d == "imp":
            return Implies(self.build(ch[0]), self.build(ch[1]))
        if d == "iff_chain":
            parts = [self.build(c) for c in ch]
            out = Iff(parts[0], parts[1])
            for p in parts[2:]:
                out = Iff(out, p)
            return out
        raise AssertionError(f"unhandled parse node {d}")

    def _agent(self, node: Any) -> str:
        return str(node.children[0])
