"""One hundred prisoners and a light bulb, bounded (SMCDEL's ``SMCDEL.Examples.Prisoners``; van Ditmarsch,
van Eijck & Wu, *Verifying one hundred prisoners and a lightbulb*, JANCL 20(3), 2010; Dehaye, Ford &
Segerman, *One hundred prisoners and a lightbulb*, Mathematical Intelligencer 25(4), 2003; van Ditmarsch &
Kooi, *One Hundred Prisoners and a Light Bulb*, Springer 2015).

Every day one of n prisoners is interviewed in a room with a light bulb, off at first; the others see
nothing. Protocol: prisoner 1 is the *counter*; every other prisoner turns the light on the first time he
finds it off (and never again); the counter turns it off whenever he finds it on and counts; at the count
n − 1 he announces "everyone has been interviewed".

Literature answer: the protocol is correct — when the counter announces, every prisoner has been
interviewed, and he does announce (with probability 1 under a fair schedule); in DEL terms the counter
*knows* "everyone has been interviewed" (K_1 ⋀_k vis_k) exactly from the day his count reaches n − 1, for n ≥
3 (with two prisoners he knows earlier: the days count, and a day without his interview was the other's).
Under a uniformly random schedule the expected number of days is n(n − 1) + n·H_{n−1} (each of the n − 1
switches waits n/(n − 1 − c) days for a new prisoner and n days for the counter): 10,417.7 days for 100
prisoners, the "about 28.5 years" usually quoted.

Encoding (delkit's; SMCDEL's has the same idea): V = {light, vis_k (k has been interviewed), sw_k (k ≥ 2 has
switched the light on)}, θ = all false; only the counter is an agent and he observes nothing of V. Each
day is one transformer: event variables ``i<d>_k`` (exactly one prisoner is interviewed) and ``s<d>`` (what
the counter sees: the light, when he is the one; else false), both observed by the counter;
light := ¬i_1 ∧ (light ∨ ⋁_k (i_k ∧ ¬sw_k)), sw_k := sw_k ∨ (i_k ∧ ¬light), vis_k := vis_k ∨ i_k; the
designated event is the day's actual prisoner. The counter's count is not a variable: his knowledge follows
from what he observed.

Bounded: after every day the structure is reduced (:func:`reduce_structure`) — the substructure generated
by the actual state (the counter's observations are then constants and drop out) with the variables
nobody observes and outside V quantified away (a bounded morphism, so every formula over V keeps its
truth) — so it stays over V: 2n variables whatever the number of days. The explicit engine does the same
with the generated submodel and bisimulation contraction. Both grow exponentially with n (the product's
copies of the old values sit below everything in the BDD; the contracted model has up to 2·3^(n−1)·2
worlds), so engine ``image`` (:class:`ImageStructure`) computes the same reduced structure directly by a
relational product on an interleaved variable order: 100 prisoners until the counter knows (~10^4 days)
in about 12 s.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from fractions import Fraction
from typing import Any

import numpy as np

from delkit.errors import ModelError
from delkit.logic.formula import BOT, TOP, Formula, Iff, K, Not, Prop, conj, disj

__all__ = ["MAX_EXPLICIT", "MAX_PRISONERS", "MAX_TRANSFORMER", "MAX_DAYS", "ImageStructure", "PrisonersResult",
           "prisoners_start", "day_transformer",
           "day_event", "reduce_structure", "protocol_run", "expected_days", "expected_days_closed",
           "solve_prisoners", "everyone_visited", "counter_knows"]

MAX_TRANSFORMER = 7  # symbolic: each day's product (n + 1 changed variables and their copies); 10 prisoners 6.9 s
MAX_PRISONERS = 200  # the direct image (ImageStructure): ~1 ms a day at n = 100, the law ~12,000 BDD nodes
MAX_EXPLICIT = 9  # explicit: the contracted model keeps one world per (light, sw, vis) the counter cannot rule out
MAX_DAYS = 20_000

COUNTER = "1"


def _vis(k: int) -> Prop:
    return Prop(f"vis{k}")


def _sw(k: int) -> Prop:
    return Prop(f"sw{k}")


LIGHT = Prop("light")


def everyone_visited(n: int) -> Formula:
    return conj(_vis(k) for k in range(1, n + 1))


def counter_knows(n: int) -> Formula:
    """K_1 ⋀_k vis_k: the counter knows that everyone has been interviewed."""
    return K(COUNTER, everyone_visited(n))


def _vocabulary(n: int) -> list[str]:
    """light, vis1, then vis_k next to sw_k: the counter cannot tell prisoners 2..n apart, so the law is a
    symmetric function of the pairs (vis_k, sw_k) — polynomial as a BDD when each pair is adjacent (all vis
    before all sw: exponential, since the sw half must remember the vis half)."""
    return ["light", "vis1"] + [x for k in range(2, n + 1) for x in (f"vis{k}", f"sw{k}")]


ENGINES = ("explicit", "symbolic", "image")


def _check(n: int, days: int, engine: str) -> None:
    if engine not in ENGINES:
        raise ModelError(f"prisoners: unknown engine {engine!r}; use {', '.join(ENGINES)}")
    cap = {"explicit": MAX_EXPLICIT, "symbolic": MAX_TRANSFORMER, "image": MAX_PRISONERS}[engine]
    if not 2 <= n <= cap:
        why = {"explicit": f"the contracted model grows like 3^n; add --symbolic for up to {MAX_PRISONERS}",
               "symbolic": f"the transformer product's BDD grows like 4^n; engine 'image' takes up to "
                           f"{MAX_PRISONERS}",
               "image": "the law's BDD grows like n^2"}[engine]
        raise ModelError(f"prisoners: --prisoners must be 2..{cap} on the {engine} engine ({why}), got {n}")
    if not 1 <= days <= MAX_DAYS:
        raise ModelError(f"prisoners: --days must be 1..{MAX_DAYS:,}, got {days}")


# ----------------------------------------------------------------------------- the protocol itself


def protocol_step(n: int, state: tuple[bool, frozenset[int], int], k: int) -> tuple[bool, frozenset[int], int]:
    """One day of the protocol in plain Python: (light, who has switched, the counter's count) after
    prisoner ``k`` (1 = the counter) is interviewed."""
    light, switched, count = state
    if k == 1:
        return False, switched, count + int(light)
    if not light and k not in switched:
        return True, switched | {k}, count
    return light, switched, count


def protocol_run(n: int, schedule: list[int]) -> tuple[int | None, int | None]:
    """(the day the counter's count reaches n − 1, the first day everyone has been interviewed), 1-based."""
    state: tuple[bool, frozenset[int], int] = (False, frozenset(), 0)
    seen: set[int] = set()
    announce = visited = None
    for day, k in enumerate(schedule, 1):
        state = protocol_step(n, state, k)
        seen.add(k)
        if visited is None and len(seen) == n:
            visited = day
        if announce is None and state[2] >= n - 1:
            announce = day
    return announce, visited


def expected_days(n: int) -> Fraction:
    """Expected days until the counter announces under a uniformly random schedule: exact, by the absorbing
    Markov chain of :func:`protocol_step` on (light, count) — which prisoners switched matters only through
    their number, and that is count + light."""
    # E[light, count] = 1 + Σ_k P(k) E[next]; solved backwards from count = n - 1 (absorbing)
    value: dict[tuple[bool, int], Fraction] = {}
    p = Fraction(1, n)
    for count in range(n - 2, -1, -1):
        nxt = Fraction(0) if count + 1 >= n - 1 else value[(False, count + 1)]
        # light on (count + 1 have switched): the counter turns it off (→ (off, count + 1)), others nothing
        on = (1 + p * nxt) / p  # E = 1 + p·nxt + (1 − p)·E
        value[(True, count)] = on
        # light off, `count` have switched: a new prisoner (n − 1 − count of them) turns it on
        fresh = Fraction(n - 1 - count, n)
        value[(False, count)] = (1 + fresh * on) / fresh  # E = 1 + fresh·on + (1 − fresh)·E
    return value[(False, 0)]


def expected_days_closed(n: int) -> Fraction:
    """The closed form n(n − 1) + n·H_{n−1}."""
    return n * (n - 1) + n * sum(Fraction(1, k) for k in range(1, n))


# ----------------------------------------------------------------------------- symbolic


def prisoners_start(n: int, *, bdd: Any = None) -> Any:
    """Nobody has been interviewed, the light is off: common knowledge (the counter observes nothing)."""
    from delkit.backends.symbolic import KnowledgeStructure

    voc = _vocabulary(n)
    return KnowledgeStructure.create(voc, conj(Not(Prop(v)) for v in voc), {COUNTER: []}, bdd=bdd)


def day_transformer(n: int, who: int | None, tag: str) -> Any:
    """One day: prisoner ``who`` is interviewed (``None``: every prisoner is a designated event)."""
    from delkit.backends.symbolic import Transformer

    i = [None] + [Prop(f"i{tag}_{k}") for k in range(1, n + 1)]
    seen = Prop(f"s{tag}")
    one = conj([disj(i[1:])] + [Not(i[a] & i[b]) for a in range(1, n + 1) for b in range(a + 1, n + 1)])
    law = conj([one, Iff(seen, i[1] & LIGHT)])
    changes: dict[str, Formula] = {
        "light": conj([Not(i[1]), disj([LIGHT] + [i[k] & Not(_sw(k)) for k in range(2, n + 1)])])}
    changes |= {f"sw{k}": _sw(k) | (i[k] & Not(LIGHT)) for k in range(2, n + 1)}
    changes |= {f"vis{k}": _vis(k) | i[k] for k in range(1, n + 1)}
    return Transformer(tuple(p.name for p in i[1:]) + (seen.name,), law, changes, {COUNTER: (i[1].name, seen.name)},
                       designated=TOP if who is None else i[who])


def reduce_structure(ks: Any, keep: tuple[str, ...]) -> Any:
    """The substructure generated by the actual states, then: variables the law fixes are replaced by their
    value (and no longer observed), and variables outside ``keep`` that no agent observes are quantified
    away (∃). Each step maps states onto states preserving the valuation of ``keep`` and every agent's
    indistinguishability in both directions (a bounded morphism), so formulas over ``keep`` keep their truth
    at the actual states."""
    from delkit.backends.symbolic import KnowledgeStructure

    g = ks.generated()
    b = g.bdd
    law, actual = g.law, g.actual
    fixed: dict[str, bool] = {}
    for v in g.vocabulary:
        if v in keep:
            continue
        x = b.var(v)
        if (law & ~x) == b.false:
            fixed[v] = True
        elif (law & x) == b.false:
            fixed[v] = False
    if fixed:
        law, actual = b.let(fixed, law), b.let(fixed, actual)
    observed = {a: tuple(v for v in vs if v not in fixed) for a, vs in g.observed.items()}
    seen = {v for vs in observed.values() for v in vs}
    hidden = {v for v in g.vocabulary if v not in keep and v not in fixed and v not in seen}
    if hidden:
        law, actual = b.exist(hidden, law), b.exist(hidden, actual)
    voc = tuple(v for v in g.vocabulary if v not in fixed and v not in hidden)
    return KnowledgeStructure(b, voc, law, observed, actual & law, _props=g._props)


class ImageStructure:
    """The reduced structure of :func:`reduce_structure`, one day after the other, computed directly: the
    law L over V (the states the counter cannot rule out; he observes nothing of V) and the actual state.
    A day is the relational product ``L' = ∃V (L ∧ [light ↔ what the counter saw] ∧ T)`` renamed back, with
    T the transition of the counter's interview, or the disjunction of the other prisoners' — on a manager
    where every variable of V sits next to its next-day copy (the transformer's product declares the copies
    after everything, which makes the product law exponential in n). For the counter's knowledge only L
    matters: K_1 φ holds iff L ⊨ φ."""

    def __init__(self, n: int) -> None:
        from delkit.backends.symbolic import declare, new_manager

        self.n = n
        self.voc = _vocabulary(n)
        self.nxt = {v: f"{v}~" for v in self.voc}
        order = [x for pair in ((v, self.nxt[v]) for v in self.voc) for x in pair]
        mgr = self.bdd = new_manager()
        declare(mgr, order)
        self.law = mgr.cube({v: False for v in self.voc})
        self.actual = self.law
        same = {v: mgr.apply("<=>", mgr.var(self.nxt[v]), mgr.var(v)) for v in self.voc}
        var = mgr.var

        def trans(updates: dict[str, Any]) -> Any:
            out = mgr.true
            for v in reversed(self.voc):
                out = out & (mgr.apply("<=>", var(self.nxt[v]), updates[v]) if v in updates else same[v])
            return out

        light = var("light")
        self.counter_step = trans({"light": mgr.false, "vis1": mgr.true})
        self.steps = {k: trans({"light": light | ~var(f"sw{k}"), f"sw{k}": var(f"sw{k}") | ~light,
                                f"vis{k}": mgr.true}) for k in range(2, n + 1)}
        others = mgr.false
        for k in range(2, n + 1):
            others = others | self.steps[k]
        self.others = others
        self.back = {self.nxt[v]: v for v in self.voc}
        self.qvars = set(self.voc)

    def _image(self, u: Any, rel: Any) -> Any:
        import dd.cudd

        return self.bdd.let(self.back, dd.cudd.and_exists(u, rel, self.qvars))

    def day(self, who: int) -> None:
        b = self.bdd
        if who == 1:
            saw = (self.actual & b.var("light")) != b.false
            seen = b.var("light") if saw else ~b.var("light")
            self.law = self._image(self.law & seen, self.counter_step)
            self.actual = self._image(self.actual, self.counter_step)
        else:
            self.law = self._image(self.law, self.others)
            self.actual = self._image(self.actual, self.steps[who])

    def counter_knows(self) -> bool:
        b = self.bdd
        return (self.law & ~b.cube({f"vis{k}": True for k in range(1, self.n + 1)})) == b.false

    def everyone_visited(self) -> bool:
        b = self.bdd
        return (self.actual & ~b.cube({f"vis{k}": True for k in range(1, self.n + 1)})) == b.false

    def node_size(self) -> int:
        return len(self.law)

    def states(self) -> list[dict[str, bool]]:
        return [dict(x) for x in self.bdd.pick_iter(self.law, care_vars=set(self.voc))]


# ----------------------------------------------------------------------------- explicit


def _start_model(n: int) -> Any:
    from delkit.models.kripke import KripkeModel
    from delkit.models.relation import Relation

    voc = _vocabulary(n)
    return KripkeModel(tuple(voc), (COUNTER,), np.zeros((1, len(voc)), dtype=bool),
                       {COUNTER: Relation.from_labels(np.zeros(1, dtype=np.int64))}, (0,))


def day_event(n: int, who: int | None) -> Any:
    """One day as an event model: events ``1on`` / ``1off`` (the counter finds the light on / off) and ``k``
    (prisoner k ≥ 2); the counter tells apart 1on, 1off and "someone else"."""
    from delkit.models.events import EventModel

    events: dict[str, dict] = {"1on": {"pre": LIGHT, "post": {"light": BOT, "vis1": TOP}},
                               "1off": {"pre": Not(LIGHT), "post": {"vis1": TOP}}}
    for k in range(2, n + 1):
        events[str(k)] = {"pre": TOP, "post": {"light": LIGHT | Not(_sw(k)), f"sw{k}": _sw(k) | Not(LIGHT),
                                               f"vis{k}": TOP}}
    designated = list(events) if who is None else (["1on", "1off"] if who == 1 else [str(who)])
    return EventModel.build(events, {COUNTER: [["1on"], ["1off"], [str(k) for k in range(2, n + 1)]]},
                            designated=designated, agents=(COUNTER,), name="day")


# ----------------------------------------------------------------------------- the puzzle


@dataclass(frozen=True)
class PrisonersResult:
    """``knows_day``: first day the counter knows everyone has been interviewed (DEL); ``announce_day``: the
    day his count reaches n − 1 (the protocol); ``visited_day``: the day the last prisoner was first
    interviewed; ``sound``: everyone had been interviewed whenever the counter knew; ``sizes``: the largest
    reduced structure (variables / BDD nodes) or contracted model (worlds)."""

    n: int
    days: int
    schedule_seed: int | None
    knows_day: int | None
    announce_day: int | None
    visited_day: int | None
    sound: bool
    expected_days: float
    largest: int
    engine: str
    seconds: float

    def as_dict(self) -> dict:
        return {"puzzle": "prisoners", "engine": self.engine, "prisoners": self.n, "days": self.days,
                "seed": self.schedule_seed, "counter_knows_day": self.knows_day,
                "counter_announces_day": self.announce_day, "everyone_visited_day": self.visited_day,
                "knows_exactly_when_count_reaches_n_minus_1": self.knows_day == self.announce_day,
                "sound": self.sound, "expected_days_uniform_schedule": self.expected_days,
                "largest_" + ("worlds" if self.engine == "explicit" else "bdd_nodes"): self.largest,
                "seconds": self.seconds}


def random_schedule(n: int, days: int, seed: int) -> list[int]:
    return [int(k) + 1 for k in np.random.default_rng(seed).integers(0, n, size=days)]


def run_schedule(n: int, schedule: list[int], engine: str = "symbolic", *, stop: bool = True) \
        -> tuple[list[bool], list[bool], int]:
    """Per day: does the counter know that everyone has been interviewed, has everyone been; and the
    largest structure. ``stop``: end on the first day he knows."""
    goal, knows = everyone_visited(n), counter_knows(n)
    out_k: list[bool] = []
    out_v: list[bool] = []
    largest = 0
    if engine == "image":
        img = ImageStructure(n)
        for who in schedule:
            img.day(who)
            largest = max(largest, img.node_size())
            out_k.append(img.counter_knows())
            out_v.append(img.everyone_visited())
            if stop and out_k[-1]:
                break
    elif engine == "symbolic":
        state = prisoners_start(n)
        keep = tuple(state.vocabulary)
        for day, who in enumerate(schedule):
            state = reduce_structure(state.transform(day_transformer(n, who, str(day))), keep)
            largest = max(largest, state.node_size())
            out_k.append(bool(state.holds(knows)))
            out_v.append(bool(state.holds(goal)))
            if stop and out_k[-1]:
                break
    else:
        from delkit.models.bisimulation import contract
        from delkit.models.update import product_update

        model = _start_model(n)
        for who in schedule:
            model = contract(product_update(model, day_event(n, who)))
            largest = max(largest, model.n_worlds)
            out_k.append(bool(model.holds(knows)))
            out_v.append(bool(model.holds(goal)))
            if stop and out_k[-1]:
                break
    return out_k, out_v, largest


def solve_prisoners(n: int = 4, days: int = 200, seed: int = 0, *, schedule: list[int] | None = None,
                    engine: str = "symbolic") -> PrisonersResult:
    """Run a schedule (given, or uniformly random from ``seed``) until the counter knows or ``days`` end."""
    if schedule is not None:
        days = len(schedule)
    if not 0 <= seed < 2**63:
        raise ModelError(f"prisoners: --seed must be 0..2^63-1 (a non-negative integer), got {seed}")
    _check(n, days, engine)
    if schedule is not None:
        bad = [k for k in schedule if not 1 <= k <= n]
        if bad:
            raise ModelError(f"prisoners: the schedule names prisoners {sorted(set(bad))}; prisoners are 1..{n}")
    sched = schedule if schedule is not None else random_schedule(n, days, seed)
    if engine != "explicit":
        from delkit.backends.symbolic import prepare

        prepare()
    t0 = time.process_time()
    knows, visited, largest = run_schedule(n, sched, engine)
    seconds = time.process_time() - t0
    knows_day = knows.index(True) + 1 if any(knows) else None
    announce, visited_day = protocol_run(n, sched[:len(knows)])
    sound = all(v for k, v in zip(knows, visited, strict=True) if k)
    return PrisonersResult(n, len(knows), None if schedule is not None else seed, knows_day, announce, visited_day,
                           sound, float(expected_days(n)), largest, engine, seconds)
