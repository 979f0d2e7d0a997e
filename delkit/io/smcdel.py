"""Reader for SMCDEL's input language (``.smcdel.txt``) and its answers on delkit's symbolic backend.

A file gives a knowledge structure and a list of queries (SMCDEL's ``exec/smcdel`` reads the same)::

    -- comments start with two dashes
    VARS 1,2,3                     -- propositional variables are numbers
    LAW  Top                       -- the state law θ (a Boolean formula)
    OBS  alice: 2,3                -- the variables each agent observes
         bob:   1,3
    TRUE?  {1,2} alice knows that 2    -- truth at the state where exactly 1 and 2 are true
    VALID? [ ! (1|2|3) ] ~ bob knows whether 2
    WHERE? alice knows whether 1   -- the states where the formula is true

Formulas: ``Top Bot``, numbers, ``~ φ`` (also ``Not``/``not``/``¬``), ``φ & ψ``, ``φ | ψ``, ``φ -> ψ``,
``φ iff ψ``, ``AND(φ,…)``, ``OR(φ,…)``, ``XOR(φ,…)`` (odd parity), ``ONEOF(φ,…)`` (exactly one),
``K a φ`` / ``a knows that φ``, ``Kw a φ`` / ``a knows whether φ``, ``a,b comknow that φ`` /
``(a,b) comknow whether φ``, ``a,b distknow that φ`` / ``(a,b) distknow whether φ``, public
announcements ``[! φ] ψ``, announce-whether ``[?! φ] ψ``, their
duals ``<! φ> ψ`` and ``<?! φ> ψ``, group announcements ``[a,b ! φ] ψ`` / ``[a,b ?! φ] ψ`` (a and b learn
φ / whether φ, the others learn that they did), Boolean quantifiers ``Forall 1,2 φ`` / ``Exists 1 φ``
(on Boolean φ). Unary operators bind tighter than ``&``/``|``, which bind tighter than ``->``/``iff``.

**delkit extension — belief structures.** SMCDEL's file language describes S5 knowledge structures only
(its belief structures, ``SMCDEL.Symbolic.K``, are used from Haskell). delkit also reads a ``REL`` block in
place of ``OBS``: one relation per agent, a Boolean formula over the variables and their primed copies
(``1'`` = the value of 1 at the state the agent considers possible)::

    VARS 1,2
    LAW  Top
    REL  alice: 1' iff 1        -- alice sees the states that agree on 1 (as OBS alice: 1)
         bob:   ~2'             -- bob always believes ~2 (KD45 if some state has ~2)

Then ``K a φ`` / ``a knows that φ`` (also ``a believes that φ``) is the box of that relation (belief on
KD45 relations), and the file describes a :class:`delkit.backends.symbolic_belief.BeliefStructure` (K, KD45 or
S5, whatever the relations are). Primed variables are allowed in REL lines only.

Parsing uses lark (like delkit's other grammars); errors carry the line and column. Queries are answered
on :class:`delkit.backends.symbolic.KnowledgeStructure` (OBS) or
:class:`delkit.backends.symbolic_belief.BeliefStructure` (REL).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from typing import Any

import numpy as np

from delkit.errors import ModelError, ParseError
from delkit.logic.formula import (
    BOT,
    TOP,
    Announce,
    C,
    D,
    Dkw,
    Formula,
    Iff,
    Implies,
    K,
    Kw,
    Not,
    Prop,
    Update,
    conj,
    disj,
    is_propositional,
    substitute,
)

__all__ = ["SmcdelFile", "Query", "parse_smcdel", "answer", "check_file"]

_GRAMMAR = r"""
start: "VARS" ints "LAW" form (OBS obsline+ | REL relline+) query*
obsline: NAME ":" ints?
relline: NAME ":" form
query: TRUEQ state form     -> true_q
     | VALIDQ form          -> valid_q
     | WHEREQ form          -> where_q
state: "{" ints? "}"
ints: INT ("," INT)*
names: NAME ("," NAME)*

?form: bin
?bin: disj
    | bin "->" disj             -> implies
    | bin "iff" disj            -> iff
?disj: unary
     | disj "&" unary           -> and2
     | disj "|" unary           -> or2
?unary: NEG unary               -> neg
      | "K" NAME unary          -> knows
      | "Kw" NAME unary         -> knows_whether
      | NAME "knows" "that" unary      -> knows
      | NAME "knows" "whether" unary   -> knows_whether
      | NAME "believes" "that" unary   -> knows
      | names "comknow" "that" unary   -> ck
      | names "comknow" "whether" unary -> ckw
      | "(" names ")" "comknow" "that" unary    -> ck
      | "(" names ")" "comknow" "whether" unary -> ckw
      | names "distknow" "that" unary   -> dk
      | names "distknow" "whether" unary -> dkw
      | "(" names ")" "distknow" "that" unary    -> dk
      | "(" names ")" "distknow" "whether" unary -> dkw
      | "[" "!" form "]" unary             -> pub
      | "[" "?" "!" form "]" unary         -> pubw
      | "<" "!" form ">" unary             -> dpub
      | "<" "?" "!" form ">" unary         -> dpubw
      | "[" names "!" form "]" unary       -> grp
      | "[" names "?" "!" form "]" unary   -> grpw
      | "<" names "!" form ">" unary       -> dgrp
      | "<" names "?" "!" form ">" unary   -> dgrpw
      | FORALL ints unary              -> forall
      | "Exists" ints unary            -> exists
      | atom
?atom: "Top"                    -> top
     | "Bot"                    -> bot
     | INT                      -> var
     | PRIMED                   -> primed
     | "(" form ")"
     | "AND" "(" forms ")"      -> conj
     | "OR" "(" forms ")"       -> disj
     | "XOR" "(" forms ")"      -> xor
     | "ONEOF" "(" forms ")"    -> oneof
forms: form ("," form)*

OBS.3: "OBS"
REL.3: "REL"
PRIMED.2: /[0-9]+'/
TRUEQ.3: "TRUE?"
VALIDQ.3: "VALID?"
WHEREQ.3: "WHERE?"
NEG.3: "~" | "¬" | "Not" | "not"
FORALL.3: "Forall" | "ForAll"
NAME: /[a-zA-Z][a-zA-Z0-9]*/
INT: /[0-9]+/
COMMENT: /--[^\n]*/
%ignore COMMENT
%ignore /[ \t\r\n]+/
"""


@lru_cache(maxsize=1)
def _parser() -> Any:
    from lark import Lark

    return Lark(_GRAMMAR, parser="lalr", propagate_positions=True, maybe_placeholders=False)


@dataclass(frozen=True)
class Query:
    """One query: ``kind`` is "true", "valid" or "where"; ``text`` the formula as written."""

    kind: str
    formula: Formula
    text: str
    line: int
    column: int
    state: tuple[int, ...] | None = None


@dataclass(frozen=True)
class SmcdelFile:
    """A parsed file. ``observed`` (OBS, a knowledge structure) or ``relations`` (REL, delkit's extension:
    a belief structure, one formula over V and V' per agent) describes the agents."""

    variables: tuple[int, ...]
    law: Formula
    observed: dict[str, tuple[int, ...]]
    queries: tuple[Query, ...]
    relations: dict[str, Formula] | None = None


def _name(n: int | str) -> str:
    return str(n)


def parse_smcdel(text: str, *, source: str = "<smcdel>") -> SmcdelFile:
    """Parse a ``.smcdel.txt`` text; :class:`ParseError` with line and column on bad input."""
    from lark.exceptions import UnexpectedCharacters, UnexpectedEOF, UnexpectedInput, UnexpectedToken

    try:
        tree = _parser().parse(text)
    except UnexpectedToken as exc:
        tok = exc.token
        shown = "end of file" if tok.type == "$END" else repr(str(tok))
        expected = sorted({_readable(t) for t in exc.expected})[:12]
        line, column = (exc.line, exc.column) if tok.type != "$END" else _end(text)
        raise ParseError(f"unexpected {shown}", source=source, line=line, column=column, expected=expected) from None
    except UnexpectedCharacters as exc:
        raise ParseError(f"unexpected character {text[exc.pos_in_stream]!r}", source=source, line=exc.line,
                         column=exc.column) from None
    except UnexpectedEOF:
        line, column = _end(text)
        raise ParseError("file ends too early", source=source, line=line, column=column) from None
    except UnexpectedInput as exc:  # pragma: no cover - other lark errors
        raise ParseError(str(exc), source=source) from None
    return _Build(text, source).file(tree)


def _end(text: str) -> tuple[int, int]:
    lines = text.splitlines() or [""]
    return len(lines), len(lines[-1]) + 1


_READABLE = {"INT": "a variable number", "PRIMED": "a primed variable", "OBS": "OBS", "REL": "REL",
             "NAME": "an agent name", "NEG": "~", "FORALL": "Forall",
             "TRUEQ": "TRUE?", "VALIDQ": "VALID?", "WHEREQ": "WHERE?", "$END": "end of file"}


def _readable(terminal: str) -> str:
    if terminal in _READABLE:
        return _READABLE[terminal]
    try:
        pattern = _parser().get_terminal(terminal).pattern
        return str(pattern.value) if pattern.type == "str" else terminal
    except Exception:  # noqa: BLE001 - unknown to the grammar: keep lark's name
        return terminal


class _Build:
    def __init__(self, text: str, source: str) -> None:
        self.text = text
        self.source = source
        self.variables: set[str] = set()

    def error(self, message: str, node: Any) -> ParseError:
        meta = getattr(node, "meta", None)
        line = getattr(node, "line", None) or (meta.line if meta is not None and not meta.empty else None)
        column = getattr(node, "column", None) or (meta.column if meta is not None and not meta.empty else None)
        return ParseError(message, source=self.source, line=line, column=column)

    def file(self, tree: Any) -> SmcdelFile:
        ch = tree.children
        variables = tuple(int(t) for t in ch[0].children)
        dup = sorted({v for v in variables if variables.count(v) > 1})
        if dup:
            raise self.error(f"VARS lists {dup} more than once", ch[0])
        self.variables = {_name(v) for v in variables}
        law = self.form(ch[1])
        observed: dict[str, tuple[int, ...]] = {}
        relations: dict[str, Formula] | None = {} if str(ch[2]) == "REL" else None
        queries = []
        for node in ch[3:]:
            if node.data == "relline":
                agent = str(node.children[0])
                if agent in relations:
                    raise self.error(f"REL names agent {agent!r} twice", node)
                self.primes_allowed = True
                try:
                    relations[agent] = self.form(node.children[1])
                finally:
                    self.primes_allowed = False
                observed[agent] = ()
            elif node.data == "obsline":
                agent = str(node.children[0])
                if agent in observed:
                    raise self.error(f"OBS names agent {agent!r} twice", node)
                obs = tuple(int(t) for t in node.children[1].children) if len(node.children) > 1 else ()
                bad = sorted(set(obs) - set(variables))
                if bad:
                    raise self.error(f"agent {agent!r} observes {bad}, not declared in VARS", node)
                observed[agent] = obs
            else:
                queries.append(self.query(node, observed))
        return SmcdelFile(variables, law, observed, tuple(queries), relations)

    def query(self, node: Any, observed: dict[str, tuple[int, ...]]) -> Query:
        self.agents = set(observed)
        f_node = node.children[-1]
        formula = self.form(f_node)
        text = " ".join(self.text[f_node.meta.start_pos:f_node.meta.end_pos].split()) \
            if not f_node.meta.empty else str(f_node)
        state = None
        if node.data == "true_q":
            st = node.children[1]
            state = tuple(int(t) for t in st.children[0].children) if st.children else ()
            bad = sorted(set(state) - {int(v) for v in self.variables})
            if bad:
                raise self.error(f"state lists {bad}, not declared in VARS", st)
        kind = {"true_q": "true", "valid_q": "valid", "where_q": "where"}[node.data]
        return Query(kind, formula, text, node.meta.line, node.meta.column, state)

    def _agent(self, tok: Any) -> str:
        name = str(tok)
        agents = getattr(self, "agents", None)
        if agents is not None and name not in agents:
            raise self.error(f"unknown agent {name!r} (OBS declares {', '.join(sorted(agents))})", tok)
        return name

    def _names(self, node: Any) -> list[str]:
        return [self._agent(t) for t in node.children]

    def form(self, t: Any) -> Formula:  # noqa: C901 - one clause per construct
        from lark import Token

        if isinstance(t, Token):
            if t.type == "INT":
                return self._var(t)
            raise AssertionError(t)
        d, ch = t.data, t.children
        if d == "top":
            return TOP
        if d == "bot":
            return BOT
        if d == "var":
            return self._var(ch[0])
        if d == "primed":
            tok = ch[0]
            if not getattr(self, "primes_allowed", False):
                raise self.error(f"primed variable {tok} outside a REL line (only relations talk about the "
                                 "successor state)", tok)
            base = self._var(tok.update("INT", str(tok)[:-1]))
            return Prop(base.name + "'")
        if d == "neg":
            return Not(self.form(ch[1]))
        if d == "and2":
            return conj([self.form(ch[0]), self.form(ch[1])])
        if d == "or2":
            return disj([self.form(ch[0]), self.form(ch[1])])
        if d == "implies":
            return Implies(self.form(ch[0]), self.form(ch[1]))
        if d == "iff":
            return Iff(self.form(ch[0]), self.form(ch[1]))
        if d in ("conj", "disj", "xor", "oneof"):
            parts = [self.form(c) for c in ch[0].children]
            if d == "conj":
                return conj(parts)
            if d == "disj":
                return disj(parts)
            if d == "xor":
                return _xor(parts)
            return disj(conj([p if i == j else Not(p) for j, p in enumerate(parts)]) for i in range(len(parts)))
        if d == "knows":
            return K(self._agent(ch[0]), self.form(ch[1]))
        if d == "knows_whether":
            return Kw(self._agent(ch[0]), self.form(ch[1]))
        if d in ("ck", "ckw"):
            group, arg = self._names(ch[0]), self.form(ch[1])
            return C(group, arg) if d == "ck" else disj([C(group, arg), C(group, Not(arg))])
        if d in ("dk", "dkw"):
            group, arg = self._names(ch[0]), self.form(ch[1])
            return D(group, arg) if d == "dk" else Dkw(group, arg)
        if d in ("pub", "pubw", "dpub", "dpubw"):
            what, arg = self.form(ch[0]), self.form(ch[1])
            dual = d.startswith("d")
            inner = Not(arg) if dual else arg
            out = Announce(what, inner) if d in ("pub", "dpub") else announce_whether(what, inner)
            return Not(out) if dual else out
        if d in ("grp", "grpw", "dgrp", "dgrpw"):
            group, what, arg = self._names(ch[0]), self.form(ch[1]), self.form(ch[2])
            dual = d.startswith("d")
            inner = Not(arg) if dual else arg
            out = self._group_announce(group, what, inner, whether=d.endswith("w"))
            return Not(out) if dual else out
        if d in ("forall", "exists"):
            ints = [self._var(tk) for tk in ch[-2].children]
            body = self.form(ch[-1])
            if not is_propositional(body):
                raise self.error("Forall/Exists are supported on Boolean formulas only", t)
            out = body
            for p in ints:
                cases = [substitute(out, {p.name: TOP}), substitute(out, {p.name: BOT})]
                out = conj(cases) if d == "forall" else disj(cases)
            return out
        raise AssertionError(f"unhandled parse node {d}")

    def _var(self, tok: Any) -> Formula:
        name = _name(int(tok))
        if name not in self.variables:
            raise self.error(f"variable {name} is not declared in VARS", tok)
        return Prop(name)

    def _group_announce(self, group: list[str], what: Formula, arg: Formula, *, whether: bool) -> Formula:
        """SMCDEL's group announcement: the agents in G learn whether φ (a fresh variable q ↔ φ that only G
        observes); the others learn nothing. ``[G!φ]ψ = φ → ψ after the "yes" event``; with ``whether``
        ψ must hold after whichever event is true."""
        from delkit.models.events import EventModel
        from delkit.models.relation import Relation

        agents = tuple(sorted(self.agents))
        ev = ("yes", "no")
        rels = {a: Relation.from_labels(np.array([0, 1] if a in group else [0, 0])) for a in agents}
        model = EventModel(ev, agents, (what, Not(what)), ({}, {}), rels, (0, 1), "G" + "".join(sorted(group)))
        if not whether:
            return Update(model, 0, arg, model.name)
        return conj([Implies(what, Update(model, 0, arg, model.name)),
                     Implies(Not(what), Update(model, 1, arg, model.name))])


def _xor(parts: list[Formula]) -> Formula:
    if not parts:
        return BOT
    out = parts[0]
    for p in parts[1:]:
        out = Not(Iff(out, p))
    return out


def announce_whether(what: Formula, arg: Formula) -> Formula:
    """SMCDEL's ``[?!φ]ψ``: ``(φ → [!φ]ψ) ∧ (¬φ → [!¬φ]ψ)``."""
    return conj([Implies(what, Announce(what, arg)), Implies(Not(what), Announce(Not(what), arg))])


def structure(spec: SmcdelFile) -> Any:
    """The knowledge structure of a parsed file (variables named by their numbers); with REL lines, the
    belief structure (:class:`delkit.backends.symbolic_belief.BeliefStructure`, primed variables ``1'``)."""
    from delkit.backends.symbolic import KnowledgeStructure

    if spec.relations is not None:
        from delkit.backends.symbolic_belief import BeliefStructure

        return BeliefStructure.create([_name(v) for v in spec.variables], spec.law, spec.relations)

    return KnowledgeStructure.create([_name(v) for v in spec.variables], spec.law,
                                     {a: [_name(v) for v in obs] for a, obs in spec.observed.items()})


#: the most states a WHERE? answer lists (CLI: ``delkit smcdel --max-states``)
MAX_STATES = 100_000


def answer(spec: SmcdelFile, *, max_states: int = MAX_STATES, source: str = "<smcdel>") -> list[dict]:
    """Answer every query: ``{"query", "formula", "line", "column", "answer"}``; for WHERE? the answer is
    the list of states, each the sorted list of its true variables (as SMCDEL prints them) — refused when it
    would list more than ``max_states`` states (counted on the BDD first)."""
    from delkit.resources import counters

    live = counters()  # queries answered so far, for a limit answer
    live["queries"], live["queries_answered"] = len(spec.queries), 0
    ks = structure(spec)
    out = []
    for q in spec.queries:
        live["queries_answered"] = len(out)
        row: dict[str, Any] = {"query": q.kind, "formula": q.text, "line": q.line, "column": q.column}
        if q.kind == "valid":
            row["answer"] = bool(ks.valid(q.formula))
        elif q.kind == "where":
            node = ks.evaluate(q.formula) & ks.law
            count = int(ks.bdd.count(node, nvars=len(ks.vocabulary))) if ks.vocabulary else int(node == ks.bdd.true)
            if count > max_states:
                raise ModelError(f"{source}:{q.line}:{q.column}: WHERE? {q.text} holds at {count} states, more than "
                                 f"the {max_states} an answer lists; ask a narrower query (or VALID?), or raise "
                                 f"--max-states")
            states = ks.states(node)
            row["answer"] = sorted(sorted(int(v) for v, val in s.items() if val) for s in states)
        else:
            assignment = {_name(v): v in q.state for v in spec.variables}
            if not ks.truth(spec.law, assignment):
                raise ModelError(f"{source}:{q.line}:{q.column}: TRUE? state {{{', '.join(map(str, q.state))}}} "
                                 "does not satisfy the LAW")
            row["state"] = list(q.state)
            row["answer"] = bool(ks.truth(q.formula, assignment))
        out.append(row)
    return out


def check_file(path: str, *, max_states: int = MAX_STATES) -> list[dict]:
    """Read, parse and answer a ``.smcdel.txt`` file."""
    from pathlib import Path

    p = Path(path)
    try:
        from delkit.paths import read_input

        text = read_input(p, "SMCDEL file")
    except UnicodeDecodeError:
        raise ParseError("not UTF-8 text", source=str(path)) from None
    return answer(parse_smcdel(text, source=str(path)), max_states=max_states, source=str(path))
