"""Reader for the mA* language (EFP's input format, used by every standard benchmark) into a :class:`Task`.

Statements (each ends with ``;``, ``%`` starts a comment)::

    fluent f1, f2;          action a1, a2;          agent i, j;
    executable A if φ;                      (several: conjunction)
    A causes l1, l2 [if φ];                 ontic, conditional effects evaluated per world
    A determines φ [if ψ];                  sensing
    A announces φ [if ψ];                   announcement
    i observes A [if φ];                    fully observant  (condition at the pointed world)
    i aware_of A [if φ];                    partially observant; everyone else is oblivious
    initially l1, l2, ...;                  the actual world
    initially C([i,j], φ);                  common knowledge (finitary S5)
    goal φ;                                 (several: conjunction)

Formulas: ``f``, ``-φ``, ``φ & ψ``, ``φ | ψ``, ``φ , ψ`` (conjunction, lowest precedence), ``(φ)``,
``B(i, φ)``, ``C([i,j], φ)``, ``E([i,j], φ)``, ``D([i,j], φ)``. Errors carry file, line and column.
"""

from __future__ import annotations

import re
from pathlib import Path

from delkit._records import DataclassFields, Record
from delkit.errors import ParseError, io_reason
from delkit.logic.formula import TOP, C, D, E, Formula, K, Not, Or, Prop, conj
from planners.lang.initial import finitary_s5
from planners.task import ActionSpec, Task, merge_observers

__all__ = ["parse_mastar", "load_mastar", "parse_mastar_formula", "Tok", "tokenize"]


class Tok(Record):
    """A token (a frozen record, :mod:`delkit._records`)."""

    __dataclass_fields__ = DataclassFields("kind", "text", "line", "col")
    kind: str  # "id", "punct", "eof"
    text: str
    line: int
    col: int

    def __init__(self, kind: str, text: str, line: int, col: int) -> None:
        d = self.__dict__  # item by item: faster than update(**kw) (one Tok per token)
        d["kind"], d["text"], d["line"], d["col"] = kind, text, line, col


_TOKEN = re.compile(r"\s+|%[^\n]*|[A-Za-z_][A-Za-z0-9_]*|[(),;\[\]&|\-]|.", re.S)


def tokenize(text: str, source: str) -> list[Tok]:
    """Split mA* text into identifiers and punctuation with 1-based line/column."""
    toks: list[Tok] = []
    line, lstart = 1, 0
    for m in _TOKEN.finditer(text):
        s = m.group(0)
        col = m.start() - lstart + 1
        if s[0].isspace() or s[0] == "%":
            pass
        elif s[0].isalpha() or s[0] == "_":
            toks.append(Tok("id", s, line, col))
        elif s in "(),;[]&|-":
            toks.append(Tok("punct", s, line, col))
        else:
            raise ParseError(f"unexpected character {s!r}", source=source, line=line, column=col)
        nl = s.count("\n")
        if nl:
            line += nl
            lstart = m.start() + s.rfind("\n") + 1
    toks.append(Tok("eof", "<end of file>", line, len(text) - lstart + 1))
    return toks


_KEYWORDS = {"fluent", "action", "agent", "executable", "causes", "determines", "announces", "observes",
             "aware_of", "initially", "goal", "if"}


class _Parser:
    def __init__(self, text: str, source: str, *, strict: bool = False, deadline: float | None = None) -> None:
        self.source = source
        self.strict = strict
        self.deadline = deadline
        self.warnings: list[str] = []
        self.toks = tokenize(text, source)
        self.i = 0
        self.tok = self.toks[0]  # the current token, self.toks[self.i] (an attribute: read at every step)
        self.fluents: list[str] = []
        self.actions: list[str] = []
        self.agents: list[str] = []
        self.decl_at: dict[str, Tok] = {}

    # ------------------------------------------------------------------ token helpers
    def seek(self, i: int) -> None:
        self.i = i
        self.tok = self.toks[i]

    def err(self, msg: str, tok: Tok | None = None, expected: list[str] | None = None) -> ParseError:
        t = tok or self.tok
        return ParseError(msg, source=self.source, line=t.line, column=t.col, expected=expected)

    def where(self, tok: Tok) -> str:
        return f"{self.source}:{tok.line}:{tok.col}"

    def next(self) -> Tok:
        t = self.tok
        self.i += 1
        self.tok = self.toks[self.i] if t.kind != "eof" else t  # (the parser never moves past end of file)
        return t

    def accept(self, text: str) -> bool:
        t = self.tok
        if t.text == text and t.kind != "eof":
            self.i += 1
            self.tok = self.toks[self.i]
            return True
        return False

    def expect(self, text: str) -> Tok:
        if self.tok.text != text or self.tok.kind == "eof":
            raise self.err(f"found {self.tok.text!r}", expected=[repr(text)])
        return self.next()

    def ident(self, what: str) -> Tok:
        if self.tok.kind != "id" or self.tok.text in _KEYWORDS:
            raise self.err(f"found {self.tok.text!r}", expected=[what])
        return self.next()

    # ------------------------------------------------------------------ names
    def fluent(self, t: Tok) -> str:
        if t.text not in self._fl:
            raise self.err(f"unknown fluent {t.text!r} (declare it in a 'fluent' statement)", t)
        return t.text

    def agent(self, t: Tok) -> str:
        if t.text not in self._ag:
            raise self.err(f"unknown agent {t.text!r}; agents are {self.agents}", t)
        return t.text

    def action_name(self, t: Tok) -> str:
        if t.text not in self._ac:
            raise self.err(f"unknown action {t.text!r} (declare it in an 'action' statement)", t)
        return t.text

    # ------------------------------------------------------------------ formulas
    def formula(self) -> Formula:
        """φ ::= disj (',' disj)*   — the comma is a conjunction with the lowest precedence."""
        parts = [self.disj()]
        while self.accept(","):
            parts.append(self.disj())
        return conj(parts)

    def disj(self) -> Formula:
        parts = [self.conj()]
        while self.accept("|"):
            parts.append(self.conj())
        return parts[0] if len(parts) == 1 else Or(tuple(parts))

    def conj(self) -> Formula:
        parts = [self.unary()]
        while self.accept("&"):
            parts.append(self.unary())
        return conj(parts)

    def unary(self) -> Formula:
        t = self.tok
        if self.accept("-"):
            return Not(self.unary())
        if self.accept("("):
            f = self.formula()
            self.expect(")")
            return f
        if t.kind == "id" and t.text in ("B", "K") and self.toks[self.i + 1].text == "(" and t.text not in self._fl:
            self.next()
            self.expect("(")
            ag = self.agent(self.ident("an agent name"))
            self.expect(",")
            f = self.formula()
            self.expect(")")
            return K(ag, f)
        if t.kind == "id" and t.text in ("C", "E", "D") and self.toks[self.i + 1].text == "(" \
                and t.text not in self._fl:
            self.next()
            self.expect("(")
            group = self.group()
            self.expect(",")
            f = self.formula()
            self.expect(")")
            return {"C": C, "E": E, "D": D}[t.text](group, f)
        if t.kind == "id" and t.text not in _KEYWORDS:
            self.next()
            if t.text in ("true", "TRUE") and t.text not in self._fl:
                return TOP
            return Prop(self.fluent(t))
        raise self.err(f"found {t.text!r}", expected=["a fluent", "'-'", "'('", "B(", "C("])

    def group(self) -> tuple[str, ...]:
        self.expect("[")
        ags = [self.agent(self.ident("an agent name"))]
        while self.accept(","):
            ags.append(self.agent(self.ident("an agent name")))
        self.expect("]")
        return tuple(ags)

    def literals(self) -> list[tuple[str, bool, Tok]]:
        out = []
        while True:
            t = self.tok
            neg = self.accept("-")
            if self.accept("("):  # -(f) or (f)
                neg2 = self.accept("-")
                name = self.fluent(self.ident("a fluent"))
                self.expect(")")
                neg = neg != neg2
            else:
                name = self.fluent(self.ident("a fluent"))
            out.append((name, not neg, t))
            if not self.accept(","):
                return out

    # ------------------------------------------------------------------ statements
    def parse(self) -> Task:
        # first pass: declarations (mA* files may use names before their declaration statement)
        self._declarations()
        self._fl, self._ag, self._ac = set(self.fluents), set(self.agents), set(self.actions)
        self.seek(0)
        exe: dict[str, list[Formula]] = {a: [] for a in self.actions}
        kind: dict[str, str] = {}
        kind_at: dict[str, Tok] = {}
        effects: dict[str, list] = {a: [] for a in self.actions}
        sensed: dict[str, list] = {a: [] for a in self.actions}
        full: dict[str, list] = {a: [] for a in self.actions}
        partial: dict[str, list] = {a: [] for a in self.actions}
        first: dict[str, Tok] = {}
        pointed: dict[str, bool] = {}
        common: list[tuple[Formula, str]] = []
        others: list[tuple[Formula, str]] = []
        goals: list[Formula] = []
        while self.tok.kind != "eof":
            t = self.tok
            if t.text in ("fluent", "action", "agent"):
                while self.next().text != ";":
                    pass
                continue
            if t.text == "executable":
                self.next()
                a = self.action_name(self.ident("an action name"))
                first.setdefault(a, t)
                if self.accept("if"):
                    exe[a].append(self.formula())
            elif t.text == "initially":
                self.next()
                f = self.formula()
                self._initially(f, t, pointed, common, others)
            elif t.text == "goal":
                self.next()
                goals.append(self.formula())
            elif t.kind == "id":
                name = self.next()
                verb = self.tok
                if verb.text in ("causes", "determines", "announces"):
                    a = self.action_name(name)
                    first.setdefault(a, name)
                    self.next()
                    k = {"causes": "ontic", "determines": "sensing", "announces": "announcement"}[verb.text]
                    if kind.setdefault(a, k) != k:
                        raise self.err(f"action {a!r} is {kind[a]} (line {kind_at[a].line}) and cannot also "
                                       f"be {k}", verb)
                    kind_at.setdefault(a, verb)
                    if k == "ontic":
                        lits = self.literals()
                        cond = self.formula() if self.accept("if") else TOP
                        effects[a].extend((p, v, cond) for p, v, _ in lits)
                    else:
                        f = self.formula()
                        cond = self.formula() if self.accept("if") else TOP
                        items = list(f.args) if (k == "sensing" and f.__class__.__name__ == "And") else [f]
                        sensed[a].extend((g, cond) for g in items)
                elif verb.text in ("observes", "aware_of"):
                    ag = self.agent(name)
                    self.next()
                    a = self.action_name(self.ident("an action name"))
                    cond = self.formula() if self.accept("if") else TOP
                    (full if verb.text == "observes" else partial)[a].append((ag, cond))
                else:
                    raise self.err(f"found {verb.text!r} after {name.text!r}", verb,
                                   expected=["causes", "determines", "announces", "observes", "aware_of"])
            else:
                raise self.err(f"found {t.text!r} at the start of a statement",
                               expected=["fluent", "action", "agent", "executable", "initially", "goal",
                                         "an action or agent name"])
            if self.tok.text != ";":
                raise self.err(f"found {self.tok.text!r}", expected=["';'", "','", "'&'", "'|'", "'if'"])
            self.next()
        if not goals:
            raise ParseError("no 'goal' statement", source=self.source)
        specs = []
        for a in self.actions:
            where = self.where(first.get(a, self.decl_at[a]))
            specs.append(ActionSpec(
                name=a, kind=kind.get(a, "ontic"), executable=conj(exe[a]), effects=tuple(effects[a]),
                sensed=tuple(sensed[a]), full=tuple(merge_observers(full[a])),
                partial=tuple(merge_observers(partial[a])), where=where))
        model = finitary_s5(self.fluents, self.agents, pointed, common, others, source=self.source,
                            deadline=self.deadline)
        name = Path(self.source).stem
        return Task(name, tuple(self.fluents), tuple(self.agents), model, tuple(specs), conj(goals), self.source)

    def _initially(self, f: Formula, t: Tok, pointed: dict[str, bool], common: list, others: list) -> None:
        where = self.where(t)
        parts = list(f.args) if f.__class__.__name__ == "And" else [f]
        for g in parts:
            if isinstance(g, C):
                if set(g.group) != set(self.agents):
                    # EFP reads C statements of the initial state as holding in every world (S5 finitary)
                    pass
                common.append((g.arg, where))
            elif isinstance(g, Prop) or (isinstance(g, Not) and isinstance(g.arg, Prop)):
                name, value = (g.name, True) if isinstance(g, Prop) else (g.arg.name, False)  # type: ignore[union-attr]
                if pointed.get(name, value) != value:  # `initially p; initially -p;`: no actual world
                    raise self.err(f"the 'initially' literals contradict each other: fluent {name!r} is given "
                                   f"both true and false; keep one of them", t)
                pointed[name] = value
            else:
                others.append((g, where))

    def _declarations(self) -> None:
        while self.tok.kind != "eof":
            t = self.next()
            if t.text in ("fluent", "action", "agent") and t.kind == "id":
                target = {"fluent": self.fluents, "action": self.actions, "agent": self.agents}[t.text]
                while True:
                    n = self.ident(f"a name for the {t.text}")
                    if n.text in self.decl_at and not self.strict and n.text in target:
                        first = self.decl_at[n.text]
                        msg = (f"{self.source}:{n.line}: warning: {t.text} {n.text!r} is declared twice (first at "
                               f"line {first.line}); the duplicate is ignored (--strict makes this an error)")
                        self.warnings.append(msg)  # printed once the file has been read without error
                        if self.accept(";"):
                            break
                        self.expect(",")
                        continue
                    if n.text in self.decl_at:
                        raise self.err(f"{n.text!r} is declared twice (first at line {self.decl_at[n.text].line})",
                                       n)
                    self.decl_at[n.text] = n
                    target.append(n.text)
                    if self.accept(";"):
                        break
                    self.expect(",")
        if not self.agents:
            raise ParseError("no 'agent' statement", source=self.source)
        self.seek(0)


def _warn(msg: str) -> None:
    """One line on stderr (the CLI's channel for warnings); tests capture it with ``capsys``."""
    import sys

    print(f"delkit: {msg}", file=sys.stderr)


def parse_mastar(text: str, source: str = "<mA*>", *, strict: bool = False, deadline: float | None = None) -> Task:
    """Parse mA* ``text`` into a grounded :class:`Task` (errors name ``source``, line and column).

    A name declared twice in the same kind of list (``fluent p, q, p;``, as some published files do) is
    accepted with a one-line warning naming the file, line and duplicate; ``strict`` keeps it an error.
    ``deadline`` (``time.monotonic()``) bounds building the initial state."""
    parser = _Parser(text, source, strict=strict, deadline=deadline)
    task = parser.parse()
    for msg in parser.warnings:  # after the parse: a file that fails is one error line, no warnings before it
        _warn(msg)
    return task


def parse_mastar_formula(text: str, task: Task, *, source: str = "<formula>") -> Formula:
    """One mA* formula over the fluents and agents of ``task``. Outside mA* files (a property, a goal given on
    the command line) ``~`` and ``!`` are read as mA*'s negation ``-`` too, as in delkit's own syntax, so a
    formula may mix the two (``~B(a, p)``); the replacement keeps every column."""
    p = _Parser(re.sub(r"[~!]", "-", text), source)
    p.fluents, p.agents = list(task.props), list(task.agents)
    p._fl, p._ag, p._ac = set(task.props), set(task.agents), {a.name for a in task.actions}
    f = p.formula()
    if p.tok.kind != "eof":
        raise p.err(f"found {p.tok.text!r} after the formula", expected=["end of formula"])
    return f


def load_mastar(path: str | Path, *, strict: bool = False, deadline: float | None = None) -> Task:
    """Read an mA* file (see :func:`parse_mastar`)."""
    p = Path(path)
    try:
        from delkit.paths import read_input

        text = read_input(p, "mA* file")
    except (OSError, UnicodeDecodeError) as exc:
        raise ParseError(f"cannot read the mA* file: {io_reason(exc)}", source=str(p)) from None
    return parse_mastar(text, str(p), strict=strict, deadline=deadline)
