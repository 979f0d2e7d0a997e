"""Muddy children on the number triangle (Gierasimczuk & Szymanik, *A note on a generalization of the Muddy
Children puzzle*, TARK 2011; SMCDEL's ``SMCDEL.Other.MCTRIANGLE``).

Children who are in the same situation are not told apart: a state is a pair (c, m) — c clean and m muddy
children, c + m = n. A muddy child sees (c, m − 1) and so considers (c, m) and (c + 1, m − 1) possible; a
clean child sees (c − 1, m) and considers (c, m) and (c − 1, m + 1). The model of n children therefore has
n + 1 *factual* states (one row of Pascal's triangle) and n *observational* ones — 2n + 1 points instead of
the 2^n worlds of the classical model (:mod:`delkit.puzzles.muddy`).

The father announces a generalised quantifier Q ("some of you", "at least k", "an even number", …): the
factual states (n − m, m) with Q(m) remain. Then "nobody knows" — no muddy child and no clean child could
tell its state, vacuously true of a kind nobody is of, as in the paper's language — is announced as long
as it is true (SMCDEL's ``findNumberTriangle`` protocol); the run ends with the first round in which some
child knows (or when the announcement no longer changes the model: then nobody ever will).

Literature answer: with Q = "at least one" (the classical puzzle) "nobody knows" is announced M − 1 times,
then the muddy children know — on a model with 2n + 1 points. Beyond it (derived here, and tested on every
quantifier of up to 9 children against the classical model): with L < M < U the nearest counts where Q
fails, the muddy children are the first to know after M − L − 1 rounds when L is at least as near as U,
the clean ones after U − M − 1 when U is ("at least k": M − k rounds); for increasing quantifiers (no U)
this agrees with the paper's Theorem 1 as its review states it (Computing Reviews #139441): the muddy
children come to know iff some L < M has ¬Q(L).

The module also runs the same anonymous protocol on the classical explicit model (2^n worlds) and on a
knowledge structure, for the differential tests: every round's answers are the same on all three.
"""

from __future__ import annotations

import re
import time
from dataclasses import dataclass
from typing import Any

import numpy as np

from delkit.errors import ModelError
from delkit.logic.formula import Formula, Implies, Kw, Not, Prop, conj

__all__ = ["MAX_CHILDREN", "MAX_EXPLICIT", "TriangleResult", "parse_quantifier", "triangle_run", "classic_run",
           "solve_number_triangle"]

MAX_CHILDREN = 1_000_000  # the triangle row is a numpy mask of n + 1 booleans per round
MAX_EXPLICIT = 14  # the classical cross-check: 2^14 worlds x 14 children
MAX_SYMBOLIC = 200  # the cross-check on a knowledge structure: count-BDDs of n^2 nodes

_QUANTIFIER_HELP = ("'some', 'all', 'none', 'even', 'odd', 'at-least-K', 'at-most-K', 'exactly-K', "
                    "'more-than-K', 'fewer-than-K' or a list of counts like '1,3,4'")


def parse_quantifier(spec: str, n: int) -> np.ndarray:
    """The counts 0..n of muddy children for which Q holds, as a boolean mask of n + 1 entries."""
    s = spec.strip().lower()
    m = np.arange(n + 1)
    fixed = {"some": m >= 1, "all": m == n, "none": m == 0, "even": m % 2 == 0, "odd": m % 2 == 1}
    if s in fixed:
        return fixed[s]
    hit = re.fullmatch(r"(at-least|at-most|exactly|more-than|fewer-than)-(\d+)", s)
    if hit:
        k = int(hit.group(2))
        return {"at-least": m >= k, "at-most": m <= k, "exactly": m == k, "more-than": m > k,
                "fewer-than": m < k}[hit.group(1)]
    if re.fullmatch(r"\d+(\s*,\s*\d+)*", s):
        counts = [int(x) for x in s.split(",")]
        bad = [c for c in counts if c > n]
        if bad:
            raise ModelError(f"number triangle: quantifier {spec!r} names counts {bad} above the {n} children; "
                             f"use counts 0..{n}")
        mask = np.zeros(n + 1, dtype=bool)
        mask[counts] = True
        return mask
    raise ModelError(f"number triangle: unknown quantifier {spec!r}; use {_QUANTIFIER_HELP}")


@dataclass(frozen=True)
class TriangleResult:
    """One run. ``nobody_knows_rounds``: how often "nobody knows" was announced; then, in the round after,
    ``muddy_know`` / ``clean_know``: whether the muddy / the clean children know their state (``None``:
    nobody is of that kind; both ``False``: nobody ever knows — the announcements stopped changing the
    model); ``states``: factual states (muddy counts) left after the father and after each "nobody knows";
    ``points``: the triangle model's size, 2n + 1, against the classical 2^n worlds."""

    children: int
    muddy: int
    quantifier: str
    nobody_knows_rounds: int
    muddy_know: bool | None
    clean_know: bool | None
    states: tuple[int, ...]
    engine: str
    seconds: float

    @property
    def someone_knows(self) -> bool:
        return bool(self.muddy_know) or bool(self.clean_know)

    def as_dict(self) -> dict:
        return {"puzzle": "number-triangle", "engine": self.engine, "children": self.children, "muddy": self.muddy,
                "quantifier": self.quantifier, "nobody_knows_rounds": self.nobody_knows_rounds,
                "someone_knows": self.someone_knows, "muddy_know": self.muddy_know, "clean_know": self.clean_know,
                "factual_states": list(self.states), "triangle_points": 2 * self.children + 1,
                "classical_worlds": f"2^{self.children}", "seconds": self.seconds}


def _check(n: int, muddy: int, q: np.ndarray, spec: str) -> None:
    if not 1 <= n <= MAX_CHILDREN:
        raise ModelError(f"number triangle: --children must be 1..{MAX_CHILDREN:,}, got {n}")
    if not 0 <= muddy <= n:
        raise ModelError(f"number triangle: --muddy must be 0..{n} (the number of children), got {muddy}")
    if not q[muddy]:
        raise ModelError(f"number triangle: the father's announcement {spec!r} is false when {muddy} of {n} "
                         "children are muddy; choose a quantifier true of --muddy")


def _knows(alive: np.ndarray, m: int) -> tuple[bool, bool]:
    """(the muddy children know, the clean children know) at state (n − m, m) of the row ``alive``; a
    muddy child considers m − 1 possible, a clean one m + 1."""
    n = alive.size - 1
    return (m > 0 and not alive[m - 1]), (m < n and not alive[m + 1])


def _nobody_knows(alive: np.ndarray) -> np.ndarray:
    """The row after the public announcement "nobody knows": the states where no muddy child could tell
    (m = 0 or m − 1 still possible) and no clean child could (m = n or m + 1 still possible)."""
    lower = np.concatenate(([True], alive[:-1]))  # alive[m - 1], vacuous at m = 0
    upper = np.concatenate((alive[1:], [True]))  # alive[m + 1], vacuous at m = n
    return alive & lower & upper


def _run(step, n: int, muddy: int, spec: str, engine: str, t0: float) -> TriangleResult:
    """The protocol on any engine: ``step(first)`` announces "nobody knows" (unless ``first``) and returns
    (muddy know, clean know) at the actual state, the number of factual states left, whether it changed."""
    (mk, ck), states, _ = step(True)
    counts = [states]
    rounds = 0
    while not (mk or ck):
        (mk2, ck2), states, changed = step(False)
        if not changed:  # "nobody knows" no longer removes anything: nobody will ever know
            break
        rounds += 1
        counts.append(states)
        mk, ck = mk2, ck2
    return TriangleResult(n, muddy, spec, rounds, mk if muddy > 0 else None, ck if muddy < n else None,
                          tuple(counts), engine, time.process_time() - t0)


def triangle_run(n: int, muddy: int, quantifier: str = "some") -> TriangleResult:
    """The protocol on the number triangle (n + 1 factual states)."""
    q = parse_quantifier(quantifier, n)
    _check(n, muddy, q, quantifier)
    t0 = time.process_time()
    row = [q.copy()]

    def step(first: bool):
        changed = True
        if not first:
            new = _nobody_knows(row[0])
            changed = not np.array_equal(new, row[0])
            row[0] = new
        return _knows(row[0], muddy), int(row[0].sum()), changed

    return _run(step, n, muddy, quantifier, "triangle", t0)


# ----------------------------------------------------------------------------- the classical model


def _kind_formulas(n: int) -> tuple[Formula, Formula, Formula]:
    """⋀_i (m_i → Kw_i m_i) (the muddy children know), ⋀_i (¬m_i → Kw_i m_i) and ⋀_i ¬Kw_i m_i."""
    m = [Prop(f"m{i}") for i in range(n)]
    kw = [Kw(f"c{i}", m[i]) for i in range(n)]
    return (conj(Implies(m[i], kw[i]) for i in range(n)), conj(Implies(Not(m[i]), kw[i]) for i in range(n)),
            conj(Not(k) for k in kw))


def _count_bdd(mgr: Any, names: list[str], q: np.ndarray) -> Any:
    """BDD of "the number of true ``names`` is in Q" (dynamic programming from the last variable up)."""
    n = len(names)
    # level[k]: the function "k more of the remaining variables make the count land in Q", from the bottom
    level = [mgr.true if q[k] else mgr.false for k in range(n + 1)]  # no variables left: count = k so far
    for i in range(n - 1, -1, -1):
        x = mgr.var(names[i])
        level = [(x & level[k + 1]) | (~x & level[k]) for k in range(i + 1)]
    return level[0]


def classic_run(n: int, muddy: int, quantifier: str = "some", *, symbolic: bool = False) -> TriangleResult:
    """The same anonymous protocol on the classical model: 2^n worlds (explicit, :func:`muddy_model`) or a
    knowledge structure (V = {m_i}, child i observes every m_j but m_i), with the father's Q as the law."""
    q = parse_quantifier(quantifier, n)
    _check(n, muddy, q, quantifier)
    cap = MAX_SYMBOLIC if symbolic else MAX_EXPLICIT
    if n > cap:
        raise ModelError(f"number triangle: the classical {'knowledge structure' if symbolic else 'model'} "
                         f"cross-check takes at most {cap} children, got {n}; leave out "
                         f"{'--symbolic' if symbolic else '--explicit'} (the triangle has 2n + 1 points)")
    mk, ck, nobody = _kind_formulas(n)
    if symbolic:
        from delkit.backends.symbolic import KnowledgeStructure, declare, new_manager, prepare

        prepare()
    t0 = time.process_time()
    if symbolic:
        names = [f"m{i}" for i in range(n)]
        mgr = new_manager()
        declare(mgr, names)
        law = _count_bdd(mgr, names, q)
        actual = mgr.cube({p: i < muddy for i, p in enumerate(names)})
        bare = KnowledgeStructure.create(names, observed={f"c{i}": [p for p in names if p != names[i]]
                                                          for i in range(n)}, bdd=mgr)
        model: Any = KnowledgeStructure(mgr, bare.vocabulary, law, bare.observed, law & actual, _props=bare._props)

        def size(x: Any) -> int:
            return x.count_states()
    else:
        from delkit.puzzles.muddy import muddy_model

        full = muddy_model(n, muddy)
        model = full.restrict(q[full.valuation.sum(axis=1)])

        def size(x: Any) -> int:
            return x.n_worlds
    cur = [model]

    def step(first: bool):
        changed = True
        if not first:
            before = size(cur[0])
            cur[0] = cur[0].announce(nobody)
            changed = size(cur[0]) != before
        muddy_know = muddy > 0 and cur[0].holds(mk)
        clean_know = muddy < n and cur[0].holds(ck)
        return (muddy_know, clean_know), _factual_states(cur[0], n, symbolic), changed

    return _run(step, n, muddy, quantifier, "symbolic" if symbolic else "explicit", t0)


def _factual_states(model: Any, n: int, symbolic: bool) -> int:
    """The number of distinct muddy counts left (the triangle's factual states)."""
    if not symbolic:
        return int(np.unique(model.valuation.sum(axis=1)).size)
    return bin(_bdd_counts(model.bdd, model.law, n)).count("1")


def _spread(mask: int, free: int) -> int:
    """Add 0..free to every count in ``mask`` (free variables, either value)."""
    out = 0
    for j in range(free + 1):
        out |= mask << j
    return out


def _bdd_counts(mgr: Any, u: Any, n: int) -> int:
    """The set of numbers of true variables among the ``n`` variables (levels 0..n-1) of the assignments in
    ``u``, as a bit mask (bit k: some assignment has k true variables); one pass over the BDD's nodes,
    children before parents (no recursion, and no node outlives the call: the manager may go first)."""
    true, false = mgr.true, mgr.false

    def level(f: Any) -> int:
        return n if f == true or f == false else f.level

    memo: dict[Any, int] = {true: 1, false: 0}
    stack = [u]
    while stack:
        f = stack[-1]
        if f in memo:
            stack.pop()
            continue
        lo, hi = (~f.low, ~f.high) if f.negated else (f.low, f.high)
        todo = [g for g in (lo, hi) if g not in memo]
        if todo:
            stack.extend(todo)
            continue
        stack.pop()
        memo[f] = _spread(memo[lo], level(lo) - f.level - 1) | (_spread(memo[hi], level(hi) - f.level - 1) << 1)
    out = _spread(memo[u], level(u))
    memo.clear()
    return out


def solve_number_triangle(n: int, muddy: int, quantifier: str = "some", *, engine: str = "triangle") \
        -> TriangleResult:
    """Run the protocol on ``engine``: ``"triangle"`` (default), ``"explicit"`` or ``"symbolic"``."""
    cap = {"triangle": MAX_CHILDREN, "explicit": MAX_EXPLICIT, "symbolic": MAX_SYMBOLIC}.get(engine)
    if cap is not None and not 1 <= n <= cap:  # before anything is built from n (a mask of n + 1 entries)
        how = {"triangle": "", "explicit": " with --explicit", "symbolic": " with --symbolic"}[engine]
        raise ModelError(f"number triangle: --children must be 1..{cap:,}{how}, got {n}")
    if engine == "triangle":
        return triangle_run(n, muddy, quantifier)
    if engine in ("explicit", "symbolic"):
        return classic_run(n, muddy, quantifier, symbolic=engine == "symbolic")
    raise ModelError(f"number triangle: unknown engine {engine!r}; use triangle, explicit or symbolic")
