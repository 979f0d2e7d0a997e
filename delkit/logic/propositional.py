"""Propositional validity and satisfiability with z3 (exact: z3 decides SAT).

The tools every DEL construction needs for pre- and postconditions: :func:`to_z3`, :func:`counterexample`,
:func:`valid`, :func:`satisfiable`, :func:`equivalent`. They are used by :mod:`delkit.models.compose` (pruning
impossible events of a macro) and :mod:`delkit.verify` (macro checks, reductions), which re-exports them.
A modal or dynamic formula raises :class:`~delkit.errors.VerificationError`.
"""

from __future__ import annotations

from delkit.errors import VerificationError
from delkit.logic.formula import And, Bot, Formula, Iff, Implies, Not, Or, Prop, Top, parse, show

__all__ = ["to_z3", "counterexample", "valid", "satisfiable", "equivalent"]


def _f(x: Formula | str) -> Formula:
    return parse(x) if isinstance(x, str) else x


def to_z3(formula: Formula | str, variables: dict[str, object] | None = None):
    """Translate a propositional formula into a z3 Boolean expression.

    ``variables`` maps proposition names to z3 Booleans; missing ones are created (``z3.Bool(name)``)
    and added to the dict.
    """
    import z3

    f = _f(formula)
    env: dict[str, object] = {} if variables is None else variables
    memo: dict[Formula, object] = {}

    def go(g: Formula):
        hit = memo.get(g)
        if hit is not None:
            return hit
        if isinstance(g, Top):
            out = z3.BoolVal(True)
        elif isinstance(g, Bot):
            out = z3.BoolVal(False)
        elif isinstance(g, Prop):
            if g.name not in env:
                env[g.name] = z3.Bool(g.name)
            out = env[g.name]
        elif isinstance(g, Not):
            out = z3.Not(go(g.arg))
        elif isinstance(g, And):
            out = z3.And([go(a) for a in g.args]) if g.args else z3.BoolVal(True)
        elif isinstance(g, Or):
            out = z3.Or([go(a) for a in g.args]) if g.args else z3.BoolVal(False)
        elif isinstance(g, Implies):
            out = z3.Implies(go(g.left), go(g.right))
        elif isinstance(g, Iff):
            out = go(g.left) == go(g.right)
        else:
            raise VerificationError(f"{show(f)}: not propositional (contains {show(g)}); reduce dynamic "
                                    f"operators with delkit.verify.reduce or use delkit.verify.prove for modal "
                                    f"formulas")
        memo[g] = out
        return out

    return go(f)


def counterexample(formula: Formula | str) -> dict[str, bool] | None:
    """A valuation (proposition ↦ bool) falsifying a propositional formula, or None if it is valid."""
    import z3

    env: dict[str, object] = {}
    expr = to_z3(formula, env)
    s = z3.Solver()
    s.add(z3.Not(expr))
    if s.check() != z3.sat:
        return None
    m = s.model()
    return {p: bool(z3.is_true(m.eval(v, model_completion=True))) for p, v in sorted(env.items())}


def valid(formula: Formula | str) -> bool:
    """⊨ φ for a propositional φ (exact)."""
    return counterexample(formula) is None


def satisfiable(formula: Formula | str) -> bool:
    """Is the propositional φ satisfiable? (Used by ``compose(..., prune=True)``.)"""
    return not valid(Not(_f(formula)))


def equivalent(a: Formula | str, b: Formula | str) -> bool:
    """⊨ a ↔ b for propositional a, b."""
    return valid(Iff(_f(a), _f(b)))
