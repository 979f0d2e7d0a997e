"""e-PICO instances (seed 004, Sec. 4.4 and 5): the two-arm block world, goals α β γ δ, 1–8 colours.

One :class:`Layout` (which block is where, its colour, what lies on the shared table) feeds both levels:

* the *epistemic* problem (E-PDDL, ``specs/epico/domain.epddl``): the fluents ``hold_R_C`` (a block of
  colour C lies in front of robot R) and ``occup_by_R_C`` (R's block of colour C is on the shared table);
  nobody knows initially which colours anybody has, the shared table's content is common knowledge;
* the *classical* initial state (:class:`planners.classical.CState`): stacks bottom → top, the barrier;
* the arms world (:meth:`Layout.to_world`, the ``world`` object of ``delkit.arms.plan/1``).

Goals (Sec. 5; "one agent" = either robot, a disjunction over both directions):

* α: a robot knows the colour of at least one block in front of the other robot;
* β: α and the shared table is free at the end;
* γ: a robot knows two different colours of blocks in front of the other robot;
* δ: γ and the shared table is free at the end.

γ and δ are not defined (ND) for one colour. :func:`generate` builds an :class:`Instance`; the default
layout (``seed=None``) generalises the seed's Listing 5 scene (robot1's *red* block under *black* in stack 1);
``seed=S`` draws a random layout. Which model: a :class:`Reading` — by default the paper's (§4.4: both
robots ignorant of their own colours, 4^n worlds); ``owners=("robot1",)`` the reduced one (2^n worlds);
per-colour sensing; hand-over takes (for the §5 prose macro) — named in every output.
"""

from __future__ import annotations

import random
import re
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from types import MappingProxyType
from typing import Any

from delkit.errors import DelkitError

__all__ = ["EpicoError", "Layout", "Instance", "Reading", "generate", "GOALS", "PALETTE", "ROBOTS",
           "domain_path", "domain_text", "problem_text", "defined", "reading_of"]

ROBOTS = ("robot1", "robot2")
#: colour names in the order instances use them (1 colour = red, 2 = red black, ...)
PALETTE = ("red", "black", "green", "blue", "yellow", "white", "orange", "purple")
GOALS = ("alpha", "beta", "gamma", "delta")
_GREEK = {"α": "alpha", "β": "beta", "γ": "gamma", "δ": "delta", "a": "alpha", "b": "beta", "c": "gamma",
          "d": "delta"}


class EpicoError(DelkitError):
    """Bad e-PICO input (goal, colours, layout) or a task of the hierarchy that cannot be carried out."""


def domain_path() -> Path:
    """``specs/epico/domain.epddl``."""
    from planners.demo import specs_dir

    return specs_dir() / "epico" / "domain.epddl"


def goal_name(goal: str) -> str:
    g = _GREEK.get(goal.strip().lower(), goal.strip().lower())
    if g not in GOALS:
        raise EpicoError(f"unknown goal {goal!r}; use one of {', '.join(GOALS)} (or α β γ δ)")
    return g


def defined(goal: str, colors: int) -> bool:
    """γ and δ need two colours (ND with one)."""
    return not (goal_name(goal) in ("gamma", "delta") and colors < 2)


@dataclass(frozen=True)
class Layout:
    """Where the blocks are: per robot its 3 stacks (bottom → top block names), each block's colour, the
    shared table's content (bottom → top) and, for blocks on the shared table, the robot they belong to."""

    stacks: Mapping[str, tuple[tuple[str, ...], ...]]
    colors: Mapping[str, str]
    shared: tuple[str, ...] = ()
    owners: Mapping[str, str] = field(default_factory=dict)

    def __post_init__(self) -> None:
        names = [b for r in ROBOTS for st in self.stacks.get(r, ()) for b in st] + list(self.shared)
        if set(self.stacks) != set(ROBOTS):
            raise EpicoError(f"a layout has stacks for exactly {', '.join(ROBOTS)}, got {sorted(self.stacks)}")
        dup = sorted({b for b in names if names.count(b) > 1})
        if dup:
            raise EpicoError(f"block names must be unique; repeated: {', '.join(dup)}")
        missing = [b for b in names if b not in self.colors]
        if missing:
            raise EpicoError(f"blocks without a colour: {', '.join(missing)}")
        bad = sorted({c for c in self.colors.values() if c not in PALETTE})
        if bad:
            raise EpicoError(f"unknown colour(s) {', '.join(bad)}; the e-PICO colours are {', '.join(PALETTE)}")
        for b in self.shared:
            if self.owners.get(b) not in ROBOTS:
                raise EpicoError(f"block {b!r} on the shared table needs an owner (one of {', '.join(ROBOTS)})")
        if len(self.shared) > 1:
            raise EpicoError("the shared table holds at most one block")

    @property
    def blocks(self) -> tuple[str, ...]:
        return tuple(b for r in ROBOTS for st in self.stacks[r] for b in st) + self.shared

    def palette(self) -> tuple[str, ...]:
        """The colours of the instance, in palette order."""
        used = set(self.colors.values())
        return tuple(c for c in PALETTE if c in used)

    def has(self, robot: str, color: str) -> bool:
        """hold(robot, color): a block of that colour is in front of the robot (or is its block on the
        shared table)."""
        return any(self.colors[b] == color for st in self.stacks[robot] for b in st) or any(
            self.colors[b] == color and self.owners.get(b) == robot for b in self.shared)

    def to_world(self) -> dict[str, Any]:
        """The ``world`` object of the ``delkit.arms.plan/1`` format."""
        return {"robots": list(ROBOTS),
                "stacks": {r: [list(s) for s in self.stacks[r]] for r in ROBOTS},
                "barrier": list(self.shared),
                "colors": {b: self.colors[b] for b in self.blocks}}

    def to_json(self) -> dict[str, Any]:
        return {**self.to_world(), "owners": dict(self.owners)}

    @staticmethod
    def from_world(obj: Mapping[str, Any], owners: Mapping[str, str] | None = None) -> Layout:
        """A layout from a ``world`` object (block colours must be e-PICO colour names). Robots, stacks and
        owners must name the instance's robots (``ROBOTS``); an owner must name a block on the shared table."""
        if isinstance(obj, Mapping):
            listed = obj.get("robots", [])
            stacks_of = obj.get("stacks", {})
            named = set(map(str, listed if isinstance(listed, list) else [listed]))
            named |= set(map(str, stacks_of)) if isinstance(stacks_of, Mapping) else set()
            extra = sorted(named - set(ROBOTS))
            if extra:
                raise EpicoError(f"world object: robot(s) {extra} are not e-PICO robots; e-PICO has exactly "
                                 f"{', '.join(ROBOTS)}")
        try:
            stacks = {r: tuple(tuple(s) for s in obj["stacks"][r]) for r in ROBOTS}
            shared = tuple(obj.get("barrier", ()))
            for what, names in (("stacks", [b for r in ROBOTS for s in stacks[r] for b in s]), ("barrier", shared)):
                odd = [b for b in names if not isinstance(b, str)]
                if odd:
                    raise EpicoError(f"world object: {what} must list block names (strings), got {odd[0]!r}")
            colors = {b: obj.get("colors", {}).get(b, b) for r in ROBOTS for s in stacks[r] for b in s}
            colors.update({b: obj.get("colors", {}).get(b, b) for b in shared})
        except (KeyError, TypeError, AttributeError) as exc:
            raise EpicoError(f"not an e-PICO world object ({exc})") from None
        try:
            own = dict(owners or obj.get("owners", {}))
        except (TypeError, ValueError) as exc:
            raise EpicoError(f"world object: 'owners' must map block names to robots ({exc})") from None
        odd_c = [c for c in colors.values() if not isinstance(c, str)]
        odd_o = [x for kv in own.items() for x in kv if not isinstance(x, str)]
        if odd_c or odd_o:
            raise EpicoError(f"world object: colours and owners must be names (strings), got {(odd_c + odd_o)[0]!r}")
        for block, robot in own.items():
            if robot not in ROBOTS:
                raise EpicoError(f"owner {block}={robot}: {robot!r} is not a robot; use one of {', '.join(ROBOTS)}")
            if block not in shared:
                raise EpicoError(f"owner {block}={robot}: no block {block!r} on the shared table (the barrier "
                                 f"lists {list(shared) or 'none'})")
        return Layout(MappingProxyType(stacks), MappingProxyType(colors), shared, MappingProxyType(own))

    def classical(self):
        """The classical initial state (:class:`planners.classical.CState`)."""
        from planners.classical import CState

        return CState.make(self.stacks, self.shared, self.colors, self.owners)


def default_layout(colors: int) -> Layout:
    """The seed's scene generalised to ``colors`` colours: robot1 has one block of every colour, with *red*
    under *black* in stack 1 (Listing 5), *green* in stack 0, *blue* in stack 2, then *yellow* on *green* and
    *white* on *blue*, *orange* and *purple* on top of those; robot2 has one block of every colour, named
    ``COLOUR_2``, spread over its stacks."""
    pal = PALETTE[:colors]
    r1_slots = {"red": 1, "black": 1, "green": 0, "blue": 2, "yellow": 0, "white": 2, "orange": 0, "purple": 2}
    r1: list[list[str]] = [[], [], []]
    for c in pal:
        r1[r1_slots[c]].append(c)
    r2: list[list[str]] = [[], [], []]
    for i, c in enumerate(pal):
        r2[i % 3].append(f"{c}_2")
    colors_of = {c: c for c in pal} | {f"{c}_2": c for c in pal}
    return Layout(MappingProxyType({"robot1": tuple(map(tuple, r1)), "robot2": tuple(map(tuple, r2))}),
                  MappingProxyType(colors_of))


def random_layout(colors: int, seed: int, *, need_two: bool, owner_two: bool = True) -> Layout:
    """Each robot gets a random non-empty set of the colours (one block each) on random stacks; with
    ``need_two`` robot1 (``owner_two``) or some robot has two colours (γ, δ)."""
    rng = random.Random(seed)
    pal = PALETTE[:colors]
    while True:
        sets = {r: [c for c in pal if rng.random() < 0.6] for r in ROBOTS}
        two = len(sets["robot1"]) >= 2 if owner_two else any(len(v) >= 2 for v in sets.values())
        if all(sets.values()) and (not need_two or two):
            break
    stacks: dict[str, tuple[tuple[str, ...], ...]] = {}
    colors_of: dict[str, str] = {}
    for k, r in enumerate(ROBOTS):
        st: list[list[str]] = [[], [], []]
        for c in rng.sample(sets[r], len(sets[r])):
            name = c if k == 0 else f"{c}_2"
            st[rng.randrange(3)].append(name)
            colors_of[name] = c
        stacks[r] = tuple(map(tuple, st))
    return Layout(MappingProxyType(stacks), MappingProxyType(colors_of))


# ----------------------------------------------------------------------------- E-PDDL problem text

_FREE = "(forall (?a - owner ?k - color) (not (occup_by ?a ?k)))"


def goal_text(goal: str, colors: Iterable[str], owners: Iterable[str] = ROBOTS) -> str:
    """The goal formula of α β γ δ in E-PDDL (a robot knows colour(s) of an owner's blocks)."""
    g = goal_name(goal)
    cols = list(colors)
    parts = []
    for owner in owners:
        for knower in ROBOTS:
            if knower == owner:
                continue
            if g in ("alpha", "beta"):
                parts += [f"([{knower}](hold {owner} {c}))" for c in cols]
            else:
                parts += [f"(and ([{knower}](hold {owner} {c})) ([{knower}](hold {owner} {d})))"
                          for i, c in enumerate(cols) for d in cols[i + 1:]]
    know = "(or\n    " + "\n    ".join(parts) + ")"
    return f"(and {know}\n    {_FREE})" if g in ("beta", "delta") else know


def problem_text(layout: Layout, goal: str, *, colors: int | None = None, owners: Iterable[str] = ROBOTS,
                 known: Mapping[str, Iterable[Any]] | None = None, name: str | None = None) -> str:
    """The epistemic problem of a layout: the colours of the ``owners`` (the robots whose colours are modelled;
    the others learn them), common knowledge of the shared table, ``known`` (robot ↦ colours C — or
    (owner, C) pairs — whose ``hold`` it knows) as common knowledge."""
    cols = PALETTE[:colors] if colors is not None else layout.palette()
    owners = tuple(owners)
    if not owners or any(o not in ROBOTS for o in owners):
        raise EpicoError(f"owners must be robots among {', '.join(ROBOTS)}, got {list(owners)}")
    g = goal_name(goal)
    if not defined(g, len(cols)):
        raise EpicoError(f"goal {g} is not defined with {len(cols)} colour(s): it needs two different colours")
    init = [f"(hold {r} {c})" for r in owners for c in cols if layout.has(r, c)]
    on_table = {(layout.owners[b], layout.colors[b]) for b in layout.shared}
    stray = sorted(r for r, _ in on_table if r not in owners)
    if stray:
        raise EpicoError(f"the shared table holds a block of {stray[0]}, whose colours are not modelled; "
                         f"make it an owner (symmetric instance)")
    init += [f"(occup_by {r} {c})" for r, c in sorted(on_table)]
    group = " ".join(ROBOTS)
    for r in owners:
        for c in cols:
            lit = f"(occup_by {r} {c})" if (r, c) in on_table else f"(not (occup_by {r} {c}))"
            init.append(f"([{group}]{lit})")
    for r, items in (known or {}).items():
        if r not in ROBOTS:
            raise EpicoError(f"known: unknown robot {r!r}; robots are {', '.join(ROBOTS)}")
        for it in items:
            owner, c = (it if isinstance(it, (tuple, list)) else (r, it))
            if owner not in owners or c not in cols:
                raise EpicoError(f"known[{r!r}]: {it!r} is not a colour of this instance ({', '.join(cols)}) "
                                 f"or an (owner, colour) pair with owner among {', '.join(owners)}")
            init.append(f"([{group}](or ([{r}](hold {owner} {c})) ([{r}](not (hold {owner} {c})))))")
    name = name or f"epico_{g}_{len(cols)}"
    return (f"(define (problem {name})\n  (:domain epico)\n  (:agents {' '.join(ROBOTS)})\n"
            f"  (:objects {' '.join(cols)} - color {' '.join(owners)} - owner)\n  (:init\n    "
            + "\n    ".join(init) + ")\n"
            f"  (:goal {goal_text(g, cols, owners)}))\n")


#: the robots whose colours are fluents in the paper's reading (§4.4: both robots)
PAPER_OWNERS = ROBOTS
SENSINGS = ("table", "color")
TAKES = ("seen", "handover")


@dataclass(frozen=True)
class Reading:
    """Which e-PICO model an instance is (seed 004 leaves these choices open; §4.4 fixes the first).

    * ``owners``: the robots whose colours are fluents. The paper (§4.4): "Initially, they do not know
      what blocks they are able to manipulate" — both robots (4^n worlds for n colours), the default.
      ``("robot1",)`` is the reduced reading (2^n worlds; robot2 learns robot1's colours).
    * ``sensing``: ``table`` — one ``sense_table ?ag`` reveals all of the robot's colours (default);
      ``color`` — one ``sense_color ?ag ?c`` per colour (the prose "sensing actions" allows it too).
    * ``takes``: ``seen`` — any robot may take a block from the shared table, both see it (default);
      ``handover`` — the block goes to the other robot (the one that did not put it), whose take the owner
      only partially observes (it cannot tell whether the table was cleared): the observability under
      which the §5 prose macro "take from the shared table + announce that it is free"
      (``take_and_announce``) carries information.
    """

    owners: tuple[str, ...] = PAPER_OWNERS
    sensing: str = "table"
    takes: str = "seen"

    def __post_init__(self) -> None:
        own = tuple(self.owners)
        if not own or len(set(own)) != len(own) or any(o not in ROBOTS for o in own):
            raise EpicoError(f"owners must be distinct robots among {', '.join(ROBOTS)}, got {list(own)}")
        object.__setattr__(self, "owners", tuple(r for r in ROBOTS if r in own))
        if self.sensing == "colour":
            object.__setattr__(self, "sensing", "color")
        if self.sensing not in SENSINGS:
            raise EpicoError(f"sensing {self.sensing!r}: use {' or '.join(SENSINGS)}")
        if self.takes not in TAKES:
            raise EpicoError(f"takes {self.takes!r}: use {' or '.join(TAKES)}")

    @property
    def is_paper(self) -> bool:
        return self == Reading()

    @property
    def name(self) -> str:
        """``paper``, ``owner robot1``, ``per-colour sensing``, ``hand-over`` (several joined by ``, ``)."""
        parts = []
        if self.owners != PAPER_OWNERS:
            parts.append("owner " + "+".join(self.owners))
        if self.sensing == "color":
            parts.append("per-colour sensing")
        if self.takes == "handover":
            parts.append("hand-over")
        return ", ".join(parts) or "paper"

    def describe(self) -> str:
        """One line: whose colours are unknown, how many worlds, how a robot senses, who takes."""
        who = " and ".join(f"{o}'s" for o in self.owners)
        sense = ("one sense_table ?ag reveals all of a robot's colours" if self.sensing == "table"
                 else "one sense_color ?ag ?c per colour")
        take = ("any robot takes from the shared table, both see it" if self.takes == "seen" else
                "the other robot takes, the owner only partially observes it (macro take_and_announce)")
        return (f"{self.name} reading: {who} colours unknown ({'2' if len(self.owners) == 1 else '4'}^n worlds "
                f"for n colours); {sense}; {take}")

    def to_json(self) -> dict[str, Any]:
        return {"name": self.name, "owners": list(self.owners), "sensing": self.sensing, "takes": self.takes}


def reading_of(owners: Iterable[str] | str | None = None, *, sensing: str = "table", takes: str = "seen",
               symmetric: bool | None = None) -> Reading:
    """The :class:`Reading` of :func:`generate`'s keywords (``owners`` None = both robots, the paper's; a
    robot name or ``robot1,robot2`` is accepted). ``symmetric`` is the old spelling, kept for a while: True =
    both robots (the default now), False = ``owners=("robot1",)``; it warns (DeprecationWarning)."""
    if symmetric is not None:
        import warnings

        warnings.warn("symmetric= is deprecated: both robots' colours (the paper's reading) are the default; "
                      "pass owners=('robot1',) for the reduced reading", DeprecationWarning, stacklevel=3)
        if owners is None:
            owners = PAPER_OWNERS if symmetric else ("robot1",)
    if owners is None:
        owners = PAPER_OWNERS
    elif isinstance(owners, str):
        owners = tuple(o.strip() for o in owners.replace("+", ",").split(",") if o.strip())
    return Reading(tuple(owners), sensing, takes)


@dataclass(frozen=True)
class Instance:
    """An e-PICO instance: the layout, the goal, the reading, the E-PDDL texts and the classical initial
    state."""

    layout: Layout
    goal: str
    colors: int
    domain_text: str
    problem_text: str
    known: Mapping[str, tuple] = field(default_factory=dict)
    reading: Reading = Reading()

    @property
    def owners(self) -> tuple[str, ...]:
        """The robots whose colours are fluents (the objects of type ``owner``)."""
        return self.reading.owners

    @property
    def classical_init(self):
        """The classical initial state (:class:`planners.classical.CState`)."""
        return self.layout.classical()

    def with_known(self, known: Mapping[str, Iterable[Any]] | None) -> Instance:
        k = {r: tuple(v) for r, v in (known or {}).items()}
        return Instance(self.layout, self.goal, self.colors, self.domain_text,
                        problem_text(self.layout, self.goal, colors=self.colors, owners=self.owners, known=k),
                        MappingProxyType(k), self.reading)

    def to_json(self) -> dict[str, Any]:
        return {"goal": self.goal, "colors": self.colors, "reading": self.reading.to_json(),
                "owners": list(self.owners), "layout": self.layout.to_json(),
                "classical_init": self.classical_init.to_json(), "known": {r: list(v) for r, v in self.known.items()}}


def domain_text(reading: Reading = Reading()) -> str:
    """The E-PDDL domain of a reading: ``specs/epico/domain.epddl``; for per-colour sensing its
    ``sense_table`` replaced by ``sense_color``; for hand-over takes its ``take_from_shared`` replaced and
    ``announce_table_free`` and the macro ``take_and_announce`` added — the forms of
    ``specs/epico/variants.txt``."""
    text = domain_path().read_text()
    if reading.sensing == "table" and reading.takes == "seen":
        return text
    forms = _variant_forms()
    if reading.sensing == "color":
        text = _replace_form(text, "(:action sense_table", forms["sense_color"])
    if reading.takes == "handover":
        text = _replace_form(text, "(:action take_from_shared", forms["take_from_shared"])
        end = text.rstrip().rfind(")")
        text = text[:end].rstrip() + "\n\n  " + forms["announce_table_free"] + "\n\n  " + \
            forms["take_and_announce"] + "\n)\n"
    return text


def _form_end(text: str, i: int) -> int:
    """The index just after the parenthesised form that starts at ``text[i]``."""
    depth = 0
    for j in range(i, len(text)):
        if text[j] == "(":
            depth += 1
        elif text[j] == ")":
            depth -= 1
            if depth == 0:
                return j + 1
    raise EpicoError(f"unbalanced parentheses in the form at offset {i}")


def _replace_form(text: str, head: str, new: str) -> str:
    """``text`` with the form starting with ``head`` (and the comment lines just above it) replaced by ``new``."""
    i = text.index(head)
    start = text.rfind("\n", 0, i) + 1
    while start > 0:  # the comment block that describes the replaced form goes with it
        prev = text.rfind("\n", 0, start - 1) + 1
        if not text[prev:start].lstrip().startswith(";"):
            break
        start = prev
    return text[:start] + "  " + new + text[_form_end(text, i):]


def _variant_forms() -> dict[str, str]:
    """``specs/epico/variants.txt``: name ↦ the text of its ``(:action NAME ...)`` / ``(:macro NAME ...)``."""
    text = (domain_path().parent / "variants.txt").read_text()
    return {m.group(2): text[m.start():_form_end(text, m.start())]
            for m in re.finditer(r"\((:action|:macro)\s+([A-Za-z_][\w-]*)", text)}


def generate(goal: str, colors: int, seed: int | None = None, *, layout: Layout | None = None,
             owners: Iterable[str] | str | None = None, sensing: str = "table", takes: str = "seen",
             reading: Reading | None = None, symmetric: bool | None = None) -> Instance:
    """The instance of ``goal`` with ``colors`` colours: the seed's layout (``seed=None``), a random one, or
    the given ``layout``. By default the paper's reading (§4.4): both robots ignorant of their own colours
    (4^n worlds), either may learn the other's; ``owners=("robot1",)`` is the reduced reading (robot1's
    colours only, 2^n worlds, robot2 learns them). ``sensing``, ``takes``: see :class:`Reading` (or pass
    ``reading``)."""
    rd = reading if reading is not None else reading_of(owners, sensing=sensing, takes=takes, symmetric=symmetric)
    g = goal_name(goal)
    if not isinstance(colors, int) or not 1 <= colors <= len(PALETTE):
        raise EpicoError(f"--colors must be 1..{len(PALETTE)}, got {colors!r}")
    if not defined(g, colors):
        raise EpicoError(f"goal {g} is not defined (ND) with 1 colour: it asks for two different colours")
    if layout is None:
        layout = default_layout(colors) if seed is None else random_layout(
            colors, seed, need_two=g in ("gamma", "delta"), owner_two=rd.owners == ("robot1",))
    return Instance(layout, g, colors, domain_text(rd), problem_text(layout, g, colors=colors, owners=rd.owners),
                    reading=rd)
