"""Which language a planning file is written in, decided by its content (never by its extension).

* **EPDDL (2026)**: a ``(define ...)`` form with constructs only EPDDL has — ``(action-type-library``,
  ``:action-type``, ``(:event``, ``:observability-conditions``, ``:facts-init``, ``[C.``/``Kw.``
  modalities, an explicit ``:worlds`` initial state, or ``(:init (:and``.
* **E-PDDL (2021)**: a ``(define ...)`` form otherwise (its own markers ``:act_type``, ``:observers``,
  ``:p_observers``, ``:depth`` and the singular ``:effect`` are recorded in the reason).
* **mA\\***: statements such as ``fluent``, ``action``, ``agent``, ``initially``, ``goal``, ``executable``,
  ``... causes ...``, ``... observes ...``.

Anything else is refused with an error naming the file.
"""

from __future__ import annotations

import re
from pathlib import Path

from delkit.errors import ParseError, io_reason

TYPE_CHECKING = False  # typing.TYPE_CHECKING without importing typing (start-up: delkit._records)
if TYPE_CHECKING:
    from typing import Literal

__all__ = ["Dialect", "detect", "detect_text"]

if TYPE_CHECKING:
    Dialect = Literal["mastar", "epddl2021", "epddl2026"]
else:
    Dialect = str

# patterns, compiled on first use (re's cache): a file needs one branch's only (start-up)
_E2026 = (r"\(\s*action-type-library\b|:action-type\b|\(\s*:event\b|:observability-conditions\b|"
          r":facts-init\b|\[\s*C\.|\bKw\.|\(\s*:init\s+:worlds\b|\(\s*:init\s*\(\s*:and\b|"
          r":action-type-libraries\b|:finitary-S5-theories\b")
_E2021 = r":act_type\b|:p_observers\b|:observers\b|\(\s*:depth\b|:effect\b"
_MASTAR = (r"(?m)^\s*(fluent|action|agent|initially|goal|executable)\b|\b(causes|observes|aware_of|"
           r"determines|announces)\b")


def _strip(text: str, comment: str) -> str:
    return "\n".join(ln.split(comment, 1)[0] for ln in text.splitlines())


def detect_text(text: str, source: str = "<text>") -> tuple[Dialect, str]:
    """(dialect, why) for a file's text; :class:`ParseError` naming ``source`` if it is none of them."""
    lisp = _strip(text, ";")
    if lisp.lstrip().startswith("("):
        if not re.match(r"\s*\(\s*define\b", lisp):
            raise ParseError("not an mA*, E-PDDL (2021) or EPDDL (2026) file: it starts with '(' but not "
                             "'(define'", source=source)
        m = re.search(_E2026, lisp)
        if m:
            return "epddl2026", f"EPDDL (2026) construct {m.group().strip()!r}"
        m = re.search(_E2021, lisp)
        return "epddl2021", (f"E-PDDL (2021) construct {m.group().strip()!r}" if m
                             else "a (define ...) form with no EPDDL (2026) construct")
    m = re.search(_MASTAR, _strip(text, "%"))
    if m:
        return "mastar", f"mA* statement {m.group().strip()!r}"
    first = next((ln.strip() for ln in text.splitlines() if ln.strip()), "")
    raise ParseError("not an mA*, E-PDDL (2021) or EPDDL (2026) file"
                     + (f" (it starts with {first[:40]!r})" if first else " (it is empty)"), source=source)


def detect(path: str | Path) -> Dialect:
    """The dialect of the file at ``path`` (see :func:`detect_text`)."""
    p = Path(path)
    try:
        from delkit.paths import read_input

        text = read_input(p, "spec")
    except (OSError, UnicodeDecodeError) as exc:
        raise ParseError(f"cannot read: {io_reason(exc)}", source=str(p)) from None
    return detect_text(text, str(p))[0]
