"""Instances of four frontier families, written as EPDDL (2026), with a known plan and a known optimum.

They imitate the shapes of competition domains the planner had trouble with (written from scratch, not
copied): multi-agent coordination under partial observability (``ugv``), knowledge distributed over guests
that one agent must come to hold while keeping it from the others (``hotel``), and a spy's secret passed along
a chain of contacts, known from the start (``spy-linear``) or sensed first (``spy-sensing``). Each instance
uses the action-type library :data:`LIBRARY` (written beside it by :meth:`Instance.write`).

Each :class:`Instance` carries a plan that solves it (``plan``) and its optimal length (``optimum``), both
known by construction; the argument is in each generator's docstring and the tests check both (the plan
with the project's validator, the optimum with BFS on the small sizes).

Sizes grow from BFS-easy to BFS-hard: :data:`SIZES` lists, per family, the parameters the benchmark uses.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

__all__ = ["Instance", "LIBRARY", "FAMILIES", "SIZES", "generate", "spy", "hotel", "ugv", "write"]


@dataclass(frozen=True)
class Instance:
    """One generated task: EPDDL domain and problem text, a known plan, its optimal length."""

    family: str
    name: str
    domain: str
    problem: str
    plan: tuple[str, ...]
    optimum: int

    def write(self, folder: Path) -> tuple[Path, Path, Path]:
        """Write ``<name>-domain.epddl``, ``<name>.epddl`` and the library ``frontier-library.epddl`` into
        ``folder``; return the three paths (``delkit plan DOMAIN PROBLEM -l LIBRARY``)."""
        folder.mkdir(parents=True, exist_ok=True)
        d, p, lib = folder / f"{self.name}-domain.epddl", folder / f"{self.name}.epddl", folder / "frontier-library.epddl"
        d.write_text(self.domain)
        p.write_text(self.problem)
        lib.write_text(LIBRARY)
        return d, p, lib


#: the action types the families use, as an EPDDL action-type library (the standard definitions: public ontic
#: change; semi-private sensing and announcement — the Partially observers cannot tell ?pos from ?neg;
#: private announcement — the Oblivious observers see the trivial ?nil)
LIBRARY = """(define (action-type-library frontier)
    (:requirements :lists :list-comprehensions :equality :partial-observability :multi-pointed-models
                   :events-conditions)
    (:action-type public-ontic
        :events (?pos)
        :observability-types (Fully)
        :relations (Fully (:forall (?e - event) (?e ?e)))
        :designated (?pos)
        :conditions (?pos (:non-trivial-postconditions)))
    (:action-type semi-private-sensing
        :events (?pos ?neg)
        :observability-types (Fully Partially)
        :relations (Fully (:forall (?e - event) (?e ?e))
                    Partially (:forall (?e ?f - event) (?e ?f)))
        :designated (?pos ?neg)
        :conditions (?pos (:trivial-postconditions) ?neg (:trivial-postconditions)))
    (:action-type semi-private-announcement
        :events (?pos ?neg)
        :observability-types (Fully Partially)
        :relations (Fully (:forall (?e - event) (?e ?e))
                    Partially (:forall (?e ?f - event) (?e ?f)))
        :designated (?pos)
        :conditions (?pos (:trivial-postconditions) ?neg (:trivial-postconditions)))
    (:action-type private-announcement
        :events (?pos ?nil)
        :observability-types (Fully Oblivious)
        :relations (Fully (:forall (?e - event) (?e ?e))
                    Oblivious (:forall (?e - event) (?e ?nil)))
        :designated (?pos)
        :conditions (?pos (:trivial-postconditions) ?nil (:trivial-event)))
)
"""


def _check_size(name: str, value: int, least: int) -> None:
    if not isinstance(value, int) or isinstance(value, bool) or value < least:
        raise ValueError(f"{name}={value!r}: must be an integer >= {least}")


# ------------------------------------------------------------------------------------------------------ spy
_SPY_DOMAIN = """(define (domain spy-{kind})
    (:requirements :typing :partial-observability :facts :lists :list-comprehensions
                   :negative-preconditions :modal-preconditions)
    (:action-type-libraries frontier)
    (:predicates (secret) (:fact link ?i ?j - agent) (:fact spy ?i - agent))
    (:event e-sense-pos :parameters (?i - agent) :precondition (and (spy ?i) (secret)))
    (:event e-sense-neg :parameters (?i - agent) :precondition (and (spy ?i) (not (secret))))
    (:action sense
        :parameters (?i - agent)
        :action-type (semi-private-sensing (e-sense-pos ?i) (e-sense-neg ?i))
        :observability-conditions (:and (?i Fully) (default Partially)))
    (:event e-tell-pos :parameters (?i ?j - agent) :precondition (and (link ?i ?j) ([?i] (secret)) (secret)))
    (:event e-tell-neg :parameters (?i ?j - agent)
        :precondition (and (link ?i ?j) ([?i] (not (secret))) (not (secret))))
    (:action tell
        :parameters (?i ?j - agent | (/= ?i ?j))
        :action-type (semi-private-announcement (e-tell-pos ?i ?j) (e-tell-neg ?i ?j))
        :observability-conditions (:and (?i Fully) (?j Fully) (default Partially)))
)
"""


def spy(chain: int, decoys: int = 0, *, sensing: bool = False) -> Instance:
    """A spy ``s`` and contacts ``c1 .. c<chain>`` linked in a line s → c1 → … → c<chain>; ``decoys`` more
    contacts ``d1 ..`` are linked from every chain contact and with each other, never back to the chain
    (they widen the search, never shorten a plan). ``tell_i_j`` (i linked to j, i believes the secret) tells j; the others see that
    i told j whether the secret holds, not what (semi-private: so no one comes to believe ⊥ — with oblivious
    onlookers, a contact told by someone it believed ignorant would). Goal: the last contact believes the secret. ``sensing``: no one knows the
    secret at first and the spy must ``sense`` it first (semi-private: the others see it sense).

    Optimum ``chain`` (``chain + 1`` with sensing), by construction: an agent comes to believe the secret only
    when told by an agent linked to it who believes it (or, the spy, by sensing), each action informs one agent,
    and the only path of links from the spy to the last contact is the chain (no link leads from a decoy back
    to the chain)."""
    _check_size("chain", chain, 1)
    _check_size("decoys", decoys, 0)
    kind = "sensing" if sensing else "linear"
    chain_agents = [f"c{i}" for i in range(1, chain + 1)]
    dec = [f"d{i}" for i in range(1, decoys + 1)]
    agents = ["s", *chain_agents, *dec]
    links = [("s", "c1")] + [(a, b) for a, b in zip(chain_agents, chain_agents[1:], strict=False)]
    for d in dec:
        links += [(c, d) for c in chain_agents] + [(x, d) for x in dec if x != d]
    links = sorted(set(links))
    knows = "" if sensing else "([C. All] ([Kw. s] (secret)))"
    problem = f"""(define (problem spy-{kind}-{chain}-{decoys})
    (:domain spy-{kind})
    (:requirements :finitary-S5-theories :modal-goals :facts)
    (:agents {' '.join(agents)})
    (:facts-init (spy s) {' '.join(f'(link {a} {b})' for a, b in links)})
    (:init (:and (secret) {knows}))
    (:goal ([{chain_agents[-1]}] (secret)))
)
"""
    steps = (["sense_s"] if sensing else []) + [f"tell_{a}_{b}" for a, b in zip(["s", *chain_agents], chain_agents, strict=False)]
    return Instance(f"spy-{kind}", f"spy-{kind}-{chain}-{decoys}", _SPY_DOMAIN.format(kind=kind), problem,
                    tuple(steps), chain + (1 if sensing else 0))


# ---------------------------------------------------------------------------------------------------- hotel
_HOTEL_DOMAIN = """(define (domain hotel-distributed)
    (:requirements :typing :partial-observability :ontic-actions :facts :lists :list-comprehensions
                   :negative-preconditions :modal-preconditions :negative-obs-conditions)
    (:action-type-libraries frontier)
    (:types digit)
    (:predicates (code ?b - digit) (in-lobby ?i - agent) (:fact owns ?i - agent ?b - digit))
    (:event nil)
    (:event e-enter :parameters (?i - agent) :precondition (not (in-lobby ?i)) :effects (in-lobby ?i))
    (:action enter :parameters (?i - agent) :action-type (public-ontic (e-enter ?i))
        :observability-conditions (default Fully))
    (:event e-leave :parameters (?i - agent) :precondition (in-lobby ?i) :effects (not (in-lobby ?i)))
    (:action leave :parameters (?i - agent) :action-type (public-ontic (e-leave ?i))
        :observability-conditions (default Fully))
    (:event e-tell :parameters (?i - agent ?b - digit)
        :precondition (and (owns ?i ?b) (in-lobby ?i) ([?i] (code ?b)) (code ?b)))
    (:action tell
        :parameters (?i - agent ?b - digit)
        :action-type (private-announcement (e-tell ?i ?b) (nil))
        :observability-conditions
            (:forall (?j - agent) (?j (if (in-lobby ?j) Fully else Oblivious))))
)
"""


def hotel(guests: int) -> Instance:
    """A receptionist ``r`` (always in the lobby) and guests ``g1 ..``; guest i alone knows whether digit ``bi``
    of the safe's code holds (all do). The code is distributed knowledge of the guests; the goal makes it the
    receptionist's own — it knows whether each digit holds — while no guest comes to know whether another's
    digit holds. A guest can ``tell`` its digit only from the lobby, and everyone in the lobby hears it
    (the others are oblivious); ``enter`` and ``leave`` the lobby are public.

    Optimum ``3·guests − 1``, by construction: each guest must enter (the receptionist learns a digit only
    from its owner: a guest who learnt another's digit would break the goal, which no later action repairs)
    and tell; of two guests, the one who tells first must have left before the other tells, or it hears that
    digit — so all but the last teller leave."""
    _check_size("guests", guests, 1)
    gs = [f"g{i}" for i in range(1, guests + 1)]
    digits = [f"b{i}" for i in range(1, guests + 1)]
    secrecy = [f"(not ([Kw. {g}] (code {b})))" for g in gs for b in digits if b[1:] != g[1:]]
    problem = f"""(define (problem hotel-{guests})
    (:domain hotel-distributed)
    (:requirements :finitary-S5-theories :modal-goals :facts :negative-goals)
    (:agents r {' '.join(gs)})
    (:objects {' '.join(digits)} - digit)
    (:facts-init {' '.join(f'(owns {g} {b})' for g, b in zip(gs, digits, strict=False))})
    (:init (:and (in-lobby r) {' '.join(f'(not (in-lobby {g}))' for g in gs)} {' '.join(f'(code {b})' for b in digits)}
        ([C. All] (and (in-lobby r) {' '.join(f'(not (in-lobby {g}))' for g in gs)}))
        {' '.join(f'([C. All] ([Kw. {g}] (code {b})))' for g, b in zip(gs, digits, strict=False))}))
    (:goal (and {' '.join(f'([Kw. r] (code {b}))' for b in digits)} {' '.join(secrecy)}))
)
"""
    steps: list[str] = []
    for i, (g, b) in enumerate(zip(gs, digits, strict=False)):
        steps += [f"enter_{g}", f"tell_{g}_{b}"] + ([f"leave_{g}"] if i < guests - 1 else [])
    return Instance("hotel-distributed", f"hotel-{guests}", _HOTEL_DOMAIN, problem, tuple(steps), 3 * guests - 1)


# ------------------------------------------------------------------------------------------------------ ugv
_UGV_DOMAIN = """(define (domain ugv-coordination)
    (:requirements :typing :partial-observability :ontic-actions :facts :lists :list-comprehensions
                   :negative-preconditions :modal-preconditions :conditional-effects)
    (:action-type-libraries frontier)
    (:types cell)
    (:predicates (at ?i - agent ?c - cell) (item-at ?c - cell) (:fact next ?c ?d - cell) (:fact ugv ?i - agent))
    (:event nil)
    (:event e-move :parameters (?i - agent ?c ?d - cell)
        :precondition (and (ugv ?i) (next ?c ?d) (at ?i ?c))
        :effects (:and (not (at ?i ?c)) (at ?i ?d)))
    (:action move :parameters (?i - agent ?c ?d - cell) :action-type (public-ontic (e-move ?i ?c ?d))
        :observability-conditions (default Fully))
    (:event e-sense-pos :parameters (?i - agent ?c - cell) :precondition (and (ugv ?i) (at ?i ?c) (item-at ?c)))
    (:event e-sense-neg :parameters (?i - agent ?c - cell) :precondition (and (ugv ?i) (at ?i ?c) (not (item-at ?c))))
    (:action sense :parameters (?i - agent ?c - cell)
        :action-type (semi-private-sensing (e-sense-pos ?i ?c) (e-sense-neg ?i ?c))
        :observability-conditions (:and (?i Fully) (default Partially)))
    (:event e-report :parameters (?i - agent ?c - cell)
        :precondition (and (ugv ?i) ([?i] (item-at ?c)) (item-at ?c)))
    (:action report :parameters (?i - agent ?c - cell)
        :action-type (private-announcement (e-report ?i ?c) (nil))
        :observability-conditions (:and (?i Fully) (base Fully) (default Oblivious)))
)
"""


def ugv(cells: int, robots: int = 1) -> Instance:
    """Robots ``u1 ..`` on a line of ``cells`` cells ``x1 .. x<cells>``, all starting at ``x1``; an item lies in
    exactly one cell (common knowledge), in fact the last. Moves along the line are public; a robot at a cell
    can ``sense`` whether the item is there (the others see it sense, not what it finds); a robot that believes where the item is can ``report``
    it to the base (privately: the others are oblivious). Goal: the base believes the item is in the last cell.

    Optimum ``min(cells + 1, 2·cells − 2)``, by construction: the base learns it only from a
    report, which needs a robot that believes it; a robot comes to believe it by sensing the last cell
    (``cells − 1`` moves and one sensing) or by sensing every other cell empty (``cells − 1`` sensings and
    ``cells − 2`` moves); one robot's sensing never informs another, so more robots do not shorten a plan."""
    _check_size("cells", cells, 2)  # one cell: the base knows from the start
    _check_size("robots", robots, 1)
    xs = [f"x{i}" for i in range(1, cells + 1)]
    us = [f"u{i}" for i in range(1, robots + 1)]
    last = xs[-1]
    one = " ".join(f"(and (item-at {c}) {' '.join(f'(not (item-at {d}))' for d in xs if d != c)})" for c in xs)
    pos = " ".join(f"(at {u} x1)" for u in us) + " " + " ".join(f"(not (at {u} {c}))" for u in us for c in xs[1:])
    problem = f"""(define (problem ugv-{cells}-{robots})
    (:domain ugv-coordination)
    (:requirements :finitary-S5-theories :modal-goals :facts)
    (:agents base {' '.join(us)})
    (:objects {' '.join(xs)} - cell)
    (:facts-init {' '.join(f'(ugv {u})' for u in us)} {' '.join(f'(next {a} {b}) (next {b} {a})' for a, b in zip(xs, xs[1:], strict=False))})
    (:init (:and {pos} (item-at {last}) {' '.join(f'(not (item-at {c}))' for c in xs[:-1])}
        ([C. All] (and {pos}))
        ([C. All] (or {one}))))
    (:goal ([base] (item-at {last})))
)
"""
    steps = [f"move_u1_{a}_{b}" for a, b in zip(xs, xs[1:], strict=False)] + [f"sense_u1_{last}", f"report_u1_{last}"]
    opt = min(cells + 1, 2 * cells - 2)
    return Instance("ugv-coordination", f"ugv-{cells}-{robots}", _UGV_DOMAIN, problem, tuple(steps), opt)


#: the families and their generators
FAMILIES = {
    "spy-linear": lambda n, k=0: spy(n, k),
    "spy-sensing": lambda n, k=0: spy(n, k, sensing=True),
    "hotel-distributed": lambda n: hotel(n),
    "ugv-coordination": lambda n, k=1: ugv(n, k),
}

#: per family, the sizes of the benchmark, easy to hard
SIZES = {
    "spy-linear": [(2, 0), (4, 2), (6, 4), (8, 6), (10, 8), (12, 10)],
    "spy-sensing": [(2, 0), (4, 2), (6, 4), (8, 6), (10, 8), (12, 10)],
    "hotel-distributed": [(2,), (3,), (4,), (5,), (6,), (7,)],
    "ugv-coordination": [(3, 1), (4, 2), (6, 2), (8, 3), (10, 3), (12, 4)],
}


def generate(family: str, *size: int) -> Instance:
    """The instance of ``family`` (a key of :data:`FAMILIES`) at ``size``."""
    if family not in FAMILIES:
        raise ValueError(f"unknown family {family!r}; use one of {', '.join(FAMILIES)}")
    return FAMILIES[family](*size)


def write(folder: Path, family: str, *size: int) -> tuple[Path, Path, Path, Instance]:
    """Generate and write one instance (see :meth:`Instance.write`)."""
    inst = generate(family, *size)
    return (*inst.write(folder), inst)
