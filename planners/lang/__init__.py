"""Readers for epistemic planning languages (mA*, E-PDDL) into grounded tasks.

:func:`load_task` picks the reader: a file whose text starts with ``(define`` (or ends in ``.epddl`` /
``.pddl``) is E-PDDL (domain + problem, or both in one file); anything else is mA*.
"""

from __future__ import annotations

from pathlib import Path

from delkit.errors import ParseError

__all__ = ["load_task", "is_epddl", "shared_benchmarks"]


def is_epddl(path: str | Path) -> bool:
    """True if ``path`` looks like an E-PDDL file (by extension or by its first form)."""
    p = Path(path)
    if p.suffix.lower() in (".epddl", ".pddl"):
        return True
    try:
        head = p.read_text()[:4096]
    except (OSError, UnicodeDecodeError):  # the reader that is tried next reports it
        return False
    lines = [ln.split(";", 1)[0].strip() for ln in head.splitlines()]
    text = " ".join(ln for ln in lines if ln)
    return text.startswith("(define") or text.startswith("( define")


def load_task(spec: str | Path, problem: str | Path | None = None):
    """Read an mA* file, or an E-PDDL domain (+ problem) into a :class:`planners.task.Task`."""
    spec = Path(spec)
    if not spec.exists():
        raise ParseError("no such file", source=str(spec))
    if problem is not None and not Path(problem).exists():
        raise ParseError("no such file", source=str(problem))
    if is_epddl(spec):
        from planners.lang.epddl import load_epddl

        return load_epddl(spec, problem)
    if problem is not None:
        raise ParseError(f"{spec} is an mA* file, which holds the whole problem; a second file "
                         f"({problem}) is only accepted with an E-PDDL domain", source=str(spec))
    from planners.lang.mastar import load_mastar

    return load_mastar(spec)


def shared_benchmarks() -> Path | None:
    """``../shared/benchmarks`` next to the repository root (read in place, never copied), or None."""
    root = Path(__file__).resolve().parent.parent.parent
    p = root.parent / "shared" / "benchmarks"
    return p if p.is_dir() else None
