"""Readers for epistemic planning languages (mA*, E-PDDL 2021, EPDDL 2026) into grounded tasks.

:func:`load_task` picks the reader by the file's content (:mod:`planners.lang.detect`): EPDDL (2026)
(domain + problem + action-type libraries), E-PDDL (2021) (domain + problem, or both in one file) or mA*.
"""

from __future__ import annotations

from pathlib import Path

from delkit.errors import ParseError

__all__ = ["load_task", "is_epddl", "shared_benchmarks", "dialect_of"]


def is_epddl(path: str | Path) -> bool:
    """True if ``path`` looks like an E-PDDL file (by extension or by its first form)."""
    p = Path(path)
    if p.suffix.lower() in (".epddl", ".pddl"):
        return True
    try:
        from delkit.paths import read_input

        head = read_input(p, "spec")[:4096]
    except (OSError, UnicodeDecodeError):  # the reader that is tried next reports it
        return False
    lines = [ln.split(";", 1)[0].strip() for ln in head.splitlines()]
    text = " ".join(ln for ln in lines if ln)
    return text.startswith("(define") or text.startswith("( define")


def load_task(spec: str | Path, problem: str | Path | None = None, libraries=(), *,
              deadline: float | None = None, strict: bool = False):
    """See :func:`_load_task`; an error raised without a file name (e.g. while building the initial state)
    is given the problem's (or the spec's) name."""
    try:
        return _load_task(spec, problem, libraries, deadline=deadline, strict=strict)
    except ParseError as exc:
        if exc.source not in ("<text>", "", None):
            raise
        raise ParseError(exc.bare_message, source=str(problem or spec), line=exc.line, column=exc.column,
                         expected=exc.expected) from None


def _load_task(spec: str | Path, problem: str | Path | None = None, libraries=(), *,
               deadline: float | None = None, strict: bool = False):
    """Read an mA* file, an E-PDDL (2021) domain (+ problem) or an EPDDL (2026) domain + problem (+ action-type
    libraries) into a :class:`planners.task.Task`. ``deadline`` (a ``time.monotonic()`` instant) bounds
    reading, grounding and the initial state (EPDDL 2026 and mA*); ``strict`` refuses what is otherwise
    accepted with a warning (mA* duplicate declarations)."""
    from planners.lang.detect import detect

    spec = Path(spec)
    if not spec.exists():
        raise ParseError("no such file", source=str(spec))
    if problem is not None and not Path(problem).exists():
        raise ParseError("no such file", source=str(problem))
    for lib in libraries:
        if not Path(lib).exists():
            raise ParseError("no such file", source=str(lib))
    dialect = detect(spec)
    if dialect == "epddl2026":
        from planners.lang.epddl2026 import load_epddl2026

        if problem is None:
            raise ParseError("an EPDDL (2026) domain needs a problem file: DOMAIN PROBLEM [--library FILE ...]",
                             source=str(spec))
        return load_epddl2026(spec, problem, list(libraries), deadline=deadline)
    if libraries:
        raise ParseError("--library is only accepted with an EPDDL (2026) domain", source=str(spec))
    if dialect == "epddl2021":
        from planners.lang.epddl import load_epddl

        return load_epddl(spec, problem)
    if problem is not None:
        raise ParseError(f"{spec} is an mA* file, which holds the whole problem; a second file "
                         f"({problem}) is only accepted with an E-PDDL domain", source=str(spec))
    from planners.lang.mastar import load_mastar

    return load_mastar(spec, deadline=deadline, strict=strict)


def dialect_of(path: str | Path) -> str:
    """``"mastar"``, ``"epddl2021"`` or ``"epddl2026"`` by the file's content."""
    from planners.lang.detect import detect

    return detect(path)


def shared_benchmarks() -> Path | None:
    """``../shared/benchmarks`` next to the repository root (read in place, never copied), or None."""
    root = Path(__file__).resolve().parent.parent.parent
    p = root.parent / "shared" / "benchmarks"
    return p if p.is_dir() else None
